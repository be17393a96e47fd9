//! The particles of a [`Sim`]: spawning them with the core columns, and the columns plugins
//! add (see [`crate::columns`]).

use crate::bodies::BodyId;
use crate::columns::{ColumnSpec, ColumnValue, Columns};
use crate::components::*;
use crate::math::Vector;
use crate::population::{
    ColumnInits, NextId, Population, Seed, apply_population, seed_columns, spawn_complete,
    spawn_core,
};
use crate::sim::{InitialInternalEnergy, ParticleInit, Sim, SimError, StepSet};
use crate::store::CoreColumns;
use bevy_ecs::prelude::*;

impl<V: Vector> Sim<V> {
    /// The columns every particle carries (see [`Sim::spawn_particles`]).
    pub(crate) fn register_core_columns(&mut self) {
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

    /// Spawns particles with the core components, with the next free ids in the given
    /// order (`0..n` for the first call). Before [`Sim::finish`] the other columns are put on
    /// them there; after it, at once (and the neighbour lists are dropped, to be rebuilt by
    /// the next step). The error says that the id space is exhausted.
    pub fn spawn_particles(&mut self, particles: &[ParticleInit<V>]) -> Result<(), SimError> {
        let first = self
            .world
            .resource_mut::<NextId>()
            .take(particles.len())
            .map_err(SimError::Build)?;
        if self.is_built() {
            spawn_complete(&mut self.world, first, particles);
            return Ok(());
        }
        spawn_core(&mut self.world, first, particles);
        let mut eps = self.world.resource_mut::<InitialInternalEnergy>();
        for (id, p) in (first..).zip(particles) {
            eps.set(id, p.internal_energy);
        }
        Ok(())
    }

    /// Number of particles (counted in the store).
    pub fn particle_count(&self) -> usize {
        crate::store::particle_count(&self.world)
    }

    /// Adds column `C` to every particle and registers it (see [`crate::columns`]): whether
    /// it is written to snapshots and kept in checkpoints. `init` gives a particle's initial
    /// value from its id and initial state ([`Seed`]); it is called for the scene's particles
    /// and for every particle a plugin adds during the run ([`crate::population`]). Adding
    /// the same column again only sets the values again. The error names a column whose
    /// name another column has already.
    ///
    /// The values are put on the scene's particles by [`Sim::finish`], every column of a
    /// particle at once: a particle then passes through the intermediate archetypes alone,
    /// so their tables never hold more than one row, and the memory peak of set-up is the
    /// core table and the final one (inserting column by column over all particles left a
    /// table of n rows behind in every intermediate archetype).
    pub fn add_column<C: ColumnValue<V>>(
        &mut self,
        spec: ColumnSpec,
        init: impl Fn(&Seed<V>) -> C + Send + Sync + 'static,
    ) -> Result<(), SimError> {
        self.world
            .resource_mut::<Columns>()
            .register::<V, C>(spec)
            .map_err(SimError::Build)?;
        self.world
            .resource_mut::<ColumnInits<V>>()
            .list
            .push(Box::new(move |e, seed| {
                e.insert(init(seed));
            }));
        Ok(())
    }

    /// Puts the values of the columns added since the last call on the particles, particle
    /// by particle, from each particle's seed: its core columns and its initial internal
    /// energy (see [`Sim::add_column`]). The initial internal energies are dropped after.
    pub(crate) fn insert_pending_columns(&mut self) {
        let eps = std::mem::take(&mut *self.world.resource_mut::<InitialInternalEnergy>());
        let mut inits = std::mem::take(&mut *self.world.resource_mut::<ColumnInits<V>>());
        if inits.applied < inits.list.len() {
            let seeded: Vec<(Entity, Seed<V>)> = self
                .world
                .query::<(Entity, &ParticleId, CoreColumns<V>, &BodyId)>()
                .iter(&self.world)
                .map(|(e, id, (r, v, m, rho, h), body)| {
                    let init = ParticleInit {
                        pos: r.0,
                        vel: v.0,
                        mass: m.0,
                        density: rho.0,
                        h: h.0,
                        internal_energy: eps.get(id.0),
                        body: body.0,
                    };
                    (e, Seed { id: id.0, init })
                })
                .collect();
            seed_columns(&mut self.world, &inits.list[inits.applied..], &seeded);
            inits.applied = inits.list.len();
        }
        *self.world.resource_mut::<ColumnInits<V>>() = inits;
    }

    /// Lets plugins add and remove particles during the run ([`crate::population`]): puts
    /// the [`Population`] resource in the world and the system that applies its requests
    /// at the end of [`crate::sim::StepSet::Population`] (once, however many plugins call
    /// this).
    pub fn enable_population(&mut self) {
        if self.enable::<Population<V>>() {
            self.add_finish_hook("population", add_population_system::<V>);
        }
    }
}

/// Adds the system that applies the plugins' requests to add and remove particles, once, when
/// the schedule is built: added last, it runs after every plugin's requests of the set.
fn add_population_system<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if !sim.is_built() {
        sim.add_system(
            StepSet::Population,
            "apply_population (add and remove particles)",
            apply_population::<V>,
        );
    }
    Ok(())
}
