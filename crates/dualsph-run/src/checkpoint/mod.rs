//! Checkpoints: the complete state of a run in one file, written atomically, from which
//! `dualsph run SCENE --resume FILE` continues bit for bit as if never interrupted.
//!
//! A checkpoint holds the particles' ids and every restart column (both in row order, the
//! order of the neighbour lists), the next particle id, the clock (t, step, dt), the
//! neighbour lists with the state of their rebuild rule (positions and smallest h of the
//! last build, the dirty flag, the build count, the steps since that build), the resources
//! plugins keep (`dualsph_core::restart`: among them the probes' samples so far, and the
//! diagnostics at t = 0 with the step of the last diagnostics row). A run whose particles were
//! added or removed resumes with the checkpoint's particles, in its row order. The
//! h-update (every m steps) and the output cadences are functions of the step counter, and
//! settings come from the scene, so nothing else is needed to take the same decisions again.
//!
//! ## File layout
//! `MAGIC` (8 bytes) · format version (u32 LE) · payload length (u64 LE) · FNV-1a 64 checksum
//! of the payload (u64 LE) · payload ([`postcard`] encoding of [`Checkpoint`]; reals are
//! stored as their 8 IEEE bytes, so they round-trip exactly). A file that is not a checkpoint,
//! truncated, corrupted or written for another scene is refused with a message saying which.

mod state;

pub use state::{capture, restore};

use dualsph_io::write_atomic;
use dualsph_scene::Scene;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// First bytes of every checkpoint file.
pub const MAGIC: &[u8; 8] = b"DSPHCKPT";
/// Version of the layout written by this build (of the file and of the columns it carries); a
/// file of another version is refused.
pub const FORMAT_VERSION: u32 = 8;
const HEADER_LEN: usize = 8 + 4 + 8 + 8;

/// One particle component: `width` reals per particle, particles in row order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ComponentData {
    /// Component name (e.g. `Position`).
    pub name: String,
    /// Reals per particle.
    pub width: u32,
    /// `n × width` values.
    pub values: Vec<f64>,
}

/// The neighbour lists and the state of their rebuild rule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NeighbourData {
    /// Verlet skin the lists were built with.
    pub skin: f64,
    /// Support CSR row starts.
    pub support_offsets: Vec<u32>,
    /// Support CSR columns.
    pub support_indices: Vec<u32>,
    /// Dual-support CSR row starts.
    pub dual_offsets: Vec<u32>,
    /// Dual-support CSR columns.
    pub dual_indices: Vec<u32>,
    /// Support slot of every dual entry.
    pub dual_slot: Vec<u32>,
    /// Positions at the last build, `n × dim` reals.
    pub build_positions: Vec<f64>,
    /// Smallest h at the last build.
    pub h_min: f64,
    /// Every particle's search radius at the last build (the slack is derived from them and
    /// the restored h).
    pub build_radii: Vec<f64>,
    /// A rebuild is pending whatever the motion (the particles changed, or an h outgrew its
    /// build radius).
    pub dirty: bool,
    /// Builds so far.
    pub builds: u64,
    /// Steps since the last build (the tuned skin's measure of the motion).
    pub steps_since_build: u64,
}

/// The complete state of a run after a step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Name of the scene (for messages).
    pub scene_name: String,
    /// [`fingerprint`] of the scene.
    pub fingerprint: u64,
    /// Spatial dimension.
    pub dimension: u32,
    /// Particle count.
    pub particles: u64,
    /// The particles' ids in row order (the order of the columns' values and of the
    /// neighbour lists).
    pub ids: Vec<u32>,
    /// The id the next particle added gets (ids are never reused).
    pub next_id: u32,
    /// Simulated time.
    pub t: f64,
    /// Completed steps.
    pub step: u64,
    /// dt of the last step.
    pub dt: f64,
    /// Every particle component the simulation carries.
    pub components: Vec<ComponentData>,
    /// Neighbour lists.
    pub neighbours: NeighbourData,
    /// The plugins' kept resources (`dualsph_core::restart`): key and encoded bytes.
    pub resources: Vec<(String, Vec<u8>)>,
}

/// Why a checkpoint cannot be read or used.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// The file could not be read.
    #[error("{}: cannot read checkpoint: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The file is damaged or not a checkpoint at all.
    #[error("{}: {why}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// The checkpoint is sound but belongs to another scene (or another build of it).
    #[error("{}: checkpoint does not belong to this scene: {why}", path.display())]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// What differs.
        why: String,
    },
    /// Writing the checkpoint failed.
    #[error(transparent)]
    Output(#[from] dualsph_io::OutputError),
}

/// FNV-1a, 64 bit.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The parts of a scene that determine the trajectory, borrowed, in the order they are
/// encoded for [`fingerprint`].
#[derive(serde::Serialize)]
struct Canonical<'a> {
    name: &'a str,
    dimension: usize,
    domain: &'a dualsph_scene::Domain,
    kernel: dualsph_core::kernels::KernelKind,
    formulation: dualsph_scene::Formulation,
    neighbours: &'a dualsph_scene::NeighbourSettings,
    bodies: &'a [dualsph_scene::BodySettings],
    particles: &'a [dualsph_scene::Generator],
    /// Each plugin's [`canonical`](dualsph_core::plugin::PluginConfig::canonical) bytes.
    plugins: Vec<Vec<u8>>,
    // then the integrator section's canonical bytes, appended (postcard encodes a struct as
    // its fields one after the other, so this is the encoding of the section as a last field)
}

/// A hash (FNV-1a) of the canonical form of everything in the scene that determines the
/// trajectory: name, dimension, domain, kernel, formulation, neighbour settings, bodies,
/// generators, plugins with their resolved settings and the integrator, encoded with postcard
/// (no `Debug` text: a new `Debug` of a type does not change it, nor do comments, whitespace,
/// field order or defaults written out). `end_time`, `max_steps`, `output` and `health` (the
/// blow-up check's sane ranges, which never change the state) are left out, so a resumed run
/// may go further, write at another cadence or check with other bounds.
pub fn fingerprint(scene: &Scene) -> u64 {
    fingerprint_of(scene, |_| true)
}

/// [`fingerprint`] with only the plugins for which `keep` holds (by name): with the
/// `Probes` left out, what `dualsph probe --scene` compares, since probes only watch the
/// state and a scene with probes added after a run still describes that run.
pub fn fingerprint_of(scene: &Scene, keep: impl Fn(&str) -> bool) -> u64 {
    let plugins = scene.plugins.iter().filter(|p| keep(p.name()));
    let canonical = Canonical {
        name: &scene.name,
        dimension: scene.dimension,
        domain: &scene.domain,
        kernel: scene.kernel,
        formulation: scene.formulation,
        neighbours: &scene.neighbours,
        bodies: &scene.bodies,
        particles: &scene.particles,
        plugins: plugins.map(|p| p.canonical()).collect(),
    };
    // every field has a known length, which is all postcard needs
    let mut bytes = postcard::to_stdvec(&canonical).unwrap_or_default();
    bytes.extend(scene.integrator.canonical());
    fnv1a(&bytes)
}

impl Checkpoint {
    /// The file content: header and payload.
    pub fn to_bytes(&self) -> Vec<u8> {
        let payload = postcard::to_stdvec(self).unwrap_or_default();
        let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        out.extend_from_slice(&fnv1a(&payload).to_le_bytes());
        out.extend_from_slice(&payload);
        out
    }

    /// Decodes a file's content; `path` is for messages only.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Checkpoint, CheckpointError> {
        let bad = |why: String| CheckpointError::Invalid {
            path: path.to_path_buf(),
            why,
        };
        if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
            return Err(bad("not a dualsph checkpoint (wrong magic bytes)".into()));
        }
        if bytes.len() < HEADER_LEN {
            return Err(bad(format!(
                "truncated checkpoint: {} bytes, shorter than its {HEADER_LEN}-byte header",
                bytes.len()
            )));
        }
        let word = |at: usize| {
            let mut b = [0u8; 8];
            b.copy_from_slice(&bytes[at..at + 8]);
            u64::from_le_bytes(b)
        };
        let mut v = [0u8; 4];
        v.copy_from_slice(&bytes[8..12]);
        let version = u32::from_le_bytes(v);
        if version != FORMAT_VERSION {
            return Err(bad(format!(
                "checkpoint format version {version}; this dualsph reads version {FORMAT_VERSION} \
                 only (a checkpoint of another version cannot be resumed: run the scene again \
                 from the start)"
            )));
        }
        let (len, sum) = (word(12), word(20));
        let payload = &bytes[HEADER_LEN..];
        if payload.len() as u64 != len {
            return Err(bad(format!(
                "truncated or padded checkpoint: the header announces {len} payload bytes, the file has {}",
                payload.len()
            )));
        }
        if fnv1a(payload) != sum {
            return Err(bad(
                "corrupted checkpoint: the payload checksum does not match".into(),
            ));
        }
        postcard::from_bytes(payload).map_err(|e| {
            bad(format!(
                "corrupted checkpoint: cannot decode the payload ({e})"
            ))
        })
    }

    /// Reads and decodes a checkpoint file.
    pub fn read(path: &Path) -> Result<Checkpoint, CheckpointError> {
        let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Checkpoint::from_bytes(&bytes, path)
    }

    /// Writes the checkpoint atomically (a crash leaves the old file or the new one).
    pub fn write(&self, path: &Path) -> Result<(), CheckpointError> {
        Ok(write_atomic(path, &self.to_bytes())?)
    }

    /// Refuses a checkpoint taken from another scene (`path` is for messages only).
    pub fn check_scene(&self, scene: &Scene, path: &Path) -> Result<(), CheckpointError> {
        let mismatch = |why: String| CheckpointError::Mismatch {
            path: path.to_path_buf(),
            why,
        };
        if self.dimension as usize != scene.dimension {
            return Err(mismatch(format!(
                "it is {}-D (scene {:?}), the scene is {}-D",
                self.dimension, self.scene_name, scene.dimension
            )));
        }
        if self.fingerprint != fingerprint(scene) {
            return Err(mismatch(format!(
                "it was written for scene {:?} with other settings (particles, plugins, kernel, \
                 formulation or integrator differ) than {:?} has now",
                self.scene_name, scene.name
            )));
        }
        Ok(())
    }
}

/// File name of the checkpoint after `step`: `checkpoint_NNNNNN.ckpt`.
pub fn checkpoint_file_name(step: u64) -> String {
    format!("checkpoint_{step:06}.ckpt")
}

/// File stem of the last good state written when a run blows up.
pub const LAST_GOOD_STEM: &str = "last_good";

#[cfg(test)]
mod tests {
    use super::*;

    /// A small scene with `plugins` and `tail` (integrator, end time, …) spliced in.
    fn scene(plugins: &str, tail: &str) -> Scene {
        let text = format!(
            "Scene(name: \"f\", dimension: 2, domain: (min: [0.0, 0.0], max: [1.0, 1.0]), \
             kernel: CubicSpline, formulation: DualSupport, \
             particles: [Block(min: [0.0, 0.0], max: [0.5, 0.5], spacing: 0.1, lattice: Square, density: 1000.0, h_factor: 2.0)], \
             plugins: [{plugins}], {tail})"
        );
        Scene::from_str(
            &text,
            std::path::Path::new("f.ron"),
            &dualsph_builtin::default_registry(),
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn fingerprint_is_of_the_settings_not_their_spelling() {
        let tail = "integrator: (dt: Fixed(1e-4)), end_time: 1.0";
        let base = fingerprint(&scene(
            "TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0), PressureForce()",
            tail,
        ));
        // field order, number spelling, comments, whitespace: the same settings
        let respelled = scene(
            "TaitEos(c0: 2e1, // speed of sound\n gamma: 7.00, rho0: 1000.)  ,PressureForce()",
            "end_time: 1.0, integrator: (dt: Fixed(0.0001))",
        );
        assert_eq!(fingerprint(&respelled), base);
        // the end time and the output are not part of the trajectory's settings
        let longer = scene(
            "TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0), PressureForce()",
            "integrator: (dt: Fixed(1e-4)), end_time: 2.0, output: (diagnostics_every: 3)",
        );
        assert_eq!(fingerprint(&longer), base);
        // any setting of a plugin, or a plugin more, changes it
        for other in [
            "TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.000001), PressureForce()",
            "TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0), PressureForce(), Gravity(g: [0.0, -9.81])",
        ] {
            assert_ne!(fingerprint(&scene(other, tail)), base, "{other}");
        }
        let smaller_step = scene(
            "TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0), PressureForce()",
            "integrator: (dt: Fixed(2e-4)), end_time: 1.0",
        );
        assert_ne!(fingerprint(&smaller_step), base);
    }

    fn sample() -> Checkpoint {
        let awkward = vec![
            0.1,
            -0.0,
            f64::MIN_POSITIVE / 3.0, // subnormal
            f64::MAX,
            f64::from_bits(0x7ff8_dead_beef_0001), // a NaN with a payload
            f64::NEG_INFINITY,
        ];
        Checkpoint {
            scene_name: "s".into(),
            fingerprint: 42,
            dimension: 2,
            particles: 3,
            t: 0.1 + 0.2,
            step: 7,
            dt: 1e-300,
            components: vec![ComponentData {
                name: "Position".into(),
                width: 2,
                values: awkward.clone(),
            }],
            neighbours: NeighbourData {
                skin: 0.15,
                support_offsets: vec![0, 1, 2, 2],
                support_indices: vec![1, 0],
                dual_offsets: vec![0, 1, 2, 2],
                dual_indices: vec![1, 0],
                dual_slot: vec![1, 0],
                build_positions: awkward.clone(),
                h_min: 0.3,
                build_radii: vec![0.345, f64::MIN_POSITIVE, 7.5],
                dirty: true,
                builds: 9,
                steps_since_build: 4,
            },
            ids: vec![0, 1, 2],
            next_id: 3,
            resources: vec![("inlet".into(), vec![0, 255, 7])],
        }
    }

    #[test]
    fn reals_round_trip_bit_for_bit() {
        let c = sample();
        let back = Checkpoint::from_bytes(&c.to_bytes(), Path::new("x")).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&back.components[0].values),
            bits(&c.components[0].values)
        );
        assert_eq!(back.to_bytes(), c.to_bytes());
        assert_eq!(back.t.to_bits(), c.t.to_bits());
    }

    #[test]
    fn every_truncation_and_every_flipped_byte_is_an_error_not_a_panic() {
        let bytes = sample().to_bytes();
        for n in 0..bytes.len() {
            assert!(Checkpoint::from_bytes(&bytes[..n], Path::new("x")).is_err());
        }
        for k in 0..bytes.len() {
            let mut b = bytes.clone();
            b[k] ^= 0x01;
            assert!(
                Checkpoint::from_bytes(&b, Path::new("x")).is_err(),
                "byte {k} flipped"
            );
        }
    }
}
