//! The pair layer of dualsph: the pair-term contract ([`pair`]), the sums a sweep writes
//! into columns ([`accum`]) and the support / dual-support pair sweep (Ren et al.,
//! Dual-support SPH, §6). It builds on `dualsph-core` (the ECS layer) and extends [`Sim`](dualsph_core::sim::Sim) with
//! [`SimSweeps`]; a plugin that adds pair terms imports [`prelude`].
//!
//! # The sweep
//!
//! For every `j ∈ H_i` a pair quantity is evaluated **once** with i's kernel
//! (`W_ij = w(r_ij/h_i)`, `∇_i W_ij`); i receives it and j receives the reaction through its
//! dual-support `H'_j`. Implementation, free of atomics and data races:
//!
//! 1. in parallel over i, loop over i's support slots, evaluate every [`PairTerm`] of the
//!    sweep, add the results to i's own sums and store the reactions in a per-slot buffer;
//! 2. in parallel over j, gather the stored reactions through the transposed (dual-support)
//!    list, in ascending order of i.
//!
//! What a sweep sums is open: every term declares its sums when it is bound
//! ([`crate::accum`]), and the sweep stores per support slot only the channels that reach j
//! ([`Reaction`]). A plugin can add terms to the force sweep of the step ([`FORCES`]) or to a
//! sweep of its own at its own place ([`SimSweeps::add_pair_term_to`]).
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
//!   `W̄_ij = ½[W(r, h_i) + W(r, h_j)]` over `H_i ∪ H'_i`, classical symmetric sums;
//! * `GradH` — grad-h SPH: `−m_i m_j [P_i/(Ω_i ρ_i²) ∇_iW_ij(h_i) + P_j/(Ω_j ρ_j²) ∇_iW_ij(h_j)]`
//!   is the sum of two support/dual-support pairs (i's term in `H_i`, j's in `H_j` with its
//!   reaction on i), so it runs on the dual-support sweep with `P/(Ωρ²)` as the owner's factor.

use crate::accum::Layout;
pub use crate::pair::{
    Acc, Binder, BoundTerm, DynPairTerm, Out, OwnerKernel, PairLanes, PairTerm, ParticleData,
    Reaction, RowTerm, Specialised,
};
use bevy_ecs::prelude::*;
use dualsph_core::components::{GradientCorrection, Position, SmoothingLength};
use dualsph_core::kernels::Kernel;
use dualsph_core::math::{Matrix, Real, Vector};
use dualsph_core::neighbours::Neighbours;
pub use dualsph_core::sim::Formulation;
use rayon::prelude::*;
use std::sync::Arc;

pub mod accum;
pub mod pair;

#[doc(hidden)]
pub mod block;
mod checks;
mod classical;
mod fuse;
mod route;
#[doc(hidden)]
pub mod row;
mod system;
use block::{Block, Sweep, block_of, dual_sum};
pub use checks::{check_lanes_2d, check_specialised_2d, lattice_2d};
pub use fuse::{Fused, FusedBound, Fusions};
use row::{RowPlan, RowScratch, Terms};
pub use system::{FORCES, PairSweep, PairSweeps, SimSweeps, sweep_into};

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
                    let rij = self.neighbours.separation(xi, pos[j].0);
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
                let row = self.neighbours.support.row(i);
                let k = OwnerKernel::new(self.kernel, hi);
                match &self.neighbours.period {
                    None => own_support(row, |j| xi - pos[j].0, &k, f),
                    Some(p) => own_support(row, |j| p.image(xi - pos[j].0), &k, f),
                }
            }
        }
    }

    /// Visits every j within the larger of the two supports, `|r_ij| < max(h_i, h_j)` (the
    /// union of i's support `H_i` and its dual-support), with `W(r, max(h_i, h_j))`.
    /// Callback: `(j, r_ij, W)`. For values extrapolated to a particle from the particles
    /// around it whatever their h (wall particles): a neighbour whose support is larger than
    /// i's own is not missed. Where `h_j = h_i` this is i's own support with its own kernel,
    /// in the same order and arithmetic as [`Support::for_each_neighbour`].
    pub fn for_each_within_either(&self, i: usize, mut f: impl FnMut(usize, V, Real)) {
        let (xi, hi) = (self.pos[i].0, self.h[i].0);
        let nb = self.neighbours;
        for_each_union(nb.support.row(i), nb.dual.row(i), |j| {
            let rij = nb.separation(xi, self.pos[j].0);
            let hm = hi.max(self.h[j].0);
            let r2 = rij.length_squared();
            if r2 < hm * hm {
                f(j, rij, OwnerKernel::new(self.kernel, hm).w(r2.sqrt()));
            }
        });
    }
}

/// The pairs of a support row with `|r_ij| < h_i`, `rij(j)` their separation, to `f` with
/// the owner kernel's `W` and `∇W` (see [`Support::for_each_neighbour`]).
#[inline(always)]
fn own_support<V: Vector>(
    row: &[u32],
    rij: impl Fn(usize) -> V,
    k: &OwnerKernel,
    mut f: impl FnMut(usize, V, Real, Real, V),
) {
    for &j in row {
        let j = j as usize;
        let rij = rij(j);
        let r2 = rij.length_squared();
        if r2 < k.h2 {
            let r = r2.sqrt();
            let (w, g) = k.eval(rij, r);
            f(j, rij, r, w, g);
        }
    }
}

/// Fewest particles per block of the dual-support sweep (see [`dual_support`]).
const MIN_BLOCK: usize = 1024;

/// Particles per block of the dual-support sweep for `n` particles: about four blocks per
/// thread, at least [`MIN_BLOCK`]. Any block length gives bitwise the same sums.
fn block_len(n: usize) -> usize {
    n.div_ceil(4 * rayon::current_num_threads()).max(MIN_BLOCK)
}

/// Where pass 1 sends each support slot's reactions (see [`dual_support`]), for one
/// generation of neighbour lists ([`Neighbours::generation`]) and one block length; kept
/// between sweeps and made anew when either changes.
#[derive(Default)]
struct Routes {
    /// `(generation, particles, block length)` of the routes.
    key: (u64, usize, usize),
    /// Per particle: it and every owner of its dual support lie in one block.
    inside: Vec<bool>,
    /// Per support slot, its route (see [`row::RowDest`]): `INSIDE | (j − a)` for a j that is
    /// `inside` (block from `a`), else the index of the slot's stored record (records in slot
    /// order).
    routes: Vec<u32>,
    /// Per block, its first support slot; then the number of slots.
    first_slot: Vec<usize>,
    /// Per block, the index of its first stored record; then their number.
    first_record: Vec<usize>,
}

impl Routes {
    /// The routes of `nb`'s lists over `n` particles in blocks of `block`.
    fn of<V: Vector>(nb: &Neighbours<V>, n: usize, block: usize) -> Self {
        let inside_of = |j: usize| {
            let lo = j / block * block;
            let hi = (lo + block).min(n);
            let owners = nb.dual.row(j);
            let first = owners.first().map_or(j, |&o| o as usize);
            let last = owners.last().map_or(j, |&o| o as usize);
            lo <= first && last < hi
        };
        let inside: Vec<bool> = (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .map(inside_of)
            .collect();
        let (offsets, indices) = (&nb.support.offsets, &nb.support.indices);
        let mut first_slot: Vec<usize> =
            (0..n).step_by(block).map(|a| offsets[a] as usize).collect();
        first_slot.push(offsets[n] as usize);
        // block b: its first particle, and the particles of its support slots
        let blocks: Vec<(usize, &[u32])> = first_slot
            .windows(2)
            .enumerate()
            .map(|(b, w)| (b * block, &indices[w[0]..w[1]]))
            .collect();
        let stored =
            |(_, js): &(usize, &[u32])| js.iter().filter(|&&j| !inside[j as usize]).count();
        let counts: Vec<usize> = blocks.par_iter().map(stored).collect();
        let mut first_record = Vec::with_capacity(blocks.len() + 1);
        let mut total = 0;
        for c in counts {
            first_record.push(total);
            total += c;
        }
        first_record.push(total);
        assert!(
            total < row::INSIDE as usize,
            "more than 2^31 stored reaction records in one sweep"
        );
        let mut routes = vec![0; indices.len()];
        let pieces = split_at_counts(&mut routes, &first_slot, 1);
        pieces
            .into_par_iter()
            .zip(&blocks)
            .zip(&first_record)
            .for_each(|((out, &(a, js)), &k)| {
                let mut k = k as u32;
                for (r, &j) in out.iter_mut().zip(js) {
                    *r = if inside[j as usize] {
                        row::INSIDE | (j - a as u32)
                    } else {
                        k += 1;
                        k - 1
                    };
                }
            });
        Routes {
            key: (nb.generation, n, block),
            inside,
            routes,
            first_slot,
            first_record,
        }
    }
}

/// Reusable buffers of a sweep, and its result: the sums of every particle.
#[derive(Default)]
pub struct SweepBuffers {
    /// The stored reactions of pass 1, `layout.reactions().len()` reals per stored record
    /// (see [`Routes`]).
    reactions: Vec<Real>,
    /// Where pass 1 sends each support slot's reactions.
    routes: Routes,
    /// The accumulators of the last sweep.
    pub layout: Layout,
    /// Every particle's sums from the last sweep: `layout.owner` reals per particle (row
    /// order), each accumulator at its channels.
    pub sums: Vec<Real>,
}

impl SweepBuffers {
    /// Particle `i`'s sum of the accumulator into column `C` (its `width` reals), if the last
    /// sweep formed one.
    pub fn sum_of<C: 'static>(&self, i: usize) -> Option<&[Real]> {
        let s = self.layout.slot::<C>()?;
        let at = i * self.layout.owner + s.i;
        Some(&self.sums[at..at + s.width])
    }
}

/// Every term bound to `data`'s columns, in order, with the sweep's accumulators; the error
/// names the term and what it misses.
pub fn bind<'w, V: Vector>(
    terms: &'w [Arc<dyn DynPairTerm<V>>],
    data: ParticleData<'w, V>,
    kernel: &'w Kernel,
) -> Result<(Vec<Box<dyn RowTerm<V> + 'w>>, Layout), String> {
    let mut layout = Layout::default();
    let mut bound = Vec::with_capacity(terms.len());
    for t in terms {
        let mut b = Binder::new(data, kernel, &mut layout, t.name());
        bound.push(t.bind_dyn(&mut b)?);
    }
    Ok((bound, layout))
}

/// Evaluates `terms` over the particles of `ctx`: every particle's sums into `buf.sums`
/// (see [`SweepBuffers`]). The error names a term whose columns are missing.
pub fn evaluate<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn DynPairTerm<V>>],
    buf: &mut SweepBuffers,
) -> Result<(), String> {
    let (bound, layout) = bind(terms, ctx.data, ctx.kernel)?;
    buf.layout = layout;
    let n = ctx.len();
    // zeroed below when a row's sums are read before they are written (see `RowPlan::fresh`)
    buf.sums.resize(n * buf.layout.owner, 0.0);
    if buf.layout.owner == 0 || n == 0 {
        return Ok(());
    }
    let all: Vec<&dyn RowTerm<V>> = bound.iter().map(|t| &**t).collect();
    let pairs: Vec<&dyn RowTerm<V>> = all.iter().copied().filter(|t| t.has_pairs()).collect();
    match ctx.formulation {
        Formulation::DualSupport | Formulation::ConstantH | Formulation::GradH => {
            dual_support(ctx, (&all, &pairs), buf)
        }
        Formulation::SingleSupport | Formulation::AveragedKernel => {
            buf.sums.fill(0.0);
            classical::classical(ctx, (&all, &pairs), &buf.layout, &mut buf.sums)
        }
    }
    Ok(())
}

/// Pass 1 and pass 2 in blocks of consecutive particles (in parallel over blocks). A particle
/// j whose dual-support owners all lie in its own block (with particles numbered in space
/// order, nearly all of them: see [`Routes`]) has its reactions added by pass 1 itself, as
/// each owner's row forms them, into a per-block accumulator in ascending owner order; the
/// accumulator is added to j's sums when the block's rows are done, and no reaction of j is
/// stored. A particle with an owner in another block has its reactions stored per support
/// slot and gathers them, in ascending owner order, once every block is done. Either way each
/// sum keeps its order (own row, then the reactions summed from zero in ascending owner
/// order), so the result is bitwise that of two separate passes, for any block length and
/// thread count.
fn dual_support<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    (terms, pair_terms): (&Terms<'_, '_, V>, &Terms<'_, '_, V>),
    buf: &mut SweepBuffers,
) {
    let nb = ctx.neighbours;
    let n = ctx.len();
    let react = buf.layout.reactions::<V>();
    let rw = react.len();
    let owner = buf.layout.owner;
    let block = block_len(n);
    if buf.routes.key != (nb.generation, n, block) {
        buf.routes = Routes::of(nb, n, block);
    }
    let routes = &buf.routes;
    let stored = *routes.first_record.last().unwrap_or(&0);
    buf.reactions.resize(stored * rw, 0.0);
    // the terms with a per-particle part, found once (not by a dynamic call per term and row)
    let inits: Vec<&dyn RowTerm<V>> = terms.iter().copied().filter(|t| t.initializes()).collect();
    let plan = RowPlan::new(
        &buf.layout,
        &react,
        (pair_terms, !inits.is_empty()),
        &routes.inside,
    );
    if !plan.fresh {
        buf.sums.fill(0.0);
    }
    let sweep = Sweep {
        ctx,
        plan: &plan,
        inits: &inits,
        react: &react,
    };
    let r_blocks = split_at_counts(&mut buf.reactions, &routes.first_record, rw);
    let route_blocks: Vec<&[u32]> = (routes.first_slot.windows(2))
        .map(|w| &routes.routes[w[0]..w[1]])
        .collect();
    let later: Vec<Vec<u32>> = buf
        .sums
        .par_chunks_mut(block * owner)
        .zip(r_blocks)
        .zip(route_blocks)
        .enumerate()
        .map_init(
            RowScratch::default,
            |s, (b, ((sums, records), routes_b))| {
                let blk = Block {
                    a: b * block,
                    sums,
                    routes: routes_b,
                    records,
                    base: routes.first_record[b],
                };
                block_of(&sweep, blk, s)
            },
        )
        .collect();
    // the particles with owners in other blocks, now that every row is done
    let later: Vec<u32> = later.concat();
    let reactions = &buf.reactions;
    let mut sums = vec![0.0; later.len() * owner];
    sums.par_chunks_mut(owner)
        .zip(&later)
        .with_min_len(64)
        .for_each(|(own, &j)| {
            let slots = &nb.dual_slot[nb.dual.slots(j as usize)];
            dual_sum((slots, &routes.routes), reactions, &react, own)
        });
    for (&j, add) in later.iter().zip(sums.chunks_exact(owner)) {
        let own = &mut buf.sums[j as usize * owner..(j as usize + 1) * owner];
        for rc in &react {
            own[rc.target] += add[rc.target];
        }
    }
}

/// `buf` cut into consecutive pieces of `width` items per record, piece `b` holding records
/// `first[b]..first[b + 1]` (`first[0] == 0`).
fn split_at_counts<'a, T>(mut buf: &'a mut [T], first: &[usize], width: usize) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(first.len().saturating_sub(1));
    for w in first.windows(2) {
        let (piece, rest) = buf.split_at_mut((w[1] - w[0]) * width);
        out.push(piece);
        buf = rest;
    }
    out
}

#[cfg(test)]
mod tests;

/// The most used items of the pair layer and of the core below it: what a plugin that adds
/// pair terms imports.
pub mod prelude {
    pub use crate::accum::{Acc, Binder, Reaction};
    pub use crate::pair::{BoundTerm, Out, OwnerSums, PairLanes, PairTerm, Specialised};
    pub use crate::{FORCES, OwnerKernel, SimSweeps, SweepCtx};
    pub use dualsph_core::prelude::*;
}
