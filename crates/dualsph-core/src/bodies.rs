//! Bodies: every particle belongs to one ([`BodyId`], a column of the store), and a body has a
//! name and a [`BodyKind`]. Kinds are data, not marker components, so all particles stay in
//! one table. Plugins take their material parameters per body (e.g. the equation of state's
//! ρ0 and c0), and the diagnostics report mass, momentum and energy per body.
//!
//! A particle of a [`BodyKind::Fixed`] body keeps its initial position and zero velocity; one
//! of a [`BodyKind::Prescribed`] body moves by its [`Motion`], a given function of time. Such
//! a particle takes part in every pair sum (its density and pressure evolve like a fluid
//! particle's, and its velocity enters the pair terms, so a moving wall drags and pushes the
//! fluid), and the force the sweep computes on it is the fluid's load on the body (its
//! `Acceleration` times its mass: body forces act on fluid bodies only, and the diagnostics
//! sum the loads per body about [`Body::moment_about`]), but the integrator's update of its
//! position and velocity is replaced by the body's law right after the predictor and the
//! corrector ([`drive_bodies`]).

use crate::chunks::{DENSE, MIN_LEN};
use crate::columns::{ColumnSpec, ColumnValue, Shape};
use crate::components::{Position, Velocity};
use crate::math::{Real, Vector};
use crate::sim::{Sim, SimError, StepSet};
use bevy_ecs::prelude::*;
use rayon::prelude::*;

/// The name of the one body of a scene that declares none.
pub const DEFAULT_BODY: &str = "fluid";

/// What moves a body's particles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BodyKind {
    /// Integrated in time by the forces on them.
    Fluid,
    /// Held at their initial positions with zero velocity (a wall, a fixed obstacle).
    Fixed,
    /// Moved by a given law of time (a piston, a flap, a lid), whatever the forces on them.
    Prescribed(Motion),
}

/// A rigid motion given as a function of time `t` (from the start of the run), for a particle
/// that starts at `x_0`: its position `x(t)` and velocity `v(t) = dx/dt`. Vectors have the
/// scene's dimension in their first components (the rest is ignored).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// `x(t) = x_0 + u t`, `v = u`.
    Translate {
        /// `u`.
        velocity: [Real; 3],
    },
    /// `x(t) = x_0 + A (sin(ωt + φ) − sin φ)`, `v(t) = A ω cos(ωt + φ)`, with `ω = 2π f`.
    Oscillate {
        /// `A`.
        amplitude: [Real; 3],
        /// `f` (Hz).
        frequency: Real,
        /// `φ` (rad).
        phase: Real,
    },
    /// A surface that moves along itself at `u` (a belt, the lid of a cavity): `x(t) = x_0`,
    /// `v = u`. The particles stay where they are and carry the velocity into the fluid's
    /// equations; it stands for a wall that the motion maps onto itself (a plane wall moved
    /// along its plane), longer than the run would carry it.
    Slide {
        /// `u`.
        velocity: [Real; 3],
    },
    /// A rotation at the constant rate `Ω` about the axis through `c` along the unit vector
    /// `n` (the z axis in 2-D): `x(t) = c + R(Ωt)(x_0 − c)` with Rodrigues' rotation
    /// `R(θ)y = y cos θ + (n × y) sin θ + n (n·y)(1 − cos θ)`, and `v = Ω n × (x − c)`.
    Rotate {
        /// `c`.
        center: [Real; 3],
        /// `n` (normalised when the motion is built; ignored in 2-D).
        axis: [Real; 3],
        /// `Ω` (rad/s, counter-clockwise about `n`).
        omega: Real,
    },
}

impl Motion {
    /// `(x(t), v(t))` of a particle that starts at `x0`.
    pub fn at<V: Vector>(&self, x0: V, t: Real) -> (V, V) {
        let vec = |a: &[Real; 3]| V::from_slice(&a[..V::DIM]).expect("DIM <= 3");
        match *self {
            Motion::Translate { velocity } => {
                let u = vec(&velocity);
                (x0 + u * t, u)
            }
            Motion::Slide { velocity } => (x0, vec(&velocity)),
            Motion::Oscillate {
                amplitude,
                frequency,
                phase,
            } => {
                let (a, w) = (vec(&amplitude), 2.0 * std::f64::consts::PI * frequency);
                let arg = w * t + phase;
                (x0 + a * (arg.sin() - phase.sin()), a * (w * arg.cos()))
            }
            Motion::Rotate {
                center,
                axis,
                omega,
            } => {
                let c = vec(&center);
                let n = if V::DIM == 3 { axis } else { [0.0, 0.0, 1.0] };
                let (y, th) = (x0 - c, omega * t);
                let cross = |a: [Real; 3], b: [Real; 3]| {
                    [
                        a[1] * b[2] - a[2] * b[1],
                        a[2] * b[0] - a[0] * b[2],
                        a[0] * b[1] - a[1] * b[0],
                    ]
                };
                let y3 = y.to_xyz();
                let ny = n[0] * y3[0] + n[1] * y3[1] + n[2] * y3[2];
                let nxy = cross(n, y3);
                let (s, co) = th.sin_cos();
                let r: [Real; 3] =
                    std::array::from_fn(|k| y3[k] * co + nxy[k] * s + n[k] * ny * (1.0 - co));
                let v = cross(n, r).map(|x| x * omega);
                (c + vec(&r), vec(&v))
            }
        }
    }

    /// The acceleration `a(t) = dv/dt` of a particle that starts at `x0`: zero for a
    /// translation, `−A ω² sin(ωt + φ)` for an oscillation, `Ω n × v` (centripetal) for a
    /// rotation.
    pub fn acceleration<V: Vector>(&self, x0: V, t: Real) -> V {
        match *self {
            Motion::Translate { .. } | Motion::Slide { .. } => V::zero(),
            Motion::Oscillate {
                amplitude,
                frequency,
                phase,
            } => {
                let w = 2.0 * std::f64::consts::PI * frequency;
                let a = V::from_slice(&amplitude[..V::DIM]).expect("DIM <= 3");
                a * (-w * w * (w * t + phase).sin())
            }
            Motion::Rotate { axis, omega, .. } => {
                let n = if V::DIM == 3 { axis } else { [0.0, 0.0, 1.0] };
                let v = self.at(x0, t).1.to_xyz();
                let a = [
                    n[1] * v[2] - n[2] * v[1],
                    n[2] * v[0] - n[0] * v[2],
                    n[0] * v[1] - n[1] * v[0],
                ];
                V::from_slice(&a.map(|x| x * omega)[..V::DIM]).expect("DIM <= 3")
            }
        }
    }

    /// The motion with a rotation's axis normalised; the error names what is wrong.
    pub fn checked(self) -> Result<Self, String> {
        let finite = |xs: &[Real]| xs.iter().all(|x| x.is_finite());
        match self {
            Motion::Translate { velocity } | Motion::Slide { velocity } if finite(&velocity) => {
                Ok(self)
            }
            Motion::Oscillate {
                amplitude,
                frequency,
                phase,
            } if finite(&amplitude) && finite(&[frequency, phase]) && frequency >= 0.0 => Ok(self),
            Motion::Rotate {
                center,
                axis,
                omega,
            } if finite(&center) && finite(&axis) && omega.is_finite() => {
                let len = axis.iter().map(|x| x * x).sum::<Real>().sqrt();
                if len > 0.0 {
                    let axis = axis.map(|x| x / len);
                    Ok(Motion::Rotate {
                        center,
                        axis,
                        omega,
                    })
                } else {
                    Err("the rotation axis is zero".into())
                }
            }
            _ => Err(format!(
                "a motion needs finite values (frequency >= 0): {self:?}"
            )),
        }
    }
}

/// A body: its name and kind. Its index in [`Bodies`] is the [`BodyId`] of its particles.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The scene's name for it.
    pub name: String,
    /// What moves it.
    pub kind: BodyKind,
    /// The point `c` the moment of the load on a fixed or prescribed body is taken about,
    /// `M = Σ_i (x_i − c) × f_i` (3-D embedding; the origin by default).
    pub moment_about: [Real; 3],
}

impl Body {
    /// A body named `name` of kind `kind`, its moment taken about the origin.
    pub fn new(name: impl Into<String>, kind: BodyKind) -> Self {
        Body {
            name: name.into(),
            kind,
            moment_about: [0.0; 3],
        }
    }

    /// True for a body whose particles are integrated (a fluid), false for one whose motion
    /// is given (fixed or prescribed): a body with a load.
    pub fn is_fluid(&self) -> bool {
        self.kind == BodyKind::Fluid
    }
}

/// The bodies of a simulation, indexed by [`BodyId`].
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct Bodies(pub Vec<Body>);

impl Default for Bodies {
    fn default() -> Self {
        Bodies(vec![Body::new(DEFAULT_BODY, BodyKind::Fluid)])
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
/// [`BodyId`]: `None` for a fluid, the motion for a prescribed body, and a translation at zero
/// velocity for a fixed one (which leaves the initial position bitwise unchanged).
#[derive(Resource, Clone, Debug, Default)]
pub struct DrivenBodies(pub Vec<Option<Motion>>);

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
    let t = clock.t + clock.dt;
    for (body, anchor, mut r, mut v) in q.contiguous_iter_mut().expect(DENSE) {
        let (r, v) = (r.bypass_change_detection(), v.bypass_change_detection());
        (body, anchor, r, v)
            .into_par_iter()
            .with_min_len(MIN_LEN)
            .for_each(|(b, a, r, v)| match driven.0[b.0 as usize] {
                None => {}
                Some(Motion::Translate { velocity }) if velocity == [0.0; 3] => {
                    r.0 = a.0;
                    v.0 = V::zero();
                }
                Some(m) => (r.0, v.0) = m.at(a.0, t),
            });
    }
}

/// Sets the simulation's bodies (before the plugins are built) and, when one of them is
/// fixed or prescribed, anchors the particles and drives them after the predictor and the
/// corrector ([`drive_bodies`]), having set those of prescribed bodies to their law at t = 0.
/// The error names a particle whose body does not exist, or a motion that is not valid.
pub fn install_bodies<V: Vector>(sim: &mut Sim<V>, bodies: Bodies) -> Result<(), SimError> {
    let n = bodies.0.len();
    let mut q = sim.world.query::<&BodyId>();
    if let Some(b) = q.iter(&sim.world).find(|b| b.0 as usize >= n) {
        return Err(SimError::Build(format!(
            "a particle belongs to body {}, but there are {n} bodies",
            b.0
        )));
    }
    let mut driven = Vec::with_capacity(n);
    for b in &bodies.0 {
        driven.push(match b.kind {
            BodyKind::Fluid => None,
            BodyKind::Fixed => Some(Motion::Translate { velocity: [0.0; 3] }),
            BodyKind::Prescribed(m) => Some(
                m.checked()
                    .map_err(|e| SimError::Build(format!("body `{}`: {e}", b.name)))?,
            ),
        });
    }
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
fn set_velocities_at_start<V: Vector>(world: &mut World, driven: &[Option<Motion>]) {
    let mut q = world.query::<(&BodyId, &Position<V>, &mut Velocity<V>)>();
    for (b, r, mut v) in q.iter_mut(world) {
        if let Some(m) = driven[b.0 as usize] {
            v.0 = m.at(r.0, 0.0).1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};
    use std::f64::consts::PI;

    fn close(a: Real, b: Real) -> bool {
        (a - b).abs() <= 1e-14 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn a_translation_moves_at_its_velocity() {
        let m = Motion::Translate {
            velocity: [0.5, -2.0, 0.0],
        };
        let (x, v) = m.at(DVec2::new(1.0, 1.0), 0.4);
        assert!(close(x.x, 1.2) && close(x.y, 0.2), "{x}");
        assert_eq!(v, DVec2::new(0.5, -2.0));
    }

    /// Starts at x0 with v(0) = Aω cos φ, and v is dx/dt (central difference, step 1e-6 s).
    #[test]
    fn an_oscillation_starts_at_its_anchor_with_the_derivative_as_velocity() {
        let m = Motion::Oscillate {
            amplitude: [0.1, 0.0, 0.0],
            frequency: 2.0,
            phase: 0.3,
        };
        let x0 = DVec2::new(1.0, 0.5);
        let (x, v) = m.at(x0, 0.0);
        assert_eq!(x, x0);
        assert!(close(v.x, 0.1 * 4.0 * PI * 0.3f64.cos()));
        let (t, e) = (0.37, 1e-6);
        let dx = (m.at(x0, t + e).0 - m.at(x0, t - e).0) / (2.0 * e);
        let v = m.at(x0, t).1;
        assert!((dx.x - v.x).abs() < 1e-8 * v.x.abs(), "{dx} vs {v}");
        assert_eq!(dx.y, 0.0);
    }

    /// A quarter turn about c takes c + (1, 0) to c + (0, 1) with speed Ω|x − c| along −x.
    #[test]
    fn a_rotation_in_2d_turns_about_its_center() {
        let m = Motion::Rotate {
            center: [2.0, 1.0, 0.0],
            axis: [0.0, 0.0, 1.0],
            omega: 3.0,
        };
        let (x, v) = m.at(DVec2::new(3.0, 1.0), PI / 6.0);
        assert!(close(x.x, 2.0) && close(x.y, 2.0), "{x}");
        assert!(
            v.x.abs() > 0.0 && close(v.x, -3.0) && v.y.abs() < 1e-14,
            "{v}"
        );
    }

    /// About the x axis (given unnormalised): y → z after a quarter turn, x unchanged.
    #[test]
    fn a_rotation_in_3d_turns_about_its_axis() {
        let m = Motion::Rotate {
            center: [0.0; 3],
            axis: [2.0, 0.0, 0.0],
            omega: 1.0,
        }
        .checked()
        .unwrap();
        let (x, _) = m.at(DVec3::new(0.7, 1.0, 0.0), PI / 2.0);
        assert!(
            close(x.x, 0.7) && x.y.abs() < 1e-15 && close(x.z, 1.0),
            "{x}"
        );
    }

    /// The acceleration is dv/dt (central difference, step 1e-6 s) for each law.
    #[test]
    fn the_acceleration_is_the_derivative_of_the_velocity() {
        let laws = [
            Motion::Translate {
                velocity: [0.5, -2.0, 0.0],
            },
            Motion::Oscillate {
                amplitude: [0.1, -0.2, 0.0],
                frequency: 2.0,
                phase: 0.3,
            },
            Motion::Rotate {
                center: [2.0, 1.0, 0.0],
                axis: [0.0, 0.0, 1.0],
                omega: 3.0,
            },
        ];
        let (x0, t, e) = (DVec2::new(3.0, 1.5), 0.37, 1e-6);
        for m in laws {
            let dv = (m.at(x0, t + e).1 - m.at(x0, t - e).1) / (2.0 * e);
            let a = m.acceleration(x0, t);
            assert!(
                (dv - a).length() < 1e-7 * (1.0 + a.length()),
                "{m:?}: {dv} vs {a}"
            );
        }
    }

    #[test]
    fn invalid_motions_are_refused_with_the_reason() {
        let zero_axis = Motion::Rotate {
            center: [0.0; 3],
            axis: [0.0; 3],
            omega: 1.0,
        };
        assert!(zero_axis.checked().unwrap_err().contains("axis is zero"));
        let nan = Motion::Oscillate {
            amplitude: [Real::NAN, 0.0, 0.0],
            frequency: 1.0,
            phase: 0.0,
        };
        assert!(nan.checked().unwrap_err().contains("finite"));
    }
}
