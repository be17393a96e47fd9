//! The `dualsph` binary: check, plan and run from the command line.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dualsph"))
}

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

#[test]
fn check_accepts_every_shipped_scene() {
    for entry in std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ron") {
            let out = bin().arg("check").arg(&path).output().unwrap();
            assert!(
                out.status.success(),
                "{}: {}",
                path.display(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

#[test]
fn check_reports_a_typo_with_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene("heat_1d.ron"))
        .unwrap()
        .replacen("spacing: 0.005", "spacng: 0.005", 1);
    let line = text.lines().position(|l| l.contains("spacng")).unwrap() + 1;
    let col = text.lines().nth(line - 1).unwrap().find("spacng").unwrap() + 1;
    let path = dir.path().join("typo.ron");
    std::fs::write(&path, &text).unwrap();
    let out = bin().arg("check").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains(&format!("typo.ron:{line}:{col}")),
        "expected typo.ron:{line}:{col} in: {err}"
    );
    assert!(
        err.contains("spacing"),
        "the message should name the expected field: {err}"
    );
}

#[test]
fn check_names_registered_plugins_for_an_unknown_one() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene("heat_1d.ron"))
        .unwrap()
        .replace("HeatConduction(", "HeatConductoin(");
    let path = dir.path().join("bad_plugin.ron");
    std::fs::write(&path, &text).unwrap();
    let out = bin().arg("check").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("HeatConductoin")
            && err.contains("HeatConduction")
            && err.contains("PressureForce"),
        "{err}"
    );
}

#[test]
fn plan_shows_only_what_the_scene_needs() {
    let out = bin()
        .arg("plan")
        .arg(scene("dam_break_2d.ron"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("pair_sweep")
            && text.contains("pressure (Eq. 4.19)")
            && text.contains("Pressure"),
        "{text}"
    );
    assert!(
        !text.to_lowercase().contains("heat"),
        "dam break has no heat conduction:\n{text}"
    );
    assert!(
        !text.contains("Conductivity"),
        "no temperature/conductivity component expected:\n{text}"
    );
    // the default integrator's and diagnostics' systems, attributed to their plugins
    let owner = |system: &str| {
        let line = text.lines().find(|l| l.contains(system));
        line.and_then(|l| l.rsplit_once('['))
            .map(|(_, p)| p.trim_end_matches(']').to_string())
    };
    for (system, plugin) in [
        ("choose_dt", "LeapfrogPC"),
        ("predict_kinematics", "LeapfrogPC"),
        ("predict_density", "LeapfrogPC"),
        ("correct_density", "LeapfrogPC"),
        ("check_time_step", "LeapfrogPC"),
        ("check_health", "Diagnostics"),
        ("compute_diagnostics", "Diagnostics"),
        ("update_neighbours", "core"),
    ] {
        assert_eq!(owner(system).as_deref(), Some(plugin), "{system}:\n{text}");
    }

    let out = bin()
        .arg("plan")
        .arg(scene("heat_1d.ron"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("heat conduction (Eq. 3.13)") && text.contains("Conductivity"),
        "{text}"
    );
    assert!(!text.contains("Pressure"), "heat scene has no EOS:\n{text}");
}

#[test]
fn run_writes_every_output_file() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("heat");
    let out = bin()
        .args(["run", "--quiet"])
        .arg(scene("heat_1d.ron"))
        .arg("--out")
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in [
        "diagnostics.csv",
        "snapshots.csv",
        "particles.pvd",
        "final.csv",
        "particles_000000.csv",
        "particles_000000.vtp",
        "particles_000400.csv",
    ] {
        assert!(out_dir.join(f).is_file(), "missing {f}");
    }
    let leftovers: Vec<_> = std::fs::read_dir(&out_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') || n.contains("tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

#[test]
fn missing_scene_file_is_a_clear_error() {
    let out = bin().args(["check", "no/such/scene.ron"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("no/such/scene.ron") && !err.contains("panicked"),
        "{err}"
    );
}

/// Output into a closed pipe (`dualsph plan scene.ron | head -1`) ends the program quietly,
/// without a panic: here the reading end is closed before the program writes anything.
#[test]
fn output_into_a_closed_pipe_is_not_a_panic() {
    for args in [vec!["plugins"], vec!["plan", "dam_break_2d.ron"]] {
        let mut cmd = bin();
        for a in &args {
            let p = scene(a);
            cmd.arg(if a.ends_with(".ron") {
                p.into_os_string()
            } else {
                a.into()
            });
        }
        let mut child = cmd
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(out.status.success(), "{args:?}: {:?} {stderr}", out.status);
    }
}

/// `dualsph run SCENE --out OUT ARGS…`: its exit code and standard error.
fn run_code(scene: &Path, out: &Path, args: &[&str]) -> (Option<i32>, String) {
    let o = bin()
        .args(["run", "--quiet", "--out"])
        .arg(out)
        .arg(scene)
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn each_kind_of_failure_exits_with_its_own_code() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    // invalid input: a scene that does not validate, an option out of range
    let bad = root.join("tests/bad_scenes/negative_density.ron");
    assert_eq!(run_code(&bad, &out, &[]).0, Some(2));
    assert_eq!(
        run_code(&scene("heat_1d.ron"), &out, &["--end-time", "-1"]).0,
        Some(2)
    );
    assert_eq!(
        run_code(&scene("heat_1d.ron"), &out, &["--threads", "0"]).0,
        Some(2)
    );
    // a file that cannot be read, an output directory that cannot be made
    let missing = tmp.path().join("no_such_scene.ron");
    assert_eq!(run_code(&missing, &out, &[]).0, Some(4));
    let file = tmp.path().join("a_file");
    std::fs::write(&file, "x").unwrap();
    let (code, err) = run_code(&scene("heat_1d.ron"), &file.join("sub"), &[]);
    assert_eq!(code, Some(4), "{err}");
    // a blow-up
    let blow = root.join("tests/restart/blow_up.ron");
    let (code, err) = run_code(&blow, &tmp.path().join("blow"), &[]);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("blow-up"), "{err}");
    // the codes are documented
    let help = bin().arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(help.contains("3 blow-up"), "{help}");
}

#[test]
fn threads_sets_the_thread_count_and_changes_no_bit() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |threads: &str| {
        let out = tmp.path().join(format!("t{threads}"));
        let o = bin()
            .args(["run", "--end-time", "0.004", "--threads", threads, "--out"])
            .arg(&out)
            .arg(scene("drop_2d.ron"))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let said = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(said.contains(&format!("{threads} threads")), "{said}");
        std::fs::read(out.join("final.csv")).unwrap()
    };
    assert!(
        run("1") == run("2"),
        "final.csv differs between 1 and 2 threads"
    );
}

fn stdout_of(args: &[&str]) -> (Option<i32>, String, String) {
    let out = bin().args(args).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn doc_prints_each_field_with_its_type_default_and_unit() {
    let (code, text, _) = stdout_of(&["doc", "TaitEos"]);
    assert_eq!(code, Some(0));
    assert!(text.starts_with("TaitEos(..) — plugin: "), "{text}");
    assert!(text.contains("  c0: SoundSpeed (optional) = none\n      Reference sound speed c0 (m/s), or `Auto(factor: 10.0)`"), "{text}");
    assert!(text.contains("\nSoundSpeed:\n"), "{text}");
    assert!(
        text.contains("  number\n      The value (m/s).\n  Auto(..)\n"),
        "{text}"
    );
    assert!(text.contains("      factor: number = 10.0\n"), "{text}");
    assert!(text.contains("  rho0: number (required)\n"), "{text}");
    assert!(text.contains("\nTaitMaterial:\n"), "{text}");
    let (_, integrator, _) = stdout_of(&["doc", "integrator"]);
    assert!(
        integrator.contains("  Fixed(number)\n      A constant step (s)"),
        "{integrator}"
    );
    assert!(
        integrator.contains("      courant: number = 0.1\n"),
        "{integrator}"
    );
    let (_, probes, _) = stdout_of(&["doc", "Probes"]);
    assert!(
        probes.contains("      dry: Zero | Skip | Nan = Zero\n"),
        "{probes}"
    );
    let (code, out, err) = stdout_of(&["doc", "Gravty"]);
    assert_eq!((code, out.as_str()), (Some(2), ""));
    assert!(
        err.contains("no plugin, scene section or body kind named `Gravty`; known: "),
        "{err}"
    );
    assert!(err.contains(" Gravity,"), "{err}");
}

#[test]
fn plugins_with_fields_documents_every_listed_name() {
    let (code, list, _) = stdout_of(&["plugins"]);
    assert_eq!(code, Some(0));
    let (code, all, _) = stdout_of(&["plugins", "--fields"]);
    assert_eq!(code, Some(0));
    let names: Vec<&str> = list
        .lines()
        .take_while(|l| !l.is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert!(names.len() > 20, "{list}");
    for n in names {
        assert!(
            all.contains(&format!("\n{n}(..) — plugin: ")) || all.starts_with(&format!("{n}(..)")),
            "{n}"
        );
    }
    for title in [
        "integrator: (..) — scene section",
        "kind: Prescribed — body kind: ",
    ] {
        assert!(all.contains(title), "{title}");
    }
}

#[test]
fn the_plugin_docs_show_doc_as_it_prints() {
    let page =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/plugins.md"))
            .unwrap();
    let start = page
        .find("$ dualsph doc Gravity\n")
        .expect("docs/plugins.md's example");
    let block = &page[start..];
    let shown = &block["$ dualsph doc Gravity\n".len()..block.find("```").unwrap()];
    let (code, printed, _) = stdout_of(&["doc", "Gravity"]);
    assert_eq!(code, Some(0));
    assert_eq!(shown, printed);
}
