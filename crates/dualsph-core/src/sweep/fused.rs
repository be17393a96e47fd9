//! The fused pass 1 for the built-in weakly-compressible terms: the pressure force (Eq. 4.19)
//! and Monaghan's artificial viscosity (Eq. 4.17), with the continuity sum (Eq. 4.9), all in
//! one loop over an owner's pairs with every per-pair value in registers.
//!
//! The general path ([`super::row`]) runs each [`PairTerm`] over the row in turn through
//! per-pair arrays; that is what makes terms plugins, and it costs loads and stores of every
//! intermediate. When a scene's pair terms are exactly built-in ones (each says so through
//! [`PairTerm::builtin`]) and the kernel correction is off, the sweep uses this loop instead.
//! It performs the same floating-point operations in the same order as the terms' own
//! `interact`, so the results are bitwise those of the general path: `tests/fused_sweep.rs`
//! compares the two through the plugins on every particle.

use super::SweepCtx;
use super::row::{Reaction, RowScratch, compact_row_into};
use crate::components::{Density, Mass, Pressure, SmoothingLength, SoundSpeed, Velocity};
use crate::kernels::{KernelKind, with_kernel_kind};
use crate::lanes::{LaneVec, Lanes};
use crate::math::{Real, Vector};
use crate::pair::{DynPairTerm, OwnerKernel};
use std::sync::Arc;
use wide::f64x2;

/// A pair term the sweep can evaluate in its fused loop (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BuiltinTerm {
    /// The pressure force of Eq. 4.19 without the kernel correction:
    /// `f_ij = −m_i m_j (p_i/ρ_i²) ∇_iW_ij`, power `m_i m_j (p_i/ρ_i²) v_ij·∇_iW_ij` to i.
    Pressure,
    /// Monaghan's artificial viscosity, Eq. 4.17 (see [`artificial_viscosity_parts`]).
    ArtificialViscosity {
        /// α.
        alpha: Real,
        /// β.
        beta: Real,
        /// η / h̄.
        eta_factor: Real,
    },
}

/// One particle's values in the artificial viscosity: `(h, c, ρ)`.
pub type AvSide = (Real, Real, Real);

/// `(num, den)` of Monaghan's `Π_ij` (Eq. 4.17) for the owner's `(h_i, c_i, ρ_i)`, the
/// neighbour's `(h_j, c_j, ρ_j)`, `v_ij·r_ij` and `|r_ij|`: with `h̄ = (h_i + h_j)/2`,
/// `D = r² + (η_f h̄)²`, `x = h̄ min(v_ij·r_ij, 0)` (so `μ_ij = x/D`) and `c̄ = (c_i + c_j)/2`,
/// `Π_ij = μ(−α c̄ + β μ)/ρ̄ = 2 num/den` with `num = x (β x − α c̄ D)` and
/// `den = D² (ρ_i + ρ_j)`: one division, and no branch (a receding pair has `x = 0`).
#[inline(always)]
pub fn artificial_viscosity_parts(
    av: (Real, Real, Real),
    side_i: AvSide,
    side_j: AvSide,
    vr: Real,
    r: Real,
) -> (Real, Real) {
    av_parts_lanes(av, side_i, side_j, vr, r)
}

/// [`artificial_viscosity_parts`] for one pair or several side by side ([`Lanes`]).
#[inline(always)]
fn av_parts_lanes<T: Lanes>(
    (alpha, beta, eta_factor): (Real, Real, Real),
    (h_i, c_i, rho_i): (T, T, T),
    (h_j, c_j, rho_j): (T, T, T),
    vr: T,
    r: T,
) -> (T, T) {
    let c = T::splat;
    let hbar = c(0.5) * (h_i + h_j);
    let eta = c(eta_factor) * hbar;
    let d = r * r + eta * eta;
    let x = hbar * T::if_lt(vr, c(0.0), vr, c(0.0));
    let cbar = c(0.5) * (c_i + c_j);
    (
        x * (c(beta) * x - c(alpha) * cbar * d),
        d * d * (rho_i + rho_j),
    )
}

/// What the fused loop evaluates: the pressure force, the artificial viscosity `(α, β, η_f)`,
/// or both in the order the scene lists them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum FusedPlan {
    /// `PressureForce` only.
    Pressure,
    /// `ArtificialViscosity` only.
    Viscosity((Real, Real, Real)),
    /// Both, pressure first.
    PressureThenViscosity((Real, Real, Real)),
    /// Both, viscosity first.
    ViscosityThenPressure((Real, Real, Real)),
}

/// The pressure and sound-speed columns the fused loop reads.
#[derive(Clone, Copy)]
pub(super) struct EosColumns<'a> {
    pressure: &'a [Pressure],
    sound: &'a [SoundSpeed],
}

/// The fused plan for `terms` when they are one of the shapes of [`FusedPlan`] and the fused
/// loop applies (no kernel correction; pressure and sound speed of every particle from an
/// equation of state), with those columns; else `None`.
pub(super) fn fused_plan<'a, V: Vector>(
    ctx: &SweepCtx<'a, V>,
    terms: &[Arc<dyn DynPairTerm<V>>],
) -> Option<(FusedPlan, EosColumns<'a>)> {
    if ctx.correction.is_some() {
        return None;
    }
    let eos = EosColumns {
        pressure: ctx.data.column()?,
        sound: ctx.data.column()?,
    };
    let b: Option<Vec<BuiltinTerm>> = terms.iter().map(|t| t.builtin()).collect();
    let av = |t: &BuiltinTerm| match *t {
        BuiltinTerm::ArtificialViscosity {
            alpha,
            beta,
            eta_factor,
        } => Some((alpha, beta, eta_factor)),
        BuiltinTerm::Pressure => None,
    };
    use BuiltinTerm::Pressure as P;
    let plan = match b?.as_slice() {
        [P] => Some(FusedPlan::Pressure),
        [v] => av(v).map(FusedPlan::Viscosity),
        [P, v] => av(v).map(FusedPlan::PressureThenViscosity),
        [v, P] => av(v).map(FusedPlan::ViscosityThenPressure),
        _ => None,
    };
    plan.map(|p| (p, eos))
}

/// Pass 1's evaluation of one owner row, fixed for a whole sweep so that the block loop is
/// compiled once per kind of row (see [`with_fused_rows`]): the same contract as
/// [`super::row::owner_row`].
pub(super) trait RowEval<V: Vector>: Sync {
    /// Owner i's sums `(force, power)`, its reactions written into `reactions` (i's support
    /// slots), and `dρ_i/dt` (Eq. 4.9) into `drho` when given.
    fn row(
        &self,
        i: usize,
        s: &mut RowScratch<V>,
        reactions: &mut [Reaction<V>],
        drho: Option<&mut Real>,
    ) -> (V, Real);
}

/// Code generic over the row evaluation, called with the one chosen for a sweep.
pub(super) trait WithRowEval<V: Vector> {
    /// Runs with `eval`.
    fn call<E: RowEval<V>>(self, eval: &E);
}

/// Calls `w` with the fused row evaluation for `plan`, the kernel of `ctx` and the
/// continuity sum when `drho`: one monomorphic block loop per (kernel, plan, continuity), so
/// that nothing is dispatched per row.
pub(super) fn with_fused_rows<V: Vector, W: WithRowEval<V>>(
    ctx: &SweepCtx<'_, V>,
    (plan, eos): (FusedPlan, EosColumns<'_>),
    drho: bool,
    w: W,
) {
    macro_rules! go {
        ($kind:expr, $p:literal, $av:literal, $first:literal, $coefs:expr) => {{
            const KIND: usize = $kind as usize;
            let (ctx, av) = (*ctx, $coefs);
            if drho {
                w.call(&FusedRows::<V, KIND, $p, $av, $first, true> { ctx, eos, av })
            } else {
                w.call(&FusedRows::<V, KIND, $p, $av, $first, false> { ctx, eos, av })
            }
        }};
    }
    macro_rules! with_kind {
        ($kind:expr) => {{
            match plan {
                FusedPlan::Pressure => go!($kind, true, false, false, NO_AV),
                FusedPlan::Viscosity(av) => go!($kind, false, true, false, av),
                FusedPlan::PressureThenViscosity(av) => go!($kind, true, true, false, av),
                FusedPlan::ViscosityThenPressure(av) => go!($kind, true, true, true, av),
            }
        }};
    }
    with_kernel_kind!(ctx.kernel.kind, K => with_kind!(K))
}

/// The fused row evaluation: kernel `KernelKind::ALL[KIND]`, `P` adds the pressure force,
/// `AV` the artificial viscosity `av`, in the order of the scene (`AV_FIRST`); the continuity
/// sum is formed when `DRHO`.
pub(super) struct FusedRows<
    'a,
    V: Vector,
    const KIND: usize,
    const P: bool,
    const AV: bool,
    const AV_FIRST: bool,
    const DRHO: bool,
> {
    ctx: SweepCtx<'a, V>,
    eos: EosColumns<'a>,
    av: (Real, Real, Real),
}

impl<
    V: Vector,
    const KIND: usize,
    const P: bool,
    const AV: bool,
    const AV_FIRST: bool,
    const DRHO: bool,
> RowEval<V> for FusedRows<'_, V, KIND, P, AV, AV_FIRST, DRHO>
{
    #[inline(always)]
    fn row(
        &self,
        i: usize,
        s: &mut RowScratch<V>,
        reactions: &mut [Reaction<V>],
        drho: Option<&mut Real>,
    ) -> (V, Real) {
        let (k, n) = compact_row_into(&self.ctx, i, s, reactions);
        let (_, g_norm, inv_h) = k.factor_parts();
        let kernel = (KernelKind::ALL[KIND], g_norm, inv_h);
        let pairs = Pairs { i, n, s: &*s };
        let (f, p, rate) = fused_pairs::<V, P, AV, AV_FIRST, DRHO>(
            (&self.ctx, self.eos),
            pairs,
            kernel,
            self.av,
            reactions,
        );
        if let Some(d) = drho {
            *d = rate;
        }
        (f, p)
    }
}

/// Unused artificial-viscosity coefficients (plans without it).
const NO_AV: (Real, Real, Real) = (0.0, 0.0, 0.0);

/// Owner i's compacted pairs `0..n` in the scratch.
#[derive(Clone, Copy)]
struct Pairs<'a, V: Vector> {
    i: usize,
    n: usize,
    s: &'a RowScratch<V>,
}

/// The owner's values the pair formulas use.
#[derive(Clone, Copy)]
struct Owner<V: Vector> {
    v: V,
    m: Real,
    /// `(h_i, c_i, ρ_i)` for the artificial viscosity.
    av: AvSide,
    /// `m_i p_i / ρ_i²`.
    p_coef: Real,
}

/// What one lane group of pairs gives: the force on i, the powers of i and j, and
/// `m_j v_ij·∇_iW_ij` (the continuity term), per lane.
struct LaneOut<T: Lanes> {
    force: LaneVec<T>,
    power_i: T,
    power_j: T,
    rate: T,
}

/// The fused loop over owner i's pairs, two pairs at a time in the lanes of an `f64x2` (and an
/// odd last pair alone): `P` adds the pressure force, `AV` the artificial viscosity `av`, in
/// the order of the scene (`AV_FIRST`); the continuity sum is formed when `DRHO`. i's sums are
/// formed pair by pair in row order, as the one-pair loop would. Returns i's force, power and
/// `Σ m_j v_ij·∇_iW_ij`, and writes the reactions.
#[inline(always)]
fn fused_pairs<V: Vector, const P: bool, const AV: bool, const AV_FIRST: bool, const DRHO: bool>(
    (ctx, eos): (&SweepCtx<'_, V>, EosColumns<'_>),
    Pairs { i, n, s }: Pairs<'_, V>,
    kernel: (KernelKind, Real, Real),
    av: (Real, Real, Real),
    reactions: &mut [Reaction<V>],
) -> (V, Real, Real) {
    let d = &ctx.data;
    let rho_i = d.rho[i].0;
    let owner = Owner {
        v: d.vel[i].0,
        m: d.mass[i].0,
        av: (d.h[i].0, eos.sound[i].0, rho_i),
        p_coef: d.mass[i].0 * eos.pressure[i].0 / (rho_i * rho_i),
    };
    let (js, slots, rijs, r2s) = s.compacted(n);
    let np = d.len();
    let row = RowPairs {
        owner,
        kernel,
        av,
        side: Side {
            vel: &d.vel[..np],
            mass: &d.mass[..np],
            rho: &d.rho[..np],
            h: &d.h[..np],
            sound: &eos.sound[..np],
        },
    };
    let mut sums = (V::zero(), 0.0, 0.0);
    let (js2, js1) = js.as_chunks::<2>();
    let (slots2, slots1) = slots.as_chunks::<2>();
    let (rijs2, rijs1) = rijs.as_chunks::<2>();
    let (r2s2, r2s1) = r2s.as_chunks::<2>();
    let two = js2.iter().zip(slots2).zip(rijs2).zip(r2s2);
    for (((js, slots), rijs), r2s) in two {
        let out = pair_lanes::<V, f64x2, P, AV, AV_FIRST>(row, js, rijs, r2s);
        add_lanes::<V, DRHO>(&mut sums, reactions, out, slots);
    }
    if let (Some(j), Some(slot), Some(rij), Some(r2)) =
        (js1.first(), slots1.first(), rijs1.first(), r2s1.first())
    {
        let out = pair_lanes::<V, Real, P, AV, AV_FIRST>(row, &[*j], &[*rij], &[*r2]).widen();
        add_lanes::<V, DRHO>(&mut sums, reactions, out, &[*slot]);
    }
    sums
}

/// Adds the lanes' pairs (their support `slots`, one per lane used) to i's sums
/// `(force, power, Σ m_j v_ij·∇_iW_ij)`, lane by lane, and writes their reactions.
#[inline(always)]
fn add_lanes<V: Vector, const DRHO: bool>(
    (f_own, p_own, rate): &mut (V, Real, Real),
    reactions: &mut [Reaction<V>],
    out: LaneOut<f64x2>,
    slots: &[u32],
) {
    for (l, &slot) in slots.iter().enumerate() {
        let force: V = out.force.lane(l);
        *f_own += force;
        *p_own += out.power_i.lane(l);
        if DRHO {
            *rate += out.rate.lane(l);
        }
        reactions[slot as usize] = Reaction {
            force,
            power: out.power_j.lane(l),
        };
    }
}

/// What the pair formulas of one owner row read: the owner, the kernel `(kind, C_d h_i^{-d-1},
/// 1/h_i)`, the viscosity's `(α, β, η_f)` and the neighbours' values.
#[derive(Clone, Copy)]
struct RowPairs<'a, V: Vector> {
    owner: Owner<V>,
    kernel: (KernelKind, Real, Real),
    av: (Real, Real, Real),
    side: Side<'a, V>,
}

/// The neighbour's values the pair formulas read, every array of the same length (so that
/// one bounds check of j covers them all).
#[derive(Clone, Copy)]
struct Side<'a, V: Vector> {
    vel: &'a [Velocity<V>],
    mass: &'a [Mass],
    rho: &'a [Density],
    h: &'a [SmoothingLength],
    sound: &'a [SoundSpeed],
}

impl<T: Lanes> LaneOut<T> {
    /// The same values as two lanes (the one-pair tail shares [`fused_pairs`]'s accumulation).
    #[inline(always)]
    fn widen(self) -> LaneOut<f64x2> {
        let w = |x: T| f64x2::from_fn(|l| x.lane(l.min(T::N - 1)));
        LaneOut {
            force: LaneVec([w(self.force.0[0]), w(self.force.0[1]), w(self.force.0[2])]),
            power_i: w(self.power_i),
            power_j: w(self.power_j),
            rate: w(self.rate),
        }
    }
}

/// The pair formulas for the `T::N` pairs `js` (with their `r_ij` and `|r_ij|²`), lane by
/// lane the operations of the pressure term's and the viscosity term's own `interact`.
#[inline(always)]
fn pair_lanes<V: Vector, T: Lanes, const P: bool, const AV: bool, const AV_FIRST: bool>(
    row: RowPairs<'_, V>,
    js: &[u32],
    rijs: &[V],
    r2s: &[Real],
) -> LaneOut<T> {
    let RowPairs {
        owner: o,
        kernel: (kind, g_norm, inv_h),
        av,
        side:
            Side {
                vel,
                mass,
                rho,
                h,
                sound,
            },
    } = row;
    // the lanes' particles, each checked once against the arrays' common length
    let jl = [js[0] as usize, js[T::N - 1] as usize];
    let j = |l: usize| jl[l];
    let c = T::splat;
    let rij = LaneVec::<T>::from_fn(|l| rijs[l]);
    let r = T::from_fn(|l| r2s[l]).sqrt();
    let raw = rij.scale::<V>(OwnerKernel::factor_lanes(kind, g_norm, inv_h, r));
    let vij = LaneVec::<T>::splat(o.v).minus::<V>(LaneVec::from_fn(|l| vel[j(l)].0));
    let vg = vij.dot::<V>(raw);
    let m_j = T::from_fn(|l| mass[j(l)].0);
    let mut out = LaneOut {
        force: LaneVec([c(0.0); 3]),
        power_i: c(0.0),
        power_j: c(0.0),
        rate: m_j * vg,
    };
    let pair = PairLanes { raw, vg, m_j };
    if AV {
        let side_j = (
            T::from_fn(|l| h[j(l)].0),
            T::from_fn(|l| sound[j(l)].0),
            T::from_fn(|l| rho[j(l)].0),
        );
        let (num, den) = av_parts_lanes(av, splat3(o.av), side_j, vij.dot::<V>(rij), r);
        let coef = c(o.m) * m_j * num / den;
        if AV_FIRST {
            add_viscosity::<V, T>(&mut out, &pair, coef);
        }
        if P {
            add_pressure::<V, T>(&mut out, &pair, o.p_coef);
        }
        if !AV_FIRST {
            add_viscosity::<V, T>(&mut out, &pair, coef);
        }
    } else if P {
        add_pressure::<V, T>(&mut out, &pair, o.p_coef);
    }
    out
}

/// Per-lane values both terms use: `∇_iW_ij`, `v_ij·∇_iW_ij`, `m_j`.
struct PairLanes<T: Lanes> {
    raw: LaneVec<T>,
    vg: T,
    m_j: T,
}

/// `(x, y, z)` in every lane.
#[inline(always)]
fn splat3<T: Lanes>((x, y, z): (Real, Real, Real)) -> (T, T, T) {
    (T::splat(x), T::splat(y), T::splat(z))
}

/// The viscosity's force `−coef ∇_iW_ij` and its heat `coef v_ij·∇_iW_ij / 2` to each of i
/// and j, with `coef = m_i m_j Π_ij / 2` (Eq. 4.17).
#[inline(always)]
fn add_viscosity<V: Vector, T: Lanes>(out: &mut LaneOut<T>, p: &PairLanes<T>, coef: T) {
    out.force = out.force.plus::<V>(p.raw.scale::<V>(-coef));
    let heat = T::splat(0.5) * coef * p.vg;
    out.power_i = out.power_i + heat;
    out.power_j = out.power_j + heat;
}

/// The pressure force `−(m_i p_i/ρ_i²) m_j ∇_iW_ij` and its power to i (Eq. 4.19).
#[inline(always)]
fn add_pressure<V: Vector, T: Lanes>(out: &mut LaneOut<T>, p: &PairLanes<T>, p_coef: Real) {
    let coef = T::splat(p_coef) * p.m_j;
    out.force = out.force.plus::<V>(p.raw.scale::<V>(-coef));
    out.power_i = out.power_i + coef * p.vg;
}
