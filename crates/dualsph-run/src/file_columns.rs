//! The columns a `File` generator's particles bring beyond their initial state: after the
//! simulation is built, every registered output column that the file holds — by its CSV
//! labels in a `.csv`, by its VTK name in a `.vtp` — takes the file's values for those
//! particles (a plugin's state written to a snapshot, the dissipated energy). The columns
//! the particles' initial state sets (position, velocity, mass, density, h, internal energy)
//! are left as they are, already the file's.

use dualsph_core::columns::{Column, Columns, ids_by_row};
use dualsph_fluid::prelude::*;
use dualsph_io::ParticleTable;
use dualsph_scene::{Generator, Scene};

/// The columns a particle's [`ParticleInit`] sets.
const INITIAL: [&str; 6] = [
    "Position",
    "Velocity",
    "Mass",
    "Density",
    "SmoothingLength",
    "InternalEnergy",
];

/// Sets, for the particles of every `File` generator of `scene`, the registered output
/// columns their file holds. Particle `k` of the scene's generated list has id `first + k`,
/// `first` the least id (the particles are spawned in that order).
pub(crate) fn apply<V: Vector>(sim: &mut Sim<V>, scene: &Scene) -> Result<(), SimError> {
    if !scene.particles.iter().any(|g| file_of(g).is_some()) {
        return Ok(());
    }
    let mut counts = vec![0usize; scene.particles.len()];
    for p in scene.generate() {
        counts[p.generator as usize] += 1;
    }
    let mut start = 0usize;
    let mut files = Vec::new();
    for (g, n) in scene.particles.iter().zip(&counts) {
        if let Some(table) = file_of(g) {
            files.push((start, table));
        }
        start += n;
    }
    let columns: Vec<Column> = sim.world.resource::<Columns>().output().cloned().collect();
    let ids = ids_by_row(&mut sim.world);
    let first = ids.iter().copied().min().unwrap_or(0) as usize;
    for col in columns
        .iter()
        .filter(|c| !INITIAL.contains(&c.key.as_str()))
    {
        let mut values = col.values_by_row(&mut sim.world);
        let mut changed = false;
        for &(start, (table, by_name)) in &files {
            let Some(file) = file_values::<V>(col, table, by_name) else {
                continue;
            };
            let w = col.width;
            for (row, &id) in ids.iter().enumerate() {
                let k = (id as usize).wrapping_sub(first).wrapping_sub(start);
                if k < table.len() {
                    values[row * w..(row + 1) * w].copy_from_slice(&file[k * w..(k + 1) * w]);
                    changed = true;
                }
            }
        }
        if changed {
            col.set_by_row(&mut sim.world, &values).map_err(|e| {
                SimError::Build(format!("column `{}` from a file: {e}", col.spec.name))
            })?;
        }
    }
    Ok(())
}

/// The table of a `File` generator's file, and whether it is named by VTK arrays.
fn file_of(g: &Generator) -> Option<(&ParticleTable, bool)> {
    match g {
        Generator::File(f) => f.table(),
        _ => None,
    }
}

/// The values of `col` in the file (`width` per particle, in the file's rows), or `None`
/// when the file does not hold all its components. A vector is written padded to x, y, z:
/// its first `V::DIM` components are taken.
fn file_values<V: Vector>(col: &Column, table: &ParticleTable, by_name: bool) -> Option<Vec<Real>> {
    let labels = col.labels(V::DIM);
    let written: Vec<&[Real]> = if by_name {
        let c = table
            .column(col.spec.name)
            .filter(|c| c.width() == labels.len())?;
        (0..labels.len()).map(|_| c.values.as_slice()).collect()
    } else {
        labels
            .iter()
            .map(|l| table.column(l).map(|c| c.values.as_slice()))
            .collect::<Option<_>>()?
    };
    let stride = if by_name { labels.len() } else { 1 };
    let used = if col.shape == dualsph_core::columns::Shape::Vector {
        V::DIM
    } else {
        labels.len()
    };
    let n = table.len();
    let mut out = Vec::with_capacity(n * used);
    for k in 0..n {
        for (m, values) in written.iter().enumerate().take(used) {
            let at = if by_name { k * stride + m } else { k };
            out.push(values[at]);
        }
    }
    (out.len() == n * col.width).then_some(out)
}
