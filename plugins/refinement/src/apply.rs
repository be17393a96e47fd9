//! The decisions and their application, in `StepSet::Population` at the start of every
//! `every`-th step, from the state the last step ended with and its neighbour lists:
//!
//! 1. the two target sizes of every particle of a refined body ([`crate::target`]): `t_s`
//!    where the regions are, `t_m` where they reach `buffer` farther;
//! 2. each is rounded down to the *ladder* of sizes `coarsest·2^{-k}` (`D(t)`, the largest
//!    ladder size not above `t`, within [`SIZE_TOLERANCE`]), with which a particle's size is
//!    compared at its ladder density (its density now, or the nominal one a gas's particles
//!    carry: [`crate::ladder::LadderSize`]);
//! 3. where a region asks for less than `coarsest`, a particle larger than `D(t_s)` splits,
//!    to the next size of the ladder below its own (`2^d` children, or `2^j` along `j < d`
//!    axes for a particle a merge left between two ladder sizes; [`crate::split`]), unless
//!    the children would be smaller than `finest`;
//! 4. a particle whose merge with an equal one would not be larger than `D(t_m)` is a merge
//!    candidate; in ascending id order, each candidate not paired yet pairs with the nearest
//!    candidate of its support list that is not paired yet, of its body and of its mass (and
//!    of its nominal density, where sizes are read at it),
//!    within 1.5 of its sizes and moving relative to it at most [`MERGE_MACH`] of the sound
//!    speed (the lower id on a tie);
//!    A split or merge that would put a particle against a wall is not made
//!    ([`WALL_CLEARANCE`]);
//! 5. the merges are applied in the order paired (the lower id is kept), then the splits in
//!    ascending id order ([`dualsph_core::population`]);
//! 6. the rates are evaluated again at the new particles before the step goes on
//!    ([`RatesStale`]): a merged particle then feels its own forces, not the pair's sum at
//!    its centre of mass, so the angular momentum stays exact through a merge as through a
//!    split.
//!
//! No particle splits and merges back while the targets stay: children are of a ladder size
//! at or above `D(t_s) ≥ D(t_m)`, and a pair of them merged would be `2^{1/d}` times larger;
//! a merged particle is at most `D(t_m) ≤ D(t_s)`, which does not split. As a region moves,
//! a particle behind it merges only once it is `buffer` past it.
//!
//! The decisions read nothing that depends on the thread count and are applied in a fixed
//! order, so a run is bitwise the same on any number of threads.

use crate::ladder::NominalDensity;
use crate::split::{self, Merge};
use crate::target::{Resolved, Rows, targets};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Bodies, BodyId};
use dualsph_core::neighbours::Neighbours;
use dualsph_core::phase::RatesStale;
use dualsph_core::population::{CoreState, merge_particles, split_particle};
use dualsph_core::sim::StepFailure;
use dualsph_fluid::prelude::*;
use dualsph_sweep::Support;
use serde::{Deserialize, Serialize};

/// What the refinement has done since the start of the run (kept in checkpoints).
#[derive(Resource, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RefinementStats {
    /// Particles split.
    pub splits: u64,
    /// Merges (each removes one particle).
    pub merges: u64,
    /// The kinetic energy the merges removed (J; per unit depth in 2-D).
    pub e_kin: Real,
    /// The angular momentum the merges removed (3-D embedding).
    pub l: [Real; 3],
}

/// The most a merge partner may be from a candidate, in the candidate's sizes.
pub const MERGE_REACH: Real = 1.5;

/// The largest relative speed of a merging pair, in units of the larger of their sound
/// speeds: a merge turns the kinetic energy of the relative motion into heat, so a pair
/// that collides or flies apart (a splash) is not merged.
pub const MERGE_MACH: Real = 0.01;

/// How close a split's child or a merged particle may come to a wall particle, in units of
/// the distance of two lattices meeting at a face (`(Δx + Δx_w)/2`): a particle of a merge
/// next to a wall sits where two smaller ones did, and its children could land against the
/// wall; such a split or merge is not made.
pub const WALL_CLEARANCE: Real = 0.9;

/// The relative tolerance of size comparisons: a particle's size `(m/ρ)^{1/d}` moves with
/// its density (by a few per cent in a liquid).
pub const SIZE_TOLERANCE: Real = 0.1;

/// `D(t)`: the largest size `coarsest·2^{-k}` (`k ≥ 0`) not above `t` (within
/// [`SIZE_TOLERANCE`]).
pub fn ladder_size(coarsest: Real, t: Real) -> Real {
    let k = libm::log2(coarsest / (t * (1.0 + SIZE_TOLERANCE)))
        .ceil()
        .max(0.0);
    coarsest * libm::pow(0.5 as Real, k)
}

/// The axes a particle of `size` splits along to reach the next ladder size below it
/// (`d`, or fewer for a size between two ladder sizes), and that size.
pub fn split_axes(dim: usize, coarsest: Real, size: Real) -> (usize, Real) {
    let d = dim as Real;
    let level = d * libm::log2(coarsest / size);
    let next = (level / d + SIZE_TOLERANCE).floor() + 1.0;
    let axes = (d * next - level).round().clamp(1.0, d) as usize;
    (axes, coarsest * libm::pow(0.5 as Real, next))
}

/// A particle's entity, id, body and core state, and its sound speed (infinite without
/// one).
#[derive(Clone, Copy, Debug)]
struct Particle<V: Vector> {
    entity: Entity,
    id: u32,
    body: u16,
    state: CoreState<V>,
    sound: Real,
    /// The density its ladder size is read at ([`crate::ladder::LadderSize`]).
    ladder_density: Real,
}

/// What one decision does.
#[derive(Debug, Default)]
struct Plan<V: Vector> {
    /// Pairs (kept, absorbed).
    merges: Vec<(Particle<V>, Particle<V>)>,
    /// Parents, ascending id, with the axes they split along.
    splits: Vec<(Particle<V>, usize)>,
}

/// The system (module docs).
pub fn refine<V: Vector>(world: &mut World) {
    let clock = *world.resource::<SimClock>();
    let every = world.resource::<Resolved<V>>().every;
    if clock.step == 0 || !clock.step.is_multiple_of(every) {
        return;
    }
    if world.resource::<Neighbours<V>>().dirty {
        return;
    }
    let plan = world.resource_scope(|world, set: Mut<Resolved<V>>| decide(world, &set, clock.t));
    if !(plan.merges.is_empty() && plan.splits.is_empty()) {
        // the children and the merged particles get their own rates before the step goes on
        world.resource_mut::<RatesStale>().0 = true;
    }
    apply(world, plan);
}

/// The particles in row order.
fn gather<V: Vector>(world: &mut World) -> Vec<Particle<V>> {
    let mut q = world.query::<(
        Entity,
        &ParticleId,
        &Position<V>,
        &Velocity<V>,
        &Mass,
        &Density,
        &SmoothingLength,
        &BodyId,
        Option<&SoundSpeed>,
        Option<&NominalDensity>,
    )>();
    q.iter(world)
        .map(|(entity, id, r, v, m, rho, h, b, c, nominal)| Particle {
            entity,
            id: id.0,
            body: b.0,
            sound: c.map_or(Real::INFINITY, |c| c.0),
            ladder_density: nominal.map_or(rho.0, |n| n.0),
            state: CoreState {
                pos: r.0,
                vel: v.0,
                mass: m.0,
                density: rho.0,
                h: h.0,
            },
        })
        .collect()
}

/// The state a decision reads, in row order.
struct Ctx<'a, V: Vector> {
    set: &'a Resolved<V>,
    particles: &'a [Particle<V>],
    body: &'a [u16],
    nb: &'a Neighbours<V>,
}

impl<V: Vector> Ctx<'_, V> {
    /// Row i's size `(m/ρ)^{1/d}`: how much space it takes now.
    fn size(&self, i: usize) -> Real {
        let s = &self.particles[i].state;
        split::size(V::DIM, s.mass, s.density)
    }

    /// Row i's size on the ladder: at its ladder density.
    fn ladder_size(&self, i: usize) -> Real {
        let p = &self.particles[i];
        split::size(V::DIM, p.state.mass, p.ladder_density)
    }

    fn refined(&self, j: usize) -> bool {
        let b = self.body[j] as usize;
        self.set.refined.get(b).copied().unwrap_or(false)
    }

    /// Whether particles of `size` at `points` would keep their distance from the particles
    /// of the bodies not refined (walls) in row i's list: at least [`WALL_CLEARANCE`] times
    /// the distance of two lattices of their sizes meeting at a face, `(Δx + Δx_w)/2`.
    fn clear_of_walls(&self, i: usize, points: &[V], size: Real) -> bool {
        self.nb.support.row(i).iter().all(|&j| {
            let j = j as usize;
            if self.refined(j) {
                return true;
            }
            let w = &self.particles[j].state;
            let gap = WALL_CLEARANCE * 0.5 * (size + split::size(V::DIM, w.mass, w.density));
            points
                .iter()
                .all(|&x| self.nb.separation(x, w.pos).length() >= gap)
        })
    }

    /// The split of row i along `axes`, if its children keep clear of the walls.
    fn split(&self, i: usize, axes: usize) -> Option<(Particle<V>, usize)> {
        let p = self.particles[i];
        let kids = split::children(&p.state, axes, self.set.offset, self.set.child_h);
        let pts: Vec<V> = kids.iter().map(|c| c.pos).collect();
        let s = &kids[0];
        let size = split::size(V::DIM, s.mass, s.density);
        self.clear_of_walls(i, &pts, size).then_some((p, axes))
    }

    /// Whether rows i and j are read on the ladder at the same density (a merge of two
    /// nominal densities would leave the merged particle off the ladder).
    fn same_ladder_density(&self, i: usize, j: usize) -> bool {
        let (a, b) = (
            self.particles[i].ladder_density,
            self.particles[j].ladder_density,
        );
        (a - b).abs() <= 1e-9 * a
    }

    /// Row i's merge partner among the candidates not paired yet (module docs), if the
    /// merged particle keeps clear of the walls.
    fn partner(&self, i: usize, candidate: &[bool], paired: &[bool]) -> Option<usize> {
        let a = self.particles[i].state;
        let reach = MERGE_REACH * self.size(i);
        let (_, _, j) = self
            .nb
            .support
            .row(i)
            .iter()
            .map(|&j| j as usize)
            .filter(|&j| {
                let b = &self.particles[j].state;
                let c = self.particles[i].sound.max(self.particles[j].sound);
                candidate[j]
                    && !paired[j]
                    && self.body[j] == self.body[i]
                    && (b.mass - a.mass).abs() <= 1e-9 * a.mass
                    && (!self.set.nominal || self.same_ladder_density(i, j))
                    && (b.vel - a.vel).length() <= MERGE_MACH * c
            })
            .map(|j| {
                let r = self
                    .nb
                    .separation(a.pos, self.particles[j].state.pos)
                    .length();
                (r, self.particles[j].id, j)
            })
            .filter(|&(r, _, _)| r <= reach)
            .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)))?;
        let m = split::merge(&a, &self.particles[j].state).state;
        let size = split::size(V::DIM, m.mass, m.density);
        self.clear_of_walls(i, &[m.pos], size).then_some(j)
    }
}

/// Steps 1–4 of the module docs.
fn decide<V: Vector>(world: &mut World, set: &Resolved<V>, t: Real) -> Plan<V> {
    let particles = gather::<V>(world);
    let body: Vec<u16> = particles.iter().map(|p| p.body).collect();
    let fluid: Vec<bool> = world
        .resource::<Bodies>()
        .0
        .iter()
        .map(|b| b.is_fluid())
        .collect();
    let pos: Vec<Position<V>> = particles.iter().map(|p| Position(p.state.pos)).collect();
    let h: Vec<SmoothingLength> = particles
        .iter()
        .map(|p| SmoothingLength(p.state.h))
        .collect();
    let vel: Vec<V> = particles.iter().map(|p| p.state.vel).collect();
    let mass: Vec<Real> = particles.iter().map(|p| p.state.mass).collect();
    let rho: Vec<Real> = particles.iter().map(|p| p.state.density).collect();
    let volume: Vec<Real> = mass.iter().zip(&rho).map(|(m, r)| m / r).collect();
    let nb = world.resource::<Neighbours<V>>();
    let state = Rows {
        support: Support {
            pos: &pos,
            h: &h,
            neighbours: nb,
            kernel: &world.resource::<KernelRes>().0,
            formulation: *world.resource::<Formulation>(),
        },
        vel: &vel,
        mass: &mass,
        rho: &rho,
        volume: &volume,
        body: &body,
        fluid: &fluid,
    };
    let ctx = Ctx {
        set,
        particles: &particles,
        body: &body,
        nb,
    };
    let rows: Vec<usize> = (0..particles.len()).filter(|&i| ctx.refined(i)).collect();
    let (t_split, t_merge) = targets(set, &state, &rows, t);
    plan(&ctx, &rows, &t_split, &t_merge)
}

/// Steps 2–4 of the module docs, from the targets of `rows`.
fn plan<V: Vector>(
    ctx: &Ctx<'_, V>,
    rows: &[usize],
    t_split: &[Real],
    t_merge: &[Real],
) -> Plan<V> {
    let set = ctx.set;
    let grow = libm::pow(2.0 as Real, 1.0 / V::DIM as Real);
    let tol = 1.0 + SIZE_TOLERANCE;
    let mut plan = Plan::default();
    let mut candidate = vec![false; ctx.particles.len()];
    for ((&i, &ts), &tm) in rows.iter().zip(t_split).zip(t_merge) {
        let size = ctx.ladder_size(i);
        // only a region's ask splits: a particle larger than `coarsest` where none asks (a
        // gas expanding into vacuum) is left as it is
        if ts < set.coarsest && size > ladder_size(set.coarsest, ts) * tol {
            let (axes, child) = split_axes(V::DIM, set.coarsest, size);
            if child >= set.finest / tol {
                plan.splits.extend(ctx.split(i, axes));
            }
        } else if size * grow <= ladder_size(set.coarsest, tm) * tol {
            candidate[i] = true;
        }
    }
    plan.splits.sort_unstable_by_key(|p| p.0.id);
    let mut order: Vec<usize> = (0..candidate.len()).filter(|&i| candidate[i]).collect();
    order.sort_unstable_by_key(|&i| ctx.particles[i].id);
    let mut paired = vec![false; candidate.len()];
    for i in order {
        if paired[i] {
            continue;
        }
        if let Some(j) = ctx.partner(i, &candidate, &paired) {
            paired[i] = true;
            paired[j] = true;
            plan.merges.push((ctx.particles[i], ctx.particles[j]));
        }
    }
    plan
}

/// Step 5 of the module docs.
fn apply<V: Vector>(world: &mut World, plan: Plan<V>) {
    let (child_offset, child_h) = {
        let set = world.resource::<Resolved<V>>();
        (set.offset, set.child_h)
    };
    for (kept, absorbed) in plan.merges {
        let Merge {
            state,
            removed_kinetic_energy: de,
            removed_angular_momentum: dl,
        } = split::merge(&kept.state, &absorbed.state);
        merge_particles(world, kept.entity, absorbed.entity, &state);
        // the relative motion's kinetic energy becomes heat where the particles carry an
        // internal energy (and is counted as dissipated)
        let heat = de / state.mass;
        if let Some(mut e) = world.get_mut::<InternalEnergy>(kept.entity) {
            e.0 += heat;
        }
        if let Some(mut d) = world.get_mut::<Dissipated>(kept.entity) {
            d.0 += heat;
        }
        let mut stats = world.resource_mut::<RefinementStats>();
        stats.merges += 1;
        stats.e_kin += de;
        for (l, x) in stats.l.iter_mut().zip(dl.to_array()) {
            *l += x;
        }
    }
    for (parent, axes) in plan.splits {
        let kids = split::children(&parent.state, axes, child_offset, child_h);
        if let Err(e) = split_particle(world, parent.entity, &kids) {
            world
                .resource_mut::<StepFailure>()
                .fail(|| format!("Refinement: particle {} could not split: {e}", parent.id));
            return;
        }
        world.resource_mut::<RefinementStats>().splits += 1;
    }
}

/// Every particle's size `Δx = (m/ρ)^{1/d}` and level `round(d log2(coarsest/Δx_l))`
/// clamped into `0..=levels`, with `Δx_l` its size on the ladder (at its ladder density,
/// [`crate::ladder::LadderSize`]; 0 the coarsest; a merge of two equal particles moves up
/// one level, a split down `d`), with whether its body is refined, in row order.
///
/// A world that never held a [`NominalDensity`] (the ladder at the current density, before
/// the first decision) has not registered it, and a query naming it, even as an option,
/// cannot be made there: the sizes are then read without it (every snapshot before the first
/// decision held NaN for both columns).
pub fn sizes_and_levels<V: Vector>(world: &World) -> Vec<(Real, usize, bool)> {
    let Some(set) = world.get_resource::<Resolved<V>>() else {
        return Vec::new();
    };
    let d = V::DIM as Real;
    let read = |m: Real, rho: Real, b: &BodyId, ladder_rho: Real| {
        let size = split::size(V::DIM, m, rho);
        let on_ladder = split::size(V::DIM, m, ladder_rho);
        let level = (d * libm::log2(set.coarsest / on_ladder)).round();
        let refined = set.refined.get(b.0 as usize).copied().unwrap_or(false);
        (size, level.clamp(0.0, set.levels as Real) as usize, refined)
    };
    if world
        .components()
        .component_id::<NominalDensity>()
        .is_some()
        && let Some(mut q) =
            world.try_query::<(&Mass, &Density, &BodyId, Option<&NominalDensity>)>()
    {
        return (q.iter(world))
            .map(|(m, rho, b, nominal)| read(m.0, rho.0, b, nominal.map_or(rho.0, |n| n.0)))
            .collect();
    }
    let Some(mut q) = world.try_query::<(&Mass, &Density, &BodyId)>() else {
        return Vec::new();
    };
    (q.iter(world))
        .map(|(m, rho, b)| read(m.0, rho.0, b, rho.0))
        .collect()
}

/// The particles of the refined bodies at each size level `0..=levels`
/// ([`sizes_and_levels`]).
pub fn level_counts<V: Vector>(world: &World, levels: usize) -> Vec<u64> {
    let mut counts = vec![0u64; levels + 1];
    for (_, level, refined) in sizes_and_levels::<V>(world) {
        if refined {
            counts[level.min(levels)] += 1;
        }
    }
    counts
}
