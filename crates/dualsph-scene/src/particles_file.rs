//! The `File` generator: particles read from a particle file the engine wrote (a snapshot
//! `particles_NNNNNN.csv` or `.vtp`, or `final.csv`), each with its own position, velocity,
//! mass, density, h and internal energy, bit for bit as written.

use crate::error::Problem;
use crate::particle::ParticleSpec;
use dualsph_io::ParticleTable;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

/// Particles from a file: `File(path: "final.csv", body: "water")`. The path is relative
/// to the scene file's directory. The file is a particle CSV written by dualsph (its `id`,
/// `x, y, z`, `vx, vy, vz`, `m`, `rho` and `h` columns, `e` when present; other columns
/// are ignored) or a `.vtp` snapshot in any of its encodings (the points, `id`, `velocity`,
/// `mass`, `density`, `smoothing_length`, `internal_energy` when present); components beyond
/// the scene's dimension must be 0.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FileParticles {
    /// The file.
    pub path: String,
    /// The body the particles belong to (a name from the scene's `bodies`); may be left out
    /// when the scene has one body.
    #[serde(default)]
    pub body: Option<String>,
    /// The particles once the scene is loaded.
    #[serde(skip)]
    pub particles: ReadParticles,
}

/// The particles of a `File` generator once its file is read (none before), with the
/// spacing and h factor that stand for them in the scene's checks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadParticles(Option<Arc<Read>>);

#[derive(Debug, PartialEq)]
struct Read {
    particles: ParticleTable,
    table: ParticleTable,
    vtk: bool,
    spacing: f64,
    h_factor: f64,
}

impl FileParticles {
    /// The particles read, their columns by name (`position`, `velocity`, `mass`, …, see
    /// [`dualsph_io::read_particles`]); empty before the file is read.
    pub fn particles(&self) -> &ParticleTable {
        static EMPTY: ParticleTable = ParticleTable {
            ids: Vec::new(),
            columns: Vec::new(),
        };
        self.particles.0.as_deref().map_or(&EMPTY, |r| &r.particles)
    }

    /// Every column of the file, in its rows' order, and whether its columns are named as
    /// VTK arrays (`.vtp`: `velocity`, 3 components) rather than by CSV labels (one column
    /// per label: `vx`, `vy`, `vz`); the engine sets from it the registered columns it
    /// matches. None before the file is read.
    pub fn table(&self) -> Option<(&ParticleTable, bool)> {
        self.particles.0.as_deref().map(|r| (&r.table, r.vtk))
    }

    /// The spacing that stands for the particles in the scene's checks (the overlap of two
    /// generators): the least `(m/ρ)^{1/d}`; NaN before the file is read.
    pub fn spacing(&self) -> f64 {
        self.particles.0.as_deref().map_or(f64::NAN, |r| r.spacing)
    }

    /// The largest h over [`FileParticles::spacing`], so that their product is the largest
    /// h; NaN before the file is read.
    pub fn h_factor(&self) -> f64 {
        self.particles.0.as_deref().map_or(f64::NAN, |r| r.h_factor)
    }

    /// The particles as generated, of `generator` and `body`.
    pub(crate) fn specs(&self, generator: u32, body: u16) -> Vec<ParticleSpec> {
        self.particles()
            .rows()
            .map(|r| ParticleSpec {
                pos: r.pos(),
                vel: r.vel(),
                mass: r.mass(),
                density: r.rho(),
                h: r.h(),
                internal_energy: r.e(),
                body,
                generator,
            })
            .collect()
    }
}

/// The columns a particle file must hold (the internal energy is 0 when absent).
const REQUIRED: [&str; 5] = [
    dualsph_io::POSITION,
    dualsph_io::VELOCITY,
    dualsph_io::MASS,
    dualsph_io::DENSITY,
    dualsph_io::SMOOTHING_LENGTH,
];

/// Reads the file of `f` (generator number `i`) in a `d`-dimensional scene, relative to
/// `dir`; a problem names `particles[{i}].path`.
pub(crate) fn read(i: usize, f: &mut FileParticles, dir: &Path, d: usize) -> Result<(), Problem> {
    let path = dir.join(&f.path);
    let at = format!("particles[{i}].path");
    let vtp = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("vtp"));
    let read = dualsph_io::read_particles(&path).and_then(|p| {
        let table = match vtp {
            true => p.clone(),
            false => dualsph_io::read_particle_table_csv(&path)?,
        };
        Ok((p, table))
    });
    let (particles, table) =
        read.map_err(|e| Problem::new(&at, format!("cannot read particles: {e}")))?;
    particles.require(&REQUIRED).map_err(|e| {
        let file = path.display();
        Problem::new(&at, format!("cannot read particles: {file}: {e}"))
    })?;
    let spacing = particles
        .rows()
        .map(|r| dualsph_core::math::particle_size(d.clamp(1, 3), r.mass(), r.rho()))
        .fold(f64::INFINITY, f64::min);
    let h = particles.rows().map(|r| r.h()).fold(0.0, f64::max);
    f.particles = ReadParticles(Some(Arc::new(Read {
        particles,
        table,
        vtk: vtp,
        spacing,
        h_factor: h / spacing,
    })));
    Ok(())
}

/// The `File` generator number `i` in a `d`-dimensional scene: read, not empty, and every
/// particle with finite values, `m, ρ, h > 0`, `e >= 0` and zero components beyond `d`.
/// A problem names the particle by its id and line in the file.
pub(crate) fn check(i: usize, f: &FileParticles, d: usize) -> Result<(), Problem> {
    let at = format!("particles[{i}].path");
    if f.particles.0.is_none() {
        return Err(Problem::new(
            at,
            "the file was not read: parse scenes with Scene::load, Scene::from_str or \
             Scene::parse_only",
        ));
    }
    if f.particles().is_empty() {
        return Err(Problem::new(at, format!("`{}` holds no particles", f.path)));
    }
    for (k, r) in f.particles().rows().enumerate() {
        let bad = |what: String| {
            Problem::new(
                &at,
                format!(
                    "`{}`, line {} (particle id {}): {what}",
                    f.path,
                    k + 2,
                    r.id()
                ),
            )
        };
        let (pos, vel) = (r.pos(), r.vel());
        if let Some(x) = pos.iter().chain(&vel).find(|x| !x.is_finite()) {
            return Err(bad(format!("a position or velocity is not finite ({x})")));
        }
        if let Some(k) = (d..3).find(|&k| pos[k] != 0.0 || vel[k] != 0.0) {
            return Err(bad(format!(
                "component {k} of the position or velocity is not 0 in a {d}-D scene"
            )));
        }
        for (name, x) in [("m", r.mass()), ("rho", r.rho()), ("h", r.h())] {
            if !(x.is_finite() && x > 0.0) {
                return Err(bad(format!(
                    "`{name}` must be a finite number > 0, got {x}"
                )));
            }
        }
        // a run writes e below zero (round-off, or the heat account of a liquid that gave
        // energy back), so any finite value is its own state to start from
        let e = r.e();
        if !e.is_finite() {
            return Err(bad(format!("`e` must be a finite number, got {e}")));
        }
    }
    Ok(())
}
