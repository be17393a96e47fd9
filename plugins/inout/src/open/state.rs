//! The state of the open boundaries: each boundary's settings as built ([`Boundary`]), the
//! list of them ([`Boundaries`]), and the column of a buffer particle's velocity and density
//! ([`BufferState`]).

use super::profile::{Profile, ramp_factor, ramp_integral};
use super::zone::Zone;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_fluid::prelude::*;

/// What an inflow prescribes, and the particle it creates.
#[derive(Clone, Debug)]
pub struct Inflow<V: Vector> {
    /// The speed across the section.
    pub profile: Profile,
    /// The ramp time T (s).
    pub ramp: Real,
    /// A new buffer particle (mass, h, internal energy, body).
    pub template: ParticleInit<V>,
}

/// One open boundary.
#[derive(Clone, Debug)]
pub struct Boundary<V: Vector> {
    /// Its buffer zone.
    pub zone: Zone<V>,
    /// The body of its buffer particles.
    pub buffer: u16,
    /// The fluid body.
    pub fluid: u16,
    /// `Some` for an inflow.
    pub inflow: Option<Inflow<V>>,
    /// A prescribed pressure (Pa).
    pub pressure: Option<Real>,
    /// For a non-reflecting outflow, the relaxation time τ (s) of its mean velocity
    /// ([`super::impedance`]).
    pub non_reflecting: Option<Real>,
}

impl<V: Vector> Boundary<V> {
    /// How far an inflow carries its buffer particle at `x` from time `t0` to `t1`:
    /// `n u(x) (S(t1) − S(t0))`, the exact travel of the ramped speed
    /// ([`super::profile::ramp_integral`]); zero for an outflow.
    pub(crate) fn inflow_travel(&self, x: V, t0: Real, t1: Real) -> V {
        match &self.inflow {
            Some(i) => {
                let travel = ramp_integral(i.ramp, t1) - ramp_integral(i.ramp, t0);
                self.zone.normal() * i.profile.speed(&self.zone, x) * travel
            }
            None => V::zero(),
        }
    }

    /// The prescribed velocity of an inflow's buffer particle at `x` at time `t`.
    pub(crate) fn inflow_velocity(&self, x: V, t: Real) -> V {
        match &self.inflow {
            Some(i) => {
                self.zone.normal() * (i.profile.speed(&self.zone, x) * ramp_factor(i.ramp, t))
            }
            None => V::zero(),
        }
    }
}

/// The boundaries of the scene, in the order built, and the boundary of each buffer body.
#[derive(Resource, Clone, Debug)]
pub struct Boundaries<V: Vector> {
    /// The boundaries.
    pub list: Vec<Boundary<V>>,
    /// By `BodyId`: the boundary whose buffer it is.
    pub of_body: Vec<Option<usize>>,
}

/// A buffer particle's velocity and density, as its boundary set them (kept in checkpoints).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct BufferState<V: Vector> {
    /// Its velocity.
    pub v: V,
    /// Its density.
    pub rho: Real,
}

impl<V: Vector> ColumnValue<V> for BufferState<V> {
    const SHAPE: Shape = Shape::Record;
    fn width() -> usize {
        V::DIM + 1
    }
    fn put(&self, out: &mut Vec<Real>) {
        dualsph_core::columns::put_vector(self.v, out);
        out.push(self.rho);
    }
    fn take(&mut self, values: &[Real]) {
        self.v = dualsph_core::columns::take_vector(values);
        self.rho = values[V::DIM];
    }
}
