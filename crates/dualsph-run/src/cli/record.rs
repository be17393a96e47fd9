//! What a run leaves behind besides its results: the output directory is its own (a new run
//! does not mix with an old one's files), and `run.json` says what produced it.

use super::exit::{self, Failure};
use crate::runner::RunSummary;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// File name of the run record.
pub const RUN_FILE: &str = "run.json";

/// Whether `name` is a file a run (or the commands that post-process one: `grid`,
/// `plot-probes`) writes into its output directory — what `--force` clears.
pub fn written_by_a_run(name: &str) -> bool {
    use crate::checkpoint::LAST_GOOD_STEM;
    use dualsph_io::{BODIES_FILE, DIAGNOSTICS_FILE, FINAL_FILE, PVD_FILE, SNAPSHOT_INDEX_FILE};
    use dualsph_probes::{PROBE_POINTS_FILE, PROBES_FILE};
    let files = [
        RUN_FILE,
        DIAGNOSTICS_FILE,
        BODIES_FILE,
        SNAPSHOT_INDEX_FILE,
        PVD_FILE,
        FINAL_FILE,
        PROBES_FILE,
        PROBE_POINTS_FILE,
    ];
    // snapshots (`particles_NNNNNN`), checkpoints, the last good state, the probes' plots
    let last_good = format!("{LAST_GOOD_STEM}.");
    let stems = ["particles_", "checkpoint_", last_good.as_str(), "probes_"];
    let temporary = name.starts_with('.') && name.ends_with(".tmp");
    let grid = name.contains("_grid.") && (name.ends_with(".vti") || name.ends_with(".png"));
    files.contains(&name) || stems.iter().any(|p| name.starts_with(p)) || temporary || grid
}

/// Makes `dir` ready for a new run: a directory that does not exist or is empty is fine; one
/// that holds files is refused unless `force`, which deletes the files a run writes (see
/// [`written_by_a_run`]; anything else is left where it is). A resumed run continues in its
/// directory and is not checked.
pub fn prepare_out_dir(dir: &Path, force: bool) -> Result<(), Failure> {
    let io = |e: std::io::Error| {
        Failure::new(exit::IO, format!("output directory {}: {e}", dir.display()))
    };
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io(e)),
    };
    let mut names: Vec<String> = Vec::new();
    for entry in entries {
        let name = entry
            .map_err(io)?
            .file_name()
            .to_string_lossy()
            .into_owned();
        // the lock of this run ([`super::lock`]), not a file of another one
        if name != super::lock::LOCK_FILE {
            names.push(name);
        }
    }
    if names.is_empty() {
        return Ok(());
    }
    if !force {
        names.sort();
        let shown: Vec<&str> = names.iter().take(3).map(String::as_str).collect();
        let more = if names.len() > 3 { ", …" } else { "" };
        return Err(Failure::new(
            exit::INVALID_INPUT,
            format!(
                "output directory {} is not empty ({} entries: {}{more}); choose another --out, \
                 add --force to clear what a previous run wrote there, or --resume a checkpoint",
                dir.display(),
                names.len(),
                shown.join(", ")
            ),
        ));
    }
    for name in names.iter().filter(|n| written_by_a_run(n)) {
        let path = dir.join(name);
        if path.is_file() {
            std::fs::remove_file(&path).map_err(io)?;
        }
    }
    Ok(())
}

/// The directory a resume writes to: `--out` when given, else the checkpoint's own directory
/// (where the interrupted run wrote its files).
pub fn resume_dir(checkpoint: &Path, out: Option<&Path>) -> PathBuf {
    match out {
        Some(o) => o.to_path_buf(),
        None => match checkpoint.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        },
    }
}

/// Refuses to resume into `dir` unless it is empty, absent, or holds a run of the same scene
/// (its `run.json` carries `fingerprint`): a resume never appends to another run's files.
/// Nothing is written.
pub fn check_resume_dir(dir: &Path, fingerprint: u64) -> Result<(), Failure> {
    let refuse = |why: String| {
        Failure::new(
            exit::INVALID_INPUT,
            format!(
                "cannot resume into {}: {why}; resume into the interrupted run's own directory \
                 (the default) or name an empty one with --out",
                dir.display()
            ),
        )
    };
    let record = dir.join(RUN_FILE);
    let text = match std::fs::read_to_string(&record) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let holds_files = std::fs::read_dir(dir)
                .map(|entries| (entries.flatten()).any(|e| e.file_name() != super::lock::LOCK_FILE))
                .unwrap_or(false);
            return if holds_files {
                Err(refuse("it holds files but no run.json".into()))
            } else {
                Ok(())
            };
        }
        Err(e) => return Err(refuse(format!("{}: {e}", record.display()))),
    };
    let recorded = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .and_then(|v| v.get("scene_fingerprint")?.as_str().map(str::to_owned));
    match recorded {
        Some(f) if f == format!("{fingerprint:016x}") => Ok(()),
        Some(f) => Err(refuse(format!(
            "its run.json is of another scene (fingerprint {f}, this scene's {fingerprint:016x})"
        ))),
        None => Err(refuse("its run.json names no scene fingerprint".into())),
    }
}

/// The `--set` overrides recorded in `dir`'s `run.json`, if it has one that can be read.
pub fn recorded_overrides(dir: &Path) -> Option<Vec<String>> {
    let text = std::fs::read_to_string(dir.join(RUN_FILE)).ok()?;
    let v = serde_json::from_str::<serde_json::Value>(&text).ok()?;
    v.get("settings")?
        .get("set")?
        .as_array()?
        .iter()
        .map(|o| o.as_str().map(str::to_owned))
        .collect()
}

/// The options a run was given.
#[derive(Clone, Debug, Serialize)]
pub struct RunSettings {
    /// Output directory.
    pub out: PathBuf,
    /// The `--set PATH=VALUE` overrides, in order (applied to `scene_text`).
    pub set: Vec<String>,
    /// `--formulation`, as the scene ended up with.
    pub formulation: String,
    /// The end time the run was given (the scene's, or `--end-time`).
    pub end_time: f64,
    /// `--checkpoint-every`.
    pub checkpoint_every: Option<u64>,
    /// `--resume`.
    pub resume: Option<PathBuf>,
    /// `--force`.
    pub force: bool,
    /// Threads the run used.
    pub threads: usize,
}

/// How the run ended.
#[derive(Clone, Debug, Serialize)]
pub struct Ending {
    /// `running` (while it runs), `completed`, `blow-up`, `interrupted`, `invalid input`,
    /// `io error` or `failed`.
    pub cause: &'static str,
    /// The process exit status; null while the run is running (so a run killed before it
    /// could rewrite its record shows no status).
    pub exit_code: Option<u8>,
    /// The error message, if it failed.
    pub message: Option<String>,
}

/// The figures of a finished run (from [`RunSummary`]).
#[derive(Clone, Debug, Serialize)]
pub struct SummaryRecord {
    /// Particles at the end.
    pub particles: u64,
    /// Particles added and removed during the run.
    pub added: u64,
    /// Particles removed during the run.
    pub removed: u64,
    /// Steps taken (counted from t = 0).
    pub steps: u64,
    /// Final simulated time (s).
    pub t: f64,
    /// Wall seconds of the stepping loop.
    pub wall_seconds: f64,
    /// CPU seconds of the stepping loop, all threads (null where the platform cannot tell).
    pub cpu_seconds: Option<f64>,
    /// Particle-steps per CPU second.
    pub particle_steps_per_cpu_second: Option<f64>,
    /// Total energy at t = 0 and at the end.
    pub e_tot: [f64; 2],
    /// Mass at t = 0 and at the end.
    pub mass: [f64; 2],
}

impl From<&RunSummary> for SummaryRecord {
    fn from(s: &RunSummary) -> Self {
        let finite = |x: f64| x.is_finite().then_some(x);
        SummaryRecord {
            particles: s.particles,
            added: s.added,
            removed: s.removed,
            steps: s.steps,
            t: s.t,
            wall_seconds: s.wall_seconds,
            cpu_seconds: finite(s.cpu_seconds),
            particle_steps_per_cpu_second: finite(s.particle_steps_per_cpu_second),
            e_tot: [s.initial.e_tot, s.last.e_tot],
            mass: [s.initial.mass, s.last.mass],
        }
    }
}

/// `run.json`: what produced an output directory and how the run ended. Written when the run
/// starts (cause `running`) and rewritten, atomically, when it ends.
#[derive(Clone, Debug, Serialize)]
pub struct RunRecord {
    /// The engine's version.
    pub version: &'static str,
    /// The git revision the binary was built from, when built from a checkout.
    pub git_revision: Option<&'static str>,
    /// The command line, program name first.
    pub command_line: Vec<String>,
    /// The working directory the command ran in.
    pub working_directory: Option<PathBuf>,
    /// The scene file as given.
    pub scene_path: PathBuf,
    /// The scene file's text.
    pub scene_text: String,
    /// The scene's fingerprint (16 hex digits): what a checkpoint of it carries, and what a
    /// resume into this directory must match (`checkpoint::fingerprint`).
    pub scene_fingerprint: String,
    /// The options of the run.
    pub settings: RunSettings,
    /// Start time, UTC (RFC 3339).
    pub started: String,
    /// End time, UTC (RFC 3339), once it has ended.
    pub ended: Option<String>,
    /// How it ended.
    pub ending: Ending,
    /// The figures, when it completed.
    pub summary: Option<SummaryRecord>,
}

/// Now, UTC, to the second (RFC 3339).
fn now() -> String {
    humantime::format_rfc3339_seconds(SystemTime::now()).to_string()
}

impl RunRecord {
    /// The record of a run starting now.
    pub fn start(
        scene_path: &Path,
        scene_text: String,
        fingerprint: u64,
        settings: RunSettings,
    ) -> Self {
        RunRecord {
            version: env!("CARGO_PKG_VERSION"),
            git_revision: option_env!("DUALSPH_GIT_REVISION"),
            command_line: std::env::args().collect(),
            working_directory: std::env::current_dir().ok(),
            scene_path: scene_path.to_path_buf(),
            scene_text,
            scene_fingerprint: format!("{fingerprint:016x}"),
            settings,
            started: now(),
            ended: None,
            ending: Ending {
                cause: "running",
                exit_code: None,
                message: None,
            },
            summary: None,
        }
    }

    /// Records the end of the run: its summary if it completed, else the failure.
    pub fn finish(&mut self, result: Result<&RunSummary, &Failure>) {
        self.ended = Some(now());
        self.ending = match result {
            Ok(summary) => {
                self.summary = Some(summary.into());
                Ending {
                    cause: exit::cause(exit::SUCCESS),
                    exit_code: Some(exit::SUCCESS),
                    message: None,
                }
            }
            Err(f) => Ending {
                cause: exit::cause(f.code),
                exit_code: Some(f.code),
                message: Some(f.message.clone()),
            },
        };
    }

    /// Writes `DIR/run.json` atomically.
    pub fn write(&self, dir: &Path) -> Result<(), Failure> {
        let path = dir.join(RUN_FILE);
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| Failure::new(exit::OTHER, format!("{}: {e}", path.display())))?;
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::new(exit::IO, format!("{}: {e}", dir.display())))?;
        dualsph_io::write_atomic(&path, format!("{text}\n").as_bytes())
            .map_err(|e| Failure::new(exit::IO, e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run's record says `running` with no exit status until the run rewrites it, so a
    /// killed run is recognisable; it carries the scene's fingerprint, which a resume into
    /// the directory must match.
    #[test]
    fn a_running_record_has_no_exit_status_and_a_resume_needs_the_same_scene() {
        let tmp = tempfile::tempdir().unwrap();
        let settings = RunSettings {
            out: tmp.path().to_path_buf(),
            formulation: "DualSupport".into(),
            end_time: 1.0,
            checkpoint_every: None,
            resume: None,
            force: false,
            threads: 1,
            set: vec!["end_time=1".into()],
        };
        let record = RunRecord::start(Path::new("a.ron"), String::new(), 0xabc, settings);
        record.write(tmp.path()).unwrap();
        let text = std::fs::read_to_string(tmp.path().join(RUN_FILE)).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["ending"]["cause"], "running");
        assert!(v["ending"]["exit_code"].is_null(), "{text}");
        assert_eq!(v["scene_fingerprint"], "0000000000000abc");
        assert_eq!(v["settings"]["set"][0], "end_time=1", "{text}");
        assert!(check_resume_dir(tmp.path(), 0xabc).is_ok());
        let other = check_resume_dir(tmp.path(), 0xabd).unwrap_err();
        assert_eq!(other.code, exit::INVALID_INPUT);
        assert!(other.message.contains("another scene"), "{}", other.message);
        let foreign = tempfile::tempdir().unwrap();
        std::fs::write(foreign.path().join("notes.txt"), "x").unwrap();
        assert!(check_resume_dir(foreign.path(), 0xabc).is_err());
        assert!(check_resume_dir(&foreign.path().join("absent"), 0xabc).is_ok());
        assert_eq!(
            resume_dir(Path::new("checkpoint_000010.ckpt"), None),
            PathBuf::from(".")
        );
        assert_eq!(
            resume_dir(Path::new("out/a/checkpoint_000010.ckpt"), None),
            PathBuf::from("out/a")
        );
    }

    #[test]
    fn force_clears_what_a_run_wrote_and_nothing_else() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let ours = [
            "diagnostics.csv",
            "particles_000200.vtp",
            "checkpoint_000100.ckpt",
            "last_good.ckpt",
            "run.json",
            "density_grid.vti",
            ".final.csv.a1b2c3.tmp",
        ];
        for f in ours.iter().chain(&["notes.txt"]) {
            std::fs::write(dir.join(f), "x").unwrap();
        }
        let refused = prepare_out_dir(dir, false).unwrap_err();
        assert_eq!(refused.code, exit::INVALID_INPUT);
        assert!(refused.message.contains("--force"), "{}", refused.message);
        prepare_out_dir(dir, true).unwrap();
        let left: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(left, ["notes.txt"]);
        assert!(prepare_out_dir(&dir.join("new"), false).is_ok());
    }
}
