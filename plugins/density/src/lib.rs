//! Density plugins: `SummationDensity()` (Eq. 4.8) and
//! `ContinuityDensity(form: Pairwise | VelocityDivergence)` (Eq. 4.9, or `−ρ ∇·v` with the
//! velocity gradient of Eq. 7.4 as in the paper's water drop, §7.3), and
//! `DensityDiffusion(delta)` (δ-SPH, Molteni & Colagrossi 2009; see [`diffusion`]).
#![warn(missing_docs)]

pub mod diffusion;
pub use diffusion::DensityDiffusion;

use dualsph_core::passes;
use dualsph_core::prelude::*;
use serde::Deserialize;

/// `ρ_i = Σ_{j ∈ H_i ∪ {i}} m_j W(r_ij, h_i)` every step.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SummationDensity {}

impl SimPlugin for SummationDensity {
    const NAME: &'static str = "SummationDensity";
    const SUMMARY: &'static str = "density by kernel summation over the own support (Eq. 4.8)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if sim.has_feature("density_integration") {
            return Err(SimError::Build(
                "SummationDensity and ContinuityDensity cannot both set the density".into(),
            ));
        }
        passes::ensure_summation_density(sim)?;
        Ok(())
    }
}

/// Which discrete form of `dρ/dt = −ρ ∇·v`.
#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
pub enum ContinuityForm {
    /// `dρ_i/dt = Σ_j m_j v_ij · ∇_iW_ij` (Eq. 4.9).
    #[default]
    Pairwise,
    /// `dρ_i/dt = −ρ_i tr(∇⊗v)_i` with Eq. 7.4.
    VelocityDivergence,
}

/// Integrated density.
#[derive(Debug, Clone, Deserialize)]
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
        if sim.has_feature("summation_density") {
            return Err(SimError::Build(
                "SummationDensity and ContinuityDensity cannot both set the density".into(),
            ));
        }
        dualsph_core::integrator::ensure_density_integration(sim)?;
        match self.form {
            ContinuityForm::Pairwise => passes::add_continuity_pairwise(sim),
            ContinuityForm::VelocityDivergence => {
                passes::ensure_velocity_gradient(sim)?;
                sim.add_system(
                    StepSet::Forces,
                    "continuity (-rho div v)",
                    passes::continuity_divergence::<V>,
                );
            }
        }
        Ok(())
    }
}
