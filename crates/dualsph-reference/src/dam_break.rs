//! Dam break over a dry bed: the water-front positions measured by Koshizuka & Oka (1996)
//! for a column of width a = 1 m (and height 2a) in a tank of length 4a, as digitised in the
//! project's design notes. The last digitised point (t = 0.751 s, x = 4.132 m) lies past the
//! far wall and is left out.

/// (t in s, front x in m) for a = 1 m.
pub const KOSHIZUKA_OKA_FRONT: [(f64, f64); 14] = [
    (0.092, 1.128),
    (0.191, 1.244),
    (0.266, 1.464),
    (0.322, 1.695),
    (0.368, 1.903),
    (0.414, 2.123),
    (0.447, 2.365),
    (0.496, 2.584),
    (0.522, 2.804),
    (0.565, 3.034),
    (0.594, 3.219),
    (0.637, 3.462),
    (0.669, 3.704),
    (0.702, 3.900),
];
