//! Particle components. Every particle is a `bevy_ecs` entity with the core set
//! ([`ParticleId`], [`Position`], [`Velocity`], [`Mass`], [`Density`], [`SmoothingLength`],
//! [`Acceleration`]); plugins add the rest only when a scene asks for them.

use crate::math::{Real, Vector};
use bevy_ecs::prelude::Component;
use bytemuck::TransparentWrapper;

/// Stable particle index `0..n`; also the row of the particle in every dense array.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ParticleId(pub u32);

/// Position `r_i`.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Position<V: Vector>(pub V);

/// Velocity `v_i`.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Velocity<V: Vector>(pub V);

/// Mass `m_i` (constant: mass is conserved exactly by construction).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Mass(pub Real);

/// Density `ρ_i`.
#[derive(Component, Clone, Copy, Debug, PartialEq, TransparentWrapper)]
#[repr(transparent)]
pub struct Density(pub Real);

/// Support radius `h_i` (paper notation: `H_i = { j : |r_ij| <= h_i }`).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SmoothingLength(pub Real);

/// Acceleration `dv_i/dt = f_i / m_i` from the last force evaluation.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Acceleration<V: Vector>(pub V);

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
/// mass (added with [`crate::integrate::ensure_dissipation`]). It is part of
/// [`InternalEnergy`], not added to it: `Σ m_i d_i` is the dissipated energy of the run and
/// `Σ m_i (ε_i − d_i)` the rest of the internal energy (the reversible compression work).
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

/// `dρ_i/dt` (added by the continuity equation; integrated into [`Density`]).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, TransparentWrapper)]
#[repr(transparent)]
pub struct DensityRate {
    /// `dρ/dt` from the last evaluation.
    pub rate: Real,
}

/// Thermal conductivity `κ_i` (added by heat conduction).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Conductivity(pub Real);

/// Kernel-gradient correction matrix `L_i` (Eq. 2.10), added by the correction plugin.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct GradientCorrection<V: Vector>(pub V::Mat);

/// The grad-h factor `Ω_i = 1 − (∂h_i/∂ρ_i) Σ_j m_j ∂W(r_ij, h_i)/∂h_i` (Springel & Hernquist
/// 2002; Price 2012: SpringelHernquist2002 and Price2012 in docs/references.md), added with the grad-h formulation; the pressure and
/// viscous forces divide the owner's factor by it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct GradHFactor(pub Real);

/// Velocity gradient `∇⊗v_i` with entries `∂v_k/∂x_l` (Eq. 7.4), added by viscous stress.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct VelocityGradient<V: Vector>(pub V::Mat);
