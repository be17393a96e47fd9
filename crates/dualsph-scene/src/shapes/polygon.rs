//! A simple polygon in 2-D: signed distance, winding-number inside test, and the checks that
//! make it simple (no crossing edges, non-zero area).

use super::{Geometry, comp};

/// The 2-D cross product `(b − a) × (c − a)`: positive when `a → b → c` turns left.
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The distance from `p` to the segment `[a, b]`: with `t = clamp((p − a)·(b − a) / |b − a|²,
/// 0, 1)`, `|p − a − t(b − a)|`.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1]];
    let w = [p[0] - a[0], p[1] - a[1]];
    let len2 = e[0] * e[0] + e[1] * e[1];
    let t = if len2 > 0.0 {
        ((w[0] * e[0] + w[1] * e[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    libm::hypot(w[0] - t * e[0], w[1] - t * e[1])
}

/// A polygon with vertices `v_0 … v_{n−1}` and edges `v_i → v_{i+1 mod n}`.
///
/// Signed distance: `s(p) = ± min_i dist(p, [v_i, v_{i+1}])`, negative when the winding number
/// of the boundary about `p` is non-zero. Winding number: the sum over edges of +1 for an edge
/// crossing the horizontal line through `p` upwards (`y_i ≤ p_y < y_{i+1}`) with `p` on its
/// left (`(v_{i+1} − v_i) × (p − v_i) > 0`), and −1 for one crossing downwards
/// (`y_{i+1} ≤ p_y < y_i`) with `p` on its right. Inside (closed) when the winding number is
/// non-zero or `p` lies within `10⁻¹²` of the polygon's size from an edge.
pub(crate) struct PolygonGeom {
    v: Vec<[f64; 2]>,
    lo: [f64; 2],
    hi: [f64; 2],
}

impl PolygonGeom {
    pub(crate) fn new(vertices: &[Vec<f64>]) -> Self {
        let v: Vec<[f64; 2]> = vertices.iter().map(|x| [comp(x, 0), comp(x, 1)]).collect();
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &v {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        PolygonGeom { v, lo, hi }
    }

    fn edges(&self) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
        let n = self.v.len();
        (0..n).map(move |i| (self.v[i], self.v[(i + 1) % n]))
    }

    fn winding(&self, p: [f64; 2]) -> i64 {
        let mut wn = 0;
        for (a, b) in self.edges() {
            if a[1] <= p[1] {
                if b[1] > p[1] && orient(a, b, p) > 0.0 {
                    wn += 1;
                }
            } else if b[1] <= p[1] && orient(a, b, p) < 0.0 {
                wn -= 1;
            }
        }
        wn
    }

    fn boundary_distance(&self, p: [f64; 2]) -> f64 {
        self.edges()
            .map(|(a, b)| segment_distance(p, a, b))
            .fold(f64::INFINITY, f64::min)
    }

    fn size(&self) -> f64 {
        (self.hi[0] - self.lo[0]).max(self.hi[1] - self.lo[1])
    }
}

impl Geometry for PolygonGeom {
    fn signed_distance(&self, p: &[f64; 3]) -> f64 {
        let q = [p[0], p[1]];
        let dist = self.boundary_distance(q);
        if self.winding(q) != 0 { -dist } else { dist }
    }
    fn contains(&self, p: &[f64; 3]) -> bool {
        let q = [p[0], p[1]];
        self.winding(q) != 0 || self.boundary_distance(q) <= 1e-12 * self.size()
    }
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        ([self.lo[0], self.lo[1], 0.0], [self.hi[0], self.hi[1], 0.0])
    }
    fn surface(&self) -> f64 {
        self.edges()
            .map(|(a, b)| libm::hypot(b[0] - a[0], b[1] - a[1]))
            .sum()
    }
}

/// The signed area `½ Σ_i v_i × v_{i+1}` (shoelace formula; positive counter-clockwise).
pub(crate) fn signed_area(v: &[[f64; 2]]) -> f64 {
    let n = v.len();
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
}

/// Whether the point `c`, collinear with `[a, b]`, lies on that segment.
fn on_segment(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    (0..2).all(|k| a[k].min(b[k]) <= c[k] && c[k] <= a[k].max(b[k]))
}

/// Whether the closed segments `[p1, p2]` and `[q1, q2]` share a point: the orientations of
/// each segment's ends about the other have opposite signs, or an end lies on the other.
fn segments_meet(p1: [f64; 2], p2: [f64; 2], q1: [f64; 2], q2: [f64; 2]) -> bool {
    let (o1, o2) = (orient(p1, p2, q1), orient(p1, p2, q2));
    let (o3, o4) = (orient(q1, q2, p1), orient(q1, q2, p2));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && on_segment(p1, p2, q1))
        || (o2 == 0.0 && on_segment(p1, p2, q2))
        || (o3 == 0.0 && on_segment(q1, q2, p1))
        || (o4 == 0.0 && on_segment(q1, q2, p2))
}

/// The first pair of edges `(i, j)` (edge `i` runs from vertex `i` to `i + 1`) that makes the
/// polygon not simple: two non-adjacent edges that meet, or two adjacent edges that fold
/// back onto each other (collinear with the shared vertex between overlapping parts). A
/// zero-length edge is reported as `(i, i)`.
pub(crate) fn first_crossing(v: &[[f64; 2]]) -> Option<(usize, usize)> {
    let n = v.len();
    let edge = |i: usize| (v[i], v[(i + 1) % n]);
    if let Some(i) = (0..n).find(|&i| v[i] == v[(i + 1) % n]) {
        return Some((i, i));
    }
    for i in 0..n {
        let (a, b) = edge(i);
        // adjacent: edge i and edge i + 1 share vertex i + 1
        let c = v[(i + 2) % n];
        let back = (c[0] - b[0]) * (a[0] - b[0]) + (c[1] - b[1]) * (a[1] - b[1]);
        if n > 2 && orient(a, b, c) == 0.0 && back > 0.0 {
            return Some((i, (i + 1) % n));
        }
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue; // adjacent through vertex 0
            }
            let (p, q) = edge(j);
            if segments_meet(a, b, p, q) {
                return Some((i, j));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(v: &[[f64; 2]]) -> PolygonGeom {
        PolygonGeom::new(&v.iter().map(|p| p.to_vec()).collect::<Vec<_>>())
    }

    #[test]
    fn square_distance_and_winding_either_orientation() {
        let ccw = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        let mut cw = ccw;
        cw.reverse();
        for v in [ccw, cw] {
            let g = poly(&v);
            assert_eq!(g.signed_distance(&[1.0, 1.0, 0.0]), -1.0);
            assert_eq!(g.signed_distance(&[0.5, 1.0, 0.0]), -0.5);
            assert_eq!(g.signed_distance(&[3.0, 1.0, 0.0]), 1.0);
            assert_eq!(g.signed_distance(&[3.0, 3.0, 0.0]), 2f64.sqrt());
            assert!(g.contains(&[2.0, 1.0, 0.0]) && g.contains(&[0.0, 0.0, 0.0]));
            assert!(!g.contains(&[2.0 + 1e-9, 1.0, 0.0]));
        }
        assert_eq!(signed_area(&ccw), 4.0);
        assert_eq!(signed_area(&cw), -4.0);
    }

    #[test]
    fn concave_polygon_inside_test() {
        // an L: the notch [1, 2] × [1, 2] is outside
        let g = poly(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ]);
        assert!(g.contains(&[0.5, 1.5, 0.0]) && g.contains(&[1.5, 0.5, 0.0]));
        assert!(!g.contains(&[1.5, 1.5, 0.0]));
        assert!((g.signed_distance(&[1.5, 1.5, 0.0]) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn crossings() {
        let bowtie = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert_eq!(first_crossing(&bowtie), Some((0, 2)));
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(first_crossing(&square), None);
        let folded = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        assert_eq!(first_crossing(&folded), Some((0, 1)));
        let repeated = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert_eq!(first_crossing(&repeated), Some((1, 1)));
        // a vertex touching a non-adjacent edge
        let touching = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 0.0], [0.0, 2.0]];
        assert!(first_crossing(&touching).is_some());
    }
}
