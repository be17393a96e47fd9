//! The column registry: every per-particle quantity of a scene, declared by the plugin that
//! owns it, with whether it is written to snapshots and kept in checkpoints.
//!
//! A plugin adds a column with [`crate::sim::Sim::add_column`]: the component type (which
//! says how it flattens to reals, [`ColumnValue`]), a [`ColumnSpec`] (names, output, restart)
//! and each particle's initial value. Snapshots (CSV, VTK) and checkpoints walk the
//! [`Columns`] resource, so a user plugin's state appears in ParaView and resumes bitwise
//! without an edit of the engine. [`crate::sim::Sim::finish`] refuses particles that carry a
//! component no plugin registered: such state would silently be lost on restart.

use crate::components::*;
use crate::math::{Matrix, Real, Vector};
use bevy_ecs::component::{ComponentId, Mutable};
use bevy_ecs::prelude::*;
use std::any::TypeId;

/// How a column's values are laid out per particle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// One real.
    Scalar,
    /// `d` reals (the scene's dimension); written padded to x, y, z.
    Vector,
    /// `d × d` reals, row-major (`entry(k, l)` = ∂·_k/∂x_l for gradients).
    Matrix,
    /// A record of several reals (e.g. an integrator's start-of-step values): kept in
    /// checkpoints, never written to snapshots.
    Record,
}

/// A component that is a per-particle column: how it flattens to reals and back.
///
/// Scalar, vector and matrix newtypes get this from [`scalar_column!`](crate::scalar_column),
/// [`vector_column!`](crate::vector_column) and [`matrix_column!`](crate::matrix_column).
pub trait ColumnValue<V: Vector>: Component<Mutability = Mutable> + Sized {
    /// The layout.
    const SHAPE: Shape;
    /// Reals per particle (`put` pushes exactly this many).
    fn width() -> usize {
        match Self::SHAPE {
            Shape::Scalar => 1,
            Shape::Vector => V::DIM,
            Shape::Matrix => V::DIM * V::DIM,
            Shape::Record => unreachable!("a Record column states its width"),
        }
    }
    /// Appends the value's reals.
    fn put(&self, out: &mut Vec<Real>);
    /// Sets the value from `width()` reals.
    fn take(&mut self, values: &[Real]);
}

/// Appends a vector's `d` components.
pub fn put_vector<V: Vector>(v: V, out: &mut Vec<Real>) {
    out.extend((0..V::DIM).map(|k| v.get(k)));
}

/// A vector from its first `d` reals.
pub fn take_vector<V: Vector>(values: &[Real]) -> V {
    let mut v = V::zero();
    for (k, x) in values.iter().take(V::DIM).enumerate() {
        v.set(k, *x);
    }
    v
}

/// Appends a matrix's `d × d` entries, row-major.
pub fn put_matrix<V: Vector>(m: V::Mat, out: &mut Vec<Real>) {
    for k in 0..V::DIM {
        out.extend((0..V::DIM).map(|l| m.entry(k, l)));
    }
}

/// A matrix from `d × d` reals, row-major.
pub fn take_matrix<V: Vector>(values: &[Real]) -> V::Mat {
    let mut m = V::Mat::zero();
    for k in 0..V::DIM {
        for l in 0..V::DIM {
            m.set_entry(k, l, values[k * V::DIM + l]);
        }
    }
    m
}

/// Implements [`ColumnValue`] for newtypes `T(pub Real)`.
#[macro_export]
macro_rules! scalar_column {
    ($($t:ty),* $(,)?) => {$(
        impl<V: $crate::math::Vector> $crate::columns::ColumnValue<V> for $t {
            const SHAPE: $crate::columns::Shape = $crate::columns::Shape::Scalar;
            fn put(&self, out: &mut Vec<$crate::math::Real>) { out.push(self.0) }
            fn take(&mut self, values: &[$crate::math::Real]) { self.0 = values[0] }
        }
    )*};
}

/// Implements [`ColumnValue`] for generic newtypes `T<V>(pub V)`.
#[macro_export]
macro_rules! vector_column {
    ($($t:ident),* $(,)?) => {$(
        impl<V: $crate::math::Vector> $crate::columns::ColumnValue<V> for $t<V> {
            const SHAPE: $crate::columns::Shape = $crate::columns::Shape::Vector;
            fn put(&self, out: &mut Vec<$crate::math::Real>) {
                $crate::columns::put_vector(self.0, out)
            }
            fn take(&mut self, values: &[$crate::math::Real]) {
                self.0 = $crate::columns::take_vector(values)
            }
        }
    )*};
}

/// Implements [`ColumnValue`] for generic newtypes `T<V>(pub V::Mat)`.
#[macro_export]
macro_rules! matrix_column {
    ($($t:ident),* $(,)?) => {$(
        impl<V: $crate::math::Vector> $crate::columns::ColumnValue<V> for $t<V> {
            const SHAPE: $crate::columns::Shape = $crate::columns::Shape::Matrix;
            fn put(&self, out: &mut Vec<$crate::math::Real>) {
                $crate::columns::put_matrix::<V>(self.0, out)
            }
            fn take(&mut self, values: &[$crate::math::Real]) {
                self.0 = $crate::columns::take_matrix::<V>(values)
            }
        }
    )*};
}

scalar_column!(Mass, Density, SmoothingLength);
vector_column!(Position, Velocity, Acceleration);

/// What a plugin declares about one of its columns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColumnSpec {
    /// The name in VTK files and listings (`velocity`, `pressure`, …).
    pub name: &'static str,
    /// The CSV label: the column itself for a scalar (`rho`), the prefix of its components
    /// for a vector (`v` → `vx,vy,vz`) or matrix (`gradv` → `gradv_xx,gradv_xy,…`).
    pub label: &'static str,
    /// Written to snapshots (CSV and VTK).
    pub output: bool,
    /// Kept in checkpoints: state that a resumed run needs to continue bitwise. A column that
    /// every step rewrites before reading it is scratch and need not be kept.
    pub restart: bool,
}

impl ColumnSpec {
    /// A column written to snapshots and kept in checkpoints.
    pub const fn state(name: &'static str, label: &'static str) -> Self {
        ColumnSpec {
            name,
            label,
            output: true,
            restart: true,
        }
    }

    /// A column kept in checkpoints only (integrator records, rates).
    pub const fn restart_only(name: &'static str) -> Self {
        ColumnSpec {
            name,
            label: name,
            output: false,
            restart: true,
        }
    }

    /// Scratch: neither written nor kept (every step rewrites it before it is read).
    pub const fn scratch(name: &'static str) -> Self {
        ColumnSpec {
            name,
            label: name,
            output: false,
            restart: false,
        }
    }

    /// The same column, also written to snapshots.
    pub const fn with_output(mut self, label: &'static str) -> Self {
        self.output = true;
        self.label = label;
        self
    }
}

/// One registered column, with its type erased.
#[derive(Clone, Debug)]
pub struct Column {
    /// What the plugin declared.
    pub spec: ColumnSpec,
    /// Layout.
    pub shape: Shape,
    /// Reals per particle.
    pub width: usize,
    /// The component's type name without module path or dimension (`Position`,
    /// `Registers<Density>`): the key of the column in checkpoints.
    pub key: String,
    /// The component's short type name with generics (`Position<DVec2>`), for listings.
    pub type_name: String,
    type_id: TypeId,
    values: fn(&mut World) -> Vec<Real>,
    write: fn(&mut World, &[Real]) -> Result<(), String>,
    copy: fn(&mut World, Entity, Entity),
    blend: fn(&mut World, Entity, [(Entity, Real); 2]),
}

/// Copies `C` of `from` to `to`; a particle without `C` leaves `to` as it was.
fn copy_values<V: Vector, C: ColumnValue<V>>(world: &mut World, from: Entity, to: Entity) {
    let mut buf = Vec::new();
    match world.get::<C>(from) {
        Some(c) => c.put(&mut buf),
        None => return,
    }
    if let Some(mut c) = world.get_mut::<C>(to) {
        c.take(&buf);
    }
}

/// Sets `C` of `to` to `Σ w_k C(from_k)` over two weighted particles, component by
/// component; a particle without `C` (or `to` without it) leaves `to` as it was.
fn blend_values<V: Vector, C: ColumnValue<V>>(
    world: &mut World,
    to: Entity,
    from: [(Entity, Real); 2],
) {
    let mut parts = [Vec::new(), Vec::new()];
    for (buf, (e, _)) in parts.iter_mut().zip(from) {
        match world.get::<C>(e) {
            Some(c) => c.put(buf),
            None => return,
        }
    }
    let [(_, wa), (_, wb)] = from;
    let mixed: Vec<Real> = parts[0]
        .iter()
        .zip(&parts[1])
        .map(|(a, b)| wa * a + wb * b)
        .collect();
    if let Some(mut c) = world.get_mut::<C>(to) {
        c.take(&mixed);
    }
}

/// The values of `C` in row order (the order of a query over the particles).
fn values_of<V: Vector, C: ColumnValue<V>>(world: &mut World) -> Vec<Real> {
    let mut q = world.query::<&C>();
    let mut out = Vec::with_capacity(q.iter(world).len() * C::width());
    for c in q.iter(world) {
        c.put(&mut out);
    }
    out
}

/// Sets `C` from values in row order; the error says that the count does not fit.
fn write_values<V: Vector, C: ColumnValue<V>>(
    world: &mut World,
    values: &[Real],
) -> Result<(), String> {
    let w = C::width();
    let mut q = world.query::<&mut C>();
    let n = q.iter(world).len();
    if values.len() != n * w {
        return Err(format!(
            "{} values for {n} particles of width {w}",
            values.len()
        ));
    }
    for (mut c, v) in q.iter_mut(world).zip(values.chunks_exact(w)) {
        c.take(v);
    }
    Ok(())
}

/// The particles' ids in row order.
pub fn ids_by_row(world: &mut World) -> Vec<u32> {
    let mut q = world.query::<&ParticleId>();
    q.iter(world).map(|id| id.0).collect()
}

impl Column {
    fn of<V: Vector, C: ColumnValue<V>>(spec: ColumnSpec) -> Self {
        let full = crate::names::short_type_name(std::any::type_name::<C>());
        // the name without the dimension (`Position<DVec2>` → `Position`), other type
        // arguments kept (`Registers<Density>`, `Registers<InternalEnergy>`)
        let key = ["<Vec1>", "<DVec2>", "<DVec3>"]
            .iter()
            .fold(full.clone(), |k, dim| k.replace(dim, ""));
        Column {
            spec,
            shape: C::SHAPE,
            width: C::width(),
            key,
            type_name: full.clone(),
            type_id: TypeId::of::<C>(),
            values: values_of::<V, C>,
            write: write_values::<V, C>,
            copy: copy_values::<V, C>,
            blend: blend_values::<V, C>,
        }
    }

    /// The particles' values in row order (`width` reals each): the order of
    /// [`ids_by_row`] and of the neighbour lists.
    pub fn values_by_row(&self, world: &mut World) -> Vec<Real> {
        (self.values)(world)
    }

    /// The particles' values in ascending id order (`width` reals each).
    pub fn values_by_id(&self, world: &mut World) -> Vec<Real> {
        let rows = self.values_by_row(world);
        let ids = ids_by_row(world);
        let mut order: Vec<usize> = (0..ids.len()).collect();
        order.sort_unstable_by_key(|&r| ids[r]);
        let w = self.width;
        order
            .into_iter()
            .flat_map(|r| rows[r * w..(r + 1) * w].iter().copied())
            .collect()
    }

    /// Sets the particles' values from `values` in row order (`width` reals each); the
    /// error says what does not fit.
    pub fn set_by_row(&self, world: &mut World, values: &[Real]) -> Result<(), String> {
        (self.write)(world, values)
    }

    /// Whether this is the column of component `C`.
    pub fn is<C: Component>(&self) -> bool {
        self.type_id == TypeId::of::<C>()
    }

    /// Copies the column's value of particle `from` to particle `to`.
    pub fn copy_value(&self, world: &mut World, from: Entity, to: Entity) {
        (self.copy)(world, from, to);
    }

    /// Sets the column's value of `to` to the weighted sum `w_a C(a) + w_b C(b)`, component
    /// by component (a mass-weighted mean with `w = m/(m_a + m_b)`).
    pub fn blend_values(&self, world: &mut World, to: Entity, from: [(Entity, Real); 2]) {
        (self.blend)(world, to, from);
    }

    /// The CSV labels of the column's components as written (vectors padded to x, y, z).
    pub fn labels(&self, dim: usize) -> Vec<String> {
        const AXES: [&str; 3] = ["x", "y", "z"];
        let l = self.spec.label;
        match self.shape {
            Shape::Scalar => vec![l.to_string()],
            Shape::Vector => AXES.iter().map(|a| format!("{l}{a}")).collect(),
            Shape::Matrix => (0..dim)
                .flat_map(|k| (0..dim).map(move |m| format!("{l}_{}{}", AXES[k], AXES[m])))
                .collect(),
            Shape::Record => (0..self.width).map(|k| format!("{l}{k}")).collect(),
        }
    }
}

/// The registered columns of a simulation, in registration order (core columns first).
#[derive(Resource, Clone, Debug, Default)]
pub struct Columns {
    columns: Vec<Column>,
}

impl Columns {
    /// Registers `C`; registering a type again keeps the first declaration. The error names
    /// a second type that claims a name already taken, or an output `Record`.
    pub fn register<V: Vector, C: ColumnValue<V>>(
        &mut self,
        spec: ColumnSpec,
    ) -> Result<(), String> {
        let col = Column::of::<V, C>(spec);
        if self.columns.iter().any(|c| c.type_id == col.type_id) {
            return Ok(());
        }
        if col.shape == Shape::Record && col.spec.output {
            return Err(format!(
                "column {}: a record cannot be written to snapshots",
                col.spec.name
            ));
        }
        if let Some(c) = self
            .columns
            .iter()
            .find(|c| c.spec.name == col.spec.name || c.key == col.key)
        {
            return Err(format!(
                "column {} ({}) is registered twice, by {} and {}",
                col.spec.name, col.key, c.key, col.key
            ));
        }
        self.columns.push(col);
        Ok(())
    }

    /// Every column, in registration order.
    pub fn iter(&self) -> impl Iterator<Item = &Column> {
        self.columns.iter()
    }

    /// The columns written to snapshots.
    pub fn output(&self) -> impl Iterator<Item = &Column> {
        self.columns.iter().filter(|c| c.spec.output)
    }

    /// The columns kept in checkpoints.
    pub fn restart(&self) -> impl Iterator<Item = &Column> {
        self.columns.iter().filter(|c| c.spec.restart)
    }

    /// The column whose checkpoint key is `key`.
    pub fn by_key(&self, key: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.key == key)
    }

    /// The column of component `C`.
    pub fn of<C: Component>(&self) -> Option<&Column> {
        self.columns.iter().find(|c| c.type_id == TypeId::of::<C>())
    }

    /// The components of the particles' table that no column declares (other than
    /// [`ParticleId`]), by type name: what [`crate::sim::Sim::finish`] refuses.
    pub fn unregistered(&self, world: &World) -> Vec<String> {
        let Some(entity) = world
            .try_query::<(Entity, &ParticleId)>()
            .and_then(|mut q| q.iter(world).next().map(|(e, _)| e))
        else {
            return Vec::new();
        };
        let id_component = world.component_id::<ParticleId>();
        let known: Vec<Option<ComponentId>> = self
            .columns
            .iter()
            .map(|c| world.components().get_id(c.type_id))
            .collect();
        let Ok(e) = world.get_entity(entity) else {
            return Vec::new();
        };
        e.archetype()
            .components()
            .iter()
            .filter(|id| Some(**id) != id_component && !known.contains(&Some(**id)))
            .filter_map(|id| world.components().get_info(*id))
            .map(|info| crate::names::short_type_name(&info.name().to_string()))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// A matrix column, as a plugin registers one.
    #[derive(Component)]
    struct VelocityGradient<V: Vector>(V::Mat);

    matrix_column!(VelocityGradient);

    #[test]
    fn values_round_trip_by_row_and_sort_by_id() {
        let mut world = World::new();
        for id in [2u32, 0, 1] {
            let x = id as Real;
            world.spawn((
                ParticleId(id),
                Position(DVec2::new(x, 10.0 + x)),
                VelocityGradient::<DVec2>(glam::DMat2::from_cols_array(&[x, 1.0, 2.0, 3.0])),
            ));
        }
        let mut cols = Columns::default();
        cols.register::<DVec2, Position<DVec2>>(ColumnSpec::state("position", ""))
            .unwrap();
        cols.register::<DVec2, VelocityGradient<DVec2>>(ColumnSpec::state("gradv", "gradv"))
            .unwrap();
        let pos = cols.of::<Position<DVec2>>().unwrap();
        assert_eq!(pos.key, "Position");
        assert_eq!(pos.width, 2);
        let v = pos.values_by_id(&mut world);
        assert_eq!(v, vec![0.0, 10.0, 1.0, 11.0, 2.0, 12.0]);
        assert_eq!(ids_by_row(&mut world), [2, 0, 1]);
        let rows = pos.values_by_row(&mut world);
        assert_eq!(rows, vec![2.0, 12.0, 0.0, 10.0, 1.0, 11.0]);
        let shifted: Vec<Real> = rows.iter().map(|x| x + 0.5).collect();
        pos.set_by_row(&mut world, &shifted).unwrap();
        assert_eq!(pos.values_by_row(&mut world), shifted);
        assert_eq!(pos.values_by_id(&mut world)[..2], [0.5, 10.5]);
        assert!(pos.set_by_row(&mut world, &shifted[..4]).is_err());
        let g = cols.by_key("VelocityGradient").unwrap();
        assert_eq!(
            g.labels(2),
            ["gradv_xx", "gradv_xy", "gradv_yx", "gradv_yy"]
        );
        assert_eq!(pos.labels(2), ["x", "y", "z"]);
        assert!(cols.unregistered(&world).is_empty());
    }

    #[test]
    fn refuses_an_unregistered_component_a_clashing_name_and_an_output_record() {
        let mut world = World::new();
        world.spawn((ParticleId(0), Position(DVec2::ZERO), Density(1.0)));
        let mut cols = Columns::default();
        cols.register::<DVec2, Position<DVec2>>(ColumnSpec::state("position", ""))
            .unwrap();
        assert_eq!(cols.unregistered(&world), ["Density"]);
        assert!(
            cols.register::<DVec2, Density>(ColumnSpec::state("position", "rho"))
                .is_err()
        );
        /// A record of two reals, like a scheme's registers.
        #[derive(Component)]
        struct Record([Real; 2]);
        impl ColumnValue<DVec2> for Record {
            const SHAPE: Shape = Shape::Record;
            fn width() -> usize {
                2
            }
            fn put(&self, out: &mut Vec<Real>) {
                out.extend(self.0);
            }
            fn take(&mut self, values: &[Real]) {
                self.0 = [values[0], values[1]];
            }
        }
        let record = ColumnSpec::restart_only("registers").with_output("k");
        assert!(cols.register::<DVec2, Record>(record).is_err());
    }
}
