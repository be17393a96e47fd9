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
use crate::kernels::with_kernel_kind;
use crate::math::{Real, Vector};
use crate::pair::{OwnerKernel, PairOut, PairTerm};
use std::sync::Arc;

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
    (alpha, beta, eta_factor): (Real, Real, Real),
    (h_i, c_i, rho_i): AvSide,
    (h_j, c_j, rho_j): AvSide,
    vr: Real,
    r: Real,
) -> (Real, Real) {
    let hbar = 0.5 * (h_i + h_j);
    let eta = eta_factor * hbar;
    let d = r * r + eta * eta;
    let x = hbar * vr.min(0.0);
    let cbar = 0.5 * (c_i + c_j);
    (x * (beta * x - alpha * cbar * d), d * d * (rho_i + rho_j))
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

/// The fused plan for `terms` when they are one of the shapes of [`FusedPlan`] and the fused
/// loop applies (no kernel correction; pressure and sound speed of every particle from an
/// equation of state); else `None`.
pub(super) fn fused_plan<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn PairTerm<V>>],
) -> Option<FusedPlan> {
    let fl = ctx.fields;
    let n = fl.len();
    if !fl.correction.is_empty() || fl.pressure.len() != n || fl.sound.len() != n {
        return None;
    }
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
    match b?.as_slice() {
        [P] => Some(FusedPlan::Pressure),
        [v] => av(v).map(FusedPlan::Viscosity),
        [P, v] => av(v).map(FusedPlan::PressureThenViscosity),
        [v, P] => av(v).map(FusedPlan::ViscosityThenPressure),
        _ => None,
    }
}

/// Pass 1 for owner i with the fused loop: the same contract as [`super::row::owner_row`].
#[inline]
pub(super) fn fused_owner_row<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    plan: FusedPlan,
    i: usize,
    s: &mut RowScratch<V>,
    reactions: &mut [Reaction<V>],
    drho: Option<&mut Real>,
) -> (V, Real) {
    let (k, n) = compact_row_into(ctx, i, s, reactions);
    let (kind, g_norm, inv_h) = k.factor_parts();
    let pairs = Pairs { i, n, s: &*s };
    let with_drho = drho.is_some();
    macro_rules! go {
        ($factor:expr, $p:literal, $av:literal, $first:literal, $coefs:expr) => {
            if with_drho {
                fused_pairs::<V, $p, $av, $first, true>(ctx, pairs, $factor, $coefs, reactions)
            } else {
                fused_pairs::<V, $p, $av, $first, false>(ctx, pairs, $factor, $coefs, reactions)
            }
        };
    }
    macro_rules! with_kind {
        ($kind:expr) => {{
            let f = |r| OwnerKernel::factor_of($kind, g_norm, inv_h, r);
            match plan {
                FusedPlan::Pressure => go!(f, true, false, false, NO_AV),
                FusedPlan::Viscosity(av) => go!(f, false, true, false, av),
                FusedPlan::PressureThenViscosity(av) => go!(f, true, true, false, av),
                FusedPlan::ViscosityThenPressure(av) => go!(f, true, true, true, av),
            }
        }};
    }
    let (f, p, rate) = with_kernel_kind!(kind, K => with_kind!(K));
    if let Some(d) = drho {
        *d = rate;
    }
    (f, p)
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

/// The fused loop over owner i's pairs (`factor(r)` is [`OwnerKernel::grad_factor`] with the
/// kind resolved): `P` adds the pressure force, `AV` the artificial viscosity `av`, in the
/// order of the scene (`AV_FIRST`); the continuity sum is formed when `DRHO`. Returns i's
/// force, power and `Σ m_j v_ij·∇_iW_ij`, and writes the reactions.
#[inline(always)]
fn fused_pairs<V: Vector, const P: bool, const AV: bool, const AV_FIRST: bool, const DRHO: bool>(
    ctx: &SweepCtx<'_, V>,
    Pairs { i, n, s }: Pairs<'_, V>,
    factor: impl Fn(Real) -> Real,
    av: (Real, Real, Real),
    reactions: &mut [Reaction<V>],
) -> (V, Real, Real) {
    let fl = ctx.fields;
    let np = fl.pos.len();
    let (vel, mass, rho, h, sound) = (
        &fl.vel[..np],
        &fl.mass[..np],
        &fl.rho[..np],
        &fl.h[..np],
        &fl.sound[..np],
    );
    let (vi, m_i, rho_i) = (vel[i], mass[i], rho[i]);
    let av_i = (h[i], sound[i], rho_i);
    let p_owner = m_i * fl.pressure[i] / (rho_i * rho_i);
    let (mut f_own, mut p_own, mut rate) = (V::zero(), 0.0, 0.0);
    let (js, slots, rijs, r2s) = s.compacted(n);
    for k in 0..n {
        let j = js[k] as usize;
        let rij = rijs[k];
        let r = r2s[k].sqrt();
        let raw = rij * factor(r);
        let vij = vi - vel[j];
        let vg = vij.dot(raw);
        let m_j = mass[j];
        if DRHO {
            rate += m_j * vg;
        }
        let mut o = PairOut::<V>::default();
        let viscosity = |o: &mut PairOut<V>| {
            let av_j = (h[j], sound[j], rho[j]);
            let (num, den) = artificial_viscosity_parts(av, av_i, av_j, vij.dot(rij), r);
            let coef = m_i * m_j * num / den;
            o.force += raw * (-coef);
            let heat = 0.5 * coef * vg;
            o.power_i += heat;
            o.power_j += heat;
        };
        if AV && AV_FIRST {
            viscosity(&mut o);
        }
        if P {
            let coef = p_owner * m_j;
            o.force += raw * (-coef);
            o.power_i += coef * vg;
        }
        if AV && !AV_FIRST {
            viscosity(&mut o);
        }
        f_own += o.force;
        p_own += o.power_i;
        reactions[slots[k] as usize] = Reaction {
            force: o.force,
            power: o.power_j,
        };
    }
    (f_own, p_own, rate)
}
