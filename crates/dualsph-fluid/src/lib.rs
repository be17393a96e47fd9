//! The shared vocabulary of the fluid plugins, so that a user's own plugin (an equation of
//! state of its own, say) takes part without any edit elsewhere:
//!
//! - the fluid's particle columns ([`components`]: pressure, sound speed, internal energy,
//!   the rates, …);
//! - the energy and continuity equations as integrated scalars ([`ensure_energy_equation`],
//!   [`ensure_dissipation`], [`ensure_density_integration`]);
//! - each body's equation of state as other plugins see it ([`BodyEos`], [`EosLaw`]);
//! - the fluid's pair sums by name ([`FluidSums`], [`FluidOut`]: the power and the density
//!   rate in the sweep's scalar registers);
//! - the types by which plugins order and require each other. Each is a marker resource (a
//!   plugin that provides the thing says so with
//!   [`Sim::enable`](dualsph_core::sim::Sim::enable), one that needs it with
//!   [`Sim::require`](dualsph_core::sim::Sim::require)) and, where systems are placed against
//!   it, a [`SystemGroup`] (systems join it with `in_group` and others run `after` it);
//! - the lane checks on a lattice with the fluid's columns ([`checks`]).
#![warn(missing_docs)]

use bevy_ecs::prelude::Resource;
use dualsph_core::order::SystemGroup;

pub mod checks;
pub mod components;
mod eos;
mod equations;
pub mod speeds;
mod sums;

pub use eos::{BodyEos, EosLaw};
pub use equations::{
    DISSIPATED, DensityIntegration, Dissipation, EnergyEquation, INTERNAL_ENERGY,
    ensure_density_integration, ensure_dissipation, ensure_energy_equation,
};
pub use sums::{DENSITY_RATE, FluidOut, FluidOwnerSums, FluidSums, POWER};

/// What a fluid plugin that adds pair terms imports: the pair layer's prelude, the fluid's
/// columns and its sums by name.
pub mod prelude {
    pub use crate::components::*;
    pub use crate::{FluidOut, FluidOwnerSums, FluidSums};
    pub use dualsph_integrate::{ScalarRate, ScalarState, SimIntegrate};
    pub use dualsph_sweep::prelude::*;
}

/// An equation of state sets every particle's pressure and sound speed (in
/// `StepSet::Eos`) and publishes its law per body ([`BodyEos`]): the pressure force, the
/// viscosity, the density diffusion and the pressure probes need one, and the walls'
/// pressure is extrapolated after it.
#[derive(Resource, Debug, Default)]
pub struct EquationOfState;

impl SystemGroup for EquationOfState {}

/// The equation of state is a liquid's (weakly compressible, with a rest density): a
/// hydrostatic start applies.
#[derive(Resource, Debug, Default)]
pub struct Liquid;

/// The density is summed over the supports at every step (rather than integrated).
#[derive(Resource, Debug, Default)]
pub struct DensitySummation;

/// A uniform gravity field acts on the particles.
#[derive(Resource, Debug, Default)]
pub struct GravityField;
