//! Input that cannot hurt a run: a refinement that multiplies the particles past the memory,
//! values nested deep enough to overflow a stack, a snapshot before the first refinement
//! decision, schemes that cannot go together, probes of another scene, two runs into one
//! directory, foreign files, body names that break a CSV header, an inlet on the fluid, a
//! fixed body without particles. Each gets a clear refusal at `dualsph check` or a clean stop
//! with exit status 3 and its cause: never an abort, a stack overflow or a NaN written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dualsph"))
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `dualsph ARGS`, asserting it did not die of a signal or panic.
fn dualsph(args: &[&std::ffi::OsStr]) -> Output {
    let o = bin().args(args).output().unwrap();
    let err = stderr(&o);
    assert!(o.status.code().is_some(), "killed by a signal: {err}");
    assert!(
        !err.contains("panicked") && !err.contains("overflow"),
        "{err}"
    );
    o
}

/// `dualsph check SCENE`: (exit code, standard error).
fn check(scene: &Path, extra: &[&str]) -> (Option<i32>, String) {
    let mut args = vec![std::ffi::OsStr::new("check"), scene.as_os_str()];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    let o = dualsph(&args);
    (o.status.code(), stderr(&o))
}

/// A scene of `tests/bad_scenes/` is refused by `check` (exit status 2) with `want`.
fn refused(file: &str, want: &str) {
    let (code, err) = check(&root().join("tests/bad_scenes").join(file), &[]);
    assert_eq!(code, Some(2), "{file}: {err}");
    assert!(err.contains(want), "{file}: expected {want:?} in {err}");
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

/// The coarse dam break of the restart tests (350 particles, with probes) with `edit`
/// applied to its text, written into `dir` as `name`.
fn dam(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(root().join("tests/restart/dam_coarse.ron")).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, edit(text)).unwrap();
    path
}

#[test]
fn a_refinement_that_outgrows_the_memory_stops_cleanly_with_exit_3() {
    let scene = root().join("tests/hostile_run/refine_multiplies.ron");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let limit = ("DUALSPH_MEMORY_LIMIT", "3000000");
    let checked = bin()
        .arg("check")
        .arg(&scene)
        .env(limit.0, limit.1)
        .output()
        .unwrap();
    assert!(checked.status.success(), "{}", stderr(&checked));
    let o = bin()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&scene)
        .env(limit.0, limit.1)
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("the particle count grew to"), "{err}");
    assert!(err.contains("100 at the start"), "{err}");
    assert_eq!(record(&out, "ending/cause"), "blow-up");
    assert_eq!(record(&out, "ending/exit_code"), 3);
    assert!(out.join("last_good.csv").is_file());
}

#[test]
fn values_nested_ten_thousand_deep_are_refused_without_a_stack_overflow() {
    let tmp = tempfile::tempdir().unwrap();
    let deep = format!("{}0.1{}", "[".repeat(10_000), "]".repeat(10_000));
    let scene = dam(tmp.path(), "dam.ron", |t| t);
    let (code, err) = check(&scene, &["--set", &format!("end_time={deep}")]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("nested more than 128 deep"), "{err}");
    // the scene file itself nested that deep, read alone and with an override
    let nested = dam(tmp.path(), "nested.ron", |t| {
        t.replace("end_time: 1.0", &format!("end_time: {deep}"))
    });
    for extra in [&[][..], &["--set", "max_steps=3"][..]] {
        let (code, err) = check(&nested, extra);
        assert_eq!(code, Some(2), "{extra:?}: {err}");
        assert!(err.contains("nested.ron"), "{err}");
    }
}

#[test]
fn a_refined_runs_first_snapshot_holds_sizes_and_levels_not_nan() {
    let scene = root().join("tests/hostile_run/refine_first_decision_late.ron");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = dualsph(&[
        "run".as_ref(),
        "--quiet".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        scene.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(out.join("particles_000000.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (size, level) = (col("size"), col("level"));
    let mut rows = 0;
    for line in lines {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert!((f[size] - 0.1).abs() < 1e-9, "size {} in {line}", f[size]);
        assert_eq!(f[level], 0.0, "{line}");
        rows += 1;
    }
    assert_eq!(rows, 100);
}

#[test]
fn constant_h_with_refinement_is_refused_at_check() {
    refused(
        "constant_h_with_refinement.ron",
        "Refinement cannot be used with formulation ConstantH",
    );
}

#[test]
fn probe_refuses_a_scene_that_does_not_describe_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = dam(tmp.path(), "dam.ron", |t| {
        t.replace("max_steps: 40", "max_steps: 15")
    });
    let out = tmp.path().join("out");
    let o = dualsph(&[
        "run".as_ref(),
        "--quiet".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        scene.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let probe = |other: &Path| {
        let dest = tmp.path().join("probed");
        let args = [
            "probe".as_ref(),
            out.as_os_str(),
            "--scene".as_ref(),
            other.as_os_str(),
            "--out".as_ref(),
            dest.as_os_str(),
        ];
        let o = dualsph(&args);
        (
            o.status.code(),
            stderr(&o),
            dest.join("probes.csv").exists(),
        )
    };
    // another flow (its water block moved), with the same probes
    let other = dam(tmp.path(), "other.ron", |t| {
        t.replace("max: [1.0, 2.0]", "max: [1.5, 2.0]")
    });
    let (code, err, wrote) = probe(&other);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("the scene does not describe the run"), "{err}");
    assert!(err.contains("other.ron") && !wrote, "{err}");
    // the run's scene with a probe added: accepted
    let more = dam(tmp.path(), "more.ron", |t| {
        t.replace(
            "WaterHeight(name: \"H1\", at: [0.3]),",
            "WaterHeight(name: \"H1\", at: [0.3]), WaterHeight(name: \"H2\", at: [0.6]),",
        )
    });
    let (code, err, wrote) = probe(&more);
    assert_eq!(code, Some(0), "{err}");
    assert!(wrote);
}

#[test]
fn a_second_run_or_resume_into_a_directory_in_use_is_refused_naming_the_first() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = dam(tmp.path(), "dam.ron", |t| {
        t.replace("max_steps: 40", "max_steps: 100000000")
            .replace("end_time: 1.0", "end_time: 1000.0")
    });
    let out = tmp.path().join("out");
    let mut first = bin()
        .args(["run", "--quiet", "--checkpoint-every", "5", "--out"])
        .arg(&out)
        .arg(&scene)
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let ckpt = out.join("checkpoint_000005.ckpt");
    let started = Instant::now();
    while !ckpt.exists() {
        assert!(started.elapsed() < Duration::from_secs(60), "no checkpoint");
        std::thread::sleep(Duration::from_millis(20));
    }
    let pid = format!("process {}", first.id());
    let again = dualsph(&[
        "run".as_ref(),
        "--quiet".as_ref(),
        "--force".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        scene.as_os_str(),
        "--set".as_ref(),
        "max_steps=2".as_ref(),
    ]);
    let resumed = dualsph(&[
        "run".as_ref(),
        "--quiet".as_ref(),
        scene.as_os_str(),
        "--resume".as_ref(),
        ckpt.as_os_str(),
        "--set".as_ref(),
        "max_steps=10".as_ref(),
    ]);
    let alive = first.try_wait().unwrap().is_none();
    first.kill().unwrap();
    first.wait().unwrap();
    assert!(alive, "the first run ended before the others were tried");
    for o in [&again, &resumed] {
        let err = stderr(o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains("is in use by another run or resume") && err.contains(&pid),
            "{err}"
        );
    }
    // the killed run's lock is gone with its process: a forced run goes ahead
    let o = dualsph(&[
        "run".as_ref(),
        "--quiet".as_ref(),
        "--force".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        scene.as_os_str(),
        "--set".as_ref(),
        "max_steps=2".as_ref(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!out.join(".lock").exists());
}

#[test]
fn errors_about_files_that_are_not_particle_files_or_checkpoints_never_quote_them() {
    const SECRET: &str = "SECRET-51c2";
    let tmp = tempfile::tempdir().unwrap();
    let foreign = tmp.path().join("elsewhere/passwd");
    std::fs::create_dir_all(foreign.parent().unwrap()).unwrap();
    // a header of labels and rows of numbers: it parses as a table, without the columns of one
    std::fs::write(&foreign, format!("{SECRET},x,y\n1,2,3\n")).unwrap();
    let path = foreign.display().to_string();
    let generator = format!("File(path: \"{path}\")");
    let scene = dam(tmp.path(), "file.ron", |t| {
        let start = t.find("particles: [").unwrap();
        let end = start + t[start..].find("],\n    plugins").unwrap() + 1;
        format!("{}particles: [{generator}]{}", &t[..start], &t[end..])
    });
    let (code, err) = check(&scene, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(!err.contains(SECRET), "the file's content is quoted: {err}");
    assert!(err.contains("passwd"), "{err}");
    let dam = dam(tmp.path(), "dam.ron", |t| t);
    let out = tmp.path().join("out");
    let o = dualsph(&[
        "run".as_ref(),
        "--quiet".as_ref(),
        dam.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--resume".as_ref(),
        foreign.as_os_str(),
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains(SECRET), "the file's content is quoted: {err}");
    assert!(
        err.contains("passwd") && err.contains("checkpoint"),
        "{err}"
    );
}

#[test]
fn body_names_that_break_a_csv_header_are_refused_at_check() {
    for case in ["comma", "newline", "quote", "bracket"] {
        refused(
            &format!("body_name_{case}.ron"),
            "a body name is made of letters, digits, `_`, `-` and `.`",
        );
    }
}

#[test]
fn an_inlet_on_the_fluid_at_the_start_is_refused_naming_both() {
    refused(
        "inlet_overlapping_fluid.ron",
        "Inlet (min: [0.1, 0.0], max: [0.15, 0.2]): its box holds particle",
    );
    refused("inlet_overlapping_fluid.ron", "of the body `water`");
}

#[test]
fn a_fixed_body_without_particles_is_refused_naming_it() {
    refused(
        "fixed_body_without_particles.ron",
        "`bodies[1]`: the body `wall` is not a fluid and no generator gives it particles",
    );
}
