//! Capturing the state of a [`Sim`] into a [`Checkpoint`] and putting it back.

use super::{Checkpoint, ComponentData, NeighbourData};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::columns::{Column, Columns, ids_by_row, put_vector, take_vector};
use dualsph_core::neighbours::{Csr, Neighbours};
use dualsph_core::population::{NextId, Seed, replace_particles};
use dualsph_core::restart::KeptResources;
use dualsph_fluid::prelude::*;

/// The registered columns kept in checkpoints, in registration order.
fn restart_columns(world: &World) -> Vec<Column> {
    world.resource::<Columns>().restart().cloned().collect()
}

/// Every restart column's values, in row order.
fn capture_columns(world: &mut World) -> Vec<ComponentData> {
    restart_columns(world)
        .into_iter()
        .map(|col| ComponentData {
            name: col.key.clone(),
            width: col.width as u32,
            values: col.values_by_row(world),
        })
        .collect()
}

/// Puts the restart columns back, after checking that the checkpoint holds exactly the
/// scene's restart columns, each with `n` values of its width.
fn restore_columns(world: &mut World, data: &[ComponentData], n: usize) -> Result<(), String> {
    let columns = restart_columns(world);
    if let Some(extra) = data
        .iter()
        .find(|d| !columns.iter().any(|c| c.key == d.name))
    {
        return Err(format!(
            "it has {} data, which this scene's particles do not carry",
            extra.name
        ));
    }
    let mut found = Vec::with_capacity(columns.len());
    for col in &columns {
        let Some(stored) = data.iter().find(|d| d.name == col.key) else {
            return Err(format!("it has no {} data", col.key));
        };
        let w = col.width;
        if stored.width as usize != w || stored.values.len() != n * w {
            return Err(format!(
                "its {} data has {} values of width {}, expected {} of width {w}",
                col.key,
                stored.values.len(),
                stored.width,
                n * w
            ));
        }
        found.push(stored);
    }
    for (col, stored) in columns.iter().zip(found) {
        col.set_by_row(world, &stored.values)
            .map_err(|e| format!("its {} data: {e}", col.key))?;
    }
    Ok(())
}

/// The complete state of `sim` after its last step.
pub fn capture<V: Vector>(sim: &mut Sim<V>, scene_name: &str, fingerprint: u64) -> Checkpoint {
    let clock = sim.clock();
    let n = sim.particle_count();
    let world = &mut sim.world;
    let components = capture_columns(world);
    let nb = world.resource::<Neighbours<V>>();
    let mut build_positions = Vec::with_capacity(nb.build_positions.len() * V::DIM);
    for p in &nb.build_positions {
        put_vector(*p, &mut build_positions);
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
        build_radii: nb.build_radii.clone(),
        dirty: nb.dirty,
        builds: nb.builds,
        steps_since_build: nb.steps_since_build,
    };
    let ids = ids_by_row(world);
    let next_id = world.resource::<NextId>().0;
    let resources = world
        .get_resource::<KeptResources>()
        .map(|k| k.0.clone())
        .unwrap_or_default()
        .iter()
        .filter_map(|k| Some((k.key.to_string(), k.save(world)?)))
        .collect();
    Checkpoint {
        scene_name: scene_name.into(),
        fingerprint,
        dimension: V::DIM as u32,
        particles: n as u64,
        t: clock.t,
        step: clock.step,
        dt: clock.dt,
        ids,
        next_id,
        resources,
        components,
        neighbours,
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

/// The lists and their rebuild state; `h`, the restored support radii in row order, gives the
/// slack (derived, not stored).
fn restore_neighbours<V: Vector>(
    nb: &mut Neighbours<V>,
    d: &NeighbourData,
    n: usize,
    h: Option<&[f64]>,
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
    let radii_ok = d.build_radii.is_empty() || d.build_radii.len() == n;
    if !(slots_ok && positions_ok && radii_ok) {
        return Err("its neighbour-list rebuild state is inconsistent".into());
    }
    nb.set_lists(support, dual, d.dual_slot.clone());
    nb.build_positions = d
        .build_positions
        .chunks(V::DIM)
        .map(take_vector::<V>)
        .collect();
    nb.h_min = d.h_min;
    nb.build_radii = d.build_radii.clone();
    nb.dirty = d.dirty;
    match h {
        Some(h) if h.len() == n => nb.h_changed(h),
        _ => nb.dirty = true,
    }
    nb.builds = d.builds;
    nb.skin = d.skin;
    nb.steps_since_build = d.steps_since_build;
    Ok(())
}

/// Puts a checkpoint's state into a freshly built `sim` of the same scene (built, not
/// initialized: the restored rates replace the initial evaluation). Every size is checked
/// first, so a damaged checkpoint gives an error, never a panic.
pub fn restore<V: Vector>(sim: &mut Sim<V>, c: &Checkpoint) -> Result<(), String> {
    let n = c.ids.len();
    if c.dimension as usize != V::DIM || c.particles != n as u64 {
        return Err(format!(
            "it holds {} particles ({} ids) in {}-D, the scene is {}-D",
            c.particles,
            n,
            c.dimension,
            V::DIM
        ));
    }
    sim.world.resource_mut::<NextId>().0 = c.next_id;
    if ids_by_row(&mut sim.world) != c.ids {
        let seeds = seeds::<V>(c)?;
        replace_particles(&mut sim.world, &seeds)?;
    }
    let world = &mut sim.world;
    restore_columns(world, &c.components, n)?;
    restore_resources(world, &c.resources)?;
    let h = c
        .components
        .iter()
        .find(|d| d.name == "SmoothingLength" && d.width == 1)
        .map(|d| d.values.as_slice());
    restore_neighbours(
        &mut world.resource_mut::<Neighbours<V>>(),
        &c.neighbours,
        n,
        h,
    )?;
    let mut clock = world.resource_mut::<SimClock>();
    clock.t = c.t;
    clock.step = c.step;
    clock.dt = c.dt;
    Ok(())
}

/// The checkpoint's particles as seeds (ids and core columns, row order): what their other
/// columns' initial values are computed from before the stored values replace them.
fn seeds<V: Vector>(c: &Checkpoint) -> Result<Vec<Seed<V>>, String> {
    let n = c.ids.len();
    let column = |key: &str, w: usize| -> Result<&[f64], String> {
        match c.components.iter().find(|d| d.name == key) {
            Some(d) if d.width as usize == w && d.values.len() == n * w => Ok(&d.values),
            Some(_) => Err(format!(
                "its {key} data does not hold {n} values of width {w}"
            )),
            None => Err(format!("it has no {key} data")),
        }
    };
    let d = V::DIM;
    let (pos, vel) = (column("Position", d)?, column("Velocity", d)?);
    let (mass, rho) = (column("Mass", 1)?, column("Density", 1)?);
    let (h, body) = (column("SmoothingLength", 1)?, column("BodyId", 1)?);
    Ok((0..n)
        .map(|k| Seed {
            id: c.ids[k],
            init: ParticleInit {
                pos: take_vector(&pos[k * d..(k + 1) * d]),
                vel: take_vector(&vel[k * d..(k + 1) * d]),
                mass: mass[k],
                density: rho[k],
                h: h[k],
                internal_energy: 0.0,
                body: body[k] as u16,
            },
        })
        .collect())
}

/// Puts the plugins' kept resources back, after checking that the checkpoint holds exactly
/// the scene's.
fn restore_resources(world: &mut World, stored: &[(String, Vec<u8>)]) -> Result<(), String> {
    let kept = world
        .get_resource::<KeptResources>()
        .map(|k| k.0.clone())
        .unwrap_or_default();
    if let Some((extra, _)) = stored.iter().find(|(k, _)| kept.iter().all(|r| r.key != k)) {
        return Err(format!(
            "it has {extra} state, which this scene's plugins do not keep"
        ));
    }
    for r in &kept {
        let Some((_, bytes)) = stored.iter().find(|(k, _)| k == r.key) else {
            return Err(format!("it has no {} state", r.key));
        };
        r.load(world, bytes)
            .map_err(|e| format!("its {} state: {e}", r.key))?;
    }
    Ok(())
}
