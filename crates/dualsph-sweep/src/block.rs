//! One block of consecutive owner rows of the dual-support sweep: pass 1 row by row, then
//! pass 2 for the block's particles whose dual support lies in the block (see
//! `sweep::dual_support`).
//!
//! The block loop is compiled once per way of evaluating a row (`RowEval`): a sweep whose
//! pair terms are one term (or one fused chain) runs the term's own instance of the loop
//! ([`RowTerm::run_block`]) — one dynamic call per block and a direct call per
//! row. The row is a function of its own (`row::row_apart`): inlined into the block
//! loop, its compaction and pair loops lost registers to the block's state (callgrind: 30 →
//! 33 instructions per candidate, 170 → 173 per two pairs, more than the call costs).

use crate::accum::ReactionChannel;
use crate::ctx::SweepCtx;
use crate::pair::{BoundTerm, Out, OwnerSums, PairLanes};
use dualsph_core::math::{Real, Vector};
use row::{DynTerms, OneTerm, RowDest, RowPlan, RowScratch, Terms, initialize, row_apart};
use wide::f64x2;

#[doc(hidden)]
pub mod row;

/// What every block of one sweep shares.
pub struct Sweep<'a, 'w, V: Vector> {
    pub(crate) ctx: &'a SweepCtx<'a, V>,
    pub(crate) plan: &'a RowPlan<'a, 'w, V>,
    /// The terms with a per-particle part ([`crate::pair::BoundTerm::initialize`]).
    pub(crate) inits: &'a Terms<'a, 'w, V>,
    /// The reaction channels of a support slot.
    pub(crate) react: &'a [ReactionChannel],
}

/// One block: its first row `a`, its rows' sums (`layout.owner` reals per row), the routes
/// of its rows' support slots and its stored reaction records, the first numbered `base`
/// (see `row::RowDest`).
pub struct Block<'b> {
    pub(crate) a: usize,
    pub(crate) sums: &'b mut [Real],
    pub(crate) routes: &'b [u32],
    pub(crate) records: &'b mut [Real],
    pub(crate) base: usize,
}

/// How the rows of a sweep are evaluated after their per-particle parts: i's pairs added to
/// i's `sums` and their reactions sent where the row's routes say.
pub(crate) trait RowEval<V: Vector> {
    fn row(&self, sw: &Sweep<'_, '_, V>, row: (usize, &mut RowScratch<V>), rec_sums: RecSums);
}

/// Where a row's reactions go, and its owner's sums.
pub(crate) type RecSums<'r> = (RowDest<'r>, &'r mut [Real]);

/// No term has a pair part: every reaction is zero (the block's records arrive zeroed).
struct NoPairs;

impl<V: Vector> RowEval<V> for NoPairs {
    #[inline(always)]
    fn row(&self, _: &Sweep<'_, '_, V>, _: (usize, &mut RowScratch<V>), _: RecSums) {}
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

/// Pass 1 over one block, then pass 2 for the block's particles whose dual support lies in
/// it (see [`super::dual_support`]); returns the block's other particles, which gather later.
pub(crate) fn block_of<V: Vector>(
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
    blk: Block<'_>,
    s: &mut RowScratch<V>,
) -> Vec<u32> {
    let Block {
        a,
        sums,
        routes,
        records,
        base,
    } = blk;
    let offsets = &sw.ctx.neighbours.support.offsets[..];
    let (owner, rw) = (sw.plan.owner, sw.react.len());
    let end = a + sums.len() / owner;
    let first = offsets[a] as usize;
    s.start_block((end - a) * rw);
    if !sw.plan.rows_zero_records() {
        records.fill(0.0);
    }
    for i in a..end {
        let slots = offsets[i] as usize - first..offsets[i + 1] as usize - first;
        let own = &mut sums[(i - a) * owner..(i - a + 1) * owner];
        if !sw.inits.is_empty() {
            initialize((sw.inits, sw.plan.layout), i, own);
        }
        let to = RowDest {
            routes: &routes[slots],
            records: &mut *records,
            base,
        };
        eval.row(sw, (i, s), (to, own));
    }
    block_sums(sw, a, sums, s.block_reactions())
}

/// Pass 2 for the particles of the block from `a` on (their `sums`) whose owners all lie in
/// the block: their reactions `accs`, summed in ascending owner order by the rows, added to
/// their sums. Returns the block's other particles.
fn block_sums<V: Vector>(
    sw: &Sweep<'_, '_, V>,
    a: usize,
    sums: &mut [Real],
    accs: &[Real],
) -> Vec<u32> {
    let owner = sw.plan.owner;
    let inside = &sw.plan.inside[a..a + sums.len() / owner];
    let rows = (sums, accs, inside);
    match sw.react.len() {
        // no reactions: nothing to add, nothing to gather later
        0 => Vec::new(),
        1 => add_block_sums::<1>(rows, sw.react, a),
        2 => add_block_sums::<2>(rows, sw.react, a),
        3 => add_block_sums::<3>(rows, sw.react, a),
        4 => add_block_sums::<4>(rows, sw.react, a),
        5 => add_block_sums::<5>(rows, sw.react, a),
        _ => add_block_sums_any(rows, sw.react, a),
    }
}

/// [`block_sums`] with `R` reaction channels.
fn add_block_sums<const R: usize>(
    (sums, accs, inside): (&mut [Real], &[Real], &[bool]),
    react: &[ReactionChannel],
    a: usize,
) -> Vec<u32> {
    let owner = sums.len() / inside.len().max(1);
    let targets: [usize; R] = std::array::from_fn(|c| react[c].target);
    // checked once here, so that the loop adds with no test
    assert!(
        targets.iter().all(|&t| t < owner),
        "reaction targets lie in the sums"
    );
    let mut later = Vec::new();
    let (accs, _) = accs.as_chunks::<R>();
    let rows = sums.chunks_exact_mut(owner).zip(accs).zip(inside);
    for (k, ((own, acc), &inside)) in rows.enumerate() {
        if inside {
            for c in 0..R {
                own[targets[c]] += acc[c];
            }
        } else {
            later.push((a + k) as u32);
        }
    }
    later
}

/// [`block_sums`] with any number of reaction channels.
fn add_block_sums_any(
    (sums, accs, inside): (&mut [Real], &[Real], &[bool]),
    react: &[ReactionChannel],
    a: usize,
) -> Vec<u32> {
    let owner = sums.len() / inside.len().max(1);
    let rw = react.len();
    let mut later = Vec::new();
    let rows = sums
        .chunks_exact_mut(owner)
        .zip(accs.chunks_exact(rw))
        .zip(inside);
    for (k, ((own, acc), &inside)) in rows.enumerate() {
        if inside {
            for (x, rc) in acc.iter().zip(react) {
                own[rc.target] += x;
            }
        } else {
            later.push((a + k) as u32);
        }
    }
    later
}

/// j's share of the reactions: over j's dual-support slots (`slots`, ascending owner i),
/// each reaction channel summed from zero, then added to j's sums at its target. A slot's
/// record is the `routes[slot]`-th of `reactions`, `R` reals each.
#[inline(always)]
fn dual_sum_fixed<const R: usize>(
    (slots, routes): (&[u32], &[u32]),
    reactions: &[Real],
    react: &[ReactionChannel],
    sums: &mut [Real],
) {
    let mut acc = [0.0; R];
    let (records, _) = reactions.as_chunks::<R>();
    for &slot in slots {
        let r = &records[routes[slot as usize] as usize];
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
pub(crate) fn dual_sum(
    (slots, routes): (&[u32], &[u32]),
    reactions: &[Real],
    react: &[ReactionChannel],
    sums: &mut [Real],
) {
    match react.len() {
        0 => {}
        1 => dual_sum_fixed::<1>((slots, routes), reactions, react, sums),
        2 => dual_sum_fixed::<2>((slots, routes), reactions, react, sums),
        3 => dual_sum_fixed::<3>((slots, routes), reactions, react, sums),
        4 => dual_sum_fixed::<4>((slots, routes), reactions, react, sums),
        5 => dual_sum_fixed::<5>((slots, routes), reactions, react, sums),
        w => {
            let mut acc = vec![0.0; w];
            for &slot in slots {
                let at = routes[slot as usize] as usize * w;
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

/// A [`BoundTerm`] with its type erased, as a sweep holds it.
pub trait RowTerm<V: Vector>: Sync {
    /// [`BoundTerm::interact`] for two pairs.
    fn pairs2(&self, p: &PairLanes<'_, f64x2, V>, out: &mut Out<'_, f64x2>);
    /// [`BoundTerm::interact`] for one pair.
    fn pair1(&self, p: &PairLanes<'_, Real, V>, out: &mut Out<'_, Real>);
    /// See [`BoundTerm::initialize`].
    fn initialize(&self, i: usize, sums: &mut OwnerSums<'_>);
    /// See [`BoundTerm::INITIALIZES`].
    fn initializes(&self) -> bool;
    /// See [`BoundTerm::has_pairs`].
    fn has_pairs(&self) -> bool;
    /// Pass 1 and the in-block part of pass 2 over one block of rows with this term alone, the
    /// block loop compiled for the term (the sweep's fast path: see
    /// [`crate::Fused`] for several terms); returns the block's particles that gather
    /// after every block is done.
    #[doc(hidden)]
    fn run_block(
        &self,
        sweep: &Sweep<'_, '_, V>,
        block: Block<'_>,
        s: &mut RowScratch<V>,
    ) -> Vec<u32>;
}

impl<V: Vector, B: BoundTerm<V>> RowTerm<V> for B {
    fn pairs2(&self, p: &PairLanes<'_, f64x2, V>, out: &mut Out<'_, f64x2>) {
        self.interact(&self.owner(p.i()), p, out)
    }

    fn pair1(&self, p: &PairLanes<'_, Real, V>, out: &mut Out<'_, Real>) {
        self.interact(&self.owner(p.i()), p, out)
    }

    fn run_block(
        &self,
        sweep: &Sweep<'_, '_, V>,
        block: Block<'_>,
        s: &mut RowScratch<V>,
    ) -> Vec<u32> {
        run_block(sweep, &OneTermRows(self), block, s)
    }

    fn initialize(&self, i: usize, sums: &mut OwnerSums<'_>) {
        BoundTerm::initialize(self, i, sums)
    }

    fn initializes(&self) -> bool {
        B::INITIALIZES
    }

    fn has_pairs(&self) -> bool {
        BoundTerm::has_pairs(self)
    }
}
