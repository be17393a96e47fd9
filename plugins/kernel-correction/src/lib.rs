//! `KernelCorrection()`: kernel-gradient correction `∇̃_iW_ij = L_i ∇_iW_ij` (Eq. 2.10), applied
//! by the pair sweep to every term's `grad`. With the correction the pressure and stress terms
//! use `1/(ρ_iρ_j)` so that angular momentum is conserved exactly (§5.2).
//!
//! Also the velocity gradient of Eq. 7.4 ([`ensure_velocity_gradient`]), which the viscous
//! stress and the divergence form of the continuity equation read. Both are one-sided pair
//! terms, each in a sweep of its own at its own place of the step. (Equation numbers refer to
//! Ren, Dai, Zhuang & Rabczuk, Dual-support Smoothed Particle Hydrodynamics, RenDSSPH in
//! `docs/references.md`.)
#![warn(missing_docs)]

use dualsph_core::bevy_ecs::prelude::Resource;
use dualsph_core::columns::take_matrix;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// Kernel-gradient correction.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KernelCorrection {}

impl SimPlugin for KernelCorrection {
    const NAME: &'static str = "KernelCorrection";
    const SUMMARY: &'static str = "kernel-gradient correction L_i (Eq. 2.10)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        ensure_kernel_correction(sim)
    }
}

/// The correction matrix as a one-sided pair term, Eq. 2.10:
/// `L_i = [Σ_{j∈H_i} V_j ∇_iW_ij ⊗ (r_j − r_i)]^{-1}`, the identity where the sum is singular
/// (too few neighbours).
#[derive(Debug, Clone, Copy)]
pub struct CorrectionTerm;

/// [`CorrectionTerm`] bound for a sweep.
#[derive(Debug, Clone, Copy)]
pub struct BoundCorrection {
    sum: Acc,
}

/// The sum's inverse, or the identity where it is singular.
fn invert<V: Vector>(l: &mut GradientCorrection<V>, s: &[Real], _m: Real) {
    let a = take_matrix::<V>(s);
    l.0 = a.try_inverse(1e-6).unwrap_or_else(V::Mat::identity);
}

impl<V: Vector> PairTerm<V> for CorrectionTerm {
    type Bound<'w> = BoundCorrection;

    fn name(&self) -> &str {
        "kernel_correction (Eq. 2.10)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundCorrection, String> {
        Ok(BoundCorrection {
            sum: b.accumulate::<GradientCorrection<V>>(
                Reaction::OneSided,
                V::DIM * V::DIM,
                invert::<V>,
            )?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundCorrection {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (g, rij, d) = (p.grad_raw(), p.rij(), p.data());
        out.add_mat::<V>(self.sum, |l| {
            V::outer(g.lane::<V>(l), -rij.lane::<V>(l)) * d.volume(p.j(l))
        });
    }
}

/// Present once the correction's column and sweep are added.
#[derive(Resource, Default)]
struct CorrectionSweep;

/// Present once the velocity gradient's column and sweep are added.
#[derive(Resource, Default)]
struct VelocityGradientSweep;

/// Adds the kernel-gradient correction once: the `GradientCorrection` column and its sweep
/// (`kernel_correction`, in [`StepSet::Correction`]).
pub fn ensure_kernel_correction<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if sim.enable::<CorrectionSweep>() {
        let spec = ColumnSpec::restart_only("gradient_correction");
        sim.add_column(spec, |_| GradientCorrection::<V>(V::Mat::identity()))?;
        sim.add_pair_term_to("kernel_correction", StepSet::Correction, CorrectionTerm)?;
    }
    Ok(())
}

/// The velocity gradient as a one-sided pair term, Eq. 7.4:
/// `(∇⊗v)_i = −Σ_{j∈H_i} V_j v_ij ⊗ ∇̃_iW_ij`, entries `∂v_k/∂x_l` (exact for linear fields
/// when the correction is active).
#[derive(Debug, Clone, Copy)]
pub struct VelocityGradientTerm;

/// [`VelocityGradientTerm`] bound for a sweep.
#[derive(Debug, Clone, Copy)]
pub struct BoundVelocityGradient {
    sum: Acc,
}

impl<V: Vector> PairTerm<V> for VelocityGradientTerm {
    type Bound<'w> = BoundVelocityGradient;

    fn name(&self) -> &str {
        "velocity_gradient (Eq. 7.4)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundVelocityGradient, String> {
        Ok(BoundVelocityGradient {
            sum: b.accumulate_column::<VelocityGradient<V>>(Reaction::OneSided)?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundVelocityGradient {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (vij, g, d) = (p.vij(), p.grad(), p.data());
        out.add_mat::<V>(self.sum, |l| {
            V::outer(vij.lane::<V>(l), g.lane::<V>(l)) * (-d.volume(p.j(l)))
        });
    }
}

/// Adds the velocity gradient once: the `VelocityGradient` column and its sweep
/// (`velocity_gradient`, in [`StepSet::Gradients`]).
pub fn ensure_velocity_gradient<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if sim.enable::<VelocityGradientSweep>() {
        let spec = ColumnSpec::restart_only("velocity_gradient");
        sim.add_column(spec, |_| VelocityGradient::<V>(V::Mat::zero()))?;
        sim.add_pair_term_to(
            "velocity_gradient",
            StepSet::Gradients,
            VelocityGradientTerm,
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        dualsph_fluid::checks::check_lanes_2d(&CorrectionTerm).unwrap();
        dualsph_fluid::checks::check_lanes_2d(&VelocityGradientTerm).unwrap();
    }
}
