//! Time integration as plugins. A scene names its scheme among its plugins — `LeapfrogPC()`
//! (the default, installed when the scene names none) or `PositionVerlet()` — and a scene
//! with two is refused, naming both.
//!
//! * [`LeapfrogPC`] ([`leapfrog`]): the leapfrog predictor–corrector of RenDSSPH §6, forces
//!   at the end of the step.
//! * [`PositionVerlet`] ([`verlet`]): the Störmer–Verlet scheme in drift–kick–drift form,
//!   forces at the middle of the step, with a predicted mid-step velocity for
//!   velocity-dependent forces.
//!
//! A scheme advances position and velocity, and every scalar the scene's plugins declare
//! with `SimIntegrate::integrate` (density with the continuity equation, internal energy with the
//! energy equation; see [`dualsph_integrate`]). Both install the time-step rule of
//! [`time_step`] (`choose_dt`, `check_time_step`), set by the scene's `integrator` section
//! ([`IntegratorSettings`], a scene section this crate owns). A scheme from another crate is written the
//! same way: a [`Scheme`](dualsph_integrate::Scheme) set by its plugin's `build`, with
//! `ROLE = Role::Integrator`.
#![warn(missing_docs)]

pub mod energy;
pub mod leapfrog;
pub mod settings;
pub mod time_step;
pub mod verlet;

use dualsph_fluid::prelude::*;
use dualsph_integrate::{ScalarEquation, ScalarKernel};
pub use energy::EnergyUpdate;
pub use settings::{IntegratorSettings, TimeStep};

/// A scheme's systems that advance positions and velocities (the leapfrog's predictor and
/// corrector, the position Verlet's halves): they run before the bodies are driven, and the
/// work-consistent energy correction after them.
pub struct Kinematics;

impl dualsph_core::order::SystemGroup for Kinematics {}
use serde::{Deserialize, Serialize};

/// The registered name of [`LeapfrogPC`].
pub const LEAPFROG_PC: &str = "LeapfrogPC";
/// The registered name of [`PositionVerlet`].
pub const POSITION_VERLET: &str = "PositionVerlet";

/// Registers `equation`'s scalar with a scheme of two updates, `(label, update)`: the first
/// in `Predict`, the second in `Correct`, each labelled `{label}_{name}`, with the registers
/// the updates share.
fn two_updates<V: Vector>(
    sim: &mut Sim<V>,
    equation: &dyn ScalarEquation<V>,
    (first, f): (&str, ScalarKernel),
    (second, g): (&str, ScalarKernel),
) -> Result<(), SimError> {
    let name = equation.name();
    equation.add_registers(sim, false)?;
    equation.add_system(sim, StepSet::Predict, format!("{first}_{name}"), f);
    equation.add_system(sim, StepSet::Correct, format!("{second}_{name}"), g);
    Ok(())
}

/// Refuses a second scheme before anything of this one is added.
fn only_scheme<V: Vector>(sim: &Sim<V>, name: &str) -> Result<(), SimError> {
    match sim.integrator() {
        Some(first) => Err(SimError::Build(format!(
            "two integrators, {first} and {name}: a simulation is advanced by one (remove one \
             of them)"
        ))),
        None => Ok(()),
    }
}

/// `LeapfrogPC()`: the leapfrog predictor–corrector of RenDSSPH §6 (see [`leapfrog`]).
#[derive(Debug, Clone, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LeapfrogPC {
    /// How the internal energy is advanced (see [`energy`]): `Consistent` (the default) or
    /// `Rates`.
    #[serde(default)]
    pub energy: EnergyUpdate,
}

impl SimPlugin for LeapfrogPC {
    const NAME: &'static str = LEAPFROG_PC;
    const SUMMARY: &'static str =
        "time integration: leapfrog predictor-corrector, forces at the end of the step (default)";
    const ROLE: Role = Role::Integrator;

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        only_scheme(sim, Self::NAME)?;
        leapfrog::install(sim, self.energy)
    }
}

/// `PositionVerlet()`: the Störmer–Verlet scheme in drift–kick–drift form (see [`verlet`]).
#[derive(Debug, Clone, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PositionVerlet {
    /// How the internal energy is advanced (see [`energy`]): `Consistent` (the default) or
    /// `Rates`.
    #[serde(default)]
    pub energy: EnergyUpdate,
}

impl SimPlugin for PositionVerlet {
    const NAME: &'static str = POSITION_VERLET;
    const SUMMARY: &'static str =
        "time integration: Stormer-Verlet drift-kick-drift, forces at the middle of the step";
    const ROLE: Role = Role::Integrator;

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        only_scheme(sim, Self::NAME)?;
        verlet::install(sim, self.energy)
    }
}
