//! Pass 1 of the dual-support sweep for one owner row: the candidates inside `h_i` are
//! compacted into per-thread scratch; then, two pairs at a time in the lanes of an `f64x2`
//! (and an odd last pair alone), the pair geometry is formed once, every term of the sweep
//! adds its contributions ([`Out`], in registers or on the stack), and i's sums and the
//! reactions are formed from them — no per-pair array between the terms and the sums.
//! Per pair the terms' contributions add up in the order of the sweep's terms, i's sums in
//! the order of `H_i`, so the sums do not depend on how the pairs are grouped in lanes.

use super::RowTerm;
use crate::accum::{Layout, ReactionChannel, SCALAR_REGISTERS, Source, Standard};
use crate::ctx::SweepCtx;
use crate::pair::{BoundTerm, Extra, Out, OwnerKernel, OwnerSums, PairLanes, ParticleData};
use dualsph_core::kernels::KernelKind;
use dualsph_core::lanes::{LaneVec, Lanes};
use dualsph_core::math::{Matrix, Real, Vector};
use route::{Cand, compact_row, flush, flush_standard};
pub(crate) use route::{INSIDE, RowDest};
use wide::f64x2;

mod route;

/// Bound terms, as a sweep runs them.
pub type Terms<'a, 'w, V> = [&'a (dyn RowTerm<V> + 'w)];

/// What one row of a sweep forms, laid out once per sweep from its [`Layout`]: the place in
/// each particle's sums (and, with a reaction, in each slot's reaction record) of the
/// registers (the force, the scalars), the other accumulators' channels, and the terms with
/// a pair part.
pub struct RowPlan<'a, 'w, V: Vector> {
    pub(crate) layout: &'a Layout,
    pub(crate) owner: usize,
    pub(crate) rw: usize,
    pub(crate) force: Option<(usize, usize)>,
    pub(crate) scalar: [Option<(usize, Option<usize>)>; SCALAR_REGISTERS],
    pub(crate) extra_own: Vec<(usize, usize)>,
    pub(crate) extra_react: Vec<(Source, usize)>,
    pub(crate) extra: (usize, usize),
    records: Records,
    pub(crate) pair_terms: &'a Terms<'a, 'w, V>,
    /// True when a row's sums are all written by its pairs with nothing added before them
    /// (pair terms, no per-particle part, standard sums only): the rows then start from zero
    /// in registers, and the sweep's sums need no zeroing beforehand.
    pub(crate) fresh: bool,
    /// Per particle: its dual support lies in its block, so pass 1 adds its reactions to the
    /// block's accumulator instead of storing them (see `sweep::dual_support`).
    pub(crate) inside: &'a [bool],
}

/// How a sweep's reaction records are laid out: the standard ones only — the force's `d`
/// components, scalar register 0 to j and, when `rate`, scalar register 1 to j, at fixed
/// places (see
/// [`crate::accum::Layout::reactions`]) — which the row loop writes with no per-pair test,
/// or any other layout, written channel by channel from the plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Records {
    Standard { rate: bool },
    General,
}

impl<'a, 'w, V: Vector> RowPlan<'a, 'w, V> {
    /// The plan of a sweep with `layout`, its reaction channels `react` and its terms with a
    /// pair part; `initializes` when some term has a per-particle part.
    pub(crate) fn new(
        layout: &'a Layout,
        react: &[ReactionChannel],
        (pair_terms, initializes): (&'a Terms<'a, 'w, V>, bool),
        inside: &'a [bool],
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
        let mut plan = RowPlan {
            layout,
            owner: layout.owner,
            rw: react.len(),
            force: at(Standard::Force).map(|i| (i, r_of(Source::Force(0)).unwrap_or(usize::MAX))),
            scalar: std::array::from_fn(|k| {
                at(Standard::Scalar(k)).map(|i| (i, r_of(Source::Scalar(k))))
            }),
            extra_own,
            extra_react,
            extra: (layout.extra_owner, layout.extra_neighbour),
            records: Records::General,
            pair_terms,
            fresh: false,
            inside,
        };
        plan.records = plan.records_shape();
        plan.fresh = !pair_terms.is_empty() && !initializes && plan.extra_own.is_empty();
        plan
    }

    /// [`Records::Standard`] when the sweep's sums are the force, scalar register 0 with a
    /// reaction and possibly scalar register 1, and nothing else.
    fn records_shape(&self) -> Records {
        let d = V::DIM;
        let standard = matches!(self.force, Some((_, 0)))
            && matches!(self.scalar[0], Some((_, Some(r))) if r == d)
            && self.extra_own.is_empty()
            && self.extra_react.is_empty()
            && self.extra == (0, 0);
        match self.scalar[1] {
            _ if !standard => Records::General,
            Some((_, Some(r))) if r == d + 1 && self.rw == d + 2 => {
                Records::Standard { rate: true }
            }
            Some((_, None)) | None if self.rw == d + 1 => Records::Standard { rate: false },
            _ => Records::General,
        }
    }
}

impl<V: Vector> RowPlan<'_, '_, V> {
    /// True when the rows zero the stored records they use (the standard layouts, with pair
    /// terms); otherwise a block's records are zeroed before its rows.
    pub(crate) fn rows_zero_records(&self) -> bool {
        !self.pair_terms.is_empty() && matches!(self.records, Records::Standard { .. })
    }
}

/// i's register sums while its row runs (in registers; the others in an array apart).
#[derive(Clone, Copy)]
pub(crate) struct RowSums<V: Vector> {
    pub(crate) force: V,
    pub(crate) scalar: [Real; SCALAR_REGISTERS],
}

/// Per-thread scratch of pass 1: one row's candidates inside `h_i`, compacted.
#[derive(Default)]
pub struct RowScratch<V: Vector> {
    extra2: Extra<f64x2>,
    extra1: Extra<Real>,
    all: Vec<Real>,
    /// The compacted candidates, each one record (one store when compacting, one slice to
    /// cut into lane groups).
    cands: Vec<Cand<V>>,
    /// One pair's reaction record, as [`flush`] forms it.
    rec: Vec<Real>,
    /// The reactions to the block's particles whose dual support lies in the block: the
    /// sweep's reaction channels per particle, summed from zero in ascending owner order.
    block: Vec<Real>,
}

impl<V: Vector> RowScratch<V> {
    /// Starts a block with `len` reals of reactions, zeroed.
    pub(crate) fn start_block(&mut self, len: usize) {
        self.block.clear();
        self.block.resize(len, 0.0);
    }

    /// The block's reactions summed so far (see [`RowScratch::start_block`]).
    pub(crate) fn block_reactions(&self) -> &[Real] {
        &self.block
    }

    /// Makes room for `m` candidates (grows only; never shrinks).
    #[inline(always)]
    fn reserve(&mut self, m: usize) {
        if self.cands.len() < m {
            self.grow(m);
        }
    }

    #[cold]
    #[inline(never)]
    fn grow(&mut self, m: usize) {
        self.cands.resize(m, Cand::default());
    }
}

/// i's sums before any pair: every term's [`crate::pair::BoundTerm::initialize`] added to `sums`, which
/// arrive zeroed (when some term has such a part: see [`RowPlan::fresh`]).
pub(crate) fn initialize<V: Vector>(
    (terms, layout): (&Terms<'_, '_, V>, &Layout),
    i: usize,
    sums: &mut [Real],
) {
    // the sweep hands over every particle's sums zeroed (see `evaluate`)
    debug_assert!(sums.iter().all(|&x| x == 0.0));
    let mut o = OwnerSums::new(sums, layout);
    for t in terms.iter().filter(|t| t.initializes()) {
        t.initialize(i, &mut o);
    }
}

/// The core columns cut to the particle count, once per row: inside the row the compiler then
/// knows every core column's length, so the terms' gathers of them (which cut to the count
/// again, see [`PairLanes::gather`]) check nothing but j, once for all columns.
#[inline(always)]
fn cut<'w, V: Vector>(d: &ParticleData<'w, V>) -> ParticleData<'w, V> {
    let (mut c, n) = (*d, d.len());
    (c.pos, c.vel, c.mass) = (&d.pos[..n], &d.vel[..n], &d.mass[..n]);
    (c.rho, c.h) = (&d.rho[..n], &d.h[..n]);
    c
}

/// The owner's values the pair geometry needs: i, `v_i`, `L_i` (read only when the row loop
/// is compiled for the correction: see [`row_of`]), its kernel and the kernel's kind with the
/// constants of [`OwnerKernel::grad_factor`].
#[derive(Clone, Copy)]
struct Owner<V: Vector> {
    i: usize,
    v: V,
    l: V::Mat,
    kernel: OwnerKernel,
    factor: (KernelKind, Real, Real),
    /// The particle count.
    n: usize,
}

/// The geometry of the `T::N` pairs `c` (with `r_ij`, `|r_ij|²`): `|r_ij|`,
/// `∇_iW_ij = r_ij ·` [`OwnerKernel::grad_factor`] (Eq. 2.2), `v_ij` and, with `CORR`,
/// `L_i∇_iW_ij` (Eq. 2.10).
#[inline(always)]
fn lanes<'a, T: Lanes, V: Vector, const CORR: bool>(
    data: &'a ParticleData<'a, V>,
    o: Owner<V>,
    c: &[Cand<V>],
) -> PairLanes<'a, T, V> {
    let vel = data.vel;
    let rij = LaneVec::<T>::from_fn(|l| c[l].rij);
    let r = T::from_fn(|l| c[l].r2).sqrt();
    let (kind, g_norm, inv_h) = o.factor;
    let raw = rij.scale::<V>(OwnerKernel::factor_lanes(kind, g_norm, inv_h, r));
    let vij = LaneVec::<T>::splat(o.v).minus::<V>(LaneVec::from_fn(|l| vel[c[l].j as usize].0));
    let grad = if CORR {
        LaneVec::from_fn(|l| o.l.mul_vec(raw.lane::<V>(l)))
    } else {
        raw
    };
    let j = [c[0].j, c[T::N - 1].j];
    PairLanes::new(
        (o.i, j),
        (rij, r, vij, raw, grad),
        (None, CORR),
        o.kernel,
        data,
    )
    .with_len(o.n)
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
/// [`RowTerm::run_block`]).
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

/// Every pair of the compacted row `0..n`, two at a time, through `eval`; returns i's
/// standard sums `own` with the pairs added. With `STD` the records are
/// [`Records::Standard`] (with the density rate to j when `RATE_J`); with `CORR` the
/// gradients are corrected (`L_i∇_iW_ij`). The reactions go to the block's stored `records`
/// or to its sums in the scratch (see [`RowDest`]).
#[inline(always)]
fn row_pairs<V: Vector, E: GroupEval<V>, const STD: bool, const RATE_J: bool, const CORR: bool>(
    data: &ParticleData<'_, V>,
    (plan, eval): (&RowPlan<'_, '_, V>, &E),
    (o, n): (Owner<V>, usize),
    s: &mut RowScratch<V>,
    records: &mut [Real],
    mut own: RowSums<V>,
) -> RowSums<V> {
    let RowScratch {
        extra2,
        extra1,
        all,
        cands,
        rec,
        block,
    } = s;
    let all = &mut all[..];
    let acc = &mut block[..];
    let (c2, c1) = cands[..n].as_chunks::<2>();
    let mut out = Out::new(extra2);
    for c in c2 {
        let p = lanes::<f64x2, V, CORR>(data, o, c);
        eval.two(&p, &mut out);
        if STD {
            flush_standard::<_, V, RATE_J>(&mut out, c, &mut own, (&mut *records, &mut *acc));
        } else {
            let to = (&mut *records, &mut *acc);
            flush(&mut out, c, plan, (&mut own, &mut *all, &mut *rec), to);
        }
    }
    if !c1.is_empty() {
        let p = lanes::<Real, V, CORR>(data, o, c1);
        let mut out = Out::new(extra1);
        eval.one(&p, &mut out);
        if STD {
            flush_standard::<_, V, RATE_J>(&mut out, c1, &mut own, (records, acc));
        } else {
            flush(&mut out, c1, plan, (&mut own, all, rec), (records, acc));
        }
    }
    own
}

/// Pass 1 for owner i after its per-particle parts: i's pairs in `H_i` ascending through
/// `eval`, added to i's `sums`, and their reactions sent where the row's routes say (`to`:
/// see [`RowDest`]; a stored record of a candidate outside `h_i` is zero).
#[inline(always)]
pub(crate) fn pairs_of_row<V: Vector, E: GroupEval<V>>(
    ctx: &SweepCtx<'_, V>,
    (plan, eval): (&RowPlan<'_, '_, V>, &E),
    (i, s): (usize, &mut RowScratch<V>),
    to: RowDest<'_>,
    sums: &mut [Real],
) {
    let row = (plan, eval);
    // the row loop compiled for the records' layout and for the correction (no per-pair test)
    macro_rules! go {
        ($std:literal, $rate:literal) => {
            if ctx.correction.is_some() {
                row_of::<V, E, $std, $rate, true>(ctx, row, (i, s), to, sums)
            } else {
                row_of::<V, E, $std, $rate, false>(ctx, row, (i, s), to, sums)
            }
        };
    }
    match plan.records {
        Records::Standard { rate: false } => go!(true, false),
        Records::Standard { rate: true } => go!(true, true),
        Records::General => go!(false, false),
    }
}

/// [`pairs_of_row`] as a function of its own, called once per row by the block loop (see
/// [`super::block`]).
#[inline(never)]
pub(crate) fn row_apart<V: Vector, E: GroupEval<V>>(
    ctx: &SweepCtx<'_, V>,
    row: (&RowPlan<'_, '_, V>, &E),
    owner: (usize, &mut RowScratch<V>),
    to: RowDest<'_>,
    sums: &mut [Real],
) {
    pairs_of_row(ctx, row, owner, to, sums)
}

/// [`pairs_of_row`] with the records' layout fixed (see [`row_pairs`]).
#[inline(always)]
fn row_of<V: Vector, E: GroupEval<V>, const STD: bool, const RATE_J: bool, const CORR: bool>(
    ctx: &SweepCtx<'_, V>,
    (plan, eval): (&RowPlan<'_, '_, V>, &E),
    (i, s): (usize, &mut RowScratch<V>),
    RowDest {
        routes,
        records,
        base,
    }: RowDest<'_>,
    sums: &mut [Real],
) {
    let data = &cut(&ctx.data);
    let kernel = OwnerKernel::new(ctx.kernel, data.h[i].0);
    let cand = ctx.neighbours.support.row(i);
    let period = ctx.neighbours.period.as_ref();
    s.reserve(cand.len());
    let xi = (data.pos[i].0, kernel.h2);
    let n = if STD {
        // each stored record zeroed as its candidate is compacted (those inside h_i are then
        // written); with other layouts the block's records arrive zeroed
        let w = V::DIM + 1 + RATE_J as usize;
        let zero = Some((&mut *records, w));
        compact_row(
            cand,
            (data.pos, period),
            xi,
            &mut s.cands,
            (routes, base, zero),
        )
    } else {
        compact_row(
            cand,
            (data.pos, period),
            xi,
            &mut s.cands,
            (routes, base, None),
        )
    };
    let mut own = if plan.fresh {
        RowSums {
            force: V::zero(),
            scalar: [0.0; SCALAR_REGISTERS],
        }
    } else {
        RowSums {
            force: plan.force.map_or(V::zero(), |(i, _)| {
                dualsph_core::columns::take_vector(&sums[i..])
            }),
            scalar: plan.scalar.map(|s| s.map_or(0.0, |(i, _)| sums[i])),
        }
    };
    if !plan.extra_own.is_empty() {
        s.all.clear();
        s.all.extend_from_slice(sums);
    }
    let o = Owner {
        i,
        v: data.vel[i].0,
        l: match ctx.correction {
            Some(l) if CORR => l[i].0,
            _ => V::Mat::identity(),
        },
        kernel,
        factor: kernel.factor_parts(),
        n: data.len(),
    };
    own = row_pairs::<V, E, STD, RATE_J, CORR>(data, (plan, eval), (o, n), s, records, own);
    if !plan.extra_own.is_empty() {
        sums.copy_from_slice(&s.all[..plan.owner]);
    }
    if let Some((i, _)) = plan.force {
        for c in 0..V::DIM {
            sums[i + c] = own.force.get(c);
        }
    }
    for (s, v) in plan.scalar.iter().zip(own.scalar) {
        if let Some((i, _)) = *s {
            sums[i] = v;
        }
    }
}
