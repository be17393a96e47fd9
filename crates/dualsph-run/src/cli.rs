//! The `dualsph` command line as a library function: [`main`] takes the plugin registry, so
//! a user's binary is the whole CLI (`run`, `check`, `plan`, `--resume`, …) with their own
//! plugins registered beside the built-in ones (the facade re-exports this module as
//! `dualsph::cli`, and the registry as `dualsph::default_registry`):
//!
//! ```no_run
//! fn main() -> std::process::ExitCode {
//!     let mut registry = dualsph_builtin::default_registry();
//!     registry.register::<dualsph_builtin::plugins::Gravity>(); // your plugin here
//!     dualsph_run::cli::main(registry)
//! }
//! ```

use crate::runner;
use clap::{Parser, Subcommand};
use dualsph_core::plugin::Registry;
use dualsph_scene::{Formulation, Scene};
use std::path::PathBuf;
use std::process::ExitCode;

pub mod exit;
pub mod record;
use exit::Failure;

/// `println!` that ends the process quietly when standard output is a closed pipe
/// (`dualsph plan scene.ron | head`) instead of panicking; output files are written
/// atomically, so nothing is left half written.
#[macro_export]
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($t)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

mod doc;
pub mod forces;
mod lock;
mod probe;
pub use doc::reference_markdown;
mod run;

#[derive(Parser)]
#[command(
    name = "dualsph",
    version,
    about = "Dual-support SPH: run, check and plan RON scenes; grid and plot their output",
    after_help = exit::HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// A formulation on the command line: one of the engine's ([`Formulation::ALL`]), written in
/// kebab case (`single-support`) or as in a scene (`SingleSupport`).
#[derive(Clone, Copy, Debug)]
struct FormulationArg(Formulation);

/// [`Formulation::ALL`] as command-line values.
const FORMULATION_ARGS: [FormulationArg; Formulation::ALL.len()] = {
    let mut out = [FormulationArg(Formulation::DualSupport); Formulation::ALL.len()];
    let mut k = 0;
    while k < out.len() {
        out[k] = FormulationArg(Formulation::ALL[k]);
        k += 1;
    }
    out
};

/// `SingleSupport` → `single-support`.
fn kebab(name: &str) -> String {
    let mut out = String::new();
    for (k, c) in name.chars().enumerate() {
        if c.is_uppercase() && k > 0 {
            out.push('-');
        }
        out.extend(c.to_lowercase());
    }
    out
}

impl clap::ValueEnum for FormulationArg {
    fn value_variants<'a>() -> &'a [Self] {
        &FORMULATION_ARGS
    }
    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        static KEBAB: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
        let kebab = KEBAB.get_or_init(|| Formulation::ALL.map(|f| kebab(f.name())).to_vec());
        let k = Formulation::ALL.iter().position(|f| *f == self.0)?;
        Some(clap::builder::PossibleValue::new(kebab[k].as_str()).alias(self.0.name()))
    }
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene headless and write diagnostics, snapshots and run.json.
    Run(run::RunArgs),
    /// Parse and validate a scene and build its simulation (plugin requirements), without running it.
    Check {
        /// The scene file (.ron).
        scene: PathBuf,
        #[command(flatten)]
        set: SetArgs,
    },
    /// Print the systems (in order), pair terms and particle components a scene produces.
    Plan {
        /// The scene file (.ron).
        scene: PathBuf,
        #[command(flatten)]
        set: SetArgs,
    },
    /// List the registered plugins, scene sections and body kinds (with --fields, each one's
    /// fields: type, default and meaning).
    Plugins {
        /// Print every plugin's, section's and body kind's fields.
        #[arg(long)]
        fields: bool,
    },
    /// Print the fields of a plugin, scene section or body kind: type, default and meaning
    /// (`dualsph doc TaitEos`, `dualsph doc integrator`).
    Doc {
        /// The plugin's (section's, body kind's) name as a scene writes it.
        name: String,
    },
    /// Sample a field of a run's particle file on a regular grid: DIR/<field>_grid.vti
    /// (ParaView) and DIR/<field>_grid.png (filled contours, white outside the fluid).
    Grid {
        /// The scene file the run used (for its dimension, kernel and domain).
        scene: PathBuf,
        /// The run's output directory (default: out/<scene name>).
        #[arg(long)]
        dir: Option<PathBuf>,
        /// Particle file in DIR (final.csv, or a particles_NNNNNN.csv or .vtp snapshot).
        #[arg(long, default_value = "final.csv")]
        file: String,
        /// The quantity, named as in the probes: a scalar column (density, pressure, a
        /// plugin's own), a component (velocity.x), speed or shepard_sum.
        #[arg(long, default_value = "density")]
        field: String,
        /// Grid spacing (m).
        #[arg(long)]
        dx: f64,
    },
    /// Sample a scene's probes over a finished run's snapshots (those snapshots.csv lists,
    /// CSV or .vtp) into OUT/probes.csv and OUT/probes_points.csv, as the Probes plugin
    /// samples a running simulation.
    Probe {
        /// The run's output directory (its run.json gives the scene, its snapshots.csv the
        /// snapshots).
        dir: PathBuf,
        /// Sample this scene's probes instead of the run's own (the run's scene with probes
        /// added after the run); its particles and plugins must be the run's.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Output directory (default: DIR/snapshot_probes).
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        set: SetArgs,
    },
    /// The force coefficients 2F/(ρU²L) of a body from DIR/bodies.csv into
    /// DIR/force_coefficients.csv, with their mean and extremes and the lift's Strouhal number
    /// over a window.
    Forces(forces::ForcesArgs),
    /// Plot DIR/probes.csv (written by the Probes plugin) into PNGs next to it.
    PlotProbes {
        /// The run's output directory.
        dir: PathBuf,
    },
}

/// `--set PATH=VALUE`, repeatable: values of the scene replaced from the command line.
#[derive(clap::Args, Clone, Default)]
pub(crate) struct SetArgs {
    /// Replace (or add) a value of the scene, as RON: `--set end_time=0.5`,
    /// `--set particles[1].spacing=0.01`, `--set TaitEos.c0=60` (the scene's one TaitEos),
    /// `--set integrator.dt.courant=0.1`. Repeatable; applied in order; recorded in run.json.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<dualsph_scene::Override>,
}

/// A file a command reads must be there: its absence is an I/O failure (exit status 4, as for
/// `run`), told apart from a file that is there but holds what the command cannot use
/// (invalid input, 2).
fn require_file(path: &std::path::Path) -> Result<(), Failure> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(_) => Err(Failure::new(
            exit::IO,
            format!("{}: not a regular file", path.display()),
        )),
        Err(e) => Err(Failure::new(exit::IO, format!("{}: {e}", path.display()))),
    }
}

fn grid_command(
    scene_path: &std::path::Path,
    s: &Scene,
    dir: Option<PathBuf>,
    file: &str,
    field: &str,
    dx: f64,
) -> Result<(), Failure> {
    let invalid = |m: String| Failure::new(exit::INVALID_INPUT, m);
    let dir = dir.unwrap_or_else(|| runner::default_out_dir(scene_path));
    let q = dualsph_probes::Quantity::parse(field).map_err(|e| invalid(format!("--field: {e}")))?;
    let path = dir.join(file);
    require_file(&path)?;
    let table = crate::gridded::read_particles(s, &path).map_err(invalid)?;
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    lo[..s.dimension].copy_from_slice(&s.domain.min);
    hi[..s.dimension].copy_from_slice(&s.domain.max);
    let f = crate::gridded::sample_table(&table, s.dimension, s.kernel, &q, dx, Some((lo, hi)))
        .map_err(|e| invalid(format!("--field {field}: {e}")))?;
    let stem = format!("{}_grid", q.name().replace('.', "_"));
    let title = format!("{} — {q} from {file}", s.name);
    let encoding = runner::snapshots::output_options(&s.output).encoding;
    let (vti, png) = crate::gridded::write_field(&f, &dir, &stem, &title, encoding)
        .map_err(|e| Failure::new(exit::IO, e.to_string()))?;
    say!("wrote {}", vti.display());
    if s.dimension >= 2 {
        say!("wrote {}", png.display());
    }
    Ok(())
}

/// `plot-probes`: the probes file must be there (else exit status 4); what it holds must be a
/// probes table (else 2).
fn plot_probes_command(dir: &std::path::Path) -> Result<(), Failure> {
    require_file(&dir.join(dualsph_probes::PROBES_FILE))?;
    let pngs =
        dualsph_probes::plot_probes(dir).map_err(|m| Failure::new(exit::INVALID_INPUT, m))?;
    for p in pngs {
        say!("wrote {}", p.display());
    }
    Ok(())
}

/// Reads, parses and validates a scene; the particle cap is also what fits in the machine's
/// memory, checked from the estimate before any particle is generated.
fn load(path: &std::path::Path, registry: &Registry, set: &SetArgs) -> Result<Scene, Failure> {
    load_with_text(path, registry, set).map(|(s, _)| s)
}

/// [`load`], also returning the file's text (as written, before `--set`).
fn load_with_text(
    path: &std::path::Path,
    registry: &Registry,
    set: &SetArgs,
) -> Result<(Scene, String), Failure> {
    let scene_error =
        |e: dualsph_scene::SceneError| Failure::new(exit::of_scene(&e), e.to_string());
    let text =
        dualsph_io::read_input_text(path, dualsph_io::SCENE_FILE_LIMIT).map_err(|source| {
            scene_error(dualsph_scene::SceneError::Io {
                path: path.to_path_buf(),
                source,
            })
        })?;
    let s = Scene::parse_overridden(&text, path, registry, &set.set).map_err(scene_error)?;
    let (limit, why) = runner::memory::particle_limit(&s, runner::memory::memory_available());
    s.validate_with_limit(path, limit, &why)
        .map_err(scene_error)?;
    Ok((s, text))
}

/// Runs the command line given to the process with the plugins of `registry`; the exit code
/// is failure with the message on standard error when the command fails.
pub fn main(registry: Registry) -> ExitCode {
    let cli = Cli::parse();
    let result: Result<(), Failure> = match cli.command {
        Command::Run(args) => run::run(args, &registry),
        Command::Check { scene, set } => load(&scene, &registry, &set).and_then(|s| {
            // building the simulation also checks what plugins require of each other
            let planned = runner::plan(&s)
                .map_err(|e| Failure::new(exit::of_sim(&e), format!("{}: {e}", scene.display())))?;
            for n in &planned.notes {
                eprintln!("note: {}: {n}", scene.display());
            }
            for w in &planned.warnings {
                eprintln!("warning: {}: {w}", scene.display());
            }
            say!(
                "{}: ok ({}-D, {} particles, {} plugins)",
                scene.display(),
                s.dimension,
                s.generate().len(),
                s.plugins.len()
            );
            Ok(())
        }),
        Command::Plan { scene, set } => load(&scene, &registry, &set).and_then(|s| {
            let runner::Planned {
                plan, pair_terms, ..
            } = runner::plan(&s)
                .map_err(|e| Failure::new(exit::of_sim(&e), format!("{}: {e}", scene.display())))?;
            say!(
                "scene {} ({}-D, formulation {:?}, kernel {:?})",
                s.name,
                s.dimension,
                s.formulation,
                s.kernel
            );
            say!("\nschedule (in order; [the plugin that added each system]):");
            for (k, (set, label, plugin)) in plan.systems.iter().enumerate() {
                say!(
                    "  {:>2}. {:<16} {:<58} [{plugin}]",
                    k + 1,
                    format!("{set:?}"),
                    label
                );
            }
            say!("\npair terms (sweep: terms; terms joined by + run as one compiled loop):");
            if pair_terms.is_empty() {
                say!("  (none)");
            }
            for t in &pair_terms {
                say!("  - {t}");
            }
            say!("\nparticle components:");
            for c in &plan.components {
                say!("  - {c}");
            }
            Ok(())
        }),
        Command::Grid {
            scene,
            dir,
            file,
            field,
            dx,
        } => load(&scene, &registry, &SetArgs::default())
            .and_then(|s| grid_command(&scene, &s, dir, &file, &field, dx)),
        Command::PlotProbes { dir } => plot_probes_command(&dir),
        Command::Forces(a) => forces::forces_command(&a),
        Command::Probe {
            dir,
            scene,
            out,
            set,
        } => probe::probe_command(&dir, scene.as_deref(), out, &set, &registry).map(|(file, n)| {
            say!("wrote {} ({n} snapshots)", file.display());
        }),
        Command::Plugins { fields } => {
            say!("{}", doc::listing(&registry, fields).trim_end());
            Ok(())
        }
        Command::Doc { name } => doc::doc(&registry, &name).map(|text| {
            say!("{}", text.trim_end());
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::ValueEnum;

    #[test]
    fn the_formulation_values_are_the_engines_in_both_spellings() {
        let listed: Vec<String> = FormulationArg::value_variants()
            .iter()
            .filter_map(|f| f.to_possible_value())
            .map(|v| v.get_name().to_string())
            .collect();
        let want = [
            "dual-support",
            "single-support",
            "constant-h",
            "averaged-kernel",
            "grad-h",
        ];
        assert_eq!(listed, want);
        for f in Formulation::ALL {
            let by_name = FormulationArg::from_str(f.name(), false).unwrap();
            let by_kebab = FormulationArg::from_str(&kebab(f.name()), false).unwrap();
            assert_eq!((by_name.0, by_kebab.0), (f, f));
        }
        assert!(FormulationArg::from_str("Single", false).is_err());
    }
}
