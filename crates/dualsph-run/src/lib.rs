//! Running `dualsph` scenes: a scene becomes a [`Sim`] ([`build_sim`], with the built-in
//! plugin group of `dualsph-builtin`), runs headless ([`runner`], through the one run loop
//! [`run_loop`]) with checkpoints
//! ([`checkpoint`]) and gridded output ([`gridded`]), and the whole command line is a library
//! function ([`cli::main`]). The `dualsph` facade re-exports all of it under its own paths.
#![warn(missing_docs)]

pub mod checkpoint;
pub mod cli;
mod error;
mod file_columns;
pub mod gridded;
pub mod run_loop;
pub mod runner;

/// The engine, for the paths inside [`with_dimension!`].
#[doc(hidden)]
pub use dualsph_core as __core;

use dualsph_builtin::{fuse_builtin_terms, plugins};
use dualsph_core::bodies::{Bodies, Body, install_bodies};
use dualsph_diagnostics::{HealthSettings, SimDiagnostics};
use dualsph_fluid::prelude::*;
use dualsph_integrator::IntegratorSettings;
use dualsph_scene::Scene;

fn vector<V: Vector>(x: &[Real], what: &str) -> Result<V, SimError> {
    V::from_slice(x).ok_or_else(|| {
        SimError::Build(format!(
            "{what}: expected {} components, got {}",
            V::DIM,
            x.len()
        ))
    })
}

/// A vector of the scene padded with zeros to 3 components.
fn padded3(v: &[f64]) -> [f64; 3] {
    std::array::from_fn(|k| v.get(k).copied().unwrap_or(0.0))
}

/// Builds a simulation of dimension `V::DIM` from a validated scene: core resources, the
/// integrator and the diagnostics (the scene's, or [`LeapfrogPC`](plugins::LeapfrogPC) and
/// [`DiagnosticsPlugin`](plugins::DiagnosticsPlugin) when it names none; two integrators are
/// an error naming both), particles from the generators and their bodies, then each other
/// plugin in the order listed.
pub fn build_sim<V: Vector>(scene: &Scene) -> Result<Sim<V>, SimError> {
    build_sim_with(scene, |_| Ok(()))
}

/// [`build_sim`] with `extra` run after the scene's plugins and before the schedule is built:
/// a caller's own systems and resources (a diagnostic such as
/// `dualsph_diagnostics::track_pair_balance`) join the step like a plugin's.
pub fn build_sim_with<V: Vector>(
    scene: &Scene,
    extra: impl FnOnce(&mut Sim<V>) -> Result<(), SimError>,
) -> Result<Sim<V>, SimError> {
    let domain = Domain {
        min: vector::<V>(&scene.domain.min, "domain.min")?,
        max: vector::<V>(&scene.domain.max, "domain.max")?,
        periodic: scene.domain.periodic_axes(),
    };
    let time_stepping = integrator_settings(scene)?.time_stepping();
    let health = health_settings(scene)?;
    let formulation = scene.formulation;
    let roles = RolePlugins::of(scene)?;
    let mut sim = Sim::<V>::new(SimConfig {
        kernel: scene.kernel,
        formulation,
        domain,
        skin: scene.neighbours.skin,
        skin_rule: if scene.neighbours.tune_skin {
            SkinRule::Tuned
        } else {
            SkinRule::Fixed
        },
        time_stepping,
    });
    // the integrator and the diagnostics first, as the engine's own systems: the scheme's
    // stages open their sets (before any body pinning), its dt is chosen first
    build_named(&mut sim, roles.integrator)?;
    build_named(&mut sim, roles.diagnostics)?;
    let particles: Vec<ParticleInit<V>> = scene
        .generate()
        .iter()
        .map(|p| ParticleInit {
            pos: vector::<V>(&p.pos[..V::DIM], "position").unwrap_or_else(|_| V::zero()),
            vel: vector::<V>(&p.vel[..V::DIM], "velocity").unwrap_or_else(|_| V::zero()),
            mass: p.mass,
            density: p.density,
            h: p.h,
            internal_energy: p.internal_energy,
            body: p.body,
        })
        .collect();
    if formulation == Formulation::ConstantH
        && let Some(first) = particles.first()
        && let Some(other) = particles.iter().find(|p| p.h != first.h)
    {
        return Err(SimError::Build(format!(
            "formulation ConstantH needs one h for all particles, found {} and {} (use one h_factor × spacing)",
            first.h, other.h
        )));
    }
    sim.spawn_particles(&particles)?;
    let bodies = scene.body_list().into_iter().map(|b| Body {
        motion: b.kind.motion(),
        name: b.name,
        moment_about: b.moment_about.as_deref().map_or([0.0; 3], padded3),
    });
    install_bodies(&mut sim, Bodies(bodies.collect()))?;
    let h_range = particles.iter().fold(None, |r, p| match r {
        None => Some((p.h, p.h)),
        Some((lo, hi)) => Some((p.h.min(lo), p.h.max(hi))),
    });
    sim.world.insert_resource(health.bounds(h_range));
    sim.world
        .insert_resource(runner::DtFloor::new(health.dt_below));
    sim.keep_resource::<runner::DtFloor>(runner::DT_FLOOR_KEY);
    sim.add_system(
        StepSet::Diagnostics,
        "check_dt_floor (a stalled run)",
        runner::check_dt_floor,
    );
    if let Some(limit) = scene.max_steps {
        sim.world
            .insert_resource(dualsph_core::output::StepLimit(limit));
    }
    sim.set_diagnostics_every(scene.output.diagnostics_every);
    {
        let mut clock = sim.world.resource_mut::<SimClock>();
        clock.t_end = scene.end_time;
    }
    fuse_builtin_terms(&mut sim);
    let physics = || scene.plugins.iter().filter(|p| p.role() == Role::Physics);
    for p in physics() {
        named(p.as_ref(), sim.prepare_plugin(p.as_ref()))?;
    }
    for p in physics() {
        build_named(&mut sim, p.as_ref())?;
    }
    extra(&mut sim)?;
    sim.finish()?;
    file_columns::apply(&mut sim, scene)?;
    Ok(sim)
}

/// The scene's `integrator` section as the integrator's settings (an error when the
/// registry that parsed it held other settings under that key).
pub fn integrator_settings(scene: &Scene) -> Result<&IntegratorSettings, SimError> {
    scene.section::<IntegratorSettings>().ok_or_else(|| {
        SimError::Build(format!(
            "the scene's integrator section is not dualsph-integrator's settings: {:?}",
            scene.integrator
        ))
    })
}

/// The scene's `health` section as the diagnostics' settings, or their defaults when the
/// scene has none (an error when the registry that parsed it held other settings under that
/// key).
pub fn health_settings(scene: &Scene) -> Result<HealthSettings, SimError> {
    match &scene.health {
        None => Ok(HealthSettings::default()),
        Some(h) => h.section::<HealthSettings>().cloned().ok_or_else(|| {
            SimError::Build(format!(
                "the scene's health section is not dualsph-diagnostics' settings: {h:?}"
            ))
        }),
    }
}

/// Builds the default integrator ([`LeapfrogPC`](plugins::LeapfrogPC)) and diagnostics
/// ([`DiagnosticsPlugin`](plugins::DiagnosticsPlugin)) into a simulation made in code
/// (`Sim::new`), before its other plugins — what [`build_sim`] does for a scene that names
/// neither.
pub fn add_default_plugins<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    build_named(sim, &DEFAULT_INTEGRATOR)?;
    build_named(sim, &DEFAULT_DIAGNOSTICS)
}

/// The plugins of a scene's exclusive roles: the ones it names, or the defaults
/// ([`LeapfrogPC`](plugins::LeapfrogPC), [`DiagnosticsPlugin`](plugins::DiagnosticsPlugin)).
struct RolePlugins<'s> {
    integrator: &'s dyn PluginConfig,
    diagnostics: &'s dyn PluginConfig,
}

static DEFAULT_INTEGRATOR: plugins::LeapfrogPC = plugins::LeapfrogPC {
    energy: plugins::EnergyUpdate::Consistent,
};
static DEFAULT_DIAGNOSTICS: plugins::DiagnosticsPlugin = plugins::DiagnosticsPlugin {};

impl<'s> RolePlugins<'s> {
    /// The scene's (at most one per role: two are an error naming both) or the default.
    fn of(scene: &'s Scene) -> Result<Self, SimError> {
        let named = |role: Role| scene.plugin_of_role(role).map_err(SimError::Build);
        Ok(RolePlugins {
            integrator: named(Role::Integrator)?.unwrap_or(&DEFAULT_INTEGRATOR),
            diagnostics: named(Role::Diagnostics)?.unwrap_or(&DEFAULT_DIAGNOSTICS),
        })
    }
}

/// Builds one plugin; its error names it.
fn build_named<V: Vector>(sim: &mut Sim<V>, p: &dyn PluginConfig) -> Result<(), SimError> {
    named(p, sim.build_plugin(p))
}

/// `result` of preparing or building `p`, its error naming the plugin.
fn named(p: &dyn PluginConfig, result: Result<(), SimError>) -> Result<(), SimError> {
    result.map_err(|e| {
        let why = match e {
            SimError::Build(m) | SimError::BlowUp(m) => m,
        };
        SimError::Build(format!("plugin {}: {why}", p.name()))
    })
}

/// Runs `f` with the scene's dimension as a type: `Vec1`, `DVec2` or `DVec3`.
#[macro_export]
macro_rules! with_dimension {
    ($dim:expr, $v:ident => $body:expr) => {
        match $dim {
            1 => {
                type $v = $crate::__core::math::Vec1;
                $body
            }
            2 => {
                type $v = $crate::__core::glam::DVec2;
                $body
            }
            _ => {
                type $v = $crate::__core::glam::DVec3;
                $body
            }
        }
    };
}
