//! Particle components. Every particle is a `bevy_ecs` entity with the core set
//! ([`ParticleId`], [`Position`], [`Velocity`], [`Mass`], [`Density`], [`SmoothingLength`],
//! [`Acceleration`]); plugins add the rest (the fluid's columns are in `dualsph-fluid`) only
//! when a scene asks for them.

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
