//! Headless runs: step a scene to its end time, writing diagnostics and snapshots.

mod dt_floor;
mod keeper;
pub mod memory;
mod rows;
pub mod snapshots;

pub use dt_floor::{DT_FLOOR_KEY, DtFloor, MAX_PROJECTED_STEPS};

pub use keeper::{DEFAULT_KEEP_EVERY, KEEP_CHECKPOINTS, RestartOptions};
pub use snapshots::SnapshotSchedule;

use crate::checkpoint::{self, Checkpoint, CheckpointError};
use crate::{build_sim, with_dimension};
use dualsph_core::bevy_ecs::world::World;
use dualsph_core::bodies::Bodies;
use dualsph_core::columns::{Column, Columns};
use dualsph_core::neighbours::Neighbours;
use dualsph_core::population::Population;
use dualsph_diagnostics::{Diagnostics, DiagnosticsLog, Health, HealthBounds, SimDiagnostics};
use dualsph_fluid::prelude::*;
use dualsph_integrator::time_step::{CFL_LIMIT, TimeStepCheck};
use dualsph_io::{OutputDir, ParticleTable, TableColumn};
use dualsph_scene::Scene;
use keeper::Keeper;
use rows::DiagnosticsOutput;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

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

/// Errors of a run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Building or stepping failed.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// Output failed.
    #[error(transparent)]
    Output(#[from] dualsph_io::OutputError),
    /// A checkpoint could not be read, written or used.
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    /// The scene's `output` section asks for something the simulation does not have (a
    /// column no plugin registers); the message names it and what is available.
    #[error("{0}")]
    InvalidOutput(String),
    /// The state became unphysical; `message` names the step, time, particle, quantity and
    /// likely cause, and where the last good state was written.
    #[error("blow-up: {message}")]
    BlowUp {
        /// What happened and what was written.
        message: String,
        /// Checkpoint of the last good state, if one could be written.
        last_good: Option<PathBuf>,
    },
    /// The run was interrupted ([`interrupt`]) and stopped after a whole step, writing a
    /// checkpoint to resume from.
    #[error(
        "interrupted at step {step}, t = {t:.6e} s; resume with --resume {}",
        checkpoint.display()
    )]
    Interrupted {
        /// The last step taken.
        step: u64,
        /// Its time.
        t: Real,
        /// The checkpoint written at that step.
        checkpoint: PathBuf,
    },
}

/// User + system CPU seconds of this process (all threads), from the `cpu-time` crate
/// (`clock_gettime(CLOCK_PROCESS_CPUTIME_ID)` on Unix, `GetProcessTimes` on Windows). NaN
/// where the platform cannot tell, so a throughput computed from it is NaN, not nonsense.
pub fn cpu_seconds() -> f64 {
    cpu_time::ProcessTime::try_now().map_or(f64::NAN, |t| t.as_duration().as_secs_f64())
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

/// The usual cause of an unphysical `quantity` (as named by [`Health`]).
pub fn likely_cause(quantity: &str) -> &'static str {
    use dualsph_diagnostics as d;
    match quantity {
        d::OUTSIDE_DOMAIN => {
            "a particle thrown out of the domain: a dt above the CFL limit, or a missing wall (SpecularWalls)"
        }
        d::DENSITY_ABOVE => {
            "density far above its initial range: likely dt too large or c0 too small for the flow speed (a compression the equation of state does not resist)"
        }
        d::DENSITY_BELOW => {
            "density far below its initial range: likely the tensile instability (particles under tension pairing up) or particles left with too few neighbours"
        }
        d::H_ABOVE => {
            "smoothing length far above its initial range: particles spreading apart (a splash or a free end with too few neighbours), or the density collapsing"
        }
        d::H_BELOW => {
            "smoothing length far below its initial range: particles clumping (the tensile instability) or a runaway compression (dt too large or c0 too small)"
        }
        "density" | "smoothing length" => {
            "a dt above the CFL limit, or particles left with too few neighbours"
        }
        _ => "a dt above the CFL limit or too few neighbours",
    }
}

/// The first unphysical value of the state (from [`Health`]) as a blow-up error naming the
/// step, time, particle, quantity and the usual cause. A simulation without the health check
/// (no diagnostics plugin) or without the fixed-dt check (a scheme with its own dt rule) is
/// not checked for what it lacks.
pub fn check<V: Vector>(sim: &Sim<V>) -> Result<(), SimError> {
    let problem = sim.world.get_resource::<Health>().and_then(|h| h.problem);
    if let Some((id, what, value)) = problem {
        let c = sim.clock();
        let sane = sim
            .world
            .get_resource::<HealthBounds>()
            .and_then(|b| b.interval(what))
            .map(|(lo, hi)| format!(", outside [{lo:.4e}, {hi:.4e}]"))
            .unwrap_or_default();
        return Err(SimError::BlowUp(format!(
            "step {}, t = {:.6e}: particle {id} has {what} = {value:e}{sane} (dt = {:.3e}; likely cause: {})",
            c.step,
            c.t,
            c.dt,
            likely_cause(what)
        )));
    }
    let violation = sim.world.get_resource::<TimeStepCheck>();
    if let Some((id, dt, limit)) = violation.and_then(|c| c.violation) {
        let c = sim.clock();
        return Err(SimError::BlowUp(format!(
            "step {}, t = {:.6e}: the fixed dt = {dt:.3e} is above the CFL limit {limit:.3e} = {CFL_LIMIT} h/(c + |v|) of particle {id} (likely cause: dt above the CFL limit; lower dt or use Adaptive)",
            c.step, c.t
        )));
    }
    Ok(())
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
    memory::check_memory(scene, n, memory::memory_available())?;
    let mut sim = build_sim::<V>(scene)?;
    for n in sim.notes() {
        eprintln!("note: {n}");
    }
    for w in sim.advice() {
        eprintln!("warning: {w}");
    }
    sim.world.insert_resource(RunOutputDir(opts.out.clone()));
    if let Some(limit) = scene.max_steps {
        sim.world.insert_resource(StepLimit(limit));
    }
    let rows = DiagnosticsOutput::new(sim.world.resource::<Bodies>(), V::DIM);
    let extra = rows.columns(&sim.world);
    snapshots::select_columns(&mut sim, &scene.output).map_err(RunError::InvalidOutput)?;
    let formats = snapshots::output_options(&scene.output);
    let mut snapshots = SnapshotSchedule::new(&scene.output);
    let (mut out, initial, mut last_written) = match &restart.resume {
        None => {
            sim.initialize()?;
            check(&sim)?;
            let mut out = OutputDir::create(&opts.out, extra, formats)?;
            rows.open(&mut out)?;
            let initial = sim.diagnostics();
            rows.push(&mut out, &initial, &sim.world)?;
            if snapshots.initial() {
                out.write_snapshot(0, 0.0, &particle_table(&mut sim))?;
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
            checkpoint::restore(&mut sim, &ck).map_err(|why| CheckpointError::Mismatch {
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
    if opts.profile {
        sim.enable_profile()?;
    }
    let mut keeper = Keeper::new(scene, restart, &opts.out);
    keeper.keep(&mut sim);
    let diag_every = scene.output.diagnostics_every.max(1);
    let mut particle_steps = 0u64;
    let end = scene.end_time;
    let max_steps = scene.max_steps.unwrap_or(u64::MAX);
    let bar = (opts.progress == Progress::Bar).then(|| {
        let b = indicatif::ProgressBar::new(1_000_000);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {percent:>3}% | {msg} | ETA {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let started = Instant::now();
    let cpu_started = cpu_seconds();
    let mut last_log = Instant::now();
    while sim.clock().t < end * (1.0 - 1e-12) && sim.clock().step < max_steps {
        sim.step()?;
        particle_steps += sim.particle_count() as u64;
        let checked =
            check(&sim).and_then(|()| dt_floor::check(&mut sim, end, scene.max_steps.is_some()));
        if let Err(e) = checked {
            if let Some(b) = &bar {
                b.finish_and_clear();
            }
            return Err(keeper.blow_up(&mut sim, &out, e));
        }
        let c = sim.clock();
        if c.step % diag_every == 0 {
            let d = sim.diagnostics();
            rows.push(&mut out, &d, &sim.world)?;
            last_written = c.step;
            sim.world.resource_mut::<DiagnosticsLog>().last_written = c.step;
        }
        if snapshots.after_step(c.step, c.t) {
            out.write_snapshot(c.step, c.t, &particle_table(&mut sim))?;
        }
        keeper.after_step(&mut sim)?;
        if interrupted() {
            if let Some(b) = &bar {
                b.finish_and_clear();
            }
            // no diagnostics row off the cadence: the resumed run's file is then the
            // uninterrupted run's
            let checkpoint = keeper.write_now(&mut sim)?;
            return Err(RunError::Interrupted {
                step: c.step,
                t: c.t,
                checkpoint,
            });
        }
        let frac = (c.t / end).clamp(0.0, 1.0);
        match (&bar, opts.progress) {
            (Some(b), _) => {
                b.set_position((frac * 1e6) as u64);
                b.set_message(format!(
                    "step {} t = {:.5} s dt = {:.2e}",
                    c.step, c.t, c.dt
                ));
            }
            (None, Progress::Log) if last_log.elapsed().as_secs_f64() > 5.0 => {
                eprintln!(
                    "step {:>8}  t = {:.6e} s  ({:5.1} %)  dt = {:.3e}",
                    c.step,
                    c.t,
                    100.0 * frac,
                    c.dt
                );
                last_log = Instant::now();
            }
            _ => {}
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let wall = started.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu_started;
    let last = sim.diagnostics();
    if last.step != last_written {
        rows.push(&mut out, &last, &sim.world)?;
    }
    let records = particle_table(&mut sim);
    if snapshots.at_end(last.step) {
        out.write_snapshot(last.step, last.t, &records)?;
    }
    out.write_final(&records)?;
    let nb = sim.world.resource::<Neighbours<V>>();
    let (list_builds, skin) = (nb.builds, nb.skin);
    let (added, removed) = sim
        .world
        .get_resource::<Population<V>>()
        .map_or((0, 0), |p| (p.spawned, p.removed));
    Ok(RunSummary {
        particles: sim.particle_count() as u64,
        added,
        removed,
        steps: last.step,
        t: last.t,
        wall_seconds: wall,
        particle_steps_per_second: particle_steps as f64 / wall.max(1e-9),
        cpu_seconds: cpu,
        particle_steps_per_cpu_second: particle_steps as f64 / cpu.max(1e-9),
        list_builds,
        skin,
        profile: sim.profile().cloned(),
        initial,
        last,
    })
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
