//! Where a row's reactions go: the compaction of a row's candidates with each one's route
//! (`INSIDE | (j − a)` into the block's sums, or a stored record), and the hand-over of each
//! lane group's pairs to i's sums and of their reactions along those routes (see
//! `sweep::dual_support`).

use super::{RowPlan, RowSums};
use crate::accum::Source;
use crate::pair::{EMPTY, Out};
use dualsph_core::components::Position;
use dualsph_core::lanes::Lanes;
use dualsph_core::math::{Real, Vector};
use dualsph_core::neighbours::Period;

/// One candidate of a row, compacted: `r_ij`, `|r_ij|²`, j and where its reactions go (a
/// route of `RowDest`, with the record's index counted from the block's first).
#[derive(Clone, Copy)]
pub(crate) struct Cand<V: Vector> {
    pub(crate) rij: V,
    pub(crate) r2: Real,
    pub(crate) j: u32,
    pub(crate) dest: u32,
}

/// The flag of a route into the block's sums (see [`RowDest`]).
pub(crate) const INSIDE: u32 = 1 << 31;

/// Where one row's reactions go (see `sweep::dual_support`): per candidate slot its route —
/// `INSIDE | (j − a)` into the block's sums, for a j whose dual support lies in the block, or
/// else the index of the slot's stored record — and the block's stored records, the first
/// of them numbered `base`.
pub(crate) struct RowDest<'r> {
    pub(crate) routes: &'r [u32],
    pub(crate) records: &'r mut [Real],
    pub(crate) base: usize,
}

impl<V: Vector> Default for Cand<V> {
    fn default() -> Self {
        Cand {
            rij: V::zero(),
            r2: 0.0,
            j: 0,
            dest: 0,
        }
    }
}

/// Compacts the candidates with `|r_ij|² < h_i²` into the front of the scratch (`j`, route,
/// `r_ij`, `|r_ij|²`) and returns their number; with `zero = Some((records, w))`, zeroes on
/// the way the stored record (`w` reals) of every candidate that has one (see [`RowDest`]).
/// `cands` has room for every candidate.
/// Branch-free: every candidate is written at the next free place and the place is kept only
/// if it is inside. On a periodic domain `r_ij` is the minimum image ([`Period::image`]).
#[inline(always)]
pub(crate) fn compact_row<V: Vector>(
    cand: &[u32],
    (pos, period): (&[Position<V>], Option<&Period<V>>),
    (xi, h2): (V, Real),
    cands: &mut [Cand<V>],
    routes: (&[u32], usize, Option<(&mut [Real], usize)>),
) -> usize {
    match period {
        None => compact_with(cand, |j| xi - pos[j].0, h2, cands, routes),
        Some(p) => compact_with(cand, |j| p.image(xi - pos[j].0), h2, cands, routes),
    }
}

/// [`compact_row`] with the separation `rij(j)` of each candidate.
#[inline(always)]
fn compact_with<V: Vector>(
    cand: &[u32],
    rij: impl Fn(usize) -> V,
    h2: Real,
    cands: &mut [Cand<V>],
    (routes, base, zero): (&[u32], usize, Option<(&mut [Real], usize)>),
) -> usize {
    let m = cand.len();
    let mut at = Compacted {
        cands: &mut cands[..m],
        n: 0,
    };
    let routes = &routes[..m];
    match zero {
        Some((records, w)) => {
            for (&j, &route) in cand.iter().zip(routes) {
                let dest = in_block(route, base);
                if dest & INSIDE == 0 {
                    let r = dest as usize;
                    records[r * w..(r + 1) * w].fill(0.0);
                }
                at.put(dest, j, rij(j as usize), h2);
            }
        }
        None => {
            for (&j, &route) in cand.iter().zip(routes) {
                at.put(in_block(route, base), j, rij(j as usize), h2);
            }
        }
    }
    at.n
}

/// A route with a stored record's index counted from the block's first (`base`).
#[inline(always)]
fn in_block(route: u32, base: usize) -> u32 {
    if route & INSIDE == 0 {
        route - base as u32
    } else {
        route
    }
}

/// The front of the scratch being filled by [`compact_row`].
struct Compacted<'s, V: Vector> {
    cands: &'s mut [Cand<V>],
    n: usize,
}

impl<V: Vector> Compacted<'_, V> {
    /// Writes a candidate (particle j at `r_ij`, its reactions to `dest`) at the next free
    /// place, kept when `|r_ij|² < h²`.
    #[inline(always)]
    fn put(&mut self, dest: u32, j: u32, rij: V, h2: Real) {
        let r2 = rij.length_squared();
        let n = self.n;
        // n <= the candidate's place < m: the writes stay in bounds
        self.cands[n] = Cand { rij, r2, j, dest };
        self.n += (r2 < h2) as usize;
    }
}

/// Adds the lanes' pairs to i's sums, pair by pair, sends each pair's reaction record (formed
/// in `rec`) where its route says — the block's stored `records` or the block's sums `acc` —
/// and clears `out` for the next lanes.
#[inline(always)]
pub(crate) fn flush<T: Lanes, V: Vector>(
    out: &mut Out<'_, T>,
    pairs: &[Cand<V>],
    plan: &RowPlan<'_, '_, V>,
    (sums, all, rec): (&mut RowSums<V>, &mut [Real], &mut Vec<Real>),
    (records, acc): (&mut [Real], &mut [Real]),
) {
    let rw = plan.rw;
    for (l, &Cand { dest, .. }) in pairs.iter().enumerate() {
        rec.clear();
        rec.resize(rw, 0.0);
        if let Some((_, r)) = plan.force {
            let f: V = out.force.lane(l);
            sums.force += f;
            for (c, x) in rec[r..r + V::DIM].iter_mut().enumerate() {
                *x = -f.get(c);
            }
        }
        for (k, s) in plan.scalar.iter().enumerate() {
            if let Some((_, r)) = *s {
                sums.scalar[k] += out.scalar[k].lane(l);
                if let Some(r) = r {
                    rec[r] = out.scalar_j[k].lane(l);
                }
            }
        }
        for &(c, k) in &plan.extra_own {
            all[k] += out.extra.own[c].lane(l);
        }
        for &(src, r) in &plan.extra_react {
            rec[r] = match src {
                Source::Owner(c) => -out.extra.own[c].lane(l),
                Source::Neighbour(c) => out.extra.nbr[c].lane(l),
                _ => unreachable!("standard sums are written above"),
            };
        }
        if dest & INSIDE != 0 {
            let k = (dest ^ INSIDE) as usize * rw;
            for (x, r) in acc[k..k + rw].iter_mut().zip(&*rec) {
                *x += r;
            }
        } else {
            let k = dest as usize * rw;
            records[k..k + rw].copy_from_slice(rec);
        }
    }
    out.clear_registers();
    let z = T::splat(EMPTY);
    if plan.extra != (0, 0) {
        out.extra.own[..plan.extra.0].fill(z);
        out.extra.nbr[..plan.extra.1].fill(z);
    }
}

/// [`flush`] for the standard records (`Records::Standard` of `row.rs`): the records have
/// `d + 1 + RATE_J` channels at fixed places, so nothing is tested per pair but the route.
#[inline(always)]
pub(crate) fn flush_standard<T: Lanes, V: Vector, const RATE_J: bool>(
    out: &mut Out<'_, T>,
    pairs: &[Cand<V>],
    sums: &mut RowSums<V>,
    to: (&mut [Real], &mut [Real]),
) {
    // the record width as a constant, so that a record is one array (one bounds check)
    match V::DIM + RATE_J as usize {
        1 => flush_records::<T, V, RATE_J, 2>(out, pairs, sums, to),
        2 => flush_records::<T, V, RATE_J, 3>(out, pairs, sums, to),
        3 => flush_records::<T, V, RATE_J, 4>(out, pairs, sums, to),
        _ => flush_records::<T, V, RATE_J, 5>(out, pairs, sums, to),
    }
}

/// [`flush_standard`] with records of `W = d + 1 + RATE_J` reals: each pair's record into
/// the block's stored `records` or added to the block's sums `acc`, as its route says.
#[inline(always)]
fn flush_records<T: Lanes, V: Vector, const RATE_J: bool, const W: usize>(
    out: &mut Out<'_, T>,
    pairs: &[Cand<V>],
    sums: &mut RowSums<V>,
    (records, acc): (&mut [Real], &mut [Real]),
) {
    debug_assert_eq!(W, V::DIM + 1 + RATE_J as usize);
    let (records, _) = records.as_chunks_mut::<W>();
    let (accs, _) = acc.as_chunks_mut::<W>();
    for (l, &Cand { dest, .. }) in pairs.iter().enumerate() {
        let f: V = out.force.lane(l);
        sums.force += f;
        sums.scalar[0] += out.scalar[0].lane(l);
        sums.scalar[1] += out.scalar[1].lane(l);
        let mut rec = [0.0; W];
        for (c, x) in rec[..V::DIM].iter_mut().enumerate() {
            *x = -f.get(c);
        }
        rec[V::DIM] = out.scalar_j[0].lane(l);
        if RATE_J {
            rec[V::DIM + 1] = out.scalar_j[1].lane(l);
        }
        if dest & INSIDE != 0 {
            let sum = &mut accs[(dest ^ INSIDE) as usize];
            for (s, r) in sum.iter_mut().zip(rec) {
                *s += r;
            }
        } else {
            records[dest as usize] = rec;
        }
    }
    out.clear_registers();
}
