//! What the run loop keeps for safety: checkpoint files every N steps (atomically, the last
//! [`KEEP_CHECKPOINTS`] of them), and in memory the last good state, which is written out
//! when the run blows up.

use super::{RunError, particle_table};
use crate::checkpoint::{self, Checkpoint, LAST_GOOD_STEM, checkpoint_file_name, fingerprint};
use dualsph_fluid::prelude::*;
use dualsph_io::OutputDir;
use dualsph_scene::Scene;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};

/// Steps between in-memory copies of the last good state when no checkpoint cadence is set
/// (a copy costs about one gather of every component and the neighbour lists).
pub const DEFAULT_KEEP_EVERY: u64 = 50;

/// Checkpoint files kept in the output directory; older ones are deleted.
pub const KEEP_CHECKPOINTS: usize = 3;

/// Checkpoint and resume settings of a run.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RestartOptions {
    /// Write `checkpoint_NNNNNN.ckpt` into the output directory every this many steps.
    pub checkpoint_every: Option<u64>,
    /// Continue from this checkpoint instead of starting at t = 0.
    pub resume: Option<PathBuf>,
}

/// Checkpoint files and the last good state of one run.
pub(crate) struct Keeper {
    scene_name: String,
    fingerprint: u64,
    every: Option<u64>,
    dir: PathBuf,
    last_good: Option<Checkpoint>,
    written: VecDeque<PathBuf>,
}

impl Keeper {
    pub(crate) fn new(scene: &Scene, restart: &RestartOptions, dir: &Path) -> Self {
        Keeper {
            scene_name: scene.name.clone(),
            fingerprint: fingerprint(scene),
            every: restart.checkpoint_every.filter(|&e| e > 0),
            dir: dir.to_path_buf(),
            last_good: None,
            written: VecDeque::new(),
        }
    }

    /// Copies the current (checked) state as the last good one.
    pub(crate) fn keep<V: Vector>(&mut self, sim: &mut Sim<V>) -> &Checkpoint {
        let ck = checkpoint::capture(sim, &self.scene_name, self.fingerprint);
        self.last_good.insert(ck)
    }

    /// After a checked step: keeps a copy every [`DEFAULT_KEEP_EVERY`] steps and writes a
    /// checkpoint file every `checkpoint_every` steps.
    pub(crate) fn after_step<V: Vector>(&mut self, sim: &mut Sim<V>) -> Result<(), RunError> {
        let step = sim.clock().step;
        let write = self.every.is_some_and(|e| step.is_multiple_of(e));
        if !(write || step.is_multiple_of(DEFAULT_KEEP_EVERY)) {
            return Ok(());
        }
        let path = self.dir.join(checkpoint_file_name(step));
        let ck = self.keep(sim);
        if write {
            ck.write(&path)?;
            self.written.push_back(path);
            while self.written.len() > KEEP_CHECKPOINTS {
                if let Some(old) = self.written.pop_front() {
                    let _ = std::fs::remove_file(old);
                }
            }
        }
        Ok(())
    }

    /// Writes a checkpoint of the current state now, whatever the cadence, and returns its
    /// path (an interrupted run's).
    pub(crate) fn write_now<V: Vector>(&mut self, sim: &mut Sim<V>) -> Result<PathBuf, RunError> {
        let path = self.dir.join(checkpoint_file_name(sim.clock().step));
        self.keep(sim).write(&path)?;
        Ok(path)
    }

    /// The error for a blow-up `e`, after writing the last good state (particles as
    /// `last_good.csv` and, with VTK snapshots, `.vtp`; the state as `last_good.ckpt`) to the
    /// output directory.
    pub(crate) fn blow_up<V: Vector>(
        &mut self,
        sim: &mut Sim<V>,
        out: &OutputDir,
        e: SimError,
    ) -> RunError {
        let mut message = match e {
            SimError::BlowUp(m) | SimError::Build(m) => m,
        };
        let Some(ck) = self.last_good.take() else {
            return RunError::BlowUp {
                message,
                last_good: None,
            };
        };
        let path = out.dir().join(format!("{LAST_GOOD_STEM}.ckpt"));
        let written = checkpoint::restore(sim, &ck).and_then(|()| {
            out.write_particles_as(LAST_GOOD_STEM, &particle_table(sim))
                .map_err(|e| e.to_string())?;
            ck.write(&path).map_err(|e| e.to_string())
        });
        match written {
            Ok(()) => {
                let vtp = if out.options().vtk {
                    format!("{LAST_GOOD_STEM}.vtp, ")
                } else {
                    String::new()
                };
                message.push_str(&format!(
                    "; the last good state (step {}, t = {:.6e}) is written to {}/{LAST_GOOD_STEM}.csv, \
                     {vtp}{LAST_GOOD_STEM}.ckpt",
                    ck.step,
                    ck.t,
                    out.dir().display()
                ));
                RunError::BlowUp {
                    message,
                    last_good: Some(path),
                }
            }
            Err(w) => {
                message.push_str(&format!("; writing the last good state failed: {w}"));
                RunError::BlowUp {
                    message,
                    last_good: None,
                }
            }
        }
    }
}
