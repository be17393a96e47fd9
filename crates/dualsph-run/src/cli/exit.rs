//! The exit status of the `dualsph` command: one code per kind of failure, so a script or a
//! parameter sweep can tell a typo from a blow-up.

use crate::checkpoint::CheckpointError;
use crate::runner::RunError;
use dualsph_core::sim::SimError;
use dualsph_scene::SceneError;

/// The command succeeded.
pub const SUCCESS: u8 = 0;
/// Any other failure (e.g. a field that cannot be gridded, a probes file that cannot be plotted).
pub const OTHER: u8 = 1;
/// Invalid input: a scene that does not parse or validate, an option out of range, a
/// simulation that cannot be built, a checkpoint that is damaged or of another scene.
pub const INVALID_INPUT: u8 = 2;
/// The run blew up: the state became unphysical (the last good state is written).
pub const BLOW_UP: u8 = 3;
/// A file could not be read or written.
pub const IO: u8 = 4;
/// The run was interrupted (Ctrl-C): it stopped after a whole step and wrote a checkpoint
/// (128 + SIGINT, the shells' convention).
pub const INTERRUPTED: u8 = 130;

/// A failed command: its exit code and its message.
#[derive(Debug)]
pub struct Failure {
    /// One of the codes above.
    pub code: u8,
    /// What went wrong.
    pub message: String,
}

impl Failure {
    /// A failure with `code`.
    pub fn new(code: u8, message: impl Into<String>) -> Self {
        Failure {
            code,
            message: message.into(),
        }
    }
}

impl Failure {
    /// The failure with `hint` appended to its message (nothing when `hint` is empty).
    pub fn with_hint(mut self, hint: &str) -> Self {
        self.message.push_str(hint);
        self
    }
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        Failure::new(OTHER, message)
    }
}

/// The code of a scene error: unreadable file or invalid content.
pub fn of_scene(e: &SceneError) -> u8 {
    match e {
        SceneError::Io { .. } => IO,
        _ => INVALID_INPUT,
    }
}

/// The code of a simulation error.
pub fn of_sim(e: &SimError) -> u8 {
    match e {
        SimError::Build(_) => INVALID_INPUT,
        SimError::BlowUp(_) => BLOW_UP,
    }
}

/// The code of a run error.
pub fn of_run(e: &RunError) -> u8 {
    match e {
        RunError::Sim(s) => of_sim(s),
        RunError::Output(_) => IO,
        RunError::Checkpoint(CheckpointError::Io { .. } | CheckpointError::Output(_)) => IO,
        RunError::Checkpoint(_) => INVALID_INPUT,
        RunError::InvalidOutput(_) => INVALID_INPUT,
        RunError::BlowUp { .. } => BLOW_UP,
        RunError::Interrupted { .. } => INTERRUPTED,
    }
}

/// The word for a failure of `code`, as `run.json` records it.
pub fn cause(code: u8) -> &'static str {
    match code {
        SUCCESS => "completed",
        INVALID_INPUT => "invalid input",
        BLOW_UP => "blow-up",
        IO => "io error",
        INTERRUPTED => "interrupted",
        _ => "failed",
    }
}

/// The table of codes, for `--help` and `docs/cli.md`.
pub const HELP: &str = "Exit status: 0 success, 1 other failure, 2 invalid input (scene, \
options, checkpoint, an output directory in use), 3 blow-up or stalled run (the last good \
state is written), 4 a file could not be read or written, 130 interrupted by Ctrl-C (a \
checkpoint of the last whole step is written).";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_of_failure_has_its_own_code() {
        let build = RunError::Sim(SimError::Build("x".into()));
        let blow = RunError::BlowUp {
            message: "x".into(),
            last_good: None,
        };
        let columns = RunError::InvalidOutput("x".into());
        let codes = [of_run(&build), of_run(&blow), OTHER, IO, of_run(&columns)];
        assert_eq!(codes, [INVALID_INPUT, BLOW_UP, 1, 4, INVALID_INPUT]);
        let io = SceneError::Io {
            path: "s.ron".into(),
            source: std::io::Error::other("gone"),
        };
        assert_eq!(of_scene(&io), IO);
    }
}
