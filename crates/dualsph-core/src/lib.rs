//! dualsph core: dimensions, kernels, neighbour lists, the support/dual-support pair sweep,
//! the registry of integrated quantities, and the `Sim`/`SimPlugin` machinery. The
//! integrator and the diagnostics are plugins (`dualsph-integrator`, `dualsph-diagnostics`).
//!
//! Notation follows Ren, Dai, Zhuang & Rabczuk, *Dual-support Smoothed Particle
//! Hydrodynamics* (RenDSSPH in the project's `docs/references.md`): `h_i` is the support radius
//! of particle i, `H_i` its support and `H'_i` its dual-support.
#![warn(missing_docs)]
pub mod accum;
pub mod bodies;
pub mod chunks;
pub mod columns;
pub mod components;
pub mod integrate;
pub mod order;
pub mod output;
pub mod pair;
pub mod plugin;
pub mod population;
pub mod potentials;
pub mod profile;
pub mod restart;
pub mod sim;
pub mod store;
pub mod sweep;

pub use dualsph_math as math;
pub use dualsph_math::{kernels, lanes};
pub use dualsph_neighbours as neighbours;
pub use dualsph_neighbours::sampling;

pub use bevy_ecs;
pub use glam;

/// The most used items.
pub mod prelude {
    pub use crate::accum::{Acc, Binder, Reaction};
    pub use crate::bodies::{BodyId, BodyKind};
    pub use crate::columns::{ColumnSpec, ColumnValue, Shape};
    pub use crate::components::*;
    pub use crate::integrate::{ScalarRate, ScalarState};
    pub use crate::kernels::{Kernel, KernelKind};
    pub use crate::lanes::{LaneVec, Lanes};
    pub use crate::math::{Mat1, Matrix, Real, Vec1, Vector};
    pub use crate::neighbours::SkinRule;
    pub use crate::output::{RunOutputDir, StepLimit};
    pub use crate::pair::{BoundTerm, Out, OwnerSums, PairLanes, PairTerm, Specialised};
    pub use crate::plugin::{PluginConfig, Registry, Role, SceneInfo, SimPlugin};
    pub use crate::sim::{
        Domain, KernelRes, ParticleInit, Sim, SimClock, SimConfig, SimError, StepSet, TimeStepping,
    };
    pub use crate::store::ParticleData;
    pub use crate::sweep::{FORCES, Formulation, OwnerKernel, SweepCtx};
}
