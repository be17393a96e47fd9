//! The sweep itself: binding a sweep's terms ([`bind`]), and evaluating them
//! ([`evaluate`]) with the dual-support pass in blocks, or classically for the comparison
//! formulations; the buffers kept between sweeps ([`SweepBuffers`]).

use crate::accum::Layout;
use crate::block::row::{self, RowPlan, RowScratch, Terms};
use crate::block::{Block, RowTerm, Sweep, block_of, dual_sum};
use crate::classical;
use crate::ctx::SweepCtx;
use crate::erased::DynPairTerm;
use crate::pair::{Binder, ParticleData};
use dualsph_core::kernels::Kernel;
use dualsph_core::math::{Real, Vector};
use dualsph_core::neighbours::Neighbours;
use dualsph_core::sim::Formulation;
use rayon::prelude::*;
use std::sync::Arc;

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
