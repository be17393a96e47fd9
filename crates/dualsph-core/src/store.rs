//! The particle store: the ECS components of the particles, read and written in place.
//!
//! Every particle carries the same set of components (kinds and bodies are data, never marker
//! components), so all particles live in **one bevy table** and every component is one
//! contiguous column. A particle's **row** in that table is its index in every neighbour
//! list and per-particle loop; the hot loops read the columns as slices
//! ([`ParticleData`], [`column()`]) and write them through typed queries
//! (`Query::contiguous_iter_mut`, [`single_table`]). No copy of the state is kept anywhere
//! else.

use crate::components::*;
use crate::math::{Real, Vector};
use bevy_ecs::prelude::*;

/// The item of a query over the particles' single table, or `None` when there are no
/// particles. Every particle has the same components (see the module docs), so a second
/// table means a plugin gave a component to only some particles — an engine bug, refused
/// by [`crate::sim::Sim::finish`] before any step runs.
pub fn single_table<T>(mut tables: impl Iterator<Item = T>) -> Option<T> {
    let first = tables.next();
    assert!(
        tables.next().is_none(),
        "particles span several tables: a component was added to only some of them"
    );
    first
}

/// The column of component `C` over the particles (row order), or `None` when the particles
/// do not have it (or span several tables). Empty when there are no particles.
pub fn column<C: Component>(world: &World) -> Option<&[C]> {
    let mut state = world.try_query::<&C>()?;
    let mut tables = state.contiguous_iter(world).ok()?;
    match (tables.next(), tables.next()) {
        (Some(rows), None) => Some(rows),
        (None, _) if particle_count(world) == 0 => Some(&[]),
        _ => None,
    }
}

/// Number of particles (entities with a [`ParticleId`]).
pub fn particle_count(world: &World) -> usize {
    let Some(mut state) = world.try_query::<&ParticleId>() else {
        return 0;
    };
    state
        .contiguous_iter(world)
        .map_or(0, |tables| tables.map(<[ParticleId]>::len).sum())
}

/// Number of tables holding particles: 1 for a sound store, 0 without particles.
pub fn particle_tables(world: &World) -> usize {
    let Some(mut state) = world.try_query::<&ParticleId>() else {
        return 0;
    };
    state.contiguous_iter(world).map_or(0, Iterator::count)
}

/// The core columns in a query (`Query<(CoreColumns<V>, &mut Out)>`): its table slices make a
/// [`ParticleData`] with [`ParticleData::from_columns`].
pub type CoreColumns<V> = (
    &'static Position<V>,
    &'static Velocity<V>,
    &'static Mass,
    &'static Density,
    &'static SmoothingLength,
);

/// Read access to the particles' core columns, by row: what every neighbour loop reads.
/// Other columns are fetched by type with [`ParticleData::column`] (once per sweep, not per
/// pair).
#[derive(Clone, Copy)]
pub struct ParticleData<'w, V: Vector> {
    /// `r_i`.
    pub pos: &'w [Position<V>],
    /// `v_i`.
    pub vel: &'w [Velocity<V>],
    /// `m_i`.
    pub mass: &'w [Mass],
    /// `ρ_i`.
    pub rho: &'w [Density],
    /// `h_i`.
    pub h: &'w [SmoothingLength],
    world: Option<&'w World>,
}

impl<V: Vector> std::fmt::Debug for ParticleData<'_, V> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ParticleData({} particles)", self.len())
    }
}

impl<'w, V: Vector> ParticleData<'w, V> {
    /// The core columns of `world`'s particles; `None` when a core column is missing or the
    /// particles are not one table.
    pub fn of(world: &'w World) -> Option<Self> {
        Some(ParticleData {
            pos: column(world)?,
            vel: column(world)?,
            mass: column(world)?,
            rho: column(world)?,
            h: column(world)?,
            world: Some(world),
        })
    }

    /// The core columns from the slices of a [`CoreColumns`] query item, without access to
    /// other columns ([`ParticleData::column`] gives `None`): for loops that write another
    /// column of the same table through a typed query.
    pub fn from_columns(
        (pos, vel, mass, rho, h): (
            &'w [Position<V>],
            &'w [Velocity<V>],
            &'w [Mass],
            &'w [Density],
            &'w [SmoothingLength],
        ),
    ) -> Self {
        ParticleData {
            pos,
            vel,
            mass,
            rho,
            h,
            world: None,
        }
    }

    /// Number of particles.
    #[inline]
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True without particles.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// `m_i / ρ_i`.
    #[inline(always)]
    pub fn volume(&self, i: usize) -> Real {
        self.mass[i].0 / self.rho[i].0
    }

    /// `v_i − v_j`.
    #[inline(always)]
    pub fn vij(&self, i: usize, j: usize) -> V {
        self.vel[i].0 - self.vel[j].0
    }

    /// The column of `C`, or `None` when no particle has it.
    pub fn column<C: Component>(&self) -> Option<&'w [C]> {
        self.world.and_then(column::<C>)
    }

    /// The column of `C` that `who` reads; the error says that no plugin added it.
    pub fn require<C: Component>(&self, who: &str) -> Result<&'w [C], String> {
        self.column::<C>().ok_or_else(|| {
            format!(
                "{who} reads {}, which no plugin of the scene adds",
                crate::names::short_type_name(std::any::type_name::<C>())
            )
        })
    }
}

/// Every particle's `C`, in id order (for set-up code that computes a new column from an
/// existing one).
pub fn by_id<C: Component + Copy>(world: &mut World) -> Vec<C> {
    let mut rows: Vec<(u32, C)> = world
        .query::<(&ParticleId, &C)>()
        .iter(world)
        .map(|(id, c)| (id.0, *c))
        .collect();
    rows.sort_unstable_by_key(|r| r.0);
    rows.into_iter().map(|r| r.1).collect()
}

/// Inserts component `C` on every particle, computed from its row: rows keep their order
/// (each particle moves to the new table in row order).
pub fn insert_column<C: Component>(world: &mut World, f: impl Fn(usize) -> C) {
    let entities: Vec<Entity> = world
        .query_filtered::<Entity, With<ParticleId>>()
        .iter(world)
        .collect();
    for (row, e) in entities.into_iter().enumerate() {
        world.entity_mut(e).insert(f(row));
    }
}

/// The core columns of a particle cloud, for tests and tools that drive loops without a
/// scene: [`Cloud::spawn`] puts them into a world as particles.
#[derive(Clone, Debug, Default)]
pub struct Cloud<V: Vector> {
    /// Positions.
    pub pos: Vec<V>,
    /// Velocities.
    pub vel: Vec<V>,
    /// Masses.
    pub mass: Vec<Real>,
    /// Densities.
    pub rho: Vec<Real>,
    /// Support radii.
    pub h: Vec<Real>,
}

impl<V: Vector> Cloud<V> {
    /// n particles at the origin with zero velocity, unit mass and density, h = 1.
    pub fn new(n: usize) -> Self {
        Cloud {
            pos: vec![V::zero(); n],
            vel: vec![V::zero(); n],
            mass: vec![1.0; n],
            rho: vec![1.0; n],
            h: vec![1.0; n],
        }
    }

    /// A world holding the cloud as particles (ids and rows `0..n`).
    pub fn spawn(&self) -> World {
        let mut world = World::new();
        for i in 0..self.pos.len() {
            world.spawn((
                ParticleId(i as u32),
                Position(self.pos[i]),
                Velocity(self.vel[i]),
                Mass(self.mass[i]),
                Density(self.rho[i]),
                SmoothingLength(self.h[i]),
            ));
        }
        world
    }
}
