//! The target size of every particle: the smallest size the regions ask for where it is.
//!
//! Region r asks for `s_r + γ d_r(x)` at x, with `s_r` its `spacing`, `d_r(x)` the distance
//! from x to the region (0 inside) and `γ` the scene's `grading`; the target is the least of
//! these, within `[finest, coarsest]` (`coarsest` where no region reaches; with `γ = 0` a
//! region asks for nothing outside itself). The distance to a
//! region given by particles (a body, the free surface, the particles whose gradient
//! indicator is above its threshold) is the distance to the nearest such particle (kiddo's
//! nearest-neighbour query), less the region's `distance`.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::neighbours::KdTree;
use dualsph_fluid::prelude::*;
use dualsph_sweep::Support;
use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What the gradient of a `Region::Gradient` is taken of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema)]
pub enum Indicator {
    /// `(max_j ρ_j − min_j ρ_j) / ρ_i` over i and the fluid particles of its support: the
    /// relative jump of the density across the support (shocks, contact discontinuities,
    /// interfaces). A discontinuity's jump does not shrink as its particles split, while a
    /// smooth field's (a rarefaction fan's) is the support's width times its relative
    /// gradient and shrinks with it: a threshold between the two (0.3 in
    /// `scenes/sod_1d_adaptive.ron`) keeps a discontinuity flagged once refined, and lies
    /// above the few per cent of density a split moves.
    Density,
    /// `|∇v|_i` (Frobenius norm, 1/s): shear layers, jets, impacts.
    Velocity,
}

/// The settings as the systems read them (bodies as indices, vectors of the dimension).
#[derive(Resource, Clone, Debug)]
pub struct Resolved<V: Vector> {
    /// By body index: whether its particles split and merge.
    pub refined: Vec<bool>,
    /// The regions, in scene order.
    pub regions: Vec<ResolvedRegion<V>>,
    /// Each region's size.
    pub spacings: Vec<Real>,
    /// The smallest size.
    pub finest: Real,
    /// The largest size.
    pub coarsest: Real,
    /// Growth of a region's size with distance.
    pub grading: Real,
    /// Steps between decisions.
    pub every: u64,
    /// How far outside a region a particle must be to merge.
    pub buffer: Real,
    /// The split pattern's offset.
    pub offset: Real,
    /// The children's radius ratio.
    pub child_h: Real,
    /// Whether sizes are read at the nominal density ([`crate::ladder::LadderSize`]).
    pub nominal: bool,
    /// The size levels between coarsest (0) and finest: `round(d log2(coarsest/finest))`.
    pub levels: usize,
}

/// A region as the systems read it.
#[derive(Clone, Debug)]
pub enum ResolvedRegion<V: Vector> {
    /// A box, moving.
    Box {
        /// Lower corner at t = 0.
        min: V,
        /// Upper corner at t = 0.
        max: V,
        /// Velocity.
        velocity: V,
    },
    /// Around a body.
    Around {
        /// The body.
        body: u16,
        /// The distance from its particles.
        distance: Real,
    },
    /// Near the free surface.
    FreeSurface {
        /// The distance from the surface particles.
        distance: Real,
        /// The threshold on `∇·r`.
        threshold: Real,
    },
    /// Where a gradient is steep.
    Gradient {
        /// Of what.
        quantity: Indicator,
        /// The threshold.
        above: Real,
    },
}

/// The particles' state in row order, as the decisions read it.
pub struct Rows<'a, V: Vector> {
    /// Positions and radii, with the lists and the kernel.
    pub support: Support<'a, V>,
    /// Velocities.
    pub vel: &'a [V],
    /// Masses.
    pub mass: &'a [Real],
    /// Densities.
    pub rho: &'a [Real],
    /// Volumes `m/ρ`.
    pub volume: &'a [Real],
    /// Bodies.
    pub body: &'a [u16],
    /// By body index: whether it is a fluid.
    pub fluid: &'a [bool],
}

impl<V: Vector> Rows<'_, V> {
    fn len(&self) -> usize {
        self.mass.len()
    }

    fn is_fluid(&self, j: usize) -> bool {
        self.fluid[self.body[j] as usize]
    }

    /// The distance from every row in `rows` to the nearest of `points` within `reach`
    /// (infinite beyond it, or without points), in parallel.
    fn distances(&self, rows: &[usize], points: Vec<V>, reach: Real) -> Vec<Real> {
        if points.is_empty() {
            return vec![Real::INFINITY; rows.len()];
        }
        let tree = KdTree::new(&points);
        let pos = self.support.pos;
        rows.par_iter()
            .with_min_len(256)
            .map(|&i| tree.nearest_within(pos[i].0, reach))
            .collect()
    }

    /// The positions of the rows for which `keep` holds.
    fn points_where(&self, keep: impl Fn(usize) -> bool + Sync) -> Vec<V> {
        (0..self.len())
            .filter(|&i| keep(i))
            .map(|i| self.support.pos[i].0)
            .collect()
    }

    /// `∇·r_i = −Σ_j V_j r_ij·∇_iW_ij` over i's support (the free-surface detector).
    fn position_divergence(&self, i: usize) -> Real {
        dualsph_shifting::concentration_gradient(&self.support, self.volume, i).1
    }

    /// The indicator of `quantity` at row i, over the fluid particles of its support.
    pub fn indicator(&self, quantity: Indicator, i: usize) -> Real {
        let volume = self.volume;
        match quantity {
            Indicator::Density => {
                let (mut lo, mut hi) = (self.rho[i], self.rho[i]);
                self.support
                    .for_each_neighbour(i, |j, _rij, _r, _w, _grad| {
                        if self.is_fluid(j) {
                            lo = lo.min(self.rho[j]);
                            hi = hi.max(self.rho[j]);
                        }
                    });
                (hi - lo) / self.rho[i]
            }
            Indicator::Velocity => {
                let mut m = [DVec3::ZERO; 3];
                self.support.for_each_neighbour(i, |j, _rij, _r, _w, grad| {
                    if self.is_fluid(j) {
                        let dv = DVec3::from_array((self.vel[j] - self.vel[i]).to_xyz());
                        let g = DVec3::from_array(grad.to_xyz()) * volume[j];
                        for (row, dvk) in m.iter_mut().zip(dv.to_array()) {
                            *row += g * dvk;
                        }
                    }
                });
                m.iter().map(|r| r.length_squared()).sum::<Real>().sqrt()
            }
        }
    }

    /// The distance from each row of `rows` to region `r` at time `t` (module docs), where
    /// it is below `reach` (infinite beyond: the region asks for nothing there).
    fn region_distance(
        &self,
        r: &ResolvedRegion<V>,
        rows: &[usize],
        t: Real,
        reach: Real,
    ) -> Vec<Real> {
        match r {
            ResolvedRegion::Box { min, max, velocity } => {
                let (lo, hi) = (*min + *velocity * t, *max + *velocity * t);
                rows.iter()
                    .map(|&i| {
                        let x = self.support.pos[i].0;
                        let mut out = V::zero();
                        for k in 0..V::DIM {
                            let below = lo.get(k) - x.get(k);
                            let above = x.get(k) - hi.get(k);
                            out.set(k, below.max(above).max(0.0));
                        }
                        out.length()
                    })
                    .collect()
            }
            ResolvedRegion::Around { body, distance } => {
                let pts = self.points_where(|j| self.body[j] == *body);
                let d = self.distances(rows, pts, reach + distance);
                d.into_iter().map(|x| (x - distance).max(0.0)).collect()
            }
            ResolvedRegion::FreeSurface {
                distance,
                threshold,
            } => {
                let surface: Vec<bool> = (0..self.len())
                    .into_par_iter()
                    .with_min_len(256)
                    .map(|j| self.is_fluid(j) && self.position_divergence(j) < *threshold)
                    .collect();
                let d = self.distances(rows, self.points_where(|j| surface[j]), reach + distance);
                d.into_iter().map(|x| (x - distance).max(0.0)).collect()
            }
            ResolvedRegion::Gradient { quantity, above } => {
                let flagged: Vec<bool> = rows
                    .par_iter()
                    .with_min_len(256)
                    .map(|&i| self.indicator(*quantity, i) > *above)
                    .collect();
                let pts = rows
                    .iter()
                    .zip(&flagged)
                    .filter(|(_, f)| **f)
                    .map(|(&i, _)| self.support.pos[i].0)
                    .collect();
                self.distances(rows, pts, reach)
            }
        }
    }
}

/// The target sizes of each row of `rows` (module docs): for a split, and for a merge, at
/// which every region reaches `buffer` farther.
pub fn targets<V: Vector>(
    set: &Resolved<V>,
    state: &Rows<'_, V>,
    rows: &[usize],
    t: Real,
) -> (Vec<Real>, Vec<Real>) {
    let mut split = vec![set.coarsest; rows.len()];
    let mut merge = split.clone();
    for (r, s) in set.regions.iter().zip(&set.spacings) {
        // beyond this distance the region asks for nothing below coarsest, even `buffer`
        // farther
        let reach = match set.grading > 0.0 {
            true => (set.coarsest - s) / set.grading,
            false => 0.0,
        } + set.buffer;
        let d = state.region_distance(r, rows, t, reach * (1.0 + 1e-9) + 1e-12);
        for ((a, b), d) in split.iter_mut().zip(&mut merge).zip(d) {
            *a = a.min(ask(*s, set.grading, d));
            *b = b.min(ask(*s, set.grading, (d - set.buffer).max(0.0)));
        }
    }
    for x in split.iter_mut().chain(&mut merge) {
        *x = x.clamp(set.finest, set.coarsest);
    }
    (split, merge)
}

/// The size a region of size `s` asks for at distance `d`: `s + γd` (a grading of 0 is a
/// sharp region: its size inside, nothing asked outside).
fn ask(s: Real, grading: Real, d: Real) -> Real {
    match (d > 0.0, grading > 0.0) {
        (false, _) => s,
        (true, true) => s + grading * d,
        (true, false) => Real::INFINITY,
    }
}
