//! Bodies: every particle belongs to one ([`BodyId`], a column of the store), and a body has a
//! name and, unless it is a fluid, a [`BodyMotion`]: the law that moves its particles. What a
//! scene calls a body's kind (`kind: Fixed`, `kind: Prescribed(Slide(..))`) is a [`BodyKind`]
//! a crate provides and a [`Registry`](crate::plugin::Registry) holds; its one job is to give
//! that law ([`kind`]). Bodies are data, not marker components, so all particles stay in one
//! table. Plugins take their material parameters per body (e.g. the equation of state's ρ0 and
//! c0), and the diagnostics report mass, momentum and energy per body.
//!
//! A particle of a body with a motion ("driven": fixed, prescribed) is moved by it: a
//! [`Fixed`] body's particles keep their initial position and zero velocity ([`Hold`]), others
//! follow their law, a function of time and the particle's initial position. Such a particle
//! takes part in every pair sum (its density and pressure evolve like a fluid particle's, and
//! its velocity enters the pair terms, so a moving wall drags and pushes the fluid), and the
//! force the sweep computes on it is the fluid's load on the body (its `Acceleration` times its
//! mass: body forces act on fluid bodies only, and the diagnostics sum the loads per body about
//! [`Body::moment_about`]), but the integrator's update of its position and velocity is
//! replaced by the body's law right after the predictor and the corrector ([`drive_bodies`]).
//! A law that evolves with the loads (a floating body) is a system of its own that replaces
//! its body's entry of [`DrivenBodies`] before [`DriveBodies`].

pub mod kind;

pub use kind::{BodyKind, BodyKindConfig, BodyKindEntry, Fixed, Fluid};

use crate::chunks::{DENSE, MIN_LEN};
use crate::columns::{ColumnSpec, ColumnValue, Shape};
use crate::components::{Position, Velocity};
use crate::math::{Real, Vector};
use crate::sim::{Sim, SimError, StepSet};
use bevy_ecs::prelude::*;
use rayon::prelude::*;
use std::fmt::Debug;
use std::sync::Arc;

/// The name of the one body of a scene that declares none.
pub const DEFAULT_BODY: &str = "fluid";

/// A rigid law of motion of a driven body: the position `x(t)` and velocity `v(t)` at time `t`
/// (from the start of the run) of a particle that starts at `x_0`, and its acceleration.
/// Vectors are embedded in 3-D (a 2-D scene's particles have `z = 0`; the components past the
/// scene's dimension are ignored).
pub trait BodyMotion: Debug + Send + Sync + 'static {
    /// `(x(t), v(t))` of a particle that starts at `x0`.
    fn at(&self, x0: [Real; 3], t: Real) -> ([Real; 3], [Real; 3]);
    /// `a(t) = dv/dt` of a particle that starts at `x0` (what a wall model subtracts from
    /// gravity, Adami et al. 2012, Eq. 27).
    fn acceleration(&self, x0: [Real; 3], t: Real) -> [Real; 3];
    /// True for a law that keeps every particle at `x_0` with zero velocity at all times: its
    /// particles are set from their anchor without calling [`BodyMotion::at`].
    fn holds_still(&self) -> bool {
        false
    }
}

/// The law of a [`Fixed`] body: `x(t) = x_0`, `v = 0`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Hold;

impl BodyMotion for Hold {
    fn at(&self, x0: [Real; 3], _t: Real) -> ([Real; 3], [Real; 3]) {
        (x0, [0.0; 3])
    }
    fn acceleration(&self, _x0: [Real; 3], _t: Real) -> [Real; 3] {
        [0.0; 3]
    }
    fn holds_still(&self) -> bool {
        true
    }
}

/// A vector of the scene from its 3-D embedding.
fn from_xyz<V: Vector>(x: [Real; 3]) -> V {
    V::from_slice(&x[..V::DIM]).expect("DIM <= 3")
}

/// `(x(t), v(t))` of `law` for a particle that starts at `x0`, in the scene's vectors.
pub fn motion_at<V: Vector>(law: &dyn BodyMotion, x0: V, t: Real) -> (V, V) {
    let (x, v) = law.at(x0.to_xyz(), t);
    (from_xyz(x), from_xyz(v))
}

/// `a(t)` of `law` for a particle that starts at `x0`, in the scene's vectors.
pub fn motion_acceleration<V: Vector>(law: &dyn BodyMotion, x0: V, t: Real) -> V {
    from_xyz(law.acceleration(x0.to_xyz(), t))
}

/// A body: its name and what moves it. Its index in [`Bodies`] is the [`BodyId`] of its
/// particles.
#[derive(Clone, Debug)]
pub struct Body {
    /// The scene's name for it.
    pub name: String,
    /// The law that moves its particles, or `None` for a fluid (integrated by the forces).
    pub motion: Option<Arc<dyn BodyMotion>>,
    /// The point `c` the moment of the load on a driven body is taken about,
    /// `M = Σ_i (x_i − c) × f_i` (3-D embedding; the origin by default).
    pub moment_about: [Real; 3],
}

impl Body {
    /// A fluid body named `name`.
    pub fn fluid(name: impl Into<String>) -> Self {
        Body {
            name: name.into(),
            motion: None,
            moment_about: [0.0; 3],
        }
    }

    /// A fixed body named `name` ([`Hold`]), its moment taken about the origin.
    pub fn fixed(name: impl Into<String>) -> Self {
        Body::moved_by(name, Arc::new(Hold))
    }

    /// A body named `name` moved by `law`, its moment taken about the origin.
    pub fn moved_by(name: impl Into<String>, law: Arc<dyn BodyMotion>) -> Self {
        Body {
            motion: Some(law),
            ..Body::fluid(name)
        }
    }

    /// True for a body whose particles are integrated (a fluid), false for one whose motion
    /// is given (fixed or prescribed): a body with a load.
    pub fn is_fluid(&self) -> bool {
        self.motion.is_none()
    }
}

/// The bodies of a simulation, indexed by [`BodyId`].
#[derive(Resource, Clone, Debug)]
pub struct Bodies(pub Vec<Body>);

impl Default for Bodies {
    fn default() -> Self {
        Bodies(vec![Body::fluid(DEFAULT_BODY)])
    }
}

impl Bodies {
    /// The index of the body named `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.0.iter().position(|b| b.name == name)
    }

    /// The names, in order.
    pub fn names(&self) -> Vec<String> {
        self.0.iter().map(|b| b.name.clone()).collect()
    }
}

/// The body a particle belongs to: an index into [`Bodies`].
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub u16);

impl<V: Vector> ColumnValue<V> for BodyId {
    const SHAPE: Shape = Shape::Scalar;
    fn put(&self, out: &mut Vec<Real>) {
        out.push(Real::from(self.0));
    }
    fn take(&mut self, values: &[Real]) {
        // written from a u16, so exact; anything else clamps into range
        self.0 = values[0].clamp(0.0, Real::from(u16::MAX)) as u16;
    }
}

/// Where a fixed particle is held.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Anchor<V: Vector>(pub V);

crate::vector_column!(Anchor);

/// The velocity a wall particle shows the viscous terms, less its own velocity: `v̂_w − v_w`.
/// A wall model that extrapolates the fluid's velocity to the wall (no-slip or free-slip, the
/// walls plugin's `WallPressure(viscous: ..)`) adds this column and sets it every step before
/// the forces; every other particle keeps zero. The viscous pair terms then take
/// `v̂_ij = v_ij + δ_i − δ_j` (with `δ` this column) where they read the relative velocity.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct WallVelocityOffset<V: Vector>(pub V);

crate::vector_column!(WallVelocityOffset);

/// The law of every body whose particles are moved by it rather than integrated, by
/// [`BodyId`]: `None` for a fluid. A system may replace an entry during the run (a law that
/// evolves with the loads); [`drive_bodies`] reads them after it.
#[derive(Resource, Clone, Debug, Default)]
pub struct DrivenBodies(pub Vec<Option<Arc<dyn BodyMotion>>>);

/// The systems that set the positions and velocities of fixed and prescribed bodies
/// ([`drive_bodies`], after the integrator's predictor and corrector): the integrator's
/// kinematics run before them, what reads the walls' state after.
pub struct DriveBodies;

impl crate::order::SystemGroup for DriveBodies {}

/// Sets the particles of fixed and prescribed bodies to their law at the end of the step
/// (`t + Δt`): position from their anchor (initial position), and velocity.
#[inline(never)] // a frame of its own in profiles
pub fn drive_bodies<V: Vector>(
    driven: Res<DrivenBodies>,
    clock: Res<crate::sim::SimClock>,
    mut q: Query<(&BodyId, &Anchor<V>, &mut Position<V>, &mut Velocity<V>)>,
) {
    /// What moves a body's particles this step.
    enum Drive<'a> {
        Free,
        Hold,
        Law(&'a dyn BodyMotion),
    }
    let drives: Vec<Drive> = driven
        .0
        .iter()
        .map(|m| match m.as_deref() {
            None => Drive::Free,
            Some(m) if m.holds_still() => Drive::Hold,
            Some(m) => Drive::Law(m),
        })
        .collect();
    let t = clock.t + clock.dt;
    for (body, anchor, mut r, mut v) in q.contiguous_iter_mut().expect(DENSE) {
        let (r, v) = (r.bypass_change_detection(), v.bypass_change_detection());
        (body, anchor, r, v)
            .into_par_iter()
            .with_min_len(MIN_LEN)
            .for_each(|(b, a, r, v)| match drives[b.0 as usize] {
                Drive::Free => {}
                Drive::Hold => {
                    r.0 = a.0;
                    v.0 = V::zero();
                }
                Drive::Law(m) => (r.0, v.0) = motion_at(m, a.0, t),
            });
    }
}

/// Sets the simulation's bodies (before the plugins are built) and, when one of them is
/// fixed or prescribed, anchors the particles and drives them after the predictor and the
/// corrector ([`drive_bodies`]), having set those of prescribed bodies to their law at t = 0.
/// The error names a particle whose body does not exist.
pub fn install_bodies<V: Vector>(sim: &mut Sim<V>, bodies: Bodies) -> Result<(), SimError> {
    let n = bodies.0.len();
    let mut q = sim.world.query::<&BodyId>();
    if let Some(b) = q.iter(&sim.world).find(|b| b.0 as usize >= n) {
        return Err(SimError::Build(format!(
            "a particle belongs to body {}, but there are {n} bodies",
            b.0
        )));
    }
    let driven: Vec<_> = bodies.0.iter().map(|b| b.motion.clone()).collect();
    sim.world.insert_resource(bodies);
    if driven.iter().any(Option::is_some) {
        let spec = ColumnSpec::restart_only("anchor");
        sim.add_column(spec, |seed| Anchor(seed.init.pos))?;
        set_velocities_at_start::<V>(&mut sim.world, &driven);
        sim.world.insert_resource(DrivenBodies(driven));
        sim.add_system(
            StepSet::Predict,
            "drive_bodies (fixed and prescribed, after the predictor)",
            drive_bodies::<V>,
        )
        .in_group::<DriveBodies>();
        sim.add_system(
            StepSet::Correct,
            "drive_bodies (fixed and prescribed, after the corrector)",
            drive_bodies::<V>,
        )
        .in_group::<DriveBodies>();
    }
    Ok(())
}

/// The velocity of every particle of a prescribed body at t = 0 (its position is its anchor).
fn set_velocities_at_start<V: Vector>(world: &mut World, driven: &[Option<Arc<dyn BodyMotion>>]) {
    let mut q = world.query::<(&BodyId, &Position<V>, &mut Velocity<V>)>();
    for (b, r, mut v) in q.iter_mut(world) {
        if let Some(m) = &driven[b.0 as usize] {
            v.0 = motion_at(m.as_ref(), r.0, 0.0).1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// A law of the tests: `x(t) = x_0 + (t, 2t)`.
    #[derive(Debug)]
    struct Drift;

    impl BodyMotion for Drift {
        fn at(&self, x0: [Real; 3], t: Real) -> ([Real; 3], [Real; 3]) {
            ([x0[0] + t, x0[1] + 2.0 * t, x0[2]], [1.0, 2.0, 0.0])
        }
        fn acceleration(&self, _x0: [Real; 3], _t: Real) -> [Real; 3] {
            [0.0; 3]
        }
    }

    #[test]
    fn a_law_is_read_in_the_scenes_vectors() {
        let (x, v) = motion_at(&Drift, DVec2::new(1.0, 1.0), 0.5);
        assert_eq!((x, v), (DVec2::new(1.5, 2.0), DVec2::new(1.0, 2.0)));
        assert_eq!(
            motion_at(&Hold, DVec2::new(3.0, 4.0), 9.0).0,
            DVec2::new(3.0, 4.0)
        );
        assert!(Hold.holds_still() && !Drift.holds_still());
    }

    #[test]
    fn a_body_is_a_fluid_exactly_when_it_has_no_motion() {
        assert!(Body::fluid("water").is_fluid());
        assert!(!Body::fixed("tank").is_fluid());
        assert!(!Body::moved_by("lid", Arc::new(Drift)).is_fluid());
    }
}
