//! One block of consecutive owner rows of the dual-support sweep: pass 1 row by row, and the
//! pass-2 wavefront behind it (see `sweep::dual_support`).
//!
//! The block loop is compiled once per way of evaluating a row (`RowEval`): a sweep whose
//! pair terms are one term (or one fused chain) runs the term's own instance of the loop
//! ([`crate::pair::RowTerm::run_block`]) — one dynamic call per block and a direct call per
//! row. The row is a function of its own (`row::row_apart`): inlined into the block
//! loop, its compaction and pair loops lost registers to the block's state (callgrind: 30 →
//! 33 instructions per candidate, 170 → 173 per two pairs, more than the call costs).

use super::row::{DynTerms, OneTerm, RowPlan, RowScratch, Terms, initialize, row_apart};
use super::{SweepCtx, WAVE};
use crate::accum::ReactionChannel;
use crate::math::{Real, Vector};
use crate::pair::BoundTerm;

/// What every block of one sweep shares.
pub struct Sweep<'a, 'w, V: Vector> {
    pub(crate) ctx: &'a SweepCtx<'a, V>,
    pub(crate) plan: &'a RowPlan<'a, 'w, V>,
    /// The terms with a per-particle part ([`crate::pair::BoundTerm::initialize`]).
    pub(crate) inits: &'a Terms<'a, 'w, V>,
    /// The reaction channels of a support slot.
    pub(crate) react: &'a [ReactionChannel],
}

/// One block: its first row `a`, its rows' sums (`layout.owner` reals per row) and the
/// reaction records of its rows' support slots.
pub struct Block<'b> {
    pub(crate) a: usize,
    pub(crate) sums: &'b mut [Real],
    pub(crate) reactions: &'b mut [Real],
}

/// How the rows of a sweep are evaluated after their per-particle parts: i's pairs added to
/// i's `sums` and their reactions written into the row's slots (`rec`).
pub(crate) trait RowEval<V: Vector> {
    fn row(&self, sw: &Sweep<'_, '_, V>, row: (usize, &mut RowScratch<V>), rec_sums: RecSums);
}

/// A row's reaction records and its owner's sums.
pub(crate) type RecSums<'r> = (&'r mut [Real], &'r mut [Real]);

/// No term has a pair part: every reaction is zero.
struct NoPairs;

impl<V: Vector> RowEval<V> for NoPairs {
    #[inline(always)]
    fn row(&self, _: &Sweep<'_, '_, V>, _: (usize, &mut RowScratch<V>), (rec, _): RecSums) {
        rec.fill(0.0)
    }
}

/// Several terms, each called through its vtable once per lane group.
struct ManyTerms;

impl<V: Vector> RowEval<V> for ManyTerms {
    #[inline(always)]
    fn row(&self, sw: &Sweep<'_, '_, V>, row: (usize, &mut RowScratch<V>), rs: RecSums) {
        let eval = DynTerms(sw.plan.pair_terms);
        row_apart(sw.ctx, (sw.plan, &eval), row, rs.0, rs.1)
    }
}

/// One term (or a fused chain), compiled into the block loop.
pub(crate) struct OneTermRows<'t, B>(pub(crate) &'t B);

impl<V: Vector, B: BoundTerm<V>> RowEval<V> for OneTermRows<'_, B> {
    #[inline(always)]
    fn row(&self, sw: &Sweep<'_, '_, V>, row: (usize, &mut RowScratch<V>), rs: RecSums) {
        let eval = OneTerm(self.0, self.0.owner(row.0));
        row_apart(sw.ctx, (sw.plan, &eval), row, rs.0, rs.1)
    }
}

/// Pass 1 and the pass-2 wavefront over one block (see [`super::dual_support`]); returns the
/// block's particles with a dual-support owner in another block, which gather later.
pub(super) fn block_of<V: Vector>(
    sw: &Sweep<'_, '_, V>,
    blk: Block<'_>,
    s: &mut RowScratch<V>,
) -> Vec<u32> {
    match sw.plan.pair_terms {
        [] => run_block(sw, &NoPairs, blk, s),
        [one] => one.run_block(sw, blk, s),
        _ => run_block(sw, &ManyTerms, blk, s),
    }
}

/// [`block_of`] with the rows evaluated by `eval`.
#[inline(always)]
pub(crate) fn run_block<V: Vector, E: RowEval<V>>(
    sw: &Sweep<'_, '_, V>,
    eval: &E,
    Block { a, sums, reactions }: Block<'_>,
    s: &mut RowScratch<V>,
) -> Vec<u32> {
    let nb = sw.ctx.neighbours;
    let offsets = &nb.support.offsets[..];
    let (owner, rw) = (sw.plan.owner, sw.react.len());
    let end = a + sums.len() / owner;
    let base = offsets[a] as usize;
    let mut later = Vec::new();
    let mut next = a; // the wavefront of pass 2
    for i in a..end {
        let r = (offsets[i] as usize - base) * rw..(offsets[i + 1] as usize - base) * rw;
        let own = &mut sums[(i - a) * owner..(i - a + 1) * owner];
        if !sw.inits.is_empty() {
            initialize((sw.inits, sw.plan.layout), i, own);
        }
        eval.row(sw, (i, s), (&mut reactions[r], own));
        let wave = (i - a) % WAVE == WAVE - 1 || i + 1 == end;
        while wave && next <= i {
            let owners = nb.dual.row(next);
            let first = owners.first().map_or(next, |&o| o as usize);
            let last = owners.last().map_or(next, |&o| o as usize);
            if first < a || last >= end {
                later.push(next as u32);
            } else if last <= i {
                let slots = &nb.dual_slot[nb.dual.slots(next)];
                let own = &mut sums[(next - a) * owner..(next - a + 1) * owner];
                dual_sum(slots, reactions, base, sw.react, own);
            } else {
                break;
            }
            next += 1;
        }
    }
    later
}

/// j's share of the reactions: over j's dual-support slots (`slots`, ascending owner i),
/// each reaction channel summed from zero, then added to j's sums at its target. `reactions`
/// holds `R` reals per slot from slot `base` on.
#[inline(always)]
fn dual_sum_fixed<const R: usize>(
    slots: &[u32],
    reactions: &[Real],
    base: usize,
    react: &[ReactionChannel],
    sums: &mut [Real],
) {
    let mut acc = [0.0; R];
    let (records, _) = reactions.as_chunks::<R>();
    for &slot in slots {
        let r = &records[slot as usize - base];
        for c in 0..R {
            acc[c] += r[c];
        }
    }
    for c in 0..R {
        sums[react[c].target] += acc[c];
    }
}

/// [`dual_sum_fixed`] for any number of reaction channels.
#[inline(always)]
pub(super) fn dual_sum(
    slots: &[u32],
    reactions: &[Real],
    base: usize,
    react: &[ReactionChannel],
    sums: &mut [Real],
) {
    match react.len() {
        0 => {}
        1 => dual_sum_fixed::<1>(slots, reactions, base, react, sums),
        2 => dual_sum_fixed::<2>(slots, reactions, base, react, sums),
        3 => dual_sum_fixed::<3>(slots, reactions, base, react, sums),
        4 => dual_sum_fixed::<4>(slots, reactions, base, react, sums),
        5 => dual_sum_fixed::<5>(slots, reactions, base, react, sums),
        w => {
            let mut acc = vec![0.0; w];
            for &slot in slots {
                let at = (slot as usize - base) * w;
                for (a, r) in acc.iter_mut().zip(&reactions[at..at + w]) {
                    *a += r;
                }
            }
            for (a, rc) in acc.iter().zip(react) {
                sums[rc.target] += a;
            }
        }
    }
}
