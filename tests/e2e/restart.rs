//! Checkpoint, restart and blow-up stop: a resumed run is bitwise identical to an
//! uninterrupted one, also after the process was killed; a blow-up writes the last good
//! state and exits non-zero; a damaged or foreign checkpoint is refused with a clear message.

use crate::common::{read, run};

use dualsph::checkpoint::{Checkpoint, checkpoint_file_name};
use dualsph::runner::{self, Progress, RestartOptions, RunError, RunOptions};
use dualsph::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/restart")
        .join(name)
}

fn load_text(text: &str) -> Scene {
    Scene::from_str(text, Path::new("test.ron"), &dualsph::default_registry()).unwrap()
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dualsph"))
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

/// The checkpoint of step `n` as bytes: every component of every particle, clock, lists.
fn state_bytes(dir: &Path, step: u64) -> Vec<u8> {
    read(&dir.join(checkpoint_file_name(step)))
}

fn component<'a>(c: &'a Checkpoint, name: &str) -> &'a [f64] {
    &c.components.iter().find(|x| x.name == name).unwrap().values
}

/// Runs 40 steps with a checkpoint every 20, resumes a copy of the output from step 20 and
/// compares the complete state at step 40 and every output file byte for byte.
/// `h_changes`: the scene's h-update changes h between steps 20 and 40 (with a constant
/// density it rewrites the same values); the lists are rebuilt between them in every scene.
fn check_resume(file: &str, expect: &[&str], h_changes: bool) {
    check_resume_text(
        file,
        &std::fs::read_to_string(scene_path(file)).unwrap(),
        expect,
        h_changes,
    );
}

/// [`check_resume`] of the scene `text` (`file` names it in messages).
fn check_resume_text(file: &str, text: &str, expect: &[&str], h_changes: bool) {
    let scene = load_text(text);
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let s = run(&scene, &a, 20, None);
    assert_eq!(s.steps, 40, "{file}");
    let half = Checkpoint::read(&a.join(checkpoint_file_name(20))).unwrap();
    let full = Checkpoint::read(&a.join(checkpoint_file_name(40))).unwrap();
    for name in expect {
        assert!(
            half.components.iter().any(|c| c.name == *name),
            "{file}: the test scene must carry {name}"
        );
    }
    // the second half must exercise the state a resume restores
    assert!(
        full.neighbours.builds > half.neighbours.builds,
        "{file}: no list rebuild"
    );
    if h_changes {
        assert_ne!(
            component(&half, "SmoothingLength"),
            component(&full, "SmoothingLength"),
            "{file}: no h-update in the second half"
        );
    }
    copy_dir(&a, &b);
    std::fs::remove_file(b.join(checkpoint_file_name(40))).unwrap();
    std::fs::remove_file(b.join("final.csv")).unwrap();
    let resumed = run(&scene, &b, 20, Some(b.join(checkpoint_file_name(20))));
    assert_eq!(resumed.steps, 40);
    assert_eq!(resumed.initial, s.initial, "{file}: initial diagnostics");
    assert_eq!(resumed.last, s.last, "{file}: final diagnostics");
    assert!(
        state_bytes(&a, 40) == state_bytes(&b, 40),
        "{file}: resumed state at step 40 differs from the uninterrupted one"
    );
    for f in std::fs::read_dir(&a).unwrap() {
        let name = f.unwrap().file_name();
        let name = name.to_string_lossy();
        if !name.ends_with(".png") {
            assert!(
                read(&a.join(&*name)) == read(&b.join(&*name)),
                "{file}: {name} differs after the resume"
            );
        }
    }
}

#[test]
fn resume_from_half_way_is_bitwise_identical_2d_dam_break() {
    check_resume(
        "dam_coarse.ron",
        &[
            "Position",
            "Acceleration",
            "DensityRate",
            "Pressure",
            "SoundSpeed",
            "Dissipated",
            "DissipationRate",
        ],
        false,
    );
}

#[test]
fn resume_from_half_way_is_bitwise_identical_with_the_position_verlet() {
    let text = std::fs::read_to_string(scene_path("dam_coarse.ron"))
        .unwrap()
        .replace("plugins: [", "plugins: [\n        PositionVerlet(),");
    assert!(text.contains("PositionVerlet()"));
    check_resume_text(
        "dam_coarse.ron + PositionVerlet",
        &text,
        &["DensityRate", "Dissipated", "DissipationRate"],
        false,
    );
}

#[test]
fn resume_from_half_way_is_bitwise_identical_2d_drop_with_matrices() {
    check_resume(
        "drop_coarse.ron",
        &["GradientCorrection", "VelocityGradient", "DensityRate"],
        true,
    );
}

#[test]
fn resume_from_half_way_is_bitwise_identical_in_the_middle_of_refinement() {
    // particles split and merge in both halves: the resumed run must rebuild the changed
    // population, its ids and the refinement's own counts
    check_resume("refine_drop.ron", &["DensityRate", "InternalEnergy"], false);
    let scene = load_text(&std::fs::read_to_string(scene_path("refine_drop.ron")).unwrap());
    let tmp = tempfile::tempdir().unwrap();
    run(&scene, tmp.path(), 20, None);
    let half = Checkpoint::read(&tmp.path().join(checkpoint_file_name(20))).unwrap();
    let full = Checkpoint::read(&tmp.path().join(checkpoint_file_name(40))).unwrap();
    let kept = |c: &Checkpoint| {
        c.resources
            .iter()
            .find(|(k, _)| k == "refinement")
            .map(|(_, b)| b.clone())
    };
    assert!(
        kept(&half).is_some() && kept(&half) != kept(&full),
        "no refinement after step 20"
    );
    assert_ne!(
        component(&half, "Mass").len(),
        component(&full, "Mass").len(),
        "the count changes in the second half"
    );
}

#[test]
fn resume_from_half_way_is_bitwise_identical_1d_sod() {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sod_1d.ron"))
            .unwrap()
            .replace("end_time: 0.2,", "end_time: 0.2,\n    max_steps: 40,");
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("sod_40.ron");
    std::fs::write(&path, text).unwrap();
    // same procedure as the 2-D cases, from a file outside tests/restart
    let scene = load_text(&std::fs::read_to_string(&path).unwrap());
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    run(&scene, &a, 20, None);
    copy_dir(&a, &b);
    std::fs::remove_file(b.join(checkpoint_file_name(40))).unwrap();
    run(&scene, &b, 20, Some(b.join(checkpoint_file_name(20))));
    let half = Checkpoint::read(&a.join(checkpoint_file_name(20))).unwrap();
    assert!(half.components.iter().any(|c| c.name == "EnergyRate"));
    // the plugins' own state: the probes' samples and the diagnostics' start
    let kept = |key: &str| {
        half.resources
            .iter()
            .any(|(k, b)| k == key && !b.is_empty())
    };
    assert!(kept("probes") && kept("diagnostics"));
    assert!(state_bytes(&a, 40) == state_bytes(&b, 40));
    for f in ["final.csv", "diagnostics.csv", "probes.csv"] {
        assert!(read(&a.join(f)) == read(&b.join(f)), "{f} differs");
    }
}

#[test]
fn resume_from_half_way_is_bitwise_identical_1d_sod_grad_h() {
    // h solved with the density every step, and the energy update's record of the last
    // evaluation, which the next step reads before it writes
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sod_1d.ron"))
            .unwrap()
            .replace("formulation: DualSupport,", "formulation: GradH,")
            .replace("end_time: 0.2,", "end_time: 0.2,\n    max_steps: 40,");
    check_resume_text(
        "sod_1d.ron with GradH",
        &text,
        &["EnergyRate", "Evaluations"],
        true,
    );
}

#[test]
fn resume_from_half_way_is_bitwise_identical_1d_adaptive_sod() {
    // a gas refined at its shock and contact, sizes read at the nominal density (a column of
    // the plugin's own), its first decision at step 25: particles split in the second half
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sod_1d_adaptive.ron"),
    )
    .unwrap()
    .replace("end_time: 0.2,", "end_time: 0.2,\n    max_steps: 40,")
    .replace("ladder: Nominal, every: 5,", "ladder: Nominal, every: 25,");
    assert!(
        text.contains("every: 25,"),
        "the scene's refinement was not found"
    );
    check_resume_text(
        "sod_1d_adaptive.ron",
        &text,
        &["NominalDensity", "EnergyRate"],
        true,
    );
    let scene = load_text(&text);
    let tmp = tempfile::tempdir().unwrap();
    run(&scene, tmp.path(), 20, None);
    let count = |step| {
        let c = Checkpoint::read(&tmp.path().join(checkpoint_file_name(step))).unwrap();
        component(&c, "Mass").len()
    };
    assert!(count(40) > count(20), "no split in the second half");
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn newest_checkpoint(dir: &Path) -> Option<(u64, PathBuf)> {
    std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| {
            let p = e.ok()?.path();
            let name = p.file_name()?.to_str()?.to_string();
            let step = name
                .strip_prefix("checkpoint_")?
                .strip_suffix(".ckpt")?
                .parse()
                .ok()?;
            Some((step, p))
        })
        .max()
}

#[test]
fn killed_process_resumes_bitwise_identical() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene_path("dam_coarse.ron"))
        .unwrap()
        .replace("max_steps: 40,", "max_steps: 400,");
    let scene = tmp.path().join("dam_400.ron");
    std::fs::write(&scene, text).unwrap();
    let run_cmd = |out: &Path| {
        let mut c = bin();
        c.arg("run")
            .arg(&scene)
            .arg("--quiet")
            .arg("--out")
            .arg(out)
            .args(["--checkpoint-every", "10"]);
        c
    };
    // the uninterrupted run
    let full = tmp.path().join("full");
    let o = run_cmd(&full).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // the same run, killed as soon as its first checkpoint is on disk
    let killed = tmp.path().join("killed");
    let mut child = run_cmd(&killed)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while newest_checkpoint(&killed).is_none() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its first checkpoint"
        );
        assert!(started.elapsed() < Duration::from_secs(60), "no checkpoint");
        std::thread::sleep(Duration::from_millis(1));
    }
    let still_running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(still_running, "the run finished before it could be killed");
    assert!(!killed.join("final.csv").exists(), "killed after the end");
    let (step, ck) = newest_checkpoint(&killed).unwrap();
    assert!(step < 400, "checkpoint of step {step}");
    let o = run_cmd(&killed).arg("--resume").arg(&ck).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "final.csv",
        "diagnostics.csv",
        "probes.csv",
        "snapshots.csv",
        &checkpoint_file_name(400),
    ] {
        assert!(
            read(&full.join(f)) == read(&killed.join(f)),
            "{f} differs after kill at step {step} and resume"
        );
    }
}

/// Runs a scene that must blow up through the CLI and checks the stop: a non-zero exit, no
/// panic, exactly one `error:` line containing every phrase of `expect`, and the last good
/// state written as `.ckpt`, `.csv` (one record per particle) and `.vtp` from mid-run.
/// Returns the error text and the last good particle records.
fn blow_up(scene: &str, out: &Path, expect: &[&str]) -> (String, dualsph::io::ParticleTable) {
    let o = bin()
        .arg("run")
        .arg(scene_path(scene))
        .arg("--quiet")
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    let err = stderr(&o);
    assert!(!o.status.success(), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for what in expect {
        assert!(err.contains(what), "{what:?} missing in: {err}");
    }
    assert_eq!(
        err.lines().filter(|l| l.starts_with("error:")).count(),
        1,
        "{err}"
    );
    let good = Checkpoint::read(&out.join("last_good.ckpt")).unwrap();
    let records = dualsph::io::read_particles(&out.join("last_good.csv")).unwrap();
    assert_eq!(records.len() as u64, good.particles);
    assert!(out.join("last_good.vtp").exists());
    assert!(good.step > 0, "last good state at step {}", good.step);
    (err, records)
}

#[test]
fn fixed_dt_overtaken_by_the_cfl_limit_stops_and_writes_the_last_good_state() {
    let tmp = tempfile::tempdir().unwrap();
    let expect = [
        "blow-up",
        "step ",
        "t = ",
        "particle ",
        "likely cause",
        "dt above the CFL limit",
        "last_good.ckpt",
    ];
    let (_, records) = blow_up("blow_up.ron", tmp.path(), &expect);
    // the last good state is sound (from mid-run: checked by blow_up): every position finite
    // and in the tank
    assert!(records.rows().all(|r| {
        r.pos()[0].is_finite()
            && r.pos()[1].is_finite()
            && (0.0..=4.0).contains(&r.pos()[0])
            && (0.0..=3.0).contains(&r.pos()[1])
    }));
}

#[test]
fn particle_leaving_the_domain_is_a_blow_up_and_the_last_good_state_resumes() {
    let tmp = tempfile::tempdir().unwrap();
    let go = |resume: Option<&Path>| {
        let mut c = bin();
        c.arg("run")
            .arg(scene_path("leaves_domain.ron"))
            .arg("--quiet")
            .arg("--out")
            .arg(tmp.path());
        if let Some(r) = resume {
            c.arg("--resume").arg(r);
        }
        c.output().unwrap()
    };
    let o = go(None);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(!err.contains("panicked"), "{err}");
    // 0.5 + 0.1 of travel at 100 m/s with dt = 1e-4: the first step past 0.1 out is 53
    assert!(
        err.contains("step 53,") && err.contains("distance outside the domain"),
        "{err}"
    );
    let good = Checkpoint::read(&tmp.path().join("last_good.ckpt")).unwrap();
    assert_eq!(
        good.step,
        50,
        "kept every {} steps",
        runner::DEFAULT_KEEP_EVERY
    );
    // resuming from the last good state reaches the same blow-up
    let kept = tmp.path().join("kept.ckpt");
    std::fs::rename(tmp.path().join("last_good.ckpt"), &kept).unwrap();
    let again = go(Some(&kept));
    let err2 = stderr(&again);
    assert!(!again.status.success());
    let msg = |s: &str| {
        let line = s.lines().find(|l| l.starts_with("error:")).unwrap_or("");
        line.split(';').next().unwrap_or("").to_string()
    };
    assert!(msg(&err).contains("particle 12"), "{err}");
    assert_eq!(msg(&err), msg(&err2));
}

#[test]
fn damaged_or_foreign_checkpoints_are_refused_clearly() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = load_text(&std::fs::read_to_string(scene_path("drop_coarse.ron")).unwrap());
    run(&scene, tmp.path(), 20, None);
    let good = read(&tmp.path().join(checkpoint_file_name(20)));
    let mut flipped = good.clone();
    let k = flipped.len() / 2;
    flipped[k] ^= 0x40;
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("truncated", good[..good.len() / 3].to_vec(), "truncated"),
        ("header_only", good[..10].to_vec(), "truncated"),
        ("flipped", flipped, "corrupted"),
        ("empty", Vec::new(), "not a dualsph checkpoint"),
        (
            "scene",
            read(&scene_path("drop_coarse.ron")),
            "not a dualsph checkpoint",
        ),
    ];
    let check = |file: &Path, scene: &Path, want: &str| {
        let o = bin()
            .arg("run")
            .arg(scene)
            .arg("--quiet")
            .arg("--out")
            .arg(tmp.path().join("out"))
            .arg("--resume")
            .arg(file)
            .output()
            .unwrap();
        let err = stderr(&o);
        assert!(!o.status.success(), "{}", file.display());
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            err.contains(want),
            "{}: expected {want:?} in {err}",
            file.display()
        );
        assert!(
            err.contains(&*file.to_string_lossy()),
            "names the file: {err}"
        );
    };
    for (name, bytes, want) in &cases {
        let p = tmp.path().join(format!("{name}.ckpt"));
        std::fs::write(&p, bytes).unwrap();
        check(&p, &scene_path("drop_coarse.ron"), want);
    }
    // well-formed files (valid checksum) whose content does not fit the scene
    let ck = Checkpoint::read(&tmp.path().join(checkpoint_file_name(20))).unwrap();
    let mut lists = ck.clone();
    lists.neighbours.support_indices[0] = 1_000_000;
    let mut short = ck.clone();
    short.components[0].values.pop();
    let mut missing = ck.clone();
    missing.components.retain(|c| c.name != "VelocityGradient");
    for (name, c, want) in [
        ("lists", lists, "support lists are inconsistent"),
        ("short", short, "Position data has"),
        ("no_vgrad", missing, "no VelocityGradient data"),
    ] {
        let p = tmp.path().join(format!("{name}.ckpt"));
        c.write(&p).unwrap();
        check(&p, &scene_path("drop_coarse.ron"), want);
    }
    // a sound checkpoint of another scene
    let p = tmp.path().join(checkpoint_file_name(20));
    check(
        &p,
        &scene_path("dam_coarse.ron"),
        "does not belong to this scene",
    );
    check(
        &tmp.path().join("missing.ckpt"),
        &scene_path("drop_coarse.ron"),
        "cannot read checkpoint",
    );
    // and the in-process error type says the same
    let err = runner::run_with(
        &scene,
        &RunOptions {
            out: tmp.path().join("out2"),
            progress: Progress::Silent,
            profile: false,
        },
        &RestartOptions {
            checkpoint_every: None,
            resume: Some(tmp.path().join("truncated.ckpt")),
        },
    )
    .unwrap_err();
    assert!(matches!(err, RunError::Checkpoint(_)), "{err}");
}

#[test]
fn density_driven_out_of_its_sane_range_stops_with_the_cause_and_the_last_good_state() {
    let tmp = tempfile::tempdir().unwrap();
    let expect = [
        "blow-up",
        "step ",
        "t = ",
        "particle ",
        "density above its sane range",
        // the sane range: the initial 1000 kg/m³ / 300 (default) and × 2 (the scene's)
        "outside [3.3333e0, 2.0000e3]",
        "c0 too small for the flow speed",
        "last_good.ckpt",
    ];
    let (err, records) = blow_up("compressed.ron", tmp.path(), &expect);
    // stopped on the density itself, just past 2000 kg/m³, when the continuity equation's
    // ρ0/(1 − 100t)² says so: t = (1 − 1/√2)/100 = 2.929 ms (to a step of dt = 2e-5)
    let number = |key: &str, stop: char| {
        let rest = &err[err.find(key).unwrap() + key.len()..];
        rest[..rest.find(stop).unwrap()].parse::<f64>().unwrap()
    };
    let value = number("sane range = ", ',');
    assert!(value > 2000.0 && value < 2050.0, "{value}");
    let t = number("t = ", ':');
    let exact = (1.0 - 0.5f64.sqrt()) / 100.0;
    assert!(
        (t - exact).abs() <= 4e-5,
        "stopped at t = {t}, expected {exact}"
    );
    // the last good state is inside the sane range
    assert!(
        records
            .rows()
            .all(|r| r.rho().is_finite() && r.rho() > 1000.0 / 300.0 && r.rho() <= 2000.0),
        "the last good state is already out of range"
    );
}
