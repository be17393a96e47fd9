//! `dualsph run`: a scene, headless, into an output directory of its own, with `run.json`
//! saying what produced it and how it ended.

use super::FormulationArg;
use super::exit::{self, Failure};
use super::record::{RunRecord, RunSettings, check_resume_dir, prepare_out_dir, resume_dir};
use crate::runner::{self, Progress, RestartOptions, RunOptions, RunSummary};
use dualsph_core::plugin::Registry;
use dualsph_scene::Scene;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// The options of `dualsph run`.
#[derive(clap::Args)]
pub(crate) struct RunArgs {
    /// The scene file (.ron).
    scene: PathBuf,
    /// Output directory (default: out/<scene name>; with --resume, the checkpoint's own
    /// directory). It must be empty or not exist, unless --force; a resume refuses a
    /// directory that holds another scene's run.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Run into a non-empty output directory, deleting what a previous run wrote there
    /// (snapshots, checkpoints, diagnostics, run.json, …; other files are left alone).
    #[arg(long)]
    force: bool,
    /// No progress output.
    #[arg(long)]
    quiet: bool,
    /// Replace the scene's formulation (e.g. single-support, or SingleSupport as a scene
    /// spells it, to rerun a paper's Case I).
    #[arg(long, value_enum)]
    formulation: Option<FormulationArg>,
    /// Write the complete state to OUT/checkpoint_NNNNNN.ckpt every N steps (atomically;
    /// the last three are kept).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    checkpoint_every: Option<u64>,
    /// Continue from a checkpoint of the same scene; the result is bitwise identical to an
    /// uninterrupted run.
    #[arg(long, value_name = "CHECKPOINT")]
    resume: Option<PathBuf>,
    /// Stop at this simulated time instead of the scene's end_time (e.g. to time the
    /// first 0.3 s of a dam break).
    #[arg(long, value_name = "T")]
    end_time: Option<f64>,
    /// Print the wall time of every system of the step at the end (where the time goes).
    #[arg(long)]
    profile: bool,
    #[command(flatten)]
    set: super::SetArgs,
    /// Run on N threads (default: RAYON_NUM_THREADS, else one per core); the results are
    /// bitwise the same whatever N.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
}

/// Ctrl-C presses seen: the first stops the run after its step (with a checkpoint), the
/// second ends the process at once (files are written atomically: none is left half written).
static PRESSES: AtomicU32 = AtomicU32::new(0);

/// Installs the Ctrl-C handler (once per process).
fn handle_ctrl_c() {
    let _ = ctrlc::set_handler(|| {
        if PRESSES.fetch_add(1, Ordering::SeqCst) == 0 {
            eprintln!(
                "\ndualsph: interrupted; stopping after this step (Ctrl-C again to quit at once)"
            );
            runner::interrupt();
        } else {
            std::process::exit(i32::from(exit::INTERRUPTED));
        }
    });
}

/// Sets the number of threads of the process (before any parallel work).
fn set_threads(n: u16) -> Result<(), Failure> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(usize::from(n))
        .build_global()
        .map_err(|e| Failure::new(exit::OTHER, format!("--threads {n}: {e}")))
}

/// `dualsph run`.
pub(crate) fn run(args: RunArgs, registry: &Registry) -> Result<(), Failure> {
    if let Some(n) = args.threads {
        set_threads(n)?;
    }
    let (mut s, text) = super::load_with_text(&args.scene, registry, &args.set)?;
    if let Some(f) = args.formulation {
        s.formulation = f.0;
    }
    if let Some(t) = args.end_time {
        if !(t.is_finite() && t > 0.0) {
            return Err(Failure::new(
                exit::INVALID_INPUT,
                format!("--end-time {t}: must be a positive number of seconds"),
            ));
        }
        s.end_time = t;
    }
    let fingerprint = crate::checkpoint::fingerprint(&s);
    let set: Vec<String> = args.set.set.iter().map(|o| o.given.clone()).collect();
    let out = match &args.resume {
        Some(ck) => resume_dir(ck, args.out.as_deref()),
        None => (args.out.clone()).unwrap_or_else(|| runner::default_out_dir(&args.scene)),
    };
    // held until the run has written its record: no other run or resume writes here meanwhile
    let _lock = super::lock::lock_out_dir(&out)?;
    match &args.resume {
        Some(ck) => check_resume(&args.scene, &s, ck, &out, fingerprint)
            .map_err(|f| f.with_hint(&overrides_hint(&out, &set)))?,
        None => prepare_out_dir(&out, args.force)?,
    }
    let mut record = RunRecord::start(
        &args.scene,
        text,
        fingerprint,
        RunSettings {
            out: out.clone(),
            set,
            formulation: format!("{:?}", s.formulation),
            end_time: s.end_time,
            checkpoint_every: args.checkpoint_every,
            resume: args.resume.clone(),
            force: args.force,
            threads: rayon::current_num_threads(),
        },
    );
    record.write(&out)?;
    handle_ctrl_c();
    let result = run_scene(&args, &s, &out);
    record.finish(result.as_ref());
    let recorded = record.write(&out);
    let summary = result?;
    recorded?;
    report(&summary, &out)
}

/// Refuses a resume before anything is written: a checkpoint of another scene, or an output
/// directory holding another run ([`check_resume_dir`]).
fn check_resume(
    scene_path: &Path,
    s: &Scene,
    checkpoint: &Path,
    out: &Path,
    fingerprint: u64,
) -> Result<(), Failure> {
    let ck = crate::checkpoint::Checkpoint::read(checkpoint)
        .and_then(|ck| ck.check_scene(s, checkpoint));
    if let Err(e) = ck {
        let e = runner::RunError::from(e);
        return Err(Failure::new(
            exit::of_run(&e),
            format!("{}: {e}", scene_path.display()),
        ));
    }
    check_resume_dir(out, fingerprint)
}

/// When the run in `dir` was made with other `--set` overrides than `set`, a sentence saying
/// so (a resume must repeat them to rebuild the same scene); empty otherwise.
fn overrides_hint(dir: &Path, set: &[String]) -> String {
    let Some(recorded) = super::record::recorded_overrides(dir) else {
        return String::new();
    };
    if recorded == set {
        return String::new();
    }
    let list = |s: &[String]| match s {
        [] => "none".to_string(),
        s => s
            .iter()
            .map(|o| format!("--set {o}"))
            .collect::<Vec<_>>()
            .join(" "),
    };
    format!(
        "; the run in {} was made with overrides {} and this resume gives {}: a resume \
         repeats the run's overrides",
        dir.display(),
        list(&recorded),
        list(set)
    )
}

/// Runs the scene into `out`.
fn run_scene(args: &RunArgs, s: &Scene, out: &Path) -> Result<RunSummary, Failure> {
    let progress = if args.quiet {
        Progress::Silent
    } else if std::io::stderr().is_terminal() {
        Progress::Bar
    } else {
        Progress::Log
    };
    eprintln!(
        "dualsph: running {} ({}-D, {} particles generated) → {}",
        args.scene.display(),
        s.dimension,
        s.generate().len(),
        out.display()
    );
    if let Some(ck) = &args.resume {
        eprintln!("dualsph: resuming from {}", ck.display());
    }
    let restart = RestartOptions {
        checkpoint_every: args.checkpoint_every,
        resume: args.resume.clone(),
    };
    let opts = RunOptions {
        out: out.to_path_buf(),
        progress,
        profile: args.profile,
    };
    runner::run_with(s, &opts, &restart).map_err(|e| {
        let mut message = format!("{}: {e}", args.scene.display());
        if matches!(e, runner::RunError::Interrupted { .. }) {
            // the resume must give the scene the same values
            for o in &args.set.set {
                message.push_str(&format!(" --set '{}'", o.given));
            }
        }
        Failure::new(exit::of_run(&e), message)
    })
}

/// Prints what a finished run did.
fn report(summary: &RunSummary, out: &Path) -> Result<(), Failure> {
    say!(
        "done: {} particles, {} steps to t = {:.6} s in {:.2} s wall, {:.2} CPU-s ({:.3e} particle-steps per wall-s, {:.3e} per CPU-s, {} threads; {} neighbour-list builds, last skin {:.3}); output in {}",
        summary.particles,
        summary.steps,
        summary.t,
        summary.wall_seconds,
        summary.cpu_seconds,
        summary.particle_steps_per_second,
        summary.particle_steps_per_cpu_second,
        rayon::current_num_threads(),
        summary.list_builds,
        summary.skin,
        out.display()
    );
    if summary.added + summary.removed > 0 {
        say!(
            "particles: {} added and {} removed during the run",
            summary.added,
            summary.removed
        );
    }
    let (a, b) = (&summary.initial, &summary.last);
    say!(
        "conservation: mass {:.3e} → {:.3e}, momentum [{:.3e}, {:.3e}, {:.3e}], E_tot {:.6e} → {:.6e}",
        a.mass,
        b.mass,
        b.momentum[0],
        b.momentum[1],
        b.momentum[2],
        a.e_tot,
        b.e_tot
    );
    if let Some(p) = &summary.profile {
        say!(
            "\nwall time per system over {} steps ({} threads):\n{}",
            p.steps,
            rayon::current_num_threads(),
            p.table(summary.particles)
        );
        say!(
            "steps {:.3} s of the run loop's {:.3} s; the rest is output, checkpoints and progress",
            p.total(),
            summary.wall_seconds
        );
    }
    if out.join(dualsph_probes::PROBES_FILE).exists() {
        let pngs = dualsph_probes::plot_probes(out)?;
        say!("probes: {} plots in {}", pngs.len(), out.display());
    }
    Ok(())
}
