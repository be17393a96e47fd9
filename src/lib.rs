//! # dualsph
//!
//! An entity-component-system engine for **Dual-Support Smoothed Particle Hydrodynamics**
//! (Ren, Dai, Zhuang & Rabczuk). Particles are `bevy_ecs` entities; physics are plugins that
//! add components, scheduled systems and pair terms; scenes are RON files that compose plugins.
//!
//! This crate is the facade: it re-exports the engine ([`core`], the pair layer [`sweep`] and
//! the fluid's vocabulary [`fluid`]), scenes ([`scene`]) and
//! output ([`io`]), the built-in plugins ([`plugins`], [`default_registry`], from
//! `dualsph-builtin`), and from `dualsph-run` the building of a [`Sim`] from a scene
//! ([`build_sim`]), the headless run ([`runner`]), checkpoints ([`checkpoint`]), gridded output
//! ([`gridded`]) and the command line ([`cli::main`]).
#![warn(missing_docs)]

pub use dualsph_core as core;
pub use dualsph_diagnostics as diagnostics;
pub use dualsph_fluid as fluid;
pub use dualsph_integrate as integrate;
pub use dualsph_integrator as integrator;
pub use dualsph_io as io;
pub use dualsph_plot as plot;
pub use dualsph_probes as probes;
pub use dualsph_scene as scene;
pub use dualsph_sweep as sweep;

pub use dualsph_fluid::prelude::*;

/// The most used items of the engine.
pub mod prelude {
    pub use dualsph_diagnostics::{Diagnostics, SimDiagnostics};
    pub use dualsph_fluid::prelude::*;
}

pub use dualsph_diagnostics::{Diagnostics, SimDiagnostics};

pub use dualsph_builtin::{default_registry, fuse_builtin_terms, plugins};

pub use dualsph_run::{add_default_plugins, build_sim, build_sim_with};
pub use dualsph_run::{checkpoint, cli, gridded, run_loop, runner};
pub use dualsph_run::{say, with_dimension};
