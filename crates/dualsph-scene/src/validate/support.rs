//! Supports too small to hold neighbours: a generator whose `h_factor` leaves a particle with
//! fewer than a handful of neighbours inside its support radius (`h_factor: 0.3` leaves none,
//! and every SPH sum is the particle's own term).

use super::Check;
use crate::Scene;
use crate::error::Problem;
use crate::generate;
use crate::lattice::Lattice;
use crate::schema::{Block, Generator};

/// Above this `h_factor` every lattice gives at least [`minimum`] neighbours in any
/// dimension, and the count is not taken.
const CHECKED_BELOW: f64 = 3.0;

/// The fewest neighbours a support may hold at start: one on each side along every axis, the
/// least for a gradient estimate in each direction (2 in 1-D, 4 in 2-D, 6 in 3-D).
pub(crate) fn minimum(d: usize) -> usize {
    2 * d
}

/// The neighbours within `h = h_factor·Δx` (strictly: the kernels vanish at `r = h`) of a
/// particle inside an unbounded lattice of kind `lattice`: counted on the particle nearest the
/// centre of a probe block `2⌈h_factor⌉ + 5` spacings wide, generated like a scene's.
pub(crate) fn lattice_neighbours(lattice: Lattice, h_factor: f64, d: usize) -> usize {
    let width = 2.0 * h_factor.ceil() + 5.0;
    let probe = Generator::Block(Block {
        min: vec![0.0; d],
        max: vec![width; d],
        spacing: 1.0,
        lattice,
        jitter: 0.0,
        density: 1.0,
        h_factor,
        clip: None,
        cut: Vec::new(),
        velocity: None,
        internal_energy: 0.0,
        body: None,
    });
    let mut points = Vec::new();
    generate::for_each_position(&probe, d, |p| points.push(p));
    let dist2 = |p: &[f64; 3], q: &[f64; 3]| (0..d).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>();
    let centre = [0.5 * width; 3];
    let Some(middle) = points
        .iter()
        .min_by(|a, b| dist2(a, &centre).total_cmp(&dist2(b, &centre)))
    else {
        return 0;
    };
    let h2 = h_factor * h_factor;
    points
        .iter()
        .filter(|q| *q != middle && dist2(middle, q) < h2)
        .count()
}

/// The first generator whose supports hold fewer than [`minimum`] neighbours at start.
pub(super) fn enough_neighbours(s: &Scene) -> Check {
    let d = s.dimension;
    for (i, g) in s.particles.iter().enumerate() {
        let c = g.common();
        // particles from a file are on no known lattice
        if c.h_factor >= CHECKED_BELOW || matches!(g, Generator::File(_)) {
            continue;
        }
        let n = lattice_neighbours(c.lattice, c.h_factor, d);
        if n < minimum(d) {
            return Err(Problem::new(
                format!("particles[{i}].h_factor"),
                format!(
                    "particles[{i}] ({}): with h_factor = {} a particle inside it has {n} neighbours within \
                     its support radius h = {}·Δx ({:?} lattice), fewer than the {} an SPH estimate needs \
                     in {d}-D; raise h_factor (2 to 2.6 is usual: docs/parameters.md)",
                    g.kind(),
                    c.h_factor,
                    c.h_factor,
                    c.lattice,
                    minimum(d)
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_match_the_lattice_by_hand() {
        // square lattice, r < h strictly: h = Δx holds nobody; just above, the 2d axis
        // neighbours; h = 1.5Δx adds the diagonals (2-D: 8, 3-D: 18 with the face diagonals)
        assert_eq!(lattice_neighbours(Lattice::Square, 1.0, 2), 0);
        assert_eq!(lattice_neighbours(Lattice::Square, 1.01, 1), 2);
        assert_eq!(lattice_neighbours(Lattice::Square, 1.01, 2), 4);
        assert_eq!(lattice_neighbours(Lattice::Square, 1.01, 3), 6);
        assert_eq!(lattice_neighbours(Lattice::Square, 1.5, 2), 8);
        assert_eq!(lattice_neighbours(Lattice::Square, 1.5, 3), 18);
        // 1-D, h = 2Δx: only ±Δx (2Δx is on the support's edge)
        assert_eq!(lattice_neighbours(Lattice::Square, 2.0, 1), 2);
        // 2-D, h = 2Δx: axis ±1, diagonals (√2), knight moves (√5 > 2 out): 8
        assert_eq!(lattice_neighbours(Lattice::Square, 2.0, 2), 8);
        // staggered rows shifted by Δx/2: the rows above and below are at (±0.5, ±1), r = √1.25
        assert_eq!(lattice_neighbours(Lattice::Staggered, 1.2, 2), 6);
    }
}
