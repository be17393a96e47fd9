//! dualsph core, the ECS layer: the `Sim` (world, step schedule, finish hooks), the store of
//! particle columns, population, bodies as data, restart, the integrator slot and the
//! `SimPlugin` machinery. It builds on `dualsph-math` and
//! `dualsph-neighbours` (re-exported under their old paths); the pair sweep
//! (`dualsph-sweep`), the integrator and the diagnostics are layers and plugins above it.
//!
//! Notation follows Ren, Dai, Zhuang & Rabczuk, *Dual-support Smoothed Particle
//! Hydrodynamics* (RenDSSPH in the project's `docs/references.md`): `h_i` is the support radius
//! of particle i, `H_i` its support and `H'_i` its dual-support.
#![warn(missing_docs)]
pub mod bodies;
pub mod chunks;
pub mod columns;
pub mod components;
pub mod names;
pub mod order;
pub mod output;
mod particles;
pub mod phase;
pub mod plugin;
pub mod population;
pub mod potentials;
pub mod profile;
pub mod restart;
mod setup;
pub mod sim;
pub mod store;

pub use dualsph_math as math;
pub use dualsph_math::{kernels, lanes};
pub use dualsph_neighbours as neighbours;
pub use dualsph_neighbours::sampling;

pub use bevy_ecs;
pub use glam;
pub use schemars;

/// The most used items.
pub mod prelude {
    pub use crate::bodies::{Body, BodyId, BodyKind, BodyMotion};
    pub use crate::columns::{ColumnSpec, ColumnValue, Shape};
    pub use crate::components::*;
    pub use crate::kernels::{Kernel, KernelKind};
    pub use crate::lanes::{LaneVec, Lanes};
    pub use crate::math::{Mat1, Matrix, Real, Vec1, Vector};
    pub use crate::neighbours::SkinRule;
    pub use crate::order::SystemGroup;
    pub use crate::output::{RunOutputDir, StepLimit};
    pub use crate::plugin::{PluginConfig, Registry, Role, SceneInfo, SimPlugin};
    pub use crate::sim::{
        Domain, Formulation, KernelRes, ParticleInit, Sim, SimClock, SimConfig, SimError, StepSet,
        TimeStepping,
    };
    pub use crate::store::ParticleData;
}
