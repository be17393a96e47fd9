//! The shared vocabulary of the fluid plugins: the types by which they order and require each
//! other, so that a user's own plugin (an equation of state of its own, say) takes part
//! without any edit elsewhere. Each is a marker resource (a plugin that provides the thing
//! says so with [`Sim::enable`](dualsph_core::sim::Sim::enable), one that needs it with
//! [`Sim::require`](dualsph_core::sim::Sim::require)) and, where systems are placed against
//! it, a [`SystemGroup`] (systems join it with `in_group` and others run `after` it).
#![warn(missing_docs)]

use bevy_ecs::prelude::Resource;
use dualsph_core::order::SystemGroup;

/// An equation of state sets every particle's pressure and sound speed (in
/// `StepSet::Eos`): the pressure force, the viscosity, the density diffusion and the pressure
/// probes need one, and the walls' pressure is extrapolated after it.
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
