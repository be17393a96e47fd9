//! The fluid's particle columns: what an equation of state, the energy and continuity
//! equations, heat conduction, the grad-h formulation and viscous stress add to the core set
//! (`dualsph_core::components`) when a scene asks for them.

use bevy_ecs::prelude::Component;
use bytemuck::TransparentWrapper;
use dualsph_core::columns::{ColumnValue, Shape};
use dualsph_core::math::{Real, Vector};
use dualsph_integrate::{ScalarRate, ScalarState};

/// Pressure `p_i` (added by an equation of state).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Pressure(pub Real);

/// Sound speed `c_i` (added by an equation of state).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SoundSpeed(pub Real);

/// Specific internal energy `ε_i` (added when an energy equation is solved).
#[derive(Component, Clone, Copy, Debug, PartialEq, TransparentWrapper)]
#[repr(transparent)]
pub struct InternalEnergy(pub Real);

/// `dε_i/dt` (added with the energy equation; integrated into [`InternalEnergy`]).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, TransparentWrapper)]
#[repr(transparent)]
pub struct EnergyRate {
    /// `dε/dt` from the last evaluation.
    pub rate: Real,
}

/// Specific dissipated energy `d_i = ∫ ḋ_i dt`: the heat the dissipative pair terms (the
/// artificial viscosity) have put into particle i's internal energy since the start, per unit
/// mass (added with [`crate::ensure_dissipation`]). It is part of [`InternalEnergy`], not
/// added to it: `Σ m_i d_i` is the dissipated energy of the run and `Σ m_i (ε_i − d_i)` the
/// rest of the internal energy (the reversible compression work).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, TransparentWrapper)]
#[repr(transparent)]
pub struct Dissipated(pub Real);

/// `ḋ_i`: the heating rate per unit mass of the dissipative pair terms, a part of
/// [`EnergyRate`] (integrated into [`Dissipated`]).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, TransparentWrapper)]
#[repr(transparent)]
pub struct DissipationRate {
    /// `dd/dt` from the last evaluation.
    pub rate: Real,
}

/// `dρ_i/dt` (added by the continuity equation; integrated into the density).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, TransparentWrapper)]
#[repr(transparent)]
pub struct DensityRate {
    /// `dρ/dt` from the last evaluation.
    pub rate: Real,
}

/// Thermal conductivity `κ_i` (added by heat conduction).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Conductivity(pub Real);

/// The grad-h factor `Ω_i = 1 − (∂h_i/∂ρ_i) Σ_j m_j ∂W(r_ij, h_i)/∂h_i` (Springel & Hernquist
/// 2002; Price 2012: SpringelHernquist2002 and Price2012 in docs/references.md), added with
/// the grad-h formulation; the pressure and viscous forces divide the owner's factor by it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct GradHFactor(pub Real);

/// Velocity gradient `∇⊗v_i` with entries `∂v_k/∂x_l` (Eq. 7.4), added by viscous stress.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct VelocityGradient<V: Vector>(pub V::Mat);

dualsph_core::scalar_column!(
    Pressure,
    SoundSpeed,
    InternalEnergy,
    Dissipated,
    Conductivity,
    GradHFactor
);
dualsph_core::matrix_column!(VelocityGradient);

macro_rules! rate_column {
    ($($t:ident),*) => {$(
        impl<V: Vector> ColumnValue<V> for $t {
            const SHAPE: Shape = Shape::Scalar;
            fn put(&self, out: &mut Vec<Real>) {
                out.push(self.rate);
            }
            fn take(&mut self, values: &[Real]) {
                self.rate = values[0];
            }
        }
    )*};
}
rate_column!(EnergyRate, DensityRate, DissipationRate);

impl ScalarState for InternalEnergy {}
impl ScalarState for Dissipated {}
impl ScalarRate for DensityRate {}
impl ScalarRate for EnergyRate {}
impl ScalarRate for DissipationRate {}
