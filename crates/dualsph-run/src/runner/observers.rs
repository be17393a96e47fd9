//! The observers of a `dualsph run` ([`crate::run_loop`]): the files of the output directory
//! (diagnostics rows, snapshots, `final.csv`), the checkpoints and the interrupt, and the
//! progress report.

use super::keeper::Keeper;
use super::memory::Budget;
use super::rows::DiagnosticsOutput;
use super::{Progress, RunError, SnapshotSchedule, interrupted, particle_table};
use crate::run_loop::{Flow, Observer};
use dualsph_diagnostics::{DiagnosticsLog, SimDiagnostics};
use dualsph_fluid::prelude::*;
use dualsph_io::OutputDir;
use dualsph_scene::Scene;
use std::time::Instant;

/// The files of a run's output directory written as it runs: a diagnostics row every
/// `every` steps (and at the end), the snapshots on their schedule, and at the end
/// `final.csv`.
pub(crate) struct Files {
    pub(crate) out: OutputDir,
    pub(crate) rows: DiagnosticsOutput,
    pub(crate) snapshots: SnapshotSchedule,
    /// Steps between diagnostics rows.
    pub(crate) every: u64,
    /// The step of the last row written.
    pub(crate) last_written: u64,
}

impl<V: Vector> Observer<V> for Files {
    fn after_step(&mut self, sim: &mut Sim<V>) -> Result<Flow, RunError> {
        let c = sim.clock();
        if c.step.is_multiple_of(self.every) {
            let d = sim.diagnostics();
            self.rows.push(&mut self.out, &d, &sim.world)?;
            self.last_written = c.step;
            sim.world.resource_mut::<DiagnosticsLog>().last_written = c.step;
        }
        if self.snapshots.after_step(c.step, c.t) {
            self.out.write_snapshot(c.step, c.t, &particle_table(sim))?;
        }
        Ok(Flow::Continue)
    }

    fn at_end(&mut self, sim: &mut Sim<V>) -> Result<(), RunError> {
        let last = sim.diagnostics();
        if last.step != self.last_written {
            self.rows.push(&mut self.out, &last, &sim.world)?;
        }
        let records = particle_table(sim);
        if self.snapshots.at_end(last.step) {
            self.out.write_snapshot(last.step, last.t, &records)?;
        }
        self.out.write_final(&records)?;
        Ok(())
    }
}

/// The run-time memory guard ([`Budget`]): after a step that grew the particle count, the run
/// stops as a blow-up (its last good state written) once the count needs more memory than
/// was available at the start.
pub(crate) struct MemoryGuard<'a> {
    pub(crate) budget: Budget,
    pub(crate) scene: &'a Scene,
}

impl<V: Vector> Observer<V> for MemoryGuard<'_> {
    fn after_step(&mut self, sim: &mut Sim<V>) -> Result<Flow, RunError> {
        let (n, clock) = (sim.particle_count(), sim.clock());
        self.budget.after_step(self.scene, n, &clock)?;
        Ok(Flow::Continue)
    }
}

/// The checkpoints and the last good state ([`Keeper`]), and the interrupt: after a step of
/// an interrupted process, a checkpoint is written and the run ends with
/// [`RunError::Interrupted`].
impl<V: Vector> Observer<V> for Keeper {
    fn after_step(&mut self, sim: &mut Sim<V>) -> Result<Flow, RunError> {
        Keeper::after_step(self, sim)?;
        if interrupted() {
            let c = sim.clock();
            // no diagnostics row off the cadence: the resumed run's file is then the
            // uninterrupted run's
            let checkpoint = self.write_now(sim)?;
            return Err(RunError::Interrupted {
                step: c.step,
                t: c.t,
                checkpoint,
            });
        }
        Ok(Flow::Continue)
    }
}

/// The progress report: a bar on a terminal, a line every 5 s in a log; the bar is cleared
/// when the report is dropped (the run ended, whichever way).
pub(crate) struct ProgressReport {
    bar: Option<indicatif::ProgressBar>,
    log: bool,
    last_log: Instant,
}

impl ProgressReport {
    /// The report `progress` asks for.
    pub(crate) fn new(progress: Progress) -> Self {
        let bar = (progress == Progress::Bar).then(|| {
            let b = indicatif::ProgressBar::new(1_000_000);
            b.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {percent:>3}% | {msg} | ETA {eta}",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            b
        });
        ProgressReport {
            bar,
            log: progress == Progress::Log,
            last_log: Instant::now(),
        }
    }
}

impl Drop for ProgressReport {
    fn drop(&mut self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

impl<V: Vector> Observer<V> for ProgressReport {
    fn after_step(&mut self, sim: &mut Sim<V>) -> Result<Flow, RunError> {
        let c = sim.clock();
        let frac = (c.t / c.t_end).clamp(0.0, 1.0);
        if let Some(b) = &self.bar {
            b.set_position((frac * 1e6) as u64);
            b.set_message(format!(
                "step {} t = {:.5} s dt = {:.2e}",
                c.step, c.t, c.dt
            ));
        } else if self.log && self.last_log.elapsed().as_secs_f64() > 5.0 {
            eprintln!(
                "step {:>8}  t = {:.6e} s  ({:5.1} %)  dt = {:.3e}",
                c.step,
                c.t,
                100.0 * frac,
                c.dt
            );
            self.last_log = Instant::now();
        }
        Ok(Flow::Continue)
    }
}
