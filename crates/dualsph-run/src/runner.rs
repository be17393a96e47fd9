//! Headless runs: step a scene to its end time, writing diagnostics and snapshots.

mod dt_floor;
mod keeper;
pub mod memory;
mod observers;
mod rows;
pub mod snapshots;

pub(crate) use dt_floor::check_dt_floor;
pub use dt_floor::{DT_FLOOR_KEY, DtFloor, MAX_PROJECTED_STEPS};

pub use crate::error::{RunError, cpu_seconds};
pub use keeper::{DEFAULT_KEEP_EVERY, KEEP_CHECKPOINTS, RestartOptions};
pub use snapshots::SnapshotSchedule;

use crate::checkpoint::{self, Checkpoint, CheckpointError};
use crate::run_loop::run_to_end;
use crate::{build_sim, with_dimension};
use dualsph_core::bevy_ecs::world::World;
use dualsph_core::bodies::Bodies;
use dualsph_core::columns::{Column, Columns};
use dualsph_core::neighbours::Neighbours;
use dualsph_core::population::Population;
use dualsph_diagnostics::{Diagnostics, DiagnosticsLog, SimDiagnostics};
use dualsph_fluid::prelude::*;
use dualsph_io::{OutputDir, ParticleTable, TableColumn};
use dualsph_scene::Scene;
use keeper::Keeper;
use observers::{Files, MemoryGuard, ProgressReport};
use rows::DiagnosticsOutput;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Extra diagnostics columns appended after the fixed ones.
pub const EXTRA_COLUMNS: [&str; 4] = ["lx", "ly", "rho_var_max", "dissipated"];

/// How to report progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// No progress output.
    Silent,
    /// A progress bar (terminal).
    Bar,
    /// Plain log lines on stderr.
    Log,
}

/// Options of a run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output directory.
    pub out: PathBuf,
    /// Progress reporting.
    pub progress: Progress,
    /// Time every system of the step (wall time per system in [`RunSummary::profile`]).
    pub profile: bool,
}

/// What a finished run reports.
#[derive(Clone, Debug)]
pub struct RunSummary {
    /// Particles at the end.
    pub particles: u64,
    /// Particles plugins added during the run (of this process: a resumed run counts from
    /// the resume).
    pub added: u64,
    /// Particles plugins removed during the run (likewise).
    pub removed: u64,
    /// Steps taken.
    pub steps: u64,
    /// Final time.
    pub t: Real,
    /// Wall-clock seconds of the stepping loop.
    pub wall_seconds: f64,
    /// Particle-steps per wall second.
    pub particle_steps_per_second: f64,
    /// CPU seconds of the stepping loop (user + system, all threads).
    pub cpu_seconds: f64,
    /// Particle-steps per CPU second (the throughput figure of `docs/performance.md`).
    pub particle_steps_per_cpu_second: f64,
    /// Neighbour-list builds during the run (set-up included, a resumed run's included).
    pub list_builds: u64,
    /// The Verlet skin of the last lists (chosen by the tuner unless the scene fixes it).
    pub skin: Real,
    /// Wall time per system over the run's steps, when [`RunOptions::profile`].
    pub profile: Option<dualsph_core::profile::SystemTimes>,
    /// Diagnostics at t = 0.
    pub initial: Diagnostics,
    /// Diagnostics at the end.
    pub last: Diagnostics,
}

/// Set by [`interrupt`]: running loops stop after their current step.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Asks every run of this process to stop after its current step, write a checkpoint and
/// return [`RunError::Interrupted`] (what the command line's Ctrl-C handler calls).
pub fn interrupt() {
    INTERRUPTED.store(true, Ordering::SeqCst);
}

/// Whether [`interrupt`] has been called.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// The scene's output columns (see `dualsph_core::columns`; those of `output.columns` when the
/// run chose some, see [`snapshots::select_columns`]) as a table, rows in id order, then the
/// plugins' derived columns ([`snapshots::derived_columns`]): what snapshots and `final.csv`
/// hold. Vectors are padded to three components.
pub fn particle_table<V: Vector>(sim: &mut Sim<V>) -> ParticleTable {
    let columns = snapshots::chosen_columns(&sim.world);
    let mut table = table_of::<V>(&mut sim.world, &columns);
    table
        .columns
        .extend(snapshots::derived_columns(&mut sim.world));
    table
}

/// Every registered column but the records (integrator registers) as a table, rows in id
/// order, named as in snapshots: what the probes and the grid can read by name. Vectors are
/// padded to three components.
pub fn column_table<V: Vector>(sim: &mut Sim<V>) -> ParticleTable {
    let columns: Vec<Column> = (sim.world.resource::<Columns>().iter())
        .filter(|c| c.shape != Shape::Record)
        .cloned()
        .collect();
    table_of::<V>(&mut sim.world, &columns)
}

/// `columns` of the particles of `world` as a table, rows in id order.
fn table_of<V: Vector>(world: &mut World, columns: &[Column]) -> ParticleTable {
    let mut ids: Vec<u64> = world
        .query::<&ParticleId>()
        .iter(world)
        .map(|id| u64::from(id.0))
        .collect();
    ids.sort_unstable();
    let columns = columns
        .iter()
        .map(|c| {
            let values = c.values_by_id(world);
            TableColumn {
                name: c.spec.name.to_string(),
                labels: c.labels(V::DIM),
                values: match c.shape {
                    Shape::Vector => values.chunks(V::DIM).flat_map(padded).collect(),
                    _ => values,
                },
            }
        })
        .collect();
    ParticleTable { ids, columns }
}

/// A vector's `d <= 3` components as x, y, z.
fn padded(v: &[Real]) -> [Real; 3] {
    let mut xyz = [0.0; 3];
    xyz[..v.len()].copy_from_slice(v);
    xyz
}

/// Builds and runs a scene of dimension `V::DIM` (no checkpoints, no resume).
pub fn run_dim<V: Vector>(scene: &Scene, opts: &RunOptions) -> Result<RunSummary, RunError> {
    run_dim_with::<V>(scene, opts, &RestartOptions::default())
}

/// Builds and runs a scene of dimension `V::DIM`, writing checkpoints and resuming as `restart`
/// says. On a blow-up the last good state is written to the output directory
/// ([`RunError::BlowUp`]).
pub fn run_dim_with<V: Vector>(
    scene: &Scene,
    opts: &RunOptions,
    restart: &RestartOptions,
) -> Result<RunSummary, RunError> {
    let n = scene.generate().len();
    let available = memory::memory_available();
    memory::check_memory(scene, n, available)?;
    let mut guard = MemoryGuard {
        budget: memory::Budget::new(available, n),
        scene,
    };
    let mut sim = build_sim::<V>(scene)?;
    for n in sim.notes() {
        eprintln!("note: {n}");
    }
    for w in sim.advice() {
        eprintln!("warning: {w}");
    }
    sim.world.insert_resource(RunOutputDir(opts.out.clone()));
    let (mut files, initial) = open_output(&mut sim, scene, opts, restart)?;
    if opts.profile {
        sim.enable_profile()?;
    }
    let mut keeper = Keeper::new(scene, restart, &opts.out);
    keeper.keep(&mut sim);
    let mut progress = ProgressReport::new(opts.progress);
    let ran = run_to_end(
        &mut sim,
        &mut [&mut guard, &mut files, &mut keeper, &mut progress],
    );
    drop(progress);
    let stepped = match ran {
        Ok(s) => s,
        Err(RunError::Sim(e)) => return Err(keeper.blow_up(&mut sim, &files.out, e)),
        Err(e) => return Err(e),
    };
    let last = sim.diagnostics();
    let nb = sim.world.resource::<Neighbours<V>>();
    let (list_builds, skin) = (nb.builds, nb.skin);
    let (added, removed) = sim
        .world
        .get_resource::<Population<V>>()
        .map_or((0, 0), |p| (p.spawned, p.removed));
    let (wall, cpu) = (stepped.wall_seconds, stepped.cpu_seconds);
    Ok(RunSummary {
        particles: sim.particle_count() as u64,
        added,
        removed,
        steps: last.step,
        t: last.t,
        wall_seconds: wall,
        particle_steps_per_second: stepped.particle_steps as f64 / wall.max(1e-9),
        cpu_seconds: cpu,
        particle_steps_per_cpu_second: stepped.particle_steps as f64 / cpu.max(1e-9),
        list_builds,
        skin,
        profile: sim.profile().cloned(),
        initial,
        last,
    })
}

/// The run's output directory, opened for a new run (the initial evaluation, its first
/// diagnostics row and snapshot) or reopened for a resumed one (the checkpoint restored),
/// and the diagnostics at t = 0.
fn open_output<V: Vector>(
    sim: &mut Sim<V>,
    scene: &Scene,
    opts: &RunOptions,
    restart: &RestartOptions,
) -> Result<(Files, Diagnostics), RunError> {
    let rows = DiagnosticsOutput::new(sim.world.resource::<Bodies>(), V::DIM);
    let extra = rows.columns(&sim.world);
    snapshots::select_columns(sim, &scene.output).map_err(RunError::InvalidOutput)?;
    let formats = snapshots::output_options(&scene.output);
    let mut snapshots = SnapshotSchedule::new(&scene.output);
    let (out, initial, last_written) = match &restart.resume {
        None => {
            sim.initialize()?;
            let mut out = OutputDir::create(&opts.out, extra, formats)?;
            rows.open(&mut out)?;
            let initial = sim.diagnostics();
            rows.push(&mut out, &initial, &sim.world)?;
            if snapshots.initial() {
                out.write_snapshot(0, 0.0, &particle_table(sim))?;
            }
            sim.world.insert_resource(DiagnosticsLog {
                initial: initial.clone(),
                last_written: 0,
            });
            (out, initial, 0)
        }
        Some(path) => {
            let ck = Checkpoint::read(path)?;
            ck.check_scene(scene, path)?;
            checkpoint::restore(sim, &ck).map_err(|why| CheckpointError::Mismatch {
                path: path.clone(),
                why,
            })?;
            let mut out = OutputDir::reopen(&opts.out, extra, ck.step, formats)?;
            rows.open(&mut out)?;
            let log = sim.world.get_resource_or_init::<DiagnosticsLog>().clone();
            (out, log.initial, log.last_written)
        }
    };
    snapshots.resume_at(sim.clock().t);
    let every = scene.output.diagnostics_every.max(1);
    let files = Files {
        out,
        rows,
        snapshots,
        every,
        last_written,
    };
    Ok((files, initial))
}

/// Runs a scene in its own dimension, with checkpoints and resume as `restart` says.
pub fn run_with(
    scene: &Scene,
    opts: &RunOptions,
    restart: &RestartOptions,
) -> Result<RunSummary, RunError> {
    with_dimension!(scene.dimension, V => run_dim_with::<V>(scene, opts, restart))
}

/// Runs a scene in its own dimension.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<RunSummary, RunError> {
    with_dimension!(scene.dimension, V => run_dim::<V>(scene, opts))
}

/// What a scene will run: the schedule and the particle columns ([`Plan`](dualsph_core::sim::Plan)), and the
/// pair terms as `sweep: term`.
pub fn plan(scene: &Scene) -> Result<Planned, SimError> {
    memory::check_memory(scene, scene.generate().len(), memory::memory_available())?;
    with_dimension!(scene.dimension, V => {
        let mut sim = build_sim::<V>(scene)?;
        sim.finish()?;
        Ok(Planned {
            plan: sim.plan(),
            pair_terms: sim.pair_terms(),
            warnings: sim.advice(),
            notes: sim.notes().to_vec(),
        })
    })
}

/// What [`plan`] finds: the schedule, the pair terms and the plugins' warnings about the
/// scene (`Sim::advise`).
#[derive(Debug)]
pub struct Planned {
    /// The systems and components.
    pub plan: dualsph_core::sim::Plan,
    /// The pair terms by sweep.
    pub pair_terms: Vec<String>,
    /// What the plugins warn of.
    pub warnings: Vec<String>,
    /// What the plugins derived from the scene (`Sim::note`).
    pub notes: Vec<String>,
}

/// Default output directory for a scene file: `out/<file stem>`.
pub fn default_out_dir(scene_path: &Path) -> PathBuf {
    let stem = scene_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    PathBuf::from("out").join(stem)
}
