//! Pass 1 of the dual-support sweep for one owner row: the candidates inside `h_i` are
//! compacted into per-thread scratch; then, two pairs at a time in the lanes of an `f64x2`
//! (and an odd last pair alone), the pair geometry is formed once, every term of the sweep
//! adds its contributions ([`Out`], in registers or on the stack), and i's sums and the
//! reactions are formed from them — no per-pair array between the terms and the sums.
//! Per pair the terms' contributions add up in the order of the sweep's terms, i's sums in
//! the order of `H_i`, so the sums do not depend on how the pairs are grouped in lanes.

use super::SweepCtx;
use crate::accum::{Layout, ReactionChannel, Source, Standard};
use crate::components::Position;
use crate::kernels::KernelKind;
use crate::lanes::{LaneVec, Lanes};
use crate::math::{Matrix, Real, Vector};
use crate::pair::{BoundTerm, Extra, Out, OwnerKernel, OwnerSums, PairLanes, RowTerm};
use wide::f64x2;

/// Bound terms, as a sweep runs them.
pub type Terms<'a, 'w, V> = [&'a (dyn RowTerm<V> + 'w)];

/// What one row of a sweep forms, laid out once per sweep from its [`Layout`]: the place in
/// each particle's sums (and, with a reaction, in each slot's reaction record) of the
/// standard sums, the other accumulators' channels, and the terms with a pair part.
pub struct RowPlan<'a, 'w, V: Vector> {
    pub(super) layout: &'a Layout,
    pub(super) owner: usize,
    rw: usize,
    force: Option<(usize, usize)>,
    power: Option<(usize, Option<usize>)>,
    rate: Option<(usize, Option<usize>)>,
    extra_own: Vec<(usize, usize)>,
    extra_react: Vec<(Source, usize)>,
    extra: (usize, usize),
    pub(super) pair_terms: &'a Terms<'a, 'w, V>,
}

impl<'a, 'w, V: Vector> RowPlan<'a, 'w, V> {
    /// The plan of a sweep with `layout`, its reaction channels `react` and its terms with a
    /// pair part.
    pub(super) fn new(
        layout: &'a Layout,
        react: &[ReactionChannel],
        pair_terms: &'a Terms<'a, 'w, V>,
    ) -> Self {
        let at = |k| layout.standard(k).map(|s| s.i);
        let r_of = |src: Source| react.iter().position(|r| r.source == src);
        let mut extra_own = Vec::new();
        for s in layout.slots.iter().filter(|s| s.standard.is_none()) {
            extra_own.extend((0..s.width).map(|c| (s.chan + c, s.i + c)));
        }
        let extra_react = react
            .iter()
            .enumerate()
            .filter(|(_, r)| matches!(r.source, Source::Owner(_) | Source::Neighbour(_)))
            .map(|(k, r)| (r.source, k))
            .collect();
        RowPlan {
            layout,
            owner: layout.owner,
            rw: react.len(),
            force: at(Standard::Force).map(|i| (i, r_of(Source::Force(0)).unwrap_or(usize::MAX))),
            power: at(Standard::Power).map(|i| (i, r_of(Source::Power))),
            rate: at(Standard::Rate).map(|i| (i, r_of(Source::Rate))),
            extra_own,
            extra_react,
            extra: (layout.extra_owner, layout.extra_neighbour),
            pair_terms,
        }
    }
}

/// i's standard sums while its row runs (in registers; the others in an array apart).
struct RowSums<V: Vector> {
    force: V,
    power: Real,
    rate: Real,
}

/// Per-thread scratch of pass 1: one row's candidates inside `h_i`, compacted.
#[derive(Default)]
pub struct RowScratch<V: Vector> {
    extra2: Extra<f64x2>,
    extra1: Extra<Real>,
    all: Vec<Real>,
    j: Vec<u32>,
    slot: Vec<u32>,
    rij: Vec<V>,
    r2: Vec<Real>,
}

impl<V: Vector> RowScratch<V> {
    /// Makes room for `m` candidates (grows only; never shrinks).
    #[inline(always)]
    fn reserve(&mut self, m: usize) {
        if self.j.len() < m {
            self.grow(m);
        }
    }

    #[cold]
    #[inline(never)]
    fn grow(&mut self, m: usize) {
        self.j.resize(m, 0);
        self.slot.resize(m, 0);
        self.rij.resize(m, V::zero());
        self.r2.resize(m, 0.0);
    }
}

/// i's sums before any pair: zero, then every term's [`crate::pair::BoundTerm::initialize`].
pub(super) fn initialize<V: Vector>(
    (terms, layout): (&Terms<'_, '_, V>, &Layout),
    i: usize,
    sums: &mut [Real],
) {
    sums.fill(0.0);
    let mut o = OwnerSums::new(sums, layout);
    for t in terms.iter().filter(|t| t.initializes()) {
        t.initialize(i, &mut o);
    }
}

/// Compacts the candidates with `|r_ij|² < h_i²` into the front of the scratch (`j`, slot,
/// `r_ij`, `|r_ij|²`) and returns their number. Branch-free: every candidate is written at
/// the next free place and the place is kept only if it is inside.
#[inline(always)]
fn compact_row<V: Vector>(
    cand: &[u32],
    pos: &[Position<V>],
    xi: V,
    h2: Real,
    s: &mut RowScratch<V>,
) -> usize {
    let m = cand.len();
    let (js, slots, rijs, r2s) = (
        &mut s.j[..m],
        &mut s.slot[..m],
        &mut s.rij[..m],
        &mut s.r2[..m],
    );
    let mut n = 0;
    for (slot, &j) in cand.iter().enumerate() {
        let rij = xi - pos[j as usize].0;
        let r2 = rij.length_squared();
        // n <= slot < m: the writes stay in bounds
        js[n] = j;
        slots[n] = slot as u32;
        rijs[n] = rij;
        r2s[n] = r2;
        n += (r2 < h2) as usize;
    }
    n
}

/// The owner's values the pair geometry needs: i, `v_i`, `L_i` (when corrected), its kernel
/// and the kernel's kind with the constants of [`OwnerKernel::grad_factor`].
#[derive(Clone, Copy)]
struct Owner<V: Vector> {
    i: usize,
    v: V,
    l: Option<V::Mat>,
    kernel: OwnerKernel,
    factor: (KernelKind, Real, Real),
}

/// The geometry of the `T::N` pairs `js` (with `r_ij`, `|r_ij|²`): `|r_ij|`,
/// `∇_iW_ij = r_ij ·` [`OwnerKernel::grad_factor`] (Eq. 2.2), `v_ij` and `L_i∇_iW_ij` (Eq. 2.10).
#[inline(always)]
fn lanes<'a, T: Lanes, V: Vector>(
    ctx: &'a SweepCtx<'a, V>,
    o: Owner<V>,
    js: &[u32],
    rijs: &[V],
    r2s: &[Real],
) -> PairLanes<'a, T, V> {
    let vel = ctx.data.vel;
    let rij = LaneVec::<T>::from_fn(|l| rijs[l]);
    let r = T::from_fn(|l| r2s[l]).sqrt();
    let (kind, g_norm, inv_h) = o.factor;
    let raw = rij.scale::<V>(OwnerKernel::factor_lanes(kind, g_norm, inv_h, r));
    let vij = LaneVec::<T>::splat(o.v).minus::<V>(LaneVec::from_fn(|l| vel[js[l] as usize].0));
    let grad = match o.l {
        Some(m) => LaneVec::from_fn(|l| m.mul_vec(raw.lane::<V>(l))),
        None => raw,
    };
    let j = [js[0], js[T::N - 1]];
    PairLanes::new(
        (o.i, j),
        (rij, r, vij, raw, grad),
        None,
        o.kernel,
        &ctx.data,
    )
}

/// Adds the lanes' pairs to i's sums, pair by pair, writes their reactions into their
/// support `slots` (one per lane) and clears `out` for the next lanes.
#[inline(always)]
fn flush<T: Lanes, V: Vector>(
    out: &mut Out<'_, T>,
    slots: &[u32],
    plan: &RowPlan<'_, '_, V>,
    (sums, all): (&mut RowSums<V>, &mut [Real]),
    reactions: &mut [Real],
) {
    for (l, &slot) in slots.iter().enumerate() {
        let base = slot as usize * plan.rw;
        let rec = &mut reactions[base..base + plan.rw];
        if let Some((_, r)) = plan.force {
            let f: V = out.force.lane(l);
            sums.force += f;
            for (c, x) in rec[r..r + V::DIM].iter_mut().enumerate() {
                *x = -f.get(c);
            }
        }
        if let Some((_, r)) = plan.power {
            sums.power += out.power.lane(l);
            if let Some(r) = r {
                rec[r] = out.power_j.lane(l);
            }
        }
        if let Some((_, r)) = plan.rate {
            sums.rate += out.rate.lane(l);
            if let Some(r) = r {
                rec[r] = out.rate_j.lane(l);
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
    }
    let z = T::splat(0.0);
    (out.force, out.power, out.power_j, out.rate, out.rate_j) = (LaneVec([z; 3]), z, z, z, z);
    if plan.extra != (0, 0) {
        out.extra.own[..plan.extra.0].fill(z);
        out.extra.nbr[..plan.extra.1].fill(z);
    }
}

/// How a row's lane groups are evaluated: every term of the sweep through dynamic calls
/// ([`DynTerms`]), or one term (a fused chain of terms) statically ([`OneTerm`]).
pub(crate) trait GroupEval<V: Vector> {
    /// The terms on two pairs.
    fn two(&self, p: &PairLanes<'_, f64x2, V>, out: &mut Out<'_, f64x2>);
    /// The terms on one pair.
    fn one(&self, p: &PairLanes<'_, Real, V>, out: &mut Out<'_, Real>);
}

/// The sweep's terms, one dynamic call per term and lane group.
pub(crate) struct DynTerms<'a, 'w, V: Vector>(pub(crate) &'a Terms<'a, 'w, V>);

impl<V: Vector> GroupEval<V> for DynTerms<'_, '_, V> {
    #[inline(always)]
    fn two(&self, p: &PairLanes<'_, f64x2, V>, out: &mut Out<'_, f64x2>) {
        for t in self.0 {
            t.pairs2(p, out);
        }
    }
    #[inline(always)]
    fn one(&self, p: &PairLanes<'_, Real, V>, out: &mut Out<'_, Real>) {
        for t in self.0 {
            t.pair1(p, out);
        }
    }
}

/// One term with its owner part, statically (its row loop is compiled for it: see
/// [`RowTerm::run_row`]).
pub(crate) struct OneTerm<'a, V: Vector, B: BoundTerm<V>>(pub(crate) &'a B, pub(crate) B::Owner);

impl<V: Vector, B: BoundTerm<V>> GroupEval<V> for OneTerm<'_, V, B> {
    #[inline(always)]
    fn two(&self, p: &PairLanes<'_, f64x2, V>, out: &mut Out<'_, f64x2>) {
        self.0.interact(&self.1, p, out)
    }
    #[inline(always)]
    fn one(&self, p: &PairLanes<'_, Real, V>, out: &mut Out<'_, Real>) {
        self.0.interact(&self.1, p, out)
    }
}

/// Every pair of the compacted row `0..n`, two at a time, through `eval`.
#[inline(always)]
fn row_pairs<V: Vector, E: GroupEval<V>>(
    ctx: &SweepCtx<'_, V>,
    (plan, eval): (&RowPlan<'_, '_, V>, &E),
    (o, n): (Owner<V>, usize),
    s: &mut RowScratch<V>,
    reactions: &mut [Real],
    own: &mut RowSums<V>,
) {
    let RowScratch {
        extra2,
        extra1,
        all,
        j,
        slot,
        rij,
        r2,
    } = s;
    let all = &mut all[..];
    let (js2, js1) = j[..n].as_chunks::<2>();
    let (slots2, slots1) = slot[..n].as_chunks::<2>();
    let (rijs2, rijs1) = rij[..n].as_chunks::<2>();
    let (r2s2, r2s1) = r2[..n].as_chunks::<2>();
    let mut out = Out::new(extra2);
    for (((js, slots), rijs), r2s) in js2.iter().zip(slots2).zip(rijs2).zip(r2s2) {
        let p = lanes::<f64x2, V>(ctx, o, js, rijs, r2s);
        eval.two(&p, &mut out);
        flush(&mut out, slots, plan, (&mut *own, &mut *all), reactions);
    }
    if !js1.is_empty() {
        let p = lanes::<Real, V>(ctx, o, js1, rijs1, r2s1);
        let mut out = Out::new(extra1);
        eval.one(&p, &mut out);
        flush(&mut out, slots1, plan, (own, all), reactions);
    }
}

/// Pass 1 for one owner i: i's sums (its terms' initial values, then its pairs in `H_i`
/// ascending) into `sums`, and the reactions of its pairs into the row's slots of
/// `reactions` (the sweep's reaction channels per slot; zero for candidates outside `h_i`). A
/// sweep with one term with a pair part runs that term's own compiled row loop.
#[inline]
pub(super) fn owner_row<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    (terms, plan): (&Terms<'_, '_, V>, &RowPlan<'_, '_, V>),
    i: usize,
    s: &mut RowScratch<V>,
    reactions: &mut [Real],
    sums: &mut [Real],
) {
    initialize((terms, plan.layout), i, sums);
    match plan.pair_terms {
        [] => reactions.fill(0.0),
        [one] => one.run_row(ctx, plan, (i, s), reactions, sums),
        many => pairs_of_row(ctx, (plan, &DynTerms(many)), (i, s), reactions, sums),
    }
}

/// i's pairs through `eval`, added to i's initial `sums`, and their reactions (see
/// [`owner_row`]).
#[inline(always)]
pub(crate) fn pairs_of_row<V: Vector, E: GroupEval<V>>(
    ctx: &SweepCtx<'_, V>,
    (plan, eval): (&RowPlan<'_, '_, V>, &E),
    (i, s): (usize, &mut RowScratch<V>),
    reactions: &mut [Real],
    sums: &mut [Real],
) {
    reactions.fill(0.0);
    let data = &ctx.data;
    let kernel = OwnerKernel::new(ctx.kernel, data.h[i].0);
    let cand = ctx.neighbours.support.row(i);
    s.reserve(cand.len());
    let n = compact_row(cand, data.pos, data.pos[i].0, kernel.h2, s);
    let mut own = RowSums {
        force: plan
            .force
            .map_or(V::zero(), |(i, _)| crate::columns::take_vector(&sums[i..])),
        power: plan.power.map_or(0.0, |(i, _)| sums[i]),
        rate: plan.rate.map_or(0.0, |(i, _)| sums[i]),
    };
    if !plan.extra_own.is_empty() {
        s.all.clear();
        s.all.extend_from_slice(sums);
    }
    let (kind, g_norm, inv_h) = kernel.factor_parts();
    let l = ctx.correction.map(|l| l[i].0);
    let v = data.vel[i].0;
    let o = Owner {
        i,
        v,
        l,
        kernel,
        factor: (kind, g_norm, inv_h),
    };
    row_pairs(ctx, (plan, eval), (o, n), s, reactions, &mut own);
    if !plan.extra_own.is_empty() {
        sums.copy_from_slice(&s.all[..plan.owner]);
    }
    if let Some((i, _)) = plan.force {
        for c in 0..V::DIM {
            sums[i + c] = own.force.get(c);
        }
    }
    if let Some((i, _)) = plan.power {
        sums[i] = own.power;
    }
    if let Some((i, _)) = plan.rate {
        sums[i] = own.rate;
    }
}
