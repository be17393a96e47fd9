//! Density plugins: `SummationDensity()` (Eq. 4.8) and
//! `ContinuityDensity(form: Pairwise | VelocityDivergence)` (Eq. 4.9, or `−ρ ∇·v` with the
//! velocity gradient of Eq. 7.4 as in the paper's water drop, §7.3), and
//! `DensityDiffusion(delta)` (δ-SPH, Molteni & Colagrossi 2009; see [`diffusion`]). Every
//! formula is a pair term (equation numbers: Ren, Dai, Zhuang & Rabczuk, Dual-support Smoothed
//! Particle Hydrodynamics, RenDSSPH in `docs/references.md`).
#![warn(missing_docs)]

pub mod diffusion;
pub use diffusion::DensityDiffusion;

use dualsph_fluid::DensityIntegration;
use dualsph_fluid::DensitySummation;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// `ρ_i = Σ_{j ∈ H_i ∪ {i}} m_j W(r_ij, h_i)` every step.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SummationDensity {}

impl SimPlugin for SummationDensity {
    const NAME: &'static str = "SummationDensity";
    const SUMMARY: &'static str = "density by kernel summation over the own support (Eq. 4.8)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if sim.has::<DensityIntegration>() {
            return Err(SimError::Build(
                "SummationDensity and ContinuityDensity cannot both set the density".into(),
            ));
        }
        // with grad-h the density is summed by the h solve, at the h it solves for (the
        // smoothing-length plugin's `grad_h`)
        let grad_h = *sim.world.resource::<Formulation>() == Formulation::GradH;
        if sim.enable::<DensitySummation>() && !grad_h {
            sim.add_pair_term_to("summation_density", StepSet::Density, SummationTerm)?;
        }
        Ok(())
    }
}

/// Summation density as a one-sided pair term, Eq. 4.8:
/// `ρ_i = m_i W(0, h_i) + Σ_{j∈H_i} m_j W_ij` (the self term as the term's initial value).
#[derive(Debug, Clone, Copy)]
pub struct SummationTerm;

/// [`SummationTerm`] bound for a sweep.
#[derive(Clone, Copy, Debug)]
pub struct BoundSummation<'w, V: Vector> {
    data: ParticleData<'w, V>,
    kernel: &'w Kernel,
    rho: Acc,
}

impl<V: Vector> PairTerm<V> for SummationTerm {
    type Bound<'w> = BoundSummation<'w, V>;

    fn name(&self) -> &str {
        "summation_density (Eq. 4.8)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundSummation<'w, V>, String> {
        Ok(BoundSummation {
            data: b.data(),
            kernel: b.kernel(),
            rho: b.accumulate::<Density>(
                Reaction::OneSided,
                1,
                |rho: &mut Density, s: &[Real], _| rho.0 = s[0],
            )?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundSummation<'_, V> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        out.add(self.rho, p.m_j() * p.w());
    }

    const INITIALIZES: bool = true;

    fn initialize(&self, i: usize, sums: &mut OwnerSums<'_>) {
        let d = &self.data;
        sums.add(self.rho, d.mass[i].0 * self.kernel.w(0.0, d.h[i].0));
    }
}

/// Which discrete form of `dρ/dt = −ρ ∇·v`.
#[derive(
    Debug, Clone, Copy, Default, Deserialize, Serialize, PartialEq, Eq, schemars::JsonSchema,
)]
pub enum ContinuityForm {
    /// `dρ_i/dt = Σ_j m_j v_ij · ∇_iW_ij` (Eq. 4.9).
    #[default]
    Pairwise,
    /// `dρ_i/dt = −ρ_i tr(∇⊗v)_i` with Eq. 7.4.
    VelocityDivergence,
}

/// Integrated density.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContinuityDensity {
    /// Discrete form (default `Pairwise`).
    #[serde(default)]
    pub form: ContinuityForm,
}

impl SimPlugin for ContinuityDensity {
    const NAME: &'static str = "ContinuityDensity";
    const SUMMARY: &'static str = "density from the continuity equation (Eq. 4.9 or -rho div v)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if sim.has::<DensitySummation>() {
            return Err(SimError::Build(
                "SummationDensity and ContinuityDensity cannot both set the density".into(),
            ));
        }
        dualsph_fluid::ensure_density_integration(sim)?;
        match self.form {
            ContinuityForm::Pairwise => sim.add_pair_term(ContinuityTerm),
            ContinuityForm::VelocityDivergence => {
                dualsph_kernel_correction::ensure_velocity_gradient(sim)?;
                sim.add_pair_term(DivergenceTerm);
            }
        }
        Ok(())
    }
}

/// The continuity equation as a one-sided term of the force sweep, Eq. 4.9:
/// `dρ_i/dt = Σ_{j∈H_i} m_j v_ij · ∇_iW_ij`.
#[derive(Debug, Clone, Copy)]
pub struct ContinuityTerm;

impl<V: Vector> PairTerm<V> for ContinuityTerm {
    type Bound<'w> = ContinuityTerm;

    fn name(&self) -> &str {
        "continuity (Eq. 4.9)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<ContinuityTerm, String> {
        b.density_rate(Reaction::OneSided)?;
        Ok(*self)
    }
}

impl<V: Vector> BoundTerm<V> for ContinuityTerm {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        out.add_density_rate(p.m_j() * p.vij().dot::<V>(p.grad_raw()));
    }
}

/// The continuity equation from the velocity divergence (§7.3), a per-particle term of the
/// force sweep: `dρ_i/dt = −ρ_i tr(∇⊗v)_i` with the velocity gradient of Eq. 7.4.
#[derive(Debug, Clone, Copy)]
pub struct DivergenceTerm;

/// [`DivergenceTerm`] bound for a sweep.
#[derive(Clone, Copy, Debug)]
pub struct BoundDivergence<'w, V: Vector> {
    rho: &'w [Density],
    grad: &'w [VelocityGradient<V>],
}

impl<V: Vector> PairTerm<V> for DivergenceTerm {
    type Bound<'w> = BoundDivergence<'w, V>;

    fn name(&self) -> &str {
        "continuity (-rho div v)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundDivergence<'w, V>, String> {
        b.density_rate(Reaction::OneSided)?;
        Ok(BoundDivergence {
            rho: b.data().rho,
            grad: b.require()?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundDivergence<'_, V> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), _: &PairLanes<'_, T, V>, _: &mut Out<'_, T>) {}

    const INITIALIZES: bool = true;

    fn initialize(&self, i: usize, sums: &mut OwnerSums<'_>) {
        sums.add_density_rate(-self.rho[i].0 * self.grad[i].0.trace());
    }

    fn has_pairs(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        use dualsph_fluid::checks::check_lanes_2d;
        check_lanes_2d(&SummationTerm).unwrap();
        check_lanes_2d(&ContinuityTerm).unwrap();
        check_lanes_2d(&DivergenceTerm).unwrap();
    }
}
