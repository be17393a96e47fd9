//! What can end a run before its end: a failed step, a file that could not be written, a
//! checkpoint that cannot be used, an interrupt; and the process CPU clock runs are timed by.

use crate::checkpoint::CheckpointError;
use dualsph_fluid::prelude::*;
use std::path::PathBuf;

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
    /// The run was interrupted (`runner::interrupt`) and stopped after a whole step, writing a
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
