//! The classical formulations the paper compares against (`SingleSupport`, `AveragedKernel`):
//! no reaction, each particle sums the full symmetric expression over its interpolation
//! neighbourhood. For the pair (i, j) every term is evaluated twice, as i's pair and as j's
//! mirrored pair (`r_ji`, `−∇W`, j's correction, the same `W`), and i receives, per
//! accumulator: [`Reaction::Opposite`] — its own minus the mirror's owner value
//! (`T(i←j) − T(j←i)`); [`Reaction::Separate`] — its own owner value plus the mirror's
//! neighbour value; [`Reaction::OneSided`] — its own owner value.

use crate::accum::{AccumulatorSlot, Layout, Reaction};
use crate::block::row::{Terms, initialize};
use crate::ctx::SweepCtx;
use crate::pair::{EMPTY, Extra, Out, OwnerKernel, PairLanes};
use dualsph_core::lanes::LaneVec;
use dualsph_core::math::{Real, Vector};
use rayon::prelude::*;

/// Adds one pair to i's sums for every accumulator (see the module docs): `own` and `mirror`
/// are the two evaluations' outputs.
fn combine(
    slots: &[AccumulatorSlot],
    own: &Out<'_, Real>,
    mirror: &Out<'_, Real>,
    sums: &mut [Real],
) {
    for s in slots {
        for c in 0..s.width {
            let a = own.owner_value(s, c);
            sums[s.i + c] += match s.reaction {
                Reaction::Opposite => a - mirror.owner_value(s, c),
                Reaction::Separate => a + mirror.neighbour_value(s, c),
                Reaction::OneSided => a,
            };
        }
    }
}

/// Every term on one pair, into `out`.
fn eval<V: Vector>(terms: &Terms<'_, '_, V>, p: &PairLanes<'_, Real, V>, out: &mut Out<'_, Real>) {
    for t in terms {
        t.pair1(p, out);
    }
}

/// The classical sums of every particle into `sums` (`layout.owner` per particle).
pub(super) fn classical<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    (terms, pair_terms): (&Terms<'_, '_, V>, &Terms<'_, '_, V>),
    layout: &Layout,
    sums: &mut [Real],
) {
    let (data, corr) = (&ctx.data, ctx.correction.is_some());
    let v = |x: V| LaneVec::<Real>::splat(x);
    let (own_extra, nbr_extra) = (layout.extra_owner, layout.extra_neighbour);
    sums.par_chunks_mut(layout.owner).enumerate().for_each_init(
        || (Extra::default(), Extra::default()),
        |(ea, eb), (i, sums)| {
            initialize((terms, layout), i, sums);
            if pair_terms.is_empty() {
                return;
            }
            let k_i = OwnerKernel::new(ctx.kernel, data.h[i].0);
            ctx.for_each_neighbour(i, |j, rij, r, w, g| {
                let geometry = (v(rij), r, v(data.vij(i, j)), v(g), v(ctx.corrected(i, g)));
                let own = PairLanes::new((i, [j as u32; 2]), geometry, (Some(w), corr), k_i, data);
                // the mirrored pair: owner j, neighbour i, the same W
                let k_j = OwnerKernel::new(ctx.kernel, data.h[j].0);
                let (mg, mr) = (-g, -rij);
                let geometry = (v(mr), r, v(data.vij(j, i)), v(mg), v(ctx.corrected(j, mg)));
                let mirror =
                    PairLanes::new((j, [i as u32; 2]), geometry, (Some(w), corr), k_j, data);
                let (mut a, mut b) = (Out::new(ea), Out::new(eb));
                eval(pair_terms, &own, &mut a);
                eval(pair_terms, &mirror, &mut b);
                combine(&layout.slots, &a, &b, sums);
                // the channels of other columns back to empty for the next pair
                for e in [&mut *ea, &mut *eb] {
                    e.own[..own_extra].fill(EMPTY);
                    e.nbr[..nbr_extra].fill(EMPTY);
                }
            });
        },
    );
}
