//! `--set PATH=VALUE` (and `PATH[+]=VALUE`, an append): a run with overrides is the run of the scene file edited by hand, the
//! overrides are recorded in run.json, and an override that names nothing (or a bad value)
//! is refused naming it, before anything is written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dualsph"))
}

fn heat() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/heat_1d.ron")
}

fn run(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    bin()
        .args(["run", "--quiet", "--threads", "1"])
        .arg(scene)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn a_run_with_set_is_the_run_of_the_edited_file_and_records_it() {
    let dir = tempfile::tempdir().unwrap();
    let sets = [
        "end_time=0.2",
        "particles[1].spacing=0.0025",
        "HeatConduction.conductivity=2e-4",
        "output.snapshot_every=5",
        "max_steps=15",
        "plugins[+]=Gravity(g: [0.1])",
    ];
    let mut args = Vec::new();
    for s in sets {
        args.extend(["--set", s]);
    }
    let with_set = run(&heat(), &dir.path().join("set"), &args);
    assert!(
        with_set.status.success(),
        "{}",
        String::from_utf8_lossy(&with_set.stderr)
    );

    let edited = std::fs::read_to_string(heat())
        .unwrap()
        .replace("end_time: 4.0", "end_time: 0.2, max_steps: 15")
        .replace("spacing: 0.005", "spacing: 0.0025")
        .replace("conductivity: 1e-4", "conductivity: 2e-4")
        .replace("snapshot_every: 100", "snapshot_every: 5")
        .replace(
            "heat_capacity: 1.0),   // Eq. 3.13\n",
            "heat_capacity: 1.0),   // Eq. 3.13\n    Gravity(g: [0.1]), ",
        );
    let path = dir.path().join("edited.ron");
    std::fs::write(&path, edited).unwrap();
    let by_hand = run(&path, &dir.path().join("hand"), &[]);
    assert!(
        by_hand.status.success(),
        "{}",
        String::from_utf8_lossy(&by_hand.stderr)
    );

    for f in ["final.csv", "diagnostics.csv", "particles_000015.csv"] {
        let a = std::fs::read(dir.path().join("set").join(f)).unwrap();
        let b = std::fs::read(dir.path().join("hand").join(f)).unwrap();
        assert!(a == b, "{f} differs between --set and the edited file");
    }
    let record = std::fs::read_to_string(dir.path().join("set/run.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&record).unwrap();
    let recorded: Vec<&str> = v["settings"]["set"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert_eq!(recorded, sets);
}

#[test]
fn an_override_that_names_nothing_or_holds_a_bad_value_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    for (set, says) in [
        (
            "HeatConduction.conductivty=1",
            "Unexpected field named `conductivty`",
        ),
        (
            "Block.spacing=0.01",
            "particles[0], particles[1], particles[2]",
        ),
        ("particles[3].spacing=0.01", "has 3 members"),
        ("HeatConduction.conductivity=\"a\"", "Expected float"),
        ("Gravity.g=[0.0]", "no field or list member `Gravity`"),
        ("end_time[+]=1", "`end_time` is not a list"),
    ] {
        let out_dir = dir.path().join("out");
        let out = run(&heat(), &out_dir, &["--set", set]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{set}: {err}");
        assert!(
            err.contains(&format!("--set {set}")) && err.contains(says),
            "{set}: {err}"
        );
        assert!(
            !out_dir.exists(),
            "{set}: a refused run wrote {}",
            out_dir.display()
        );
    }
    // a value the scene's checks refuse is named by its field
    let out = bin()
        .arg("check")
        .arg(heat())
        .args(["--set", "particles[1].spacing=-1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("particles[1].spacing"), "{err}");
}

#[test]
fn a_typo_in_the_file_keeps_its_line_and_column_under_set() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(heat()).unwrap().replacen(
        "h_factor: 3.0, internal_energy: 2.0",
        "h_factr: 3.0, internal_energy: 2.0",
        1,
    );
    let line = text.lines().position(|l| l.contains("h_factr")).unwrap() + 1;
    let col = text.lines().nth(line - 1).unwrap().find("h_factr").unwrap() + 1;
    let path = dir.path().join("typo.ron");
    std::fs::write(&path, &text).unwrap();
    let out = bin()
        .arg("check")
        .arg(&path)
        .args([
            "--set",
            "particles[0].spacing=0.0123456789",
            "--set",
            "max_steps=1",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("typo.ron:{line}:{col}")),
        "expected {line}:{col} in {err}"
    );
}

/// A run made with `--set` resumes only with the same overrides: without them the scene is
/// another one, and the refusal says which overrides the run was made with.
#[test]
fn a_resume_without_the_runs_overrides_is_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    let sets = [
        "--set",
        "max_steps=20",
        "--set",
        "HeatConduction.conductivity=2e-4",
    ];
    let mut args = vec!["--checkpoint-every", "10"];
    args.extend(sets);
    let first = run(&heat(), &out, &args);
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let ck = out.join("checkpoint_000010.ckpt");
    assert!(ck.exists());
    let before = std::fs::read(out.join("run.json")).unwrap();
    let resume = |extra: &[&str]| {
        bin()
            .args(["run", "--quiet", "--threads", "1"])
            .arg(heat())
            .arg("--resume")
            .arg(&ck)
            .args(extra)
            .output()
            .unwrap()
    };
    let refused = resume(&["--set", "max_steps=20"]);
    let message = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{message}");
    assert!(
        message.contains(
            "made with overrides --set max_steps=20 --set HeatConduction.conductivity=2e-4 and \
             this resume gives --set max_steps=20"
        ),
        "{message}"
    );
    assert_eq!(std::fs::read(out.join("run.json")).unwrap(), before);
    let resumed = resume(&sets);
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
}
