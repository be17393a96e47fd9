//! Capturing the state of a [`Sim`] into a [`Checkpoint`] and putting it back.

use super::{Checkpoint, ComponentData, NeighbourData};
use dualsph_core::bevy_ecs::component::Mutable;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::diagnostics::{Diagnostics, InitialDensity};
use dualsph_core::neighbours::{Csr, Neighbours};
use dualsph_core::prelude::*;
use dualsph_probes::ProbeState;

/// A particle component stored as a fixed number of reals per particle.
trait Stored<V: Vector>: Component<Mutability = Mutable> + Sized {
    const NAME: &'static str;
    fn width() -> usize;
    fn put(&self, out: &mut Vec<f64>);
    fn take(&mut self, values: &[f64]);
}

fn put_vec<V: Vector>(v: V, out: &mut Vec<f64>) {
    out.extend((0..V::DIM).map(|k| v.get(k)));
}

fn take_vec<V: Vector>(values: &[f64]) -> V {
    let mut v = V::zero();
    for k in 0..V::DIM {
        v.set(k, values[k]);
    }
    v
}

fn put_mat<V: Vector>(m: V::Mat, out: &mut Vec<f64>) {
    for k in 0..V::DIM {
        out.extend((0..V::DIM).map(|l| m.entry(k, l)));
    }
}

fn take_mat<V: Vector>(m: &mut V::Mat, values: &[f64]) {
    for k in 0..V::DIM {
        for l in 0..V::DIM {
            m.set_entry(k, l, values[k * V::DIM + l]);
        }
    }
}

macro_rules! stored_vector {
    ($($t:ident),*) => {$(
        impl<V: Vector> Stored<V> for $t<V> {
            const NAME: &'static str = stringify!($t);
            fn width() -> usize { V::DIM }
            fn put(&self, out: &mut Vec<f64>) { put_vec(self.0, out) }
            fn take(&mut self, values: &[f64]) { self.0 = take_vec(values) }
        }
    )*};
}
stored_vector!(Position, Velocity, Acceleration);

macro_rules! stored_matrix {
    ($($t:ident),*) => {$(
        impl<V: Vector> Stored<V> for $t<V> {
            const NAME: &'static str = stringify!($t);
            fn width() -> usize { V::DIM * V::DIM }
            fn put(&self, out: &mut Vec<f64>) { put_mat::<V>(self.0, out) }
            fn take(&mut self, values: &[f64]) { take_mat::<V>(&mut self.0, values) }
        }
    )*};
}
stored_matrix!(GradientCorrection, VelocityGradient);

macro_rules! stored_scalar {
    ($($t:ident),*) => {$(
        impl<V: Vector> Stored<V> for $t {
            const NAME: &'static str = stringify!($t);
            fn width() -> usize { 1 }
            fn put(&self, out: &mut Vec<f64>) { out.push(self.0) }
            fn take(&mut self, values: &[f64]) { self.0 = values[0] }
        }
    )*};
}
stored_scalar!(
    Mass,
    Density,
    SmoothingLength,
    Pressure,
    SoundSpeed,
    InternalEnergy,
    Conductivity
);

impl<V: Vector> Stored<V> for Kinematics<V> {
    const NAME: &'static str = "Kinematics";
    fn width() -> usize {
        2 * V::DIM
    }
    fn put(&self, out: &mut Vec<f64>) {
        put_vec(self.v0, out);
        put_vec(self.a0, out);
    }
    fn take(&mut self, values: &[f64]) {
        self.v0 = take_vec(values);
        self.a0 = take_vec(&values[V::DIM..]);
    }
}

macro_rules! stored_rate {
    ($t:ident, $x0:ident) => {
        impl<V: Vector> Stored<V> for $t {
            const NAME: &'static str = stringify!($t);
            fn width() -> usize {
                3
            }
            fn put(&self, out: &mut Vec<f64>) {
                out.extend([self.rate, self.$x0, self.rate0]);
            }
            fn take(&mut self, values: &[f64]) {
                (self.rate, self.$x0, self.rate0) = (values[0], values[1], values[2]);
            }
        }
    };
}
stored_rate!(EnergyRate, e0);
stored_rate!(DensityRate, rho0);

fn capture_one<V: Vector, C: Stored<V>>(world: &mut World, out: &mut Vec<ComponentData>) {
    let mut q = world.query::<(&ParticleId, &C)>();
    let mut rows: Vec<(u32, &C)> = q.iter(world).map(|(id, c)| (id.0, c)).collect();
    if rows.is_empty() {
        return;
    }
    rows.sort_unstable_by_key(|r| r.0);
    let mut values = Vec::with_capacity(rows.len() * C::width());
    for (_, c) in rows {
        c.put(&mut values);
    }
    out.push(ComponentData {
        name: C::NAME.into(),
        width: C::width() as u32,
        values,
    });
}

/// Puts one component back; an error when the checkpoint and the simulation disagree on
/// whether the particles carry it or on its size.
fn restore_one<V: Vector, C: Stored<V>>(
    world: &mut World,
    data: &[ComponentData],
    n: usize,
) -> Result<(), String> {
    let mut q = world.query::<(&ParticleId, &mut C)>();
    let present = q.iter(world).next().is_some();
    let stored = data.iter().find(|c| c.name == C::NAME);
    let stored = match (present, stored) {
        (false, None) => return Ok(()),
        (true, None) => return Err(format!("it has no {} data", C::NAME)),
        (false, Some(_)) => {
            return Err(format!(
                "it has {} data, which this scene's particles do not carry",
                C::NAME
            ));
        }
        (true, Some(c)) => c,
    };
    let w = C::width();
    if stored.width as usize != w || stored.values.len() != n * w {
        return Err(format!(
            "its {} data has {} values of width {}, expected {} of width {w}",
            C::NAME,
            stored.values.len(),
            stored.width,
            n * w
        ));
    }
    for (id, mut c) in q.iter_mut(world) {
        let i = id.0 as usize;
        c.take(&stored.values[i * w..(i + 1) * w]);
    }
    Ok(())
}

/// Calls `$f::<V, C>(args)` for every stored component type `C` (each followed by `$q`, e.g. `?`).
macro_rules! for_each_component {
    ($f:ident, $v:ty, [$($args:expr),*] $($q:tt)?) => {{
        $f::<$v, Position<$v>>($($args),*)$($q)?;
        $f::<$v, Velocity<$v>>($($args),*)$($q)?;
        $f::<$v, Acceleration<$v>>($($args),*)$($q)?;
        $f::<$v, Kinematics<$v>>($($args),*)$($q)?;
        $f::<$v, Mass>($($args),*)$($q)?;
        $f::<$v, Density>($($args),*)$($q)?;
        $f::<$v, SmoothingLength>($($args),*)$($q)?;
        $f::<$v, Pressure>($($args),*)$($q)?;
        $f::<$v, SoundSpeed>($($args),*)$($q)?;
        $f::<$v, InternalEnergy>($($args),*)$($q)?;
        $f::<$v, EnergyRate>($($args),*)$($q)?;
        $f::<$v, DensityRate>($($args),*)$($q)?;
        $f::<$v, Conductivity>($($args),*)$($q)?;
        $f::<$v, GradientCorrection<$v>>($($args),*)$($q)?;
        $f::<$v, VelocityGradient<$v>>($($args),*)$($q)?;
    }};
}

fn diagnostics_values(d: &Diagnostics) -> Vec<f64> {
    let mut v = vec![d.t, d.dt, d.mass];
    v.extend(d.momentum);
    v.extend(d.angular_momentum);
    v.extend([
        d.e_kin,
        d.e_int,
        d.e_pot,
        d.e_tot,
        d.max_density_variation,
        d.momentum_scale,
    ]);
    v
}

/// The diagnostics at t = 0 stored in a checkpoint (zeros where missing).
pub(crate) fn initial_diagnostics(c: &Checkpoint) -> Diagnostics {
    let v = |k: usize| c.initial_diagnostics.get(k).copied().unwrap_or(0.0);
    Diagnostics {
        t: v(0),
        step: 0,
        dt: v(1),
        n: c.particles,
        mass: v(2),
        momentum: [v(3), v(4), v(5)],
        angular_momentum: [v(6), v(7), v(8)],
        e_kin: v(9),
        e_int: v(10),
        e_pot: v(11),
        e_tot: v(12),
        max_density_variation: v(13),
        momentum_scale: v(14),
    }
}

/// The complete state of `sim` after its last step. `initial` is the diagnostics at t = 0 and
/// `last_diagnostics_step` the step of the last diagnostics row written.
pub fn capture<V: Vector>(
    sim: &mut Sim<V>,
    scene_name: &str,
    fingerprint: u64,
    initial: &Diagnostics,
    last_diagnostics_step: u64,
) -> Checkpoint {
    let clock = sim.clock();
    let n = sim.particle_count();
    let mut components = Vec::new();
    let world = &mut sim.world;
    for_each_component!(capture_one, V, [world, &mut components]);
    let nb = world.resource::<Neighbours<V>>();
    let mut build_positions = Vec::with_capacity(nb.build_positions.len() * V::DIM);
    for p in &nb.build_positions {
        put_vec(*p, &mut build_positions);
    }
    let neighbours = NeighbourData {
        skin: nb.skin,
        support_offsets: nb.support.offsets.clone(),
        support_indices: nb.support.indices.clone(),
        dual_offsets: nb.dual.offsets.clone(),
        dual_indices: nb.dual.indices.clone(),
        dual_slot: nb.dual_slot.clone(),
        build_positions,
        h_min: nb.h_min,
        dirty: nb.dirty,
        builds: nb.builds,
        steps_since_build: nb.steps_since_build,
    };
    let initial_density = world
        .get_resource::<InitialDensity>()
        .map(|d| d.0.clone())
        .unwrap_or_default();
    let probe_rows = world
        .get_resource::<ProbeState<V>>()
        .map(|p| p.rows.clone());
    Checkpoint {
        scene_name: scene_name.into(),
        fingerprint,
        dimension: V::DIM as u32,
        particles: n as u64,
        t: clock.t,
        step: clock.step,
        dt: clock.dt,
        components,
        neighbours,
        initial_density,
        probe_rows,
        last_diagnostics_step,
        initial_diagnostics: diagnostics_values(initial),
    }
}

/// A CSR with `rows` rows whose columns are below `cols`, or why not.
fn csr(
    what: &str,
    offsets: &[u32],
    indices: &[u32],
    rows: usize,
    cols: usize,
) -> Result<Csr, String> {
    let sound = offsets.len() == rows + 1
        && offsets.first() == Some(&0)
        && offsets.windows(2).all(|w| w[0] <= w[1])
        && offsets.last().is_some_and(|&e| e as usize == indices.len())
        && indices.iter().all(|&j| (j as usize) < cols);
    if !sound {
        return Err(format!(
            "its {what} lists are inconsistent with {rows} particles"
        ));
    }
    Ok(Csr {
        offsets: offsets.to_vec(),
        indices: indices.to_vec(),
    })
}

fn restore_neighbours<V: Vector>(
    nb: &mut Neighbours<V>,
    d: &NeighbourData,
    n: usize,
) -> Result<(), String> {
    if !(d.skin.is_finite() && d.skin >= 0.0) {
        return Err(format!(
            "its neighbour skin {} is not a number >= 0",
            d.skin
        ));
    }
    // a tuned skin is the state's; a fixed one must be the scene's
    if nb.rule == SkinRule::Fixed && d.skin.to_bits() != nb.skin.to_bits() {
        return Err(format!(
            "its neighbour skin is {}, the scene's is {}",
            d.skin, nb.skin
        ));
    }
    let support = csr("support", &d.support_offsets, &d.support_indices, n, n)?;
    let dual = csr("dual-support", &d.dual_offsets, &d.dual_indices, n, n)?;
    let slots_ok = d.dual_slot.len() == dual.indices.len()
        && d.dual_slot
            .iter()
            .all(|&s| (s as usize) < support.indices.len());
    let positions_ok = d.build_positions.len().is_multiple_of(V::DIM)
        && (d.build_positions.is_empty() || d.build_positions.len() == n * V::DIM);
    if !(slots_ok && positions_ok) {
        return Err("its neighbour-list rebuild state is inconsistent".into());
    }
    nb.support = support;
    nb.dual = dual;
    nb.dual_slot = d.dual_slot.clone();
    nb.build_positions = d
        .build_positions
        .chunks(V::DIM)
        .map(take_vec::<V>)
        .collect();
    nb.h_min = d.h_min;
    nb.dirty = d.dirty;
    nb.builds = d.builds;
    nb.skin = d.skin;
    nb.steps_since_build = d.steps_since_build;
    Ok(())
}

/// Puts a checkpoint's state into a freshly built `sim` of the same scene (built, not
/// initialized: the restored rates replace the initial evaluation). Every size is checked
/// first, so a damaged checkpoint gives an error, never a panic.
pub fn restore<V: Vector>(sim: &mut Sim<V>, c: &Checkpoint) -> Result<(), String> {
    let n = sim.particle_count();
    if c.dimension as usize != V::DIM || c.particles != n as u64 {
        return Err(format!(
            "it holds {} particles in {}-D, the scene generates {n} in {}-D",
            c.particles,
            c.dimension,
            V::DIM
        ));
    }
    if !(c.initial_density.is_empty() || c.initial_density.len() == n) {
        return Err("its initial densities do not match the particle count".into());
    }
    let world = &mut sim.world;
    match (
        world
            .get_resource::<ProbeState<V>>()
            .map(|p| p.columns.len()),
        &c.probe_rows,
    ) {
        (None, None) => {}
        (Some(cols), Some(rows)) if rows.iter().all(|r| r.2.len() == cols) => {}
        _ => return Err("its probe samples do not match the scene's probes".into()),
    }
    for_each_component!(restore_one, V, [world, &c.components, n]?);
    restore_neighbours(&mut world.resource_mut::<Neighbours<V>>(), &c.neighbours, n)?;
    world.resource_mut::<InitialDensity>().0 = c.initial_density.clone();
    if let (Some(mut p), Some(rows)) = (world.get_resource_mut::<ProbeState<V>>(), &c.probe_rows) {
        p.rows = rows.clone();
    }
    let mut clock = world.resource_mut::<SimClock>();
    clock.t = c.t;
    clock.step = c.step;
    clock.dt = c.dt;
    Ok(())
}
