//! A particle count that changes: plugins add and remove particles during a run (inflow,
//! outflow, refinement).
//!
//! A plugin asks through the [`Population`] resource: [`Population::spawn`] with a
//! particle's initial state, [`Population::remove`] with its entity. The requests are applied
//! by one core system, `apply_population`, at the end of [`StepSet::Population`] — the first
//! set of the step, so diagnostics, snapshots and checkpoints written after a step always see
//! a store whose neighbour lists match it. The system
//! - removes the particles asked for, in ascending id order (the store stays one dense
//!   table: bevy moves its last row into the hole, so the row order depends only on the
//!   requests, never on the thread count);
//! - spawns the new ones in request order, with ids from [`NextId`] (ids are never reused)
//!   and every registered column, each set to its initial value for that particle (the
//!   initialisers plugins gave [`Sim::add_column`]);
//! - drops the neighbour lists, so the step rebuilds them before any loop reads them.
//!
//! A new particle's acceleration and rates are zero until the step's force sweep: its first
//! predictor moves it with its initial velocity only.
//!
//! [`StepSet::Population`]: crate::sim::StepSet::Population
//! [`Sim::add_column`]: crate::sim::Sim::add_column

use crate::bodies::BodyId;
use crate::columns::Columns;
use crate::components::*;
use crate::math::Vector;
use crate::neighbours::Neighbours;
use crate::sim::{ParticleInit, StepFailure};
use bevy_ecs::prelude::*;

/// A particle's id and initial state: what a column's initial value is computed from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seed<V: Vector> {
    /// The particle's id.
    pub id: u32,
    /// Its initial state.
    pub init: ParticleInit<V>,
}

/// Puts one column's initial value on a particle.
pub type Initialiser<V> = Box<dyn Fn(&mut EntityWorldMut<'_>, &Seed<V>) + Send + Sync>;

/// The column initialisers of the scene, in the order they were added (a later one for the
/// same column overrides an earlier one).
#[derive(Resource)]
pub struct ColumnInits<V: Vector> {
    /// The initialisers.
    pub list: Vec<Initialiser<V>>,
    /// How many of them are on the scene's particles (see `Sim::add_column`).
    pub(crate) applied: usize,
}

impl<V: Vector> Default for ColumnInits<V> {
    fn default() -> Self {
        ColumnInits {
            list: Vec::new(),
            applied: 0,
        }
    }
}

/// The id the next particle gets: one more than the largest id ever given, so an id is
/// never reused (kept in checkpoints).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NextId(pub u32);

impl NextId {
    /// Takes `count` ids, or says why not (the 32-bit id space is exhausted).
    pub fn take(&mut self, count: usize) -> Result<u32, String> {
        let first = self.0;
        u32::try_from(count)
            .ok()
            .and_then(|c| first.checked_add(c))
            .map(|next| {
                self.0 = next;
                first
            })
            .ok_or_else(|| {
                format!(
                    "cannot give {count} more particle ids: {first} ids were given and ids \
                     are 32-bit and never reused"
                )
            })
    }
}

/// The particles plugins ask to add and remove this step, and the totals so far.
#[derive(Resource, Debug)]
pub struct Population<V: Vector> {
    spawns: Vec<ParticleInit<V>>,
    removals: Vec<Entity>,
    /// Particles added since the start of the run (of this process).
    pub spawned: u64,
    /// Particles removed since the start of the run (of this process).
    pub removed: u64,
}

impl<V: Vector> Default for Population<V> {
    fn default() -> Self {
        Population {
            spawns: Vec::new(),
            removals: Vec::new(),
            spawned: 0,
            removed: 0,
        }
    }
}

impl<V: Vector> Population<V> {
    /// Asks for a new particle.
    pub fn spawn(&mut self, particle: ParticleInit<V>) {
        self.spawns.push(particle);
    }

    /// Asks for the removal of a particle (asking twice removes it once).
    pub fn remove(&mut self, particle: Entity) {
        self.removals.push(particle);
    }

    /// Requests not applied yet.
    pub fn pending(&self) -> usize {
        self.spawns.len() + self.removals.len()
    }
}

/// Spawns particles with ids `first..` and the core columns only (the other columns are put
/// on them by [`seed_columns`]).
pub(crate) fn spawn_core<V: Vector>(
    world: &mut World,
    first: u32,
    particles: &[ParticleInit<V>],
) -> Vec<Entity> {
    particles
        .iter()
        .zip(first..)
        .map(|(p, id)| {
            world
                .spawn((
                    ParticleId(id),
                    Position(p.pos),
                    Velocity(p.vel),
                    Mass(p.mass),
                    Density(p.density),
                    SmoothingLength(p.h),
                    Acceleration(V::zero()),
                    BodyId(p.body),
                ))
                .id()
        })
        .collect()
}

/// Puts `inits` on each entity, particle by particle, from its seed: a particle passes
/// through the intermediate archetypes alone, so their tables never hold more than one row.
pub(crate) fn seed_columns<V: Vector>(
    world: &mut World,
    inits: &[Initialiser<V>],
    seeded: &[(Entity, Seed<V>)],
) {
    for (e, seed) in seeded {
        let mut particle = world.entity_mut(*e);
        for init in inits {
            init(&mut particle, seed);
        }
    }
}

/// Spawns particles with ids `first..`, every column from its initialiser, and drops the
/// neighbour lists (the rows changed); gives their entities in order.
pub(crate) fn spawn_complete<V: Vector>(
    world: &mut World,
    first: u32,
    particles: &[ParticleInit<V>],
) -> Vec<Entity> {
    let entities = spawn_core(world, first, particles);
    let seeded: Vec<(Entity, Seed<V>)> = entities
        .iter()
        .copied()
        .zip(first..)
        .zip(particles)
        .map(|((e, id), &init)| (e, Seed { id, init }))
        .collect();
    world.resource_scope(|world, inits: Mut<ColumnInits<V>>| {
        seed_columns(world, &inits.list, &seeded);
    });
    world.resource_mut::<Neighbours<V>>().invalidate();
    entities
}

/// Applies the requests in [`Population`] (see the module docs).
#[inline(never)] // a frame of its own in profiles
pub fn apply_population<V: Vector>(world: &mut World) {
    let (spawns, removals) = {
        let mut p = world.resource_mut::<Population<V>>();
        if p.pending() == 0 {
            return;
        }
        (
            std::mem::take(&mut p.spawns),
            std::mem::take(&mut p.removals),
        )
    };
    let mut doomed: Vec<(u32, Entity)> = removals
        .into_iter()
        .filter_map(|e| world.get::<ParticleId>(e).map(|id| (id.0, e)))
        .collect();
    doomed.sort_unstable();
    doomed.dedup();
    for &(_, e) in &doomed {
        world.despawn(e);
    }
    let first = match world.resource_mut::<NextId>().take(spawns.len()) {
        Ok(first) => first,
        Err(e) => {
            world
                .resource_mut::<StepFailure>()
                .fail(|| format!("particles could not be added: {e}"));
            return;
        }
    };
    spawn_complete(world, first, &spawns);
    let mut p = world.resource_mut::<Population<V>>();
    p.spawned += spawns.len() as u64;
    p.removed += doomed.len() as u64;
}

/// The core state a split or a merge gives a particle: the rest of its columns come from the
/// particles it is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoreState<V: Vector> {
    /// Position.
    pub pos: V,
    /// Velocity.
    pub vel: V,
    /// Mass.
    pub mass: crate::math::Real,
    /// Density.
    pub density: crate::math::Real,
    /// Support radius.
    pub h: crate::math::Real,
}

/// Writes `state` on particle `e`.
fn set_core<V: Vector>(world: &mut World, e: Entity, state: &CoreState<V>) {
    let mut p = world.entity_mut(e);
    p.insert((
        Position(state.pos),
        Velocity(state.vel),
        Mass(state.mass),
        Density(state.density),
        SmoothingLength(state.h),
    ));
}

/// Splits `parent` into `children`: the parent becomes the first child, in place (it keeps
/// its id), and every other child is a new particle, with the next ids in order, that
/// carries a copy of every registered column of the parent (its body, acceleration, rates,
/// internal energy, …) before its core state is set from `children`. A split makes what is
/// conserved of the children's core state the caller's to choose; everything else is the
/// parent's. The neighbour lists are dropped. The error says the id space is exhausted (and
/// nothing is changed).
pub fn split_particle<V: Vector>(
    world: &mut World,
    parent: Entity,
    children: &[CoreState<V>],
) -> Result<(), String> {
    let Some((first, rest)) = children.split_first() else {
        return Ok(());
    };
    let id0 = world.resource_mut::<NextId>().take(rest.len())?;
    let body = world.get::<BodyId>(parent).map_or(0, |b| b.0);
    let inits: Vec<ParticleInit<V>> = rest
        .iter()
        .map(|c| ParticleInit {
            pos: c.pos,
            vel: c.vel,
            mass: c.mass,
            density: c.density,
            h: c.h,
            internal_energy: 0.0,
            body,
        })
        .collect();
    let entities = spawn_complete(world, id0, &inits);
    world.resource_scope(|world, columns: Mut<Columns>| {
        for &e in &entities {
            for c in columns.iter() {
                c.copy_value(world, parent, e);
            }
        }
    });
    set_core(world, parent, first);
    for (e, c) in entities.iter().zip(rest) {
        set_core(world, *e, c);
    }
    world.resource_mut::<Population<V>>().spawned += rest.len() as u64;
    Ok(())
}

/// Merges particle `absorbed` into `kept`, which keeps its id: every registered column of
/// `kept` becomes the mass-weighted mean `(m_k C_k + m_a C_a)/(m_k + m_a)` of the two (the
/// mean that conserves `Σ m C` of a quantity per unit mass: velocity, internal energy,
/// rates), then its core state is set from `merged`, and `absorbed` is removed. The body
/// stays the kept particle's (the caller merges particles of one body). The neighbour lists
/// are dropped.
pub fn merge_particles<V: Vector>(
    world: &mut World,
    kept: Entity,
    absorbed: Entity,
    merged: &CoreState<V>,
) {
    let mass = |e| world.get::<Mass>(e).map_or(0.0, |m| m.0);
    let (mk, ma) = (mass(kept), mass(absorbed));
    let total = mk + ma;
    world.resource_scope(|world, columns: Mut<Columns>| {
        // the body is a label, not a quantity: both particles are of the kept one's body
        for c in columns.iter().filter(|c| !c.is::<BodyId>()) {
            c.blend_values(world, kept, [(kept, mk / total), (absorbed, ma / total)]);
        }
    });
    set_core(world, kept, merged);
    world.despawn(absorbed);
    world.resource_mut::<Population<V>>().removed += 1;
    world.resource_mut::<Neighbours<V>>().invalidate();
}

/// Replaces every particle by `seeds` (their ids and initial states, in row order), with
/// every registered column set from its initialiser, and drops the neighbour lists: what a
/// resumed run does when the checkpoint's particles are not the scene's (a run whose count
/// changed). The error names a repeated id or one at or past `next`.
pub fn replace_particles<V: Vector>(world: &mut World, seeds: &[Seed<V>]) -> Result<(), String> {
    let next = world.resource::<NextId>().0;
    let mut ids: Vec<u32> = seeds.iter().map(|s| s.id).collect();
    ids.sort_unstable();
    if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!("particle id {} appears twice", w[0]));
    }
    if let Some(&last) = ids.last().filter(|&&id| id >= next) {
        return Err(format!(
            "particle id {last} is not below the next id {next}"
        ));
    }
    let old: Vec<Entity> = world
        .query_filtered::<Entity, With<ParticleId>>()
        .iter(world)
        .collect();
    for e in old {
        world.despawn(e);
    }
    let mut seeded = Vec::with_capacity(seeds.len());
    for s in seeds {
        let e = spawn_core(world, s.id, std::slice::from_ref(&s.init));
        seeded.push((e[0], *s));
    }
    world.resource_scope(|world, inits: Mut<ColumnInits<V>>| {
        seed_columns(world, &inits.list, &seeded);
    });
    world.resource_mut::<Neighbours<V>>().invalidate();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[derive(Component, Debug, PartialEq)]
    struct Tag(u32);

    fn init(x: f64) -> ParticleInit<DVec2> {
        ParticleInit {
            pos: DVec2::new(x, 0.0),
            vel: DVec2::ZERO,
            mass: 1.0,
            density: 1.0,
            h: 0.1,
            internal_energy: 0.0,
            body: 0,
        }
    }

    /// A world with three particles carrying `Tag` (id + 100) and lists built for them.
    fn world() -> World {
        let mut world = World::new();
        let mut inits = ColumnInits::<DVec2>::default();
        inits.list.push(Box::new(|e, seed| {
            e.insert(Tag(seed.id + 100));
        }));
        world.insert_resource(inits);
        world.insert_resource(NextId(0));
        world.insert_resource(Population::<DVec2>::default());
        let mut nb = Neighbours::<DVec2>::new(0.0);
        let pts = [DVec2::ZERO, DVec2::X * 0.05, DVec2::X * 0.1];
        nb.rebuild(&pts, &[0.1; 3]);
        world.insert_resource(nb);
        let seeds: Vec<Seed<DVec2>> = (0..3)
            .map(|id| Seed {
                id,
                init: init(0.05 * id as f64),
            })
            .collect();
        world.resource_mut::<NextId>().0 = 3;
        replace_particles(&mut world, &seeds).unwrap();
        world
    }

    fn rows(world: &mut World) -> Vec<(u32, u32)> {
        world
            .query::<(&ParticleId, &Tag)>()
            .iter(world)
            .map(|(id, t)| (id.0, t.0))
            .collect()
    }

    #[test]
    fn requests_are_applied_in_id_order_with_fresh_ids_and_every_column() {
        let mut world = world();
        assert_eq!(rows(&mut world), [(0, 100), (1, 101), (2, 102)]);
        let entities: Vec<Entity> = world
            .query_filtered::<Entity, With<ParticleId>>()
            .iter(&world)
            .collect();
        {
            let mut p = world.resource_mut::<Population<DVec2>>();
            // asked out of order and twice: removed once each, the lowest id first
            p.remove(entities[1]);
            p.remove(entities[0]);
            p.remove(entities[1]);
            p.spawn(init(0.5));
            p.spawn(init(0.6));
        }
        apply_population::<DVec2>(&mut world);
        // removing id 0 moves the last row (2) into row 0; removing id 1 moves nothing
        assert_eq!(rows(&mut world), [(2, 102), (3, 103), (4, 104)]);
        assert_eq!(crate::store::particle_tables(&world), 1);
        assert_eq!(world.resource::<NextId>().0, 5);
        let p = world.resource::<Population<DVec2>>();
        assert_eq!((p.spawned, p.removed, p.pending()), (2, 2, 0));
        let nb = world.resource::<Neighbours<DVec2>>();
        assert!(nb.dirty && nb.support.rows() == 0, "the lists are dropped");
    }

    #[test]
    fn replacing_the_particles_refuses_repeated_or_unissued_ids() {
        let mut world = world();
        let seed = |id| Seed {
            id,
            init: init(0.0),
        };
        let e = replace_particles(&mut world, &[seed(1), seed(1)]).unwrap_err();
        assert!(e.contains("twice"), "{e}");
        let e = replace_particles(&mut world, &[seed(3)]).unwrap_err();
        assert!(e.contains("next id 3"), "{e}");
        assert_eq!(
            rows(&mut world).len(),
            3,
            "a refused replacement changes nothing"
        );
    }

    #[test]
    fn ids_are_taken_in_order_and_never_past_the_32_bit_space() {
        let mut next = NextId(5);
        assert_eq!(next.take(3), Ok(5));
        assert_eq!(next, NextId(8));
        let mut full = NextId(u32::MAX - 1);
        assert_eq!(full.take(1), Ok(u32::MAX - 1));
        let e = full.take(2).unwrap_err();
        assert!(e.contains("never reused"), "{e}");
        assert_eq!(full, NextId(u32::MAX), "a refused take gives no id");
    }
}
