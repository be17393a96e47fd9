//! The support / dual-support pair sweep (paper 001 §6).
//!
//! For every `j ∈ H_i` a pair quantity is evaluated **once** with i's kernel
//! (`W_ij = w(r_ij/h_i)`, `∇_i W_ij`); i receives it and j receives the reaction through its
//! dual-support `H'_j`. Implementation, free of atomics and data races:
//!
//! 1. in parallel over i, loop over i's support slots, evaluate every [`PairTerm`], add the
//!    result to i's own sums and store the reaction in a per-slot buffer;
//! 2. in parallel over j, gather the stored reactions through the transposed (dual-support)
//!    list, in ascending order of i.
//!
//! Every particle's sums are formed in a fixed order that does not depend on the number of
//! threads, so results are bitwise identical on 1 or N threads, and because each pair's
//! action and reaction are the same stored numbers with opposite sign, linear momentum (and
//! the energy exchanged by each pair) balances to round-off for any field of h.
//!
//! [`Formulation`] selects the paper's comparison cases:
//! * `DualSupport` — the method;
//! * `SingleSupport` — variable h, each particle sums the full classical expression over its own
//!   support only with its own kernel, no reaction (paper Cases I/II): the classical term
//!   `F_i = Σ_{j∈H_i} [T(i←j; ∇_iW_ij(h_i)) − T(j←i; −∇_iW_ij(h_i))]`;
//! * `ConstantH` — classical SPH with one h (run with the dual-support sweep, to which it is
//!   identical when every h is equal);
//! * `AveragedKernel` — the conventional reference, Eq. 2.13:
//!   `W̄_ij = ½[W(r, h_i) + W(r, h_j)]` over `H_i ∪ H'_i`, classical symmetric sums.

use crate::chunks::{DENSE, MIN_LEN};
use crate::components::{
    Acceleration, DensityRate, EnergyRate, GradientCorrection, Mass, Position, SmoothingLength,
};
use crate::kernels::Kernel;
use crate::math::{Matrix, Real, Vector};
use crate::neighbours::Neighbours;
pub use crate::pair::{
    BoundTerm, DynPairTerm, OwnerKernel, Pair, PairOut, PairTerm, PairTerms, ParticleData, Row,
};
use crate::sim::{KernelRes, Sim, StepSet};
use crate::store::single_table;
use bevy_ecs::prelude::*;
use rayon::prelude::*;
use std::sync::Arc;

mod checks;
mod fused;
mod row;
pub use checks::{check_row_matches_interact, check_row_override_2d};
pub use fused::{AvSide, BuiltinTerm, artificial_viscosity_parts};
use fused::{RowEval, WithRowEval, fused_plan, with_fused_rows};
use row::{Reaction, RowScratch, owner_row};

/// How pair interactions are summed (see module docs).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// Support + dual-support, pair once with reaction (the DS-SPH method).
    DualSupport,
    /// Variable h, own support only, no reaction (not conservative).
    SingleSupport,
    /// One h for all particles.
    ConstantH,
    /// Averaged kernel over the union of support and dual-support (Eq. 2.13).
    AveragedKernel,
}

/// Everything a pass over neighbours needs.
#[derive(Clone, Copy)]
pub struct SweepCtx<'a, V: Vector> {
    /// The particles' core columns.
    pub data: ParticleData<'a, V>,
    /// The kernel-gradient corrections `L_i` (Eq. 2.10), when the scene computes them.
    pub correction: Option<&'a [GradientCorrection<V>]>,
    /// Lists.
    pub neighbours: &'a Neighbours<V>,
    /// Kernel.
    pub kernel: &'a Kernel,
    /// Formulation.
    pub formulation: Formulation,
}

/// Visits the union of two ascending lists in ascending order.
fn for_each_union(a: &[u32], b: &[u32], mut f: impl FnMut(usize)) {
    let (mut x, mut y) = (0, 0);
    while x < a.len() || y < b.len() {
        let j = match (a.get(x), b.get(y)) {
            (Some(&p), Some(&q)) if p == q => {
                x += 1;
                y += 1;
                p
            }
            (Some(&p), Some(&q)) if p < q => {
                x += 1;
                p
            }
            (Some(_), Some(&q)) => {
                y += 1;
                q
            }
            (Some(&p), None) => {
                x += 1;
                p
            }
            (None, Some(&q)) => {
                y += 1;
                q
            }
            (None, None) => unreachable!(),
        };
        f(j as usize);
    }
}

impl<'a, V: Vector> SweepCtx<'a, V> {
    /// The context of `data`'s particles, with the correction matrices when they have them.
    pub fn new(
        data: ParticleData<'a, V>,
        neighbours: &'a Neighbours<V>,
        kernel: &'a Kernel,
        formulation: Formulation,
    ) -> Self {
        SweepCtx {
            data,
            correction: data.column(),
            neighbours,
            kernel,
            formulation,
        }
    }

    /// Number of particles.
    #[inline]
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// True without particles.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Applies `L_owner` (Eq. 2.10) to a kernel gradient if the correction is active.
    #[inline]
    pub fn corrected(&self, owner: usize, g: V) -> V {
        match self.correction {
            Some(l) => l[owner].0.mul_vec(g),
            None => g,
        }
    }

    /// The support lists and geometry of the particles.
    #[inline]
    pub fn support(&self) -> Support<'a, V> {
        Support {
            pos: self.data.pos,
            h: self.data.h,
            neighbours: self.neighbours,
            kernel: self.kernel,
            formulation: self.formulation,
        }
    }

    /// See [`Support::for_each_neighbour`].
    #[inline]
    pub fn for_each_neighbour(&self, i: usize, f: impl FnMut(usize, V, Real, Real, V)) {
        self.support().for_each_neighbour(i, f)
    }
}

/// What a loop over supports needs: positions, support radii, lists, kernel, formulation
/// (the own-support passes, which write other columns, borrow only these).
#[derive(Clone, Copy)]
pub struct Support<'a, V: Vector> {
    /// Positions.
    pub pos: &'a [Position<V>],
    /// Support radii.
    pub h: &'a [SmoothingLength],
    /// Lists.
    pub neighbours: &'a Neighbours<V>,
    /// Kernel.
    pub kernel: &'a Kernel,
    /// Formulation.
    pub formulation: Formulation,
}

impl<V: Vector> Support<'_, V> {
    /// Visits i's interpolation neighbourhood: `j ∈ H_i` with `W(r, h_i)` and its raw gradient,
    /// or for `AveragedKernel` the union `H_i ∪ H'_i` with the averaged kernel (Eq. 2.13).
    /// Callback: `(j, r_ij, r, W, ∇_iW)`. Used by own-support passes (density, correction,
    /// velocity gradient), which need no reaction.
    #[inline]
    pub fn for_each_neighbour(&self, i: usize, mut f: impl FnMut(usize, V, Real, Real, V)) {
        let (pos, h) = (self.pos, self.h);
        let (xi, hi) = (pos[i].0, h[i].0);
        match self.formulation {
            Formulation::AveragedKernel => for_each_union(
                self.neighbours.support.row(i),
                self.neighbours.dual.row(i),
                |j| {
                    let rij = xi - pos[j].0;
                    let r = rij.length();
                    let hj = h[j].0;
                    if r < hi.max(hj) {
                        let w = 0.5 * (self.kernel.w(r, hi) + self.kernel.w(r, hj));
                        let g = (self.kernel.grad(rij, r, hi) + self.kernel.grad(rij, r, hj)) * 0.5;
                        f(j, rij, r, w, g);
                    }
                },
            ),
            _ => {
                let k = OwnerKernel::new(self.kernel, hi);
                for &j in self.neighbours.support.row(i) {
                    let j = j as usize;
                    let rij = xi - pos[j].0;
                    let r2 = rij.length_squared();
                    if r2 < k.h2 {
                        let r = r2.sqrt();
                        let (w, g) = k.eval(rij, r);
                        f(j, rij, r, w, g);
                    }
                }
            }
        }
    }
}

/// Fewest particles per block of the dual-support sweep (see [`dual_support`]).
const MIN_BLOCK: usize = 1024;

/// Rows of pass 1 between two advances of the pass-2 wavefront (see [`dual_support`]). The
/// wavefront stops at the first particle with an owner not yet done; advancing it after every
/// row made that stop a branch mispredicted on ~70 % of rows (a quarter of the step's
/// mispredictions), advancing it every 16 rows mispredicts once per 16 rows. The lag is 16 rows
/// of reactions (~7 KB in 2-D), still in cache.
const WAVE: usize = 16;

/// Particles per block of the dual-support sweep for `n` particles: about four blocks per
/// thread, at least [`MIN_BLOCK`]. Any block length gives bitwise the same sums.
fn block_len(n: usize) -> usize {
    n.div_ceil(4 * rayon::current_num_threads()).max(MIN_BLOCK)
}

/// Splits a slot buffer at the slot boundaries of consecutive blocks of `rows` rows.
fn split_rows_mut<'a, T>(mut buf: &'a mut [T], offsets: &[u32], rows: usize) -> Vec<&'a mut [T]> {
    let n = offsets.len().saturating_sub(1);
    let mut out = Vec::with_capacity(n.div_ceil(rows));
    let mut start = 0;
    while start < n {
        let end = (start + rows).min(n);
        let (chunk, rest) = buf.split_at_mut((offsets[end] - offsets[start]) as usize);
        out.push(chunk);
        buf = rest;
        start = end;
    }
    out
}

/// j's share of the reactions: `(−Σ force, Σ power)` over j's dual-support slots (`slots`,
/// ascending owner i), read from `reactions`, whose first entry is slot `base`.
#[inline(always)]
fn dual_sum<V: Vector>(slots: &[u32], reactions: &[Reaction<V>], base: usize) -> (V, Real) {
    let mut f = V::zero();
    let mut p = 0.0;
    for &slot in slots {
        let r = &reactions[slot as usize - base];
        f -= r.force;
        p += r.power;
    }
    (f, p)
}

/// Bound terms, as pass 1 evaluates them.
type Bound<'w, V> = [Box<dyn BoundTerm<V> + 'w>];

#[inline]
fn eval_terms<V: Vector>(terms: &Bound<'_, V>, pair: &Pair<'_, V>) -> PairOut<V> {
    let mut out = PairOut::default();
    for t in terms {
        t.interact(pair, &mut out);
    }
    out
}

/// Reusable buffers of the sweep.
#[derive(Resource, Default)]
pub struct SweepBuffers<V: Vector> {
    /// Per-slot reactions of pass 1 (force on the owner, power credited to the neighbour),
    /// side by side so pass 2 reads one place per dual entry.
    reactions: Vec<Reaction<V>>,
    /// Total force on each particle from the last sweep.
    pub force: Vec<V>,
    /// Total `m ε̇` of each particle from the last sweep.
    pub power: Vec<Real>,
    /// When true, the dual-support sweep also forms the own-support continuity sum
    /// `dρ_i/dt = Σ_{j∈H_i} m_j v_ij·∇_iW_ij` (Eq. 4.9) from the kernel gradients it evaluates
    /// anyway, into `density_rate` (same terms, same order as [`crate::passes::continuity_pairwise`]).
    pub with_density_rate: bool,
    /// `dρ_i/dt` from the last sweep (when `with_density_rate`).
    pub density_rate: Vec<Real>,
    /// When true, the sweep never uses the fused loop for built-in terms (see
    /// [`BuiltinTerm`]), only the general row path: for comparing the two.
    pub general_only: bool,
}

/// Marker resource: the scene integrates the density with the pairwise continuity equation
/// (Eq. 4.9), which the dual-support sweep then computes alongside the pair terms.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct ContinuityInSweep;

/// True when the pair sweep of this step forms `dρ/dt` (Eq. 4.9): continuity is requested,
/// there are pair terms and the formulation uses the dual-support path.
pub fn continuity_in_sweep(requested: bool, has_terms: bool, formulation: Formulation) -> bool {
    requested
        && has_terms
        && matches!(
            formulation,
            Formulation::DualSupport | Formulation::ConstantH
        )
}

/// True when the sweep evaluates `terms` with its fused loop for built-in terms (see
/// [`BuiltinTerm`]) rather than term by term.
pub fn fused_loop_applies<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn DynPairTerm<V>>],
) -> bool {
    matches!(
        ctx.formulation,
        Formulation::DualSupport | Formulation::ConstantH
    ) && fused_plan(ctx, terms).is_some()
}

/// Evaluates all pair terms: the total force and internal-energy power `m ε̇` per particle.
/// The error names a term whose columns are missing (see [`PairTerm::bind`]).
pub fn evaluate<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn DynPairTerm<V>>],
    buf: &mut SweepBuffers<V>,
) -> Result<(), String> {
    let n = ctx.len();
    buf.force.resize(n, V::zero());
    buf.power.resize(n, 0.0);
    match ctx.formulation {
        Formulation::DualSupport | Formulation::ConstantH => dual_support(ctx, terms, buf),
        Formulation::SingleSupport | Formulation::AveragedKernel => {
            classical(ctx, &bind(terms, &ctx.data)?, buf);
            Ok(())
        }
    }
}

/// Every term bound to `data`'s columns, in order.
fn bind<'w, V: Vector>(
    terms: &'w [Arc<dyn DynPairTerm<V>>],
    data: &ParticleData<'w, V>,
) -> Result<Vec<Box<dyn BoundTerm<V> + 'w>>, String> {
    terms.iter().map(|t| t.bind_dyn(data)).collect()
}

/// Pass 1 and pass 2 in blocks of consecutive particles (in parallel over blocks). Inside a
/// block, pass 2 runs as a wavefront behind pass 1: every [`WAVE`] rows, j gathers its
/// reactions once pass 1 has done its own row and the rows of all its dual-support owners,
/// which, with particles numbered in space order, lie within about one lattice row of j — so
/// the reactions are read back from cache rather than from memory. A particle with an owner
/// outside its block waits for the end of pass 1 and gathers then. Every sum keeps its order (own row, then the
/// reactions in ascending owner order), so the result is bitwise that of two separate passes,
/// for any block length and thread count.
fn dual_support<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn DynPairTerm<V>>],
    buf: &mut SweepBuffers<V>,
) -> Result<(), String> {
    let plan = if buf.general_only {
        None
    } else {
        fused_plan(ctx, terms)
    };
    let with_drho = buf.with_density_rate;
    let blocks = Blocks { ctx, buf };
    match plan {
        Some(plan) => with_fused_rows(ctx, plan, with_drho, blocks),
        None => {
            let terms = bind(terms, &ctx.data)?;
            blocks.call(&GeneralRows {
                ctx: *ctx,
                terms: &terms,
            });
        }
    }
    Ok(())
}

/// Pass 1 by the general path: every bound term on the row in turn.
struct GeneralRows<'a, V: Vector> {
    ctx: SweepCtx<'a, V>,
    terms: &'a Bound<'a, V>,
}

impl<V: Vector> RowEval<V> for GeneralRows<'_, V> {
    #[inline]
    fn row(
        &self,
        i: usize,
        s: &mut RowScratch<V>,
        reactions: &mut [Reaction<V>],
        drho: Option<&mut Real>,
    ) -> (V, Real) {
        owner_row(&self.ctx, self.terms, i, s, reactions, drho)
    }
}

/// The blocked sweep of [`dual_support`], run with the row evaluation chosen for the sweep.
struct Blocks<'a, 'b, V: Vector> {
    ctx: &'a SweepCtx<'a, V>,
    buf: &'b mut SweepBuffers<V>,
}

impl<V: Vector> WithRowEval<V> for Blocks<'_, '_, V> {
    fn call<E: RowEval<V>>(self, eval: &E) {
        blocks(self.ctx, eval, self.buf)
    }
}

/// Pass 1 (rows by `eval`) and pass 2 of [`dual_support`].
fn blocks<V: Vector, E: RowEval<V>>(ctx: &SweepCtx<'_, V>, eval: &E, buf: &mut SweepBuffers<V>) {
    let nb = ctx.neighbours;
    let offsets = &nb.support.offsets;
    let slots = nb.support.indices.len();
    let n = ctx.len();
    // every slot is written by pass 1: no clearing needed
    buf.reactions.resize(slots, Reaction::default());
    let block = block_len(n);
    let r_blocks = split_rows_mut(&mut buf.reactions, offsets, block);
    let with_drho = buf.with_density_rate;
    buf.density_rate.resize(n, 0.0);
    let later: Vec<Vec<u32>> = buf
        .force
        .par_chunks_mut(block)
        .zip(buf.power.par_chunks_mut(block))
        .zip(buf.density_rate.par_chunks_mut(block))
        .zip(r_blocks)
        .enumerate()
        .map_init(RowScratch::default, |s, (b, (((fc, pc), dc), rc))| {
            let (a, end) = (b * block, b * block + fc.len());
            let base = offsets[a] as usize;
            let mut later = Vec::new();
            let mut next = a; // the wavefront of pass 2
            for i in a..end {
                let r = offsets[i] as usize - base..offsets[i + 1] as usize - base;
                let drho = with_drho.then_some(&mut dc[i - a]);
                (fc[i - a], pc[i - a]) = eval.row(i, s, &mut rc[r], drho);
                let wave = (i - a) % WAVE == WAVE - 1 || i + 1 == end;
                while wave && next <= i {
                    let owners = nb.dual.row(next);
                    let first = owners.first().map_or(next, |&o| o as usize);
                    let last = owners.last().map_or(next, |&o| o as usize);
                    if first < a || last >= end {
                        later.push(next as u32);
                    } else if last <= i {
                        let (f, p) = dual_sum(&nb.dual_slot[nb.dual.slots(next)], rc, base);
                        fc[next - a] += f;
                        pc[next - a] += p;
                    } else {
                        break;
                    }
                    next += 1;
                }
            }
            later
        })
        .collect();
    // the particles with owners in other blocks, now that every row is done
    let later: Vec<u32> = later.concat();
    let reactions = &buf.reactions;
    let sums: Vec<(V, Real)> = later
        .par_iter()
        .map(|&j| dual_sum(&nb.dual_slot[nb.dual.slots(j as usize)], reactions, 0))
        .collect();
    for (&j, (f, p)) in later.iter().zip(sums) {
        buf.force[j as usize] += f;
        buf.power[j as usize] += p;
    }
}

fn classical<V: Vector>(ctx: &SweepCtx<'_, V>, terms: &Bound<'_, V>, buf: &mut SweepBuffers<V>) {
    let data = &ctx.data;
    buf.force
        .par_iter_mut()
        .zip(buf.power.par_iter_mut())
        .enumerate()
        .for_each(|(i, (fi, pi))| {
            let mut f = V::zero();
            let mut p = 0.0;
            ctx.for_each_neighbour(i, |j, rij, r, w, g| {
                let own = Pair {
                    i,
                    j,
                    rij,
                    r,
                    w,
                    grad_raw: g,
                    grad: ctx.corrected(i, g),
                    data,
                };
                let mirror = Pair {
                    i: j,
                    j: i,
                    rij: -rij,
                    r,
                    w,
                    grad_raw: -g,
                    grad: ctx.corrected(j, -g),
                    data,
                };
                let a = eval_terms(terms, &own);
                let b = eval_terms(terms, &mirror);
                f += a.force - b.force;
                p += a.power_i + b.power_j;
            });
            *fi = f;
            *pi = p;
        });
}

/// The sweep as a scheduled system (exclusive: the terms read any column of the store):
/// writes `Acceleration = force / m` and, if present, `EnergyRate.rate = power / m` and
/// (continuity in the sweep) `DensityRate.rate`.
#[inline(never)] // a frame of its own in profiles
pub fn pair_sweep_system<V: Vector>(
    world: &mut World,
    rates: &mut QueryState<(
        &Mass,
        &mut Acceleration<V>,
        Option<&mut EnergyRate>,
        Option<&mut DensityRate>,
    )>,
) {
    world.resource_scope(|world, mut buf: Mut<SweepBuffers<V>>| {
        let continuity = world.contains_resource::<ContinuityInSweep>();
        sweep_into(world, &mut buf, continuity);
        let with_drho = buf.with_density_rate;
        let (force, power, rate) = (&buf.force, &buf.power, &buf.density_rate);
        let tables = rates.contiguous_iter_mut(world).expect(DENSE);
        let Some((mass, mut a, e, d)) = single_table(tables) else {
            return;
        };
        a.par_iter_mut()
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(k, a)| a.0 = force[k] / mass[k].0);
        if let Some(mut e) = e {
            e.par_iter_mut()
                .enumerate()
                .with_min_len(MIN_LEN)
                .for_each(|(k, e)| e.rate = power[k] / mass[k].0);
        }
        if with_drho && let Some(mut d) = d {
            d.par_iter_mut()
                .enumerate()
                .with_min_len(MIN_LEN)
                .for_each(|(k, d)| d.rate = rate[k]);
        }
    });
}

/// Runs the sweep over `world`'s particles into `buf` (forces, powers and, with continuity in
/// the sweep, `dρ/dt`).
fn sweep_into<V: Vector>(world: &World, buf: &mut SweepBuffers<V>, continuity: bool) {
    let terms = world.resource::<PairTerms<V>>();
    let formulation = *world.resource::<Formulation>();
    let Some(data) = ParticleData::of(world) else {
        return;
    };
    let ctx = SweepCtx::new(
        data,
        world.resource::<Neighbours<V>>(),
        &world.resource::<KernelRes>().0,
        formulation,
    );
    buf.with_density_rate = continuity_in_sweep(continuity, !terms.terms.is_empty(), formulation);
    if let Err(e) = evaluate(&ctx, &terms.terms, buf) {
        unreachable!("pair terms were bound when the simulation was built: {e}")
    }
}

pub(crate) fn add_sweep_system<V: Vector>(sim: &mut Sim<V>) {
    sim.world.insert_resource(SweepBuffers::<V>::default());
    sim.add_system(
        StepSet::Forces,
        "pair_sweep (support + dual-support)",
        pair_sweep_system::<V>,
    );
}

fn zero_accelerations<V: Vector>(mut q: Query<&mut Acceleration<V>>) {
    for mut a in &mut q {
        a.0 = V::zero();
    }
}

pub(crate) fn add_zero_acceleration_system<V: Vector>(sim: &mut Sim<V>) {
    sim.add_system(
        StepSet::Forces,
        "zero_accelerations",
        zero_accelerations::<V>,
    );
}

#[cfg(test)]
mod tests;
