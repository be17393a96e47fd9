//! Generators that overlap: two particles of different generators closer than half the
//! smaller spacing.
//!
//! Every pair of generators is checked whatever their bodies (a wall or obstacle overlapping
//! fluid, two fluids, two walls), and the first pair found is refused, naming both generators
//! (and their bodies when the scene declares bodies). Generators that only meet at a surface
//! pass: a fluid block whose square lattice sits `Δx/2` inside a box face and that box's
//! outside wall layers at `Δx/2, 3Δx/2, …` beyond it are `Δx` apart (`0.75Δx` for a staggered
//! fluid); a fluid with an obstacle's shape in its `cut` and the obstacle's inside layers (a
//! circle's first ring at `R − Δx/2`) are more than `Δx/2` apart. A solid obstacle on another
//! lattice than the fluid's can come closer across the surface: cut it `Δx/2` larger.

use super::Check;
use crate::Scene;
use crate::error::Problem;
use crate::generate;
use crate::schema::Generator;

/// A dense cell grid (cell size = one generator's spacing) over that generator's particles,
/// stored as counting-sorted index lists.
struct CellGrid {
    origin: [f64; 3],
    cell: f64,
    dims: [usize; 3],
    starts: Vec<usize>,
    items: Vec<usize>,
}

impl CellGrid {
    fn new(points: &[[f64; 3]], cell: f64, d: usize) -> Self {
        let mut origin = [0.0; 3];
        let mut dims = [1; 3];
        for k in 0..d {
            let lo = points.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
            let hi = points
                .iter()
                .map(|p| p[k])
                .fold(f64::NEG_INFINITY, f64::max);
            origin[k] = lo;
            dims[k] = ((hi - lo) / cell).floor() as usize + 1;
        }
        let mut grid = CellGrid {
            origin,
            cell,
            dims,
            starts: Vec::new(),
            items: Vec::new(),
        };
        let keys: Vec<usize> = points.iter().map(|p| grid.key(p).unwrap_or(0)).collect();
        let mut starts = vec![0; dims.iter().product::<usize>() + 1];
        for &k in &keys {
            starts[k + 1] += 1;
        }
        for c in 1..starts.len() {
            starts[c] += starts[c - 1];
        }
        let mut fill = starts.clone();
        let mut items = vec![0; points.len()];
        for (i, &k) in keys.iter().enumerate() {
            items[fill[k]] = i;
            fill[k] += 1;
        }
        grid.starts = starts;
        grid.items = items;
        grid
    }

    fn coord(&self, x: f64, k: usize) -> i64 {
        ((x - self.origin[k]) / self.cell).floor() as i64
    }

    fn key(&self, p: &[f64; 3]) -> Option<usize> {
        let mut key = 0;
        for k in 0..3 {
            let c = usize::try_from(self.coord(p[k], k))
                .ok()
                .filter(|&c| c < self.dims[k])?;
            key = key * self.dims[k] + c;
        }
        Some(key)
    }

    /// The first indexed point closer than `r` (at most one cell size) to `p`.
    fn near(&self, points: &[[f64; 3]], p: &[f64; 3], r: f64, d: usize) -> Option<usize> {
        let span = |k: usize| if k < d { -1..=1 } else { 0..=0 };
        for a in span(0) {
            for b in span(1) {
                for c in span(2) {
                    let q = [
                        p[0] + a as f64 * self.cell,
                        p[1] + b as f64 * self.cell,
                        p[2] + c as f64 * self.cell,
                    ];
                    let Some(key) = self.key(&q) else { continue };
                    for &j in &self.items[self.starts[key]..self.starts[key + 1]] {
                        let dist2: f64 = (0..d).map(|k| (points[j][k] - p[k]).powi(2)).sum();
                        if dist2 < r * r {
                            return Some(j);
                        }
                    }
                }
            }
        }
        None
    }
}

/// A generator's kind, and its body when the scene declares bodies (e.g. ``Shape(Circle),
/// body `post` ``).
fn describe(s: &Scene, i: usize) -> String {
    let g = &s.particles[i];
    match g.common().body {
        Some(b) if !s.bodies.is_empty() => format!("{}, body `{b}`", g.kind()),
        _ => g.kind().to_owned(),
    }
}

/// For generators of two different bodies (a wall or obstacle in a fluid), how to separate
/// them.
fn hint(s: &Scene, a: usize, b: usize) -> &'static str {
    let body = |i: usize| s.particles[i].common().body;
    if body(a) == body(b) {
        return "";
    }
    "; cut the obstacle's shape from the other generator (`cut: [Circle(..)]`), Δx/2 larger \
     when their lattices do not line up, or put wall layers outside the fluid \
     (`fill: Layers(n: 3, side: Outside)`)"
}

pub(super) fn fmt_point(p: &[f64; 3], d: usize) -> String {
    let parts: Vec<String> = p[..d].iter().map(|x| format!("{x}")).collect();
    format!("({})", parts.join(", "))
}

/// The bounding box `[lo, hi]` of a generator's particles (first `d` components).
pub(super) type Bounds = ([f64; 3], [f64; 3]);

/// Whether two boxes come within `r` of each other.
fn bounds_within(a: &Bounds, b: &Bounds, r: f64, d: usize) -> bool {
    (0..d).all(|k| a.0[k] <= b.1[k] + r && b.0[k] <= a.1[k] + r)
}

/// The positions of generator `g` inside `box` widened by `r` (regenerated, not stored
/// beforehand: only the part near another generator is ever held in memory).
fn positions_near(g: &Generator, d: usize, bx: &Bounds, r: f64) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    generate::for_each_position(g, d, |p| {
        if (0..d).all(|k| p[k] >= bx.0[k] - r && p[k] <= bx.1[k] + r) {
            out.push(p);
        }
    });
    out
}

/// Two particles of different generators closer than half the smaller spacing. For each pair
/// of generators whose bounding boxes come within the search radius, the particles of each
/// that lie near the other's box are generated again; each particle of the finer one is looked
/// up in a grid of the coarser one (cell size = the coarser spacing >= the search radius), so
/// the check is linear in the particles near the pair's common region and needs no memory for
/// the rest (generators far apart cost nothing: found by fuzzing, 112 side-by-side blocks took
/// minutes when every pair was searched; a 48-million-particle block 2.3 GB when all positions
/// were held).
pub(super) fn overlaps(s: &Scene, bounds: &[Bounds]) -> Check {
    let d = s.dimension;
    let spacing: Vec<f64> = s.particles.iter().map(Generator::spacing).collect();
    for a in 0..bounds.len() {
        for b in 0..bounds.len() {
            let coarser = spacing[b] > spacing[a] || (spacing[b] == spacing[a] && b > a);
            if !coarser {
                continue;
            }
            let r = 0.5 * spacing[a];
            if !bounds_within(&bounds[a], &bounds[b], r, d) {
                continue;
            }
            let pa = positions_near(&s.particles[a], d, &bounds[b], r);
            let pb = positions_near(&s.particles[b], d, &bounds[a], r);
            if pa.is_empty() || pb.is_empty() {
                continue;
            }
            let grid = CellGrid::new(&pb, spacing[b], d);
            for p in &pa {
                if let Some(j) = grid.near(&pb, p, r, d) {
                    let q = &pb[j];
                    let dist = (0..d).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
                    let (lo, hi, plo, phi) = if a < b { (a, b, p, q) } else { (b, a, q, p) };
                    return Err(Problem::new(
                        format!("particles[{hi}]"),
                        format!(
                            "particles[{hi}] ({}) overlaps particles[{lo}] ({}): its particle at {} is \
                             {dist:.6} from the particle at {} of particles[{lo}], closer than half the \
                             smaller spacing ({r}){}",
                            describe(s, hi),
                            describe(s, lo),
                            fmt_point(phi, d),
                            fmt_point(plo, d),
                            hint(s, lo, hi)
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}
