//! The particles of a [`Sim`]: spawning them with the core columns, and the columns plugins
//! add (see [`crate::columns`]).

use super::{InitialInternalEnergy, ParticleInit, Sim, SimError};
use crate::bodies::BodyId;
use crate::columns::{ColumnSpec, ColumnValue, Columns};
use crate::components::*;
use crate::math::Vector;
use bevy_ecs::prelude::*;

impl<V: Vector> Sim<V> {
    /// The columns every particle carries (see [`Sim::spawn_particles`]).
    pub(super) fn register_core_columns(&mut self) {
        use crate::columns::ColumnSpec as S;
        let cols = &mut *self.world.resource_mut::<Columns>();
        let core = [
            cols.register::<V, Position<V>>(S::state("position", "")),
            cols.register::<V, Velocity<V>>(S::state("velocity", "v")),
            cols.register::<V, Mass>(S::state("mass", "m")),
            cols.register::<V, Density>(S::state("density", "rho")),
            cols.register::<V, SmoothingLength>(S::state("smoothing_length", "h")),
            cols.register::<V, Acceleration<V>>(S::restart_only("acceleration")),
            cols.register::<V, BodyId>(S::state("body", "body")),
        ];
        for r in core {
            r.expect("the core columns have distinct names");
        }
    }

    /// Spawns particles with the core components; ids are `0..n` in the given order.
    pub fn spawn_particles(&mut self, particles: &[ParticleInit<V>]) {
        let start = self.particle_count() as u32;
        let mut eps = std::mem::take(&mut self.world.resource_mut::<InitialInternalEnergy>().0);
        for (k, p) in particles.iter().enumerate() {
            self.world.spawn((
                ParticleId(start + k as u32),
                Position(p.pos),
                Velocity(p.vel),
                Mass(p.mass),
                Density(p.density),
                SmoothingLength(p.h),
                Acceleration(V::zero()),
                BodyId(p.body),
            ));
            eps.push(p.internal_energy);
        }
        self.world.resource_mut::<InitialInternalEnergy>().0 = eps;
    }

    /// Number of particles (counted in the store).
    pub fn particle_count(&self) -> usize {
        crate::store::particle_count(&self.world)
    }

    /// Adds column `C` to every particle, with the value `init(id)`, and registers it (see
    /// [`crate::columns`]): whether it is written to snapshots and kept in checkpoints. Adding
    /// the same column again only sets the values again. The error names a column whose
    /// name another column has already.
    ///
    /// The values are put on the particles by [`Sim::finish`], every column of a particle at
    /// once: a particle then passes through the intermediate archetypes alone, so their
    /// tables never hold more than one row, and the memory peak of set-up is the core table
    /// and the final one (inserting column by column over all particles left a table of n
    /// rows behind in every intermediate archetype).
    pub fn add_column<C: ColumnValue<V>>(
        &mut self,
        spec: ColumnSpec,
        init: impl Fn(u32) -> C + Send + Sync + 'static,
    ) -> Result<(), SimError> {
        self.world
            .resource_mut::<Columns>()
            .register::<V, C>(spec)
            .map_err(SimError::Build)?;
        self.pending.push(Box::new(move |e, id| {
            e.insert(init(id));
        }));
        Ok(())
    }

    /// Puts the values of the columns added since the last call on the particles, particle
    /// by particle (see [`Sim::add_column`]).
    pub(super) fn insert_pending_columns(&mut self) {
        if self.pending.is_empty() {
            return;
        }
        let pending = std::mem::take(&mut self.pending);
        let entities: Vec<(Entity, u32)> = self
            .world
            .query::<(Entity, &ParticleId)>()
            .iter(&self.world)
            .map(|(e, id)| (e, id.0))
            .collect();
        for (e, id) in entities {
            let mut particle = self.world.entity_mut(e);
            for insert in &pending {
                insert(&mut particle, id);
            }
        }
    }
}
