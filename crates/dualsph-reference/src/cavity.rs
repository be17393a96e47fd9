//! The lid-driven cavity at Re = 100 and 1000: the centreline velocities of Ghia, Ghia & Shin (1982),
//! *High-Re solutions for incompressible flow using the Navier–Stokes equations and a
//! multigrid method*, J. Comput. Phys. 48, 387–411, Tables I and II (129 × 129 grid), for a
//! unit square whose lid (y = 1) slides at U = 1 in +x, the other walls at rest.

/// Table I, Re = 100: `(y, u)` on the vertical centreline x = 0.5, u in units of U.
pub const GHIA_U_RE100: [(f64, f64); 17] = [
    (1.0000, 1.00000),
    (0.9766, 0.84123),
    (0.9688, 0.78871),
    (0.9609, 0.73722),
    (0.9531, 0.68717),
    (0.8516, 0.23151),
    (0.7344, 0.00332),
    (0.6172, -0.13641),
    (0.5000, -0.20581),
    (0.4531, -0.21090),
    (0.2813, -0.15662),
    (0.1719, -0.10150),
    (0.1016, -0.06434),
    (0.0703, -0.04775),
    (0.0625, -0.04192),
    (0.0547, -0.03717),
    (0.0000, 0.00000),
];

/// Table II, Re = 100: `(x, v)` on the horizontal centreline y = 0.5, v in units of U.
pub const GHIA_V_RE100: [(f64, f64); 17] = [
    (1.0000, 0.00000),
    (0.9688, -0.05906),
    (0.9609, -0.07391),
    (0.9531, -0.08864),
    (0.9453, -0.10313),
    (0.9063, -0.16914),
    (0.8594, -0.22445),
    (0.8047, -0.24533),
    (0.5000, 0.05454),
    (0.2344, 0.17527),
    (0.2266, 0.17507),
    (0.1563, 0.16077),
    (0.0938, 0.12317),
    (0.0781, 0.10890),
    (0.0703, 0.10091),
    (0.0625, 0.09233),
    (0.0000, 0.00000),
];

/// Table I, Re = 1000: `(y, u)` on the vertical centreline x = 0.5, u in units of U.
pub const GHIA_U_RE1000: [(f64, f64); 17] = [
    (1.0000, 1.00000),
    (0.9766, 0.65928),
    (0.9688, 0.57492),
    (0.9609, 0.51117),
    (0.9531, 0.46604),
    (0.8516, 0.33304),
    (0.7344, 0.18719),
    (0.6172, 0.05702),
    (0.5000, -0.06080),
    (0.4531, -0.10648),
    (0.2813, -0.27805),
    (0.1719, -0.38289),
    (0.1016, -0.29730),
    (0.0703, -0.22220),
    (0.0625, -0.20196),
    (0.0547, -0.18109),
    (0.0000, 0.00000),
];

/// Table II, Re = 1000: `(x, v)` on the horizontal centreline y = 0.5, v in units of U.
pub const GHIA_V_RE1000: [(f64, f64); 17] = [
    (1.0000, 0.00000),
    (0.9688, -0.21388),
    (0.9609, -0.27669),
    (0.9531, -0.33714),
    (0.9453, -0.39188),
    (0.9063, -0.51550),
    (0.8594, -0.42665),
    (0.8047, -0.31966),
    (0.5000, 0.02526),
    (0.2344, 0.32235),
    (0.2266, 0.33075),
    (0.1563, 0.37095),
    (0.0938, 0.32627),
    (0.0781, 0.30353),
    (0.0703, 0.29012),
    (0.0625, 0.27485),
    (0.0000, 0.00000),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables end at the walls with the walls' velocities, and the flow through the
    /// centreline nearly balances: `∫ u dy` over x = 0.5 is zero for an incompressible flow
    /// (the trapezoid rule on Ghia's uneven points gives a few per cent of the peak back-flow
    /// times the width).
    #[test]
    fn tables_end_at_the_walls_and_the_flux_nearly_closes() {
        assert_eq!(GHIA_U_RE100[0], (1.0, 1.0));
        assert_eq!(GHIA_U_RE100[16], (0.0, 0.0));
        assert_eq!(GHIA_V_RE100[0], (1.0, 0.0));
        assert_eq!(GHIA_V_RE100[16], (0.0, 0.0));
        let flux: f64 = GHIA_U_RE100
            .windows(2)
            .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[0].0 - w[1].0))
            .sum();
        assert!(flux.abs() < 0.01, "∫u dy = {flux}");
        assert_eq!(GHIA_U_RE1000[0], (1.0, 1.0));
        assert_eq!(GHIA_V_RE1000[16], (0.0, 0.0));
        let flux: f64 = GHIA_U_RE1000
            .windows(2)
            .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[0].0 - w[1].0))
            .sum();
        assert!(flux.abs() < 0.01, "∫u dy = {flux} at Re = 1000");
    }
}
