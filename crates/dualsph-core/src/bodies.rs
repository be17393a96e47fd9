//! Bodies: every particle belongs to one ([`BodyId`], a column of the store), and a body has a
//! name and a [`BodyKind`]. Kinds are data, not marker components, so all particles stay in
//! one table. Plugins take their material parameters per body (e.g. the equation of state's
//! ρ0 and c0), and the diagnostics report mass, momentum and energy per body.
//!
//! A particle of a [`BodyKind::Fixed`] body keeps its initial position and zero velocity: it
//! takes part in every pair sum (its density and pressure evolve like a fluid particle's), and
//! the force the sweep computes on it is the fluid's load on the body (its `Acceleration`
//! times its mass), but the integrator's update is undone for it right after the predictor and
//! the corrector ([`pin_fixed`]).

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
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BodyKind {
    /// Integrated in time by the forces on them.
    Fluid,
    /// Held at their initial positions with zero velocity (a wall, a fixed obstacle).
    Fixed,
}

/// A body: its name and kind. Its index in [`Bodies`] is the [`BodyId`] of its particles.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Body {
    /// The scene's name for it.
    pub name: String,
    /// What moves it.
    pub kind: BodyKind,
}

/// The bodies of a simulation, indexed by [`BodyId`].
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct Bodies(pub Vec<Body>);

impl Default for Bodies {
    fn default() -> Self {
        Bodies(vec![Body {
            name: DEFAULT_BODY.into(),
            kind: BodyKind::Fluid,
        }])
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

/// Which bodies are fixed, by [`BodyId`].
#[derive(Resource, Clone, Debug, Default)]
pub struct FixedBodies(pub Vec<bool>);

/// Holds the particles of fixed bodies at their anchors with zero velocity.
#[inline(never)] // a frame of its own in profiles
pub fn pin_fixed<V: Vector>(
    fixed: Res<FixedBodies>,
    mut q: Query<(&BodyId, &Anchor<V>, &mut Position<V>, &mut Velocity<V>)>,
) {
    for (body, anchor, mut r, mut v) in q.contiguous_iter_mut().expect(DENSE) {
        (body, anchor, &mut *r, &mut *v)
            .into_par_iter()
            .with_min_len(MIN_LEN)
            .filter(|(b, ..)| fixed.0[b.0 as usize])
            .for_each(|(_, a, r, v)| {
                r.0 = a.0;
                v.0 = V::zero();
            });
    }
}

/// Sets the simulation's bodies (before the plugins are built) and, when one of them is
/// fixed, anchors its particles and pins them after the predictor and the corrector.
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
    let fixed: Vec<bool> = bodies.0.iter().map(|b| b.kind == BodyKind::Fixed).collect();
    sim.world.insert_resource(bodies);
    if fixed.iter().any(|&f| f) {
        let positions = crate::store::by_id::<Position<V>>(&mut sim.world);
        let spec = ColumnSpec::restart_only("anchor");
        sim.add_column(spec, move |id| Anchor(positions[id as usize].0))?;
        sim.world.insert_resource(FixedBodies(fixed));
        sim.add_system(
            StepSet::Predict,
            "pin_fixed (after the predictor)",
            pin_fixed::<V>,
        );
        sim.add_system(
            StepSet::Correct,
            "pin_fixed (after the corrector)",
            pin_fixed::<V>,
        );
    }
    Ok(())
}
