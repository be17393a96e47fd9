//! `Diagnostics()`: the conservation diagnostics and the health check of a run, installed by
//! default (a scene that names none gets it).
//!
//! * [`totals`]: mass, momentum, angular momentum and energies, per body and in all, and the
//!   largest density variation ([`Diagnostics`], every `output.diagnostics_every` steps and
//!   on demand, [`SimDiagnostics::diagnostics`]).
//! * [`health`]: the first non-finite or unphysical value of the state, a density or h
//!   outside its sane range, a particle far outside the domain ([`Health`], every step): what
//!   the runner stops a blown-up run on; its sane ranges are the scene's `health` section
//!   ([`HealthSettings`], a scene section this crate owns).
//! * [`balance`]: the relative net force and torque of the pair sweep ([`PairBalance`], on
//!   request).
//!
//! The potential energy is that of the body forces declared in the core's
//! [`ExternalPotentials`](dualsph_core::potentials::ExternalPotentials) (gravity's).
#![warn(missing_docs)]

pub mod balance;
pub mod health;
pub mod totals;

pub use balance::{PairBalance, pair_balance, track_pair_balance};
pub use health::settings::{DEFAULT_DT_BELOW, HealthSettings};
pub use health::*;
pub use totals::*;

use dualsph_core::bevy_ecs::prelude::Resource;
use dualsph_core::bevy_ecs::system::RunSystemOnce;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// `Diagnostics()`: the plugin (no settings; the cadence is the scene's
/// `output.diagnostics_every`, the health factors its `health` section, [`HealthSettings`]).
#[derive(Debug, Clone, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DiagnosticsPlugin {}

impl SimPlugin for DiagnosticsPlugin {
    const NAME: &'static str = "Diagnostics";
    const SUMMARY: &'static str =
        "conservation totals (per body and in all) and the health check of the state (default)";
    const ROLE: Role = Role::Diagnostics;

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        install(sim)
    }
}

/// What a run has written of its diagnostics: the totals at t = 0 (the reference of the
/// conservation errors) and the step of the last row of `diagnostics.csv`. The runner sets
/// it; it is kept in checkpoints (key `diagnostics`), so a resumed run measures its drift
/// from the same start and writes the rows an uninterrupted run would.
#[derive(Resource, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DiagnosticsLog {
    /// The diagnostics at t = 0.
    pub initial: Diagnostics,
    /// The step of the last row written.
    pub last_written: u64,
}

/// Adds the resources (the [`DiagnosticsLog`] kept in checkpoints), the [`InitialDensity`]
/// column and the systems, in `Diagnostics`: [`capture_initial_density`], [`check_health`]
/// and [`compute_diagnostics`].
pub fn install<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    sim.world.init_resource::<Diagnostics>();
    sim.world.init_resource::<DiagnosticsLog>();
    sim.keep_resource::<DiagnosticsLog>("diagnostics");
    sim.world.init_resource::<Health>();
    sim.world.init_resource::<HealthBounds>();
    sim.world.init_resource::<DiagnosticsEvery>();
    let spec = ColumnSpec::restart_only("initial_density");
    sim.add_column(spec, |seed| InitialDensity(seed.init.density))?;
    sim.add_system(
        StepSet::Diagnostics,
        "capture_initial_density (at the initial evaluation)",
        capture_initial_density,
    );
    sim.add_system(StepSet::Diagnostics, "check_health", check_health::<V>);
    sim.add_system(
        StepSet::Diagnostics,
        "compute_diagnostics (every diagnostics_every steps)",
        compute_diagnostics::<V>,
    );
    Ok(())
}

/// The diagnostics of a [`Sim`], on demand.
pub trait SimDiagnostics {
    /// The diagnostics of the current state, computed now if the last evaluation is older
    /// (see [`DiagnosticsEvery`]). Works without the plugin too (then always computed now,
    /// without a density variation: NaN).
    fn diagnostics(&mut self) -> Diagnostics;
    /// Evaluates the diagnostics only every `every` steps (and at t = 0).
    fn set_diagnostics_every(&mut self, every: u64);
}

impl<V: Vector> SimDiagnostics for Sim<V> {
    fn diagnostics(&mut self) -> Diagnostics {
        let clock = self.clock();
        self.world.init_resource::<Diagnostics>();
        let d = self.world.resource::<Diagnostics>();
        if d.step != clock.step || d.t != clock.t || d.n == 0 {
            // the system's parameters are resources that exist (above, and the core's)
            let _ = self.world.run_system_once(compute_diagnostics_now::<V>);
        }
        self.world.resource::<Diagnostics>().clone()
    }

    fn set_diagnostics_every(&mut self, every: u64) {
        self.world.insert_resource(DiagnosticsEvery(every.max(1)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::sim::{Domain, ParticleInit, SimConfig};
    use glam::DVec2;

    /// Two particles moving apart, with or without the plugin.
    fn sim(with_plugin: bool) -> Sim<DVec2> {
        let mut sim = Sim::<DVec2>::new(SimConfig {
            kernel: KernelKind::CubicSpline,
            formulation: Formulation::DualSupport,
            domain: Domain::closed(DVec2::splat(-10.0), DVec2::splat(10.0)),
            skin: 0.1,
            skin_rule: SkinRule::Fixed,
            time_stepping: TimeStepping::Fixed(1e-3),
        });
        let p = |x: f64, v: f64| ParticleInit {
            pos: DVec2::new(x, 0.0),
            vel: DVec2::new(v, 0.0),
            mass: 2.0,
            density: 1000.0,
            h: 0.1,
            internal_energy: 0.0,
            body: 0,
        };
        sim.spawn_particles(&[p(-1.0, -1.0), p(1.0, 3.0)])
            .expect("fresh particle ids");
        let integrator: &dyn PluginConfig = &dualsph_integrator::LeapfrogPC::default();
        sim.build_plugin(integrator).unwrap();
        if with_plugin {
            sim.build_plugin(&DiagnosticsPlugin {}).unwrap();
        }
        sim.initialize().unwrap();
        sim
    }

    #[test]
    fn diagnostics_on_demand_work_with_and_without_the_plugin() {
        for with_plugin in [true, false] {
            let mut s = sim(with_plugin);
            s.step().unwrap();
            let d = s.diagnostics();
            assert_eq!((d.n, d.step, d.mass), (2, 1, 4.0), "plugin: {with_plugin}");
            assert_eq!(d.momentum, [4.0, 0.0, 0.0]);
            assert_eq!(d.e_kin, 0.5 * 2.0 * (1.0 + 9.0));
            assert_eq!(s.world.contains_resource::<Health>(), with_plugin);
        }
    }
}
