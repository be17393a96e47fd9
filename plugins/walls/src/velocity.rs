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
//! [`WallVelocityOffset`] `= v̂_w − v_w`); the continuity equation keeps the wall's own
//! velocity, as in Adami et al. (2012).

use crate::WallBodies;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{BodyId, WallVelocityOffset};
use dualsph_core::chunks::DENSE;
use dualsph_core::neighbours::Neighbours;
use dualsph_fluid::prelude::*;
use dualsph_sweep::Support;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What velocity wall particles show the viscous terms (module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
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

/// `Σ_f v_f W_wf / Σ_f W_wf` over the fluid within either support of wall particle i,
/// `None` if there is none.
fn extrapolated<V: Vector>(
    support: &Support<'_, V>,
    (vel, body, walls): (&[Velocity<V>], &[BodyId], &[bool]),
    i: usize,
) -> Option<V> {
    let (mut vw, mut w_sum) = (V::zero(), 0.0);
    support.for_each_within_either(i, |j, _rij, w| {
        if !walls[body[j].0 as usize] {
            vw += vel[j].0 * w;
            w_sum += w;
        }
    });
    (w_sum > 0.0).then(|| vw * (1.0 / w_sum))
}

/// The mode as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct ViscousWallMode(pub ViscousWall);

/// Sets [`WallVelocityOffset`] `v̂_w − v_w` of every wall particle (module docs), before the
/// forces.
#[inline(never)] // a frame of its own in profiles
pub fn wall_velocity<V: Vector>(
    walls: Res<WallBodies>,
    mode: Res<ViscousWallMode>,
    kernel: Res<KernelRes>,
    nb: Res<Neighbours<V>>,
    formulation: Res<Formulation>,
    mut q: Query<(
        &Position<V>,
        &SmoothingLength,
        &BodyId,
        &Velocity<V>,
        &mut WallVelocityOffset<V>,
    )>,
) {
    let Some((pos, h, body, vel, mut offset)) =
        dualsph_core::store::single_table(q.contiguous_iter_mut().expect(DENSE))
    else {
        return;
    };
    let support = Support {
        pos,
        h,
        neighbours: &nb,
        kernel: &kernel.0,
        formulation: *formulation,
    };
    let mode = mode.0;
    let set: Vec<(usize, V)> = (0..pos.len())
        .into_par_iter()
        .with_min_len(256)
        .filter(|&i| walls.0[body[i].0 as usize])
        .map(|i| {
            let delta = match extrapolated(&support, (vel, body, &walls.0), i) {
                None => V::zero(),
                Some(v_f) => match mode {
                    ViscousWall::Own => V::zero(),
                    ViscousWall::NoSlip => vel[i].0 - v_f,
                    ViscousWall::FreeSlip => v_f - vel[i].0,
                },
            };
            (i, delta)
        })
        .collect();
    for (i, delta) in set {
        offset[i].0 = delta;
    }
}
