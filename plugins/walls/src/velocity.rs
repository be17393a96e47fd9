//! The velocity a wall particle shows the viscous terms (`WallPressure(viscous: ..)`), after
//! Adami, Hu & Adams (2012), *A generalized wall boundary condition for smoothed particle
//! hydrodynamics*, J. Comput. Phys. 231, 7057, Eq. 22–23: the fluid's velocity is first
//! extrapolated to the wall particle w, over the fluid within either support with
//! `W_wf = W(r_wf, max(h_w, h_f))` as for the pressure ([`crate::pressure`]),
//!
//! `ṽ_w = Σ_f v_f W_wf / Σ_f W_wf`,
//!
//! and the wall particle then shows the viscous terms
//!
//! * `NoSlip`: `v̂_w = 2 v_w − ṽ_w` (Eq. 23), the mirror of the fluid's velocity about the
//!   wall's, so that the velocity interpolated across the wall surface is the wall's own
//!   (no-slip);
//! * `FreeSlip`: `v̂_w = ṽ_w`, the fluid's own velocity, so that the viscous terms see no
//!   shear at the wall.
//!
//! `v_w` is the wall's velocity from its law (zero for a fixed wall). A wall particle with no
//! fluid within either support shows its own velocity. Only the viscous terms read `v̂_w` (through
//! `WallVelocityOffset` `= v̂_w − v_w`); the continuity equation keeps the wall's own
//! velocity, as in Adami et al. (2012). The sums are taken in the same walk as the pressure's
//! ([`crate::pressure::wall_pressure`]).

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::math::Vector;
use serde::{Deserialize, Serialize};

/// What velocity wall particles show the viscous terms (module docs).
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
pub enum ViscousWall {
    /// Their own (the wall's) velocity: the viscous terms see the fluid slide past wall
    /// particles that move with the wall.
    #[default]
    Own,
    /// `2 v_w − ṽ_w` (Adami et al. 2012, Eq. 23): no slip at the wall surface.
    NoSlip,
    /// `ṽ_w`: no shear at the wall.
    FreeSlip,
}

/// The mode as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct ViscousWallMode(pub ViscousWall);

/// `v̂_w − v_w` (module docs) of a wall particle of velocity `v_w` given the fluid's
/// extrapolated velocity `ṽ_w` (`None` where no fluid is within either support: zero).
#[inline]
pub fn wall_offset<V: Vector>(mode: ViscousWall, v_w: V, v_f: Option<V>) -> V {
    match (mode, v_f) {
        (ViscousWall::Own, _) | (_, None) => V::zero(),
        (ViscousWall::NoSlip, Some(v_f)) => v_w - v_f,
        (ViscousWall::FreeSlip, Some(v_f)) => v_f - v_w,
    }
}
