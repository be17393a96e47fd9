//! What a run does around its physics: an output directory of its own (`--force` to reuse
//! one), `run.json`, a stalled run stopped as a blow-up, Ctrl-C that checkpoints and exits.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dualsph"))
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The coarse dam break of the restart tests (350 particles) with `edit` applied to its text,
/// written into `dir` as `name`.
fn dam(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(root().join("tests/restart/dam_coarse.ron")).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, edit(text)).unwrap();
    path
}

fn run(scene: &Path, out: &Path, args: &[&str]) -> Output {
    bin()
        .args(["run", "--quiet", "--out"])
        .arg(out)
        .arg(scene)
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The value at `key` of `run.json` in `dir` (keys separated by `/`).
fn record(dir: &Path, key: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("run.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    for k in key.split('/') {
        v = v[k].take();
    }
    v
}

#[test]
fn a_run_refuses_a_used_directory_unless_forced_and_records_itself() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = dam(tmp.path(), "dam.ron", |t| t);
    let out = tmp.path().join("out");
    assert!(run(&scene, &out, &[]).status.success());
    let first = std::fs::read(out.join("final.csv")).unwrap();

    let again = run(&scene, &out, &[]);
    assert_eq!(again.status.code(), Some(2), "{}", stderr(&again));
    assert!(stderr(&again).contains("--force"), "{}", stderr(&again));

    // --force clears what the first run wrote (a stale snapshot too) but not a user's file
    std::fs::write(out.join("particles_999999.csv"), "stale").unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let forced = run(&scene, &out, &["--force", "--threads", "1"]);
    assert!(forced.status.success(), "{}", stderr(&forced));
    assert!(!out.join("particles_999999.csv").exists());
    assert!(out.join("notes.txt").exists());
    assert_eq!(std::fs::read(out.join("final.csv")).unwrap(), first);

    // run.json: what produced the directory, and how it ended
    let text = std::fs::read_to_string(&scene).unwrap();
    assert_eq!(record(&out, "scene_text"), text.as_str());
    assert_eq!(record(&out, "settings/threads"), 1);
    assert_eq!(record(&out, "settings/force"), true);
    assert_eq!(record(&out, "ending/cause"), "completed");
    assert_eq!(record(&out, "ending/exit_code"), 0);
    assert_eq!(record(&out, "summary/steps"), 40);
    assert_eq!(record(&out, "version"), env!("CARGO_PKG_VERSION"));
    let line = record(&out, "command_line");
    assert!(
        line.as_array().unwrap().iter().any(|a| a == "--force"),
        "{line}"
    );
    assert!(record(&out, "started").as_str().unwrap().ends_with('Z'));
    assert!(record(&out, "ended").is_string());
}

#[test]
fn a_collapsing_dt_stops_the_run_as_a_blow_up() {
    let tmp = tempfile::tempdir().unwrap();
    // the coarse dam's adaptive dt falls 3.4 % below its first step by step 900: a floor
    // 2 % below the first step stops it there; the default floor (10^6 below) does not
    let tight = dam(tmp.path(), "tight.ron", |t| {
        t.replace("max_steps: 40", "max_steps: 2000")
            .replace("output: (", "health: (dt_below: 1.02), output: (")
    });
    let out = tmp.path().join("tight");
    let o = run(&tight, &out, &[]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("fell below the floor"),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains("dt_below 1.02"), "{}", stderr(&o));
    assert_eq!(record(&out, "ending/cause"), "blow-up");
    assert_eq!(record(&out, "ending/exit_code"), 3);
    assert!(out.join("last_good.ckpt").is_file());

    let default = dam(tmp.path(), "default.ron", |t| {
        t.replace("max_steps: 40", "max_steps: 2000")
    });
    let o = run(&default, &tmp.path().join("default"), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn an_end_time_out_of_reach_stops_at_the_first_step() {
    let tmp = tempfile::tempdir().unwrap();
    let fast = dam(tmp.path(), "fast.ron", |t| {
        t.replace("max_steps: 40,", "").replacen(
            "h_factor: 2.0)",
            "h_factor: 2.0, velocity: Uniform([1e12, 0.0]))",
            1,
        )
    });
    let started = Instant::now();
    let o = run(&fast, &tmp.path().join("fast"), &[]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("steps to reach end_time"),
        "{}",
        stderr(&o)
    );
    assert!(started.elapsed() < Duration::from_secs(60));
}

/// Ctrl-C, then the resume command exactly as the message prints it (a path relative to the
/// working directory, no `--out`): the resume continues in the interrupted run's own directory,
/// and its `final.csv`, `diagnostics.csv` and `snapshots.csv` are bitwise those of an
/// uninterrupted run. A resume into a directory holding another scene's run is refused before
/// anything there is touched.
#[test]
fn ctrl_c_writes_a_checkpoint_that_resumes_bitwise() {
    let tmp = tempfile::tempdir().unwrap();
    let long = dam(tmp.path(), "long.ron", |t| {
        t.replace("max_steps: 40", "max_steps: 1500")
    });
    let whole = tmp.path().join("whole");
    assert!(run(&long, &whole, &[]).status.success());

    let out = tmp.path().join("cut");
    let mut child = bin()
        .current_dir(tmp.path())
        .args(["run", "--quiet", "--out", "cut", "long.ron"])
        .spawn()
        .unwrap();
    // wait until it is stepping (diagnostics beyond the first rows), then interrupt it: at
    // whatever step the signal lands, on the diagnostics cadence or off it
    let started = Instant::now();
    loop {
        let rows =
            std::fs::read_to_string(out.join("diagnostics.csv")).map_or(0, |t| t.lines().count());
        if rows > 20 || started.elapsed() > Duration::from_secs(120) {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(
        status.code(),
        Some(130),
        "the run should end as interrupted"
    );
    assert_eq!(record(&out, "ending/cause"), "interrupted");
    let message = record(&out, "ending/message");
    let message = message.as_str().unwrap();
    let checkpoint = message.rsplit("--resume ").next().unwrap().trim();
    assert!(
        checkpoint.starts_with("cut/") && tmp.path().join(checkpoint).is_file(),
        "{message}"
    );
    assert!(
        !out.join("final.csv").exists(),
        "an interrupted run has no final state"
    );

    // another scene's run: a resume into its directory is refused and leaves it as it was
    let other = dam(tmp.path(), "other.ron", |t| {
        t.replace("max_steps: 40", "max_steps: 30")
    });
    let other = {
        let text = std::fs::read_to_string(&other).unwrap();
        let edited = text.replacen("name: \"", "name: \"other ", 1);
        assert_ne!(edited, text);
        std::fs::write(&other, edited).unwrap();
        other
    };
    let theirs = tmp.path().join("theirs");
    assert!(run(&other, &theirs, &[]).status.success());
    let before = std::fs::read(theirs.join("run.json")).unwrap();
    let refused = bin()
        .current_dir(tmp.path())
        .args([
            "run", "--quiet", "long.ron", "--resume", checkpoint, "--out", "theirs",
        ])
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    assert!(
        stderr(&refused).contains("another scene"),
        "{}",
        stderr(&refused)
    );
    assert_eq!(std::fs::read(theirs.join("run.json")).unwrap(), before);

    let resumed = bin()
        .current_dir(tmp.path())
        .args(["run", "--quiet", "long.ron", "--resume", checkpoint])
        .output()
        .unwrap();
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    for f in ["final.csv", "diagnostics.csv", "snapshots.csv"] {
        assert!(
            std::fs::read(out.join(f)).unwrap() == std::fs::read(whole.join(f)).unwrap(),
            "{f} of the interrupted and resumed run differs from the uninterrupted one"
        );
    }
    assert_eq!(record(&out, "ending/cause"), "completed");
}
