//! The phases of a step (see `Sim::step`): the plugins' changes of the particles, the
//! rates evaluated again when a change asks for it, and the rest of the step. A leaf module:
//! the schedule's run conditions (`sim`) and the profiler read it.

use bevy_ecs::prelude::*;

/// Which part of a step a run of the step's schedule does.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StepPhase {
    /// The plugins' changes of the particles: `StepSet::Population` only.
    Population,
    /// The rates at the current state, after a change of the particles: the sets that do
    /// not advance the state, the diagnostics excepted.
    Rates,
    /// The step after its population phase (and the initial evaluation).
    #[default]
    Step,
}

/// Set by a plugin that changed the particles in `StepSet::Population` (a split, a merge) so
/// that the step evaluates the rates again at the new particles before it goes on: without
/// it the changed particles carry rates of the particles they replaced (a merged particle
/// the pair's summed force at its centre of mass, whose torque about the origin is not the
/// pair's). `Sim::step` clears it.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RatesStale(pub bool);
