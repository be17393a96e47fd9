//! dualsph scenes: the RON schema, strict parsing with `file:line:column` errors, validation
//! and particle generation.
//!
//! ```ron
//! Scene(
//!     name: "dam break",
//!     dimension: 2,
//!     domain: (min: [0.0, 0.0], max: [4.0, 3.0]),
//!     kernel: CubicSpline,
//!     formulation: DualSupport,
//!     particles: [
//!         Block(min: [0.0, 0.0], max: [1.0, 0.5], spacing: 0.0125, lattice: Staggered,
//!               density: 1000.0, h_factor: 2.0),
//!     ],
//!     plugins: [Gravity(g: [0.0, -9.81])],
//!     integrator: (dt: Fixed(1e-4)),
//!     end_time: 1.0,
//! )
//! ```
//!
//! Generators: `Block` (a box of lattice points), `Disk` (a disk, ball or segment) and
//! `Shape` (a [`Shape`] — box, polygon, circle, ball, cylinder, a polygon from a file, a
//! closed STL mesh, the files relative to the scene file's directory — filled `Solid` or with
//! `Layers(n: 3, side: Inside | Outside)` of wall particles along its surface; see
//! [`ShapeGenerator`]), and `File(path: "final.csv", body: ..)`, the particles of a particle
//! CSV or `.vtp` snapshot the engine wrote, each with its own values (see [`FileParticles`]; it takes no
//! `clip`, `cut`, `velocity` or `internal_energy`).
//!
//! Optional: `neighbours` (`skin: 0.15, tune_skin: true`: the first build's skin, then one chosen
//! from the measured motion), `plugins` (none), `max_steps` (None), `output`
//! (`diagnostics_every: 10, snapshot_every: 200, snapshot_dt: None, formats: [Csv, Vtk],
//! vtk_encoding: Binary, columns: None`; see [`OutputSettings`]), `health` (the sane ranges of
//! the blow-up check), and on every generator `clip`, `cut` (plain boxes `(min: .., max: ..)` or [`Shape`]s),
//! `velocity` (`Uniform([..])` or `Linear(G)`, `v = G·x`;
//! zero when absent), `internal_energy` (0) and `body` (the generator's body).
//!
//! Plugins are `Name(field: value, ...)` or `Name()` and are looked up in a [`Registry`] while
//! parsing: the registry is installed in a thread-local for exactly the duration of the parse
//! call, because serde's `Deserialize` cannot take arguments. The sections `integrator`
//! (required) and `health` (optional) belong to plugin crates too: the settings type the
//! registry holds under the section's key ([`SceneSection`]) parses the section in place,
//! with its own defaults, and checks it during validation (in the default registry,
//! `dualsph_integrator::IntegratorSettings` and `dualsph_diagnostics::HealthSettings`); read
//! them with [`Scene::section`]. Parsing never panics, and every error names the file and,
//! for syntax errors, the line and column.
//!
//! # Validation
//!
//! [`Scene::validate`] reports the first of: dimension not 1–3; a vector (domain corners,
//! block corners, disk centre, clip/cut corners, shape centres, corners, axes and polygon
//! vertices, uniform velocity, rows of a linear velocity
//! matrix) without exactly `dimension` finite components; domain or block `max <= min` on an
//! axis; non-positive or non-finite spacing, density, h_factor, radius, length or end_time; a
//! shape of the wrong dimension (a polygon or circle outside 2-D, a ball or
//! cylinder or STL mesh outside 3-D); a polygon with fewer than 3 vertices, crossing edges or
//! zero area; an STL `scale` not > 0; a zero cylinder axis; `Layers` with `n: 0`; a shape whose extent (with its outside layers,
//! narrowed to its clip box) leaves the domain; a section's own `validate` (the
//! `integrator`'s, then `health`'s); negative skin; `diagnostics_every == 0`; both
//! `snapshot_dt` and a `snapshot_every` other than its default or 0; a plugin's
//! own `validate`; two integrators (or two diagnostics plugins), naming both; more than [`MAX_PARTICLES`] particles (estimated before generating); a
//! generator that yields no particles; a particle outside the domain; two generators whose
//! particles come closer than half the smaller spacing; a body declared twice or with an
//! empty name, a generator naming a body the scene does not declare, or a generator without
//! a body in a scene of several.
#![warn(missing_docs)]

mod body_kinds;
mod checks;
mod de;
mod error;
mod files;
mod generate;
mod lattice;
mod output;
mod overrides;
mod particle;
mod particles_file;
mod plugins_list;
mod schema;
mod sections;
mod shapes;
mod validate;

pub use dualsph_core::kernels::KernelKind;
pub use dualsph_core::plugin::{PluginConfig, Registry, SceneSection, SectionConfig};
pub use dualsph_core::sim::Formulation;
pub use error::SceneError;
pub use generate::MAX_PARTICLES;
pub use lattice::{BoxRegion, Lattice, Velocity};
pub use output::{DEFAULT_SNAPSHOT_EVERY, OutputFormat, OutputSettings, VtkEncoding};
pub use overrides::Override;
pub use particle::ParticleSpec;
pub use particles_file::{FileParticles, ReadParticles};
pub use schema::{Block, BodySettings, Disk, Domain, Generator, NeighbourSettings};
pub use shapes::{Fill, Geometry, Outline, Region, Shape, ShapeGenerator, Side, StlMesh};

use ron::extensions::Extensions;
use serde::Deserialize;
use std::path::Path;

/// A parsed scene. Build it with [`Scene::from_str`] or [`Scene::load`] (which also
/// validate). Its `Deserialize` impl needs the registry installed by those functions.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Human-readable name.
    pub name: String,
    /// Spatial dimension: 1, 2 or 3.
    #[serde(deserialize_with = "de::int::de")]
    pub dimension: usize,
    /// The simulation box.
    pub domain: Domain,
    /// Smoothing kernel.
    pub kernel: KernelKind,
    /// SPH formulation (default `DualSupport`).
    #[serde(default)]
    pub formulation: Formulation,
    /// Neighbour search settings (optional section).
    #[serde(default)]
    pub neighbours: NeighbourSettings,
    /// The bodies (optional): named groups of particles with a kind; generators name theirs.
    /// Without it, all particles are one fluid body named `fluid`.
    #[serde(default)]
    pub bodies: Vec<BodySettings>,
    /// Particle generators, in order.
    pub particles: Vec<Generator>,
    /// Plugins with their settings, in order (optional, default none).
    #[serde(default, deserialize_with = "plugins_list::deserialize")]
    pub plugins: Vec<Box<dyn PluginConfig>>,
    /// Time stepping: the `integrator` section, parsed and checked by the settings type the
    /// registry holds under that key (`dualsph_integrator::IntegratorSettings` in the default
    /// registry); read it with [`Scene::section`]. Optional: left out, it is the settings
    /// type's default (the adaptive step).
    #[serde(
        default = "sections::default_integrator",
        deserialize_with = "sections::integrator"
    )]
    pub integrator: Box<dyn SectionConfig>,
    /// Simulated time at which the run stops (> 0).
    pub end_time: f64,
    /// Optional cap on the number of steps.
    #[serde(default, deserialize_with = "de::int::de_opt")]
    pub max_steps: Option<u64>,
    /// Output cadence (optional section).
    #[serde(default)]
    pub output: OutputSettings,
    /// Sane ranges of density, h and dt for the blow-up check: the optional `health` section,
    /// parsed and checked like `integrator` (`dualsph_diagnostics::HealthSettings` in the
    /// default registry; its defaults apply when the scene leaves the section out).
    #[serde(default, deserialize_with = "sections::health")]
    pub health: Option<Box<dyn SectionConfig>>,
}

/// ron options: variant newtypes unwrap (`Gravity(g: [..])`, not `Gravity((g: [..]))`) and
/// `Some(..)` may be omitted.
pub(crate) fn ron_options() -> ron::Options {
    ron::Options::default()
        .with_default_extension(Extensions::UNWRAP_VARIANT_NEWTYPES | Extensions::IMPLICIT_SOME)
}

impl Scene {
    /// Parses and validates `text`; `path` is used in messages only.
    #[allow(clippy::should_implement_trait)]
    pub fn from_str(text: &str, path: &Path, registry: &Registry) -> Result<Scene, SceneError> {
        let scene = Scene::parse_only(text, path, registry)?;
        scene.validate(path)?;
        Ok(scene)
    }

    /// Reads, parses and validates the scene file at `path`.
    pub fn load(path: &Path, registry: &Registry) -> Result<Scene, SceneError> {
        let text =
            dualsph_io::read_input_text(path, dualsph_io::SCENE_FILE_LIMIT).map_err(|source| {
                SceneError::Io {
                    path: path.to_path_buf(),
                    source,
                }
            })?;
        Scene::from_str(&text, path, registry)
    }

    /// The settings of the section `S` (the scene's `integrator` or `health`), when the scene
    /// gives that section and its settings are of type `S`.
    pub fn section<S: SceneSection>(&self) -> Option<&S> {
        [Some(&self.integrator), self.health.as_ref()]
            .into_iter()
            .flatten()
            .find(|s| s.key() == S::KEY)
            .and_then(|s| s.section::<S>())
    }

    /// The plugin the scene names for an exclusive role (`Role::Integrator`,
    /// `Role::Diagnostics`), if any; two are an error naming both.
    pub fn plugin_of_role(
        &self,
        role: dualsph_core::plugin::Role,
    ) -> Result<Option<&dyn PluginConfig>, String> {
        validate::one_of_role(self, role).map_err(|p| format!("{}: {}", p.field, p.message))?;
        let mut named = self.plugins.iter().filter(|p| p.role() == role);
        Ok(named.next().map(|p| p.as_ref()))
    }

    /// Parses `text` without validating it (syntax, field names and types only), and reads
    /// the files its shapes (`Stl`, `PolygonFile`) and `File` generators name, relative to
    /// the directory of `path`: a file that cannot be read, or an STL mesh that is not
    /// closed, is [`SceneError::Invalid`] naming the field.
    pub fn parse_only(text: &str, path: &Path, registry: &Registry) -> Result<Scene, SceneError> {
        // a UTF-8 byte-order mark (as some editors save) is not part of the scene; editors
        // hide it, so positions on the first line are counted without it
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let (parsed, in_plugin) =
            plugins_list::with_registry(registry, text, || ron_options().from_str::<Scene>(text));
        let mut scene = parsed.map_err(|e| match in_plugin {
            // ron places the error at the end of the plugin; its settings' parser knows where
            Some(p) => {
                let (line, col) = overrides::line_col(text, p.at);
                SceneError::parse_at(path, text, line, col, p.message)
            }
            None => SceneError::from_ron(path, text, e),
        })?;
        let dir = path.parent().unwrap_or(Path::new(""));
        files::load(&mut scene.particles, dir, scene.dimension).map_err(|p| p.into_error(path))?;
        Ok(scene)
    }

    /// [`Scene::parse_only`] of `text` with `overrides` applied first (see [`Override`]):
    /// positions in syntax errors are those of the file; an error inside an override's
    /// value, or an override naming no value of the scene, is [`SceneError::Invalid`] naming
    /// the override (`--set PATH=VALUE`).
    pub fn parse_overridden(
        text: &str,
        path: &Path,
        registry: &Registry,
        overrides: &[Override],
    ) -> Result<Scene, SceneError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        if overrides.is_empty() {
            return Scene::parse_only(text, path, registry);
        }
        let invalid = |k: usize, message: String| SceneError::Invalid {
            path: path.to_path_buf(),
            field: format!("--set {}", overrides[k].given),
            message,
        };
        let edited = match overrides::apply(text, overrides) {
            Ok(e) => e,
            Err(overrides::ApplyError::Set(k, m)) => return Err(invalid(k, m)),
            Err(overrides::ApplyError::Text(at, message)) => {
                // the scene parser tells best what is wrong with the file itself
                Scene::parse_only(text, path, registry)?;
                let (line, col) = overrides::line_col(text, at);
                return Err(SceneError::Parse {
                    path: path.to_path_buf(),
                    line,
                    col,
                    message,
                });
            }
        };
        match Scene::parse_only(&edited.text, path, registry) {
            Err(SceneError::Parse {
                line, col, message, ..
            }) => {
                let at = overrides::offset_of(&edited.text, line, col);
                Err(match edited.origin(at) {
                    overrides::Origin::Set(k) => invalid(k, message),
                    overrides::Origin::File(at) => {
                        let (line, col) = overrides::line_col(text, at);
                        SceneError::Parse {
                            path: path.to_path_buf(),
                            line,
                            col,
                            message,
                        }
                    }
                })
            }
            other => other,
        }
    }

    /// Checks every value (see the crate docs for the list) and returns the first problem as
    /// [`SceneError::Invalid`], naming the field (`particles[1].spacing`, `domain.max`,
    /// `plugins[2] (Gravity)`, ...). Estimates the particle count before generating anything
    /// and refuses more than [`MAX_PARTICLES`]; then generates the particles to check that
    /// every generator yields some, that all lie in the domain and that no two generators
    /// overlap (particles closer than half the smaller spacing).
    pub fn validate(&self, path: &Path) -> Result<(), SceneError> {
        self.validate_with_limit(path, MAX_PARTICLES, "")
    }

    /// [`Scene::validate`] with a particle cap below [`MAX_PARTICLES`] (e.g. what fits in the
    /// machine's memory), applied to the estimate before anything is generated; `why` is
    /// appended to the limit in the message (e.g. `" (what fits in 20 GB of memory)"`).
    pub fn validate_with_limit(
        &self,
        path: &Path,
        max_particles: usize,
        why: &str,
    ) -> Result<(), SceneError> {
        let limit = validate::Limit {
            max: max_particles,
            why,
        };
        validate::validate(self, limit).map_err(|p| p.into_error(path))
    }

    /// The scene's particles: generators in order, each one's lattice points in lexicographic
    /// index order (axis 0 slowest). Meant for validated scenes; on an invalid one it never
    /// panics, but generators it cannot use (or a total above [`MAX_PARTICLES`]) yield nothing.
    pub fn generate(&self) -> Vec<ParticleSpec> {
        generate::generate_all(&self.particles, &self.body_list(), self.dimension)
    }

    /// The scene's bodies: those it declares, or the one default body (a fluid named
    /// `fluid`).
    pub fn body_list(&self) -> Vec<BodySettings> {
        if self.bodies.is_empty() {
            vec![BodySettings {
                name: dualsph_core::bodies::DEFAULT_BODY.into(),
                kind: body_kinds::fluid(),
                moment_about: None,
            }]
        } else {
            self.bodies.clone()
        }
    }
}

#[cfg(test)]
mod tests;
