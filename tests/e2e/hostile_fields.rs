//! Every number a plugin's settings hold, set to an extreme (±1e308, and 1e-308 where a
//! positive number is expected) in a shipped scene that uses the plugin: `dualsph check`
//! refuses it naming the field, or accepts it and a run of a few steps ends cleanly (done, or
//! stopped as a blow-up with the reason) — under `ulimit -v` of 4 GiB, within a minute, never
//! a panic or an abort. The fields are the plugins' own, read from their settings' schema
//! (what `dualsph doc` prints), so a field added later is covered without editing this test.

use dualsph::core::plugin::fields::{fields, is_number};
use std::path::{Path, PathBuf};

use crate::limited;

/// Virtual memory the commands may use (KiB, for `ulimit -v`).
const MEMORY_KIB: u64 = 4 << 20;

/// The exit status of `dualsph ARGS` under the memory limit, with its standard error.
fn dualsph(args: &[String]) -> (Option<i32>, String) {
    let args: Vec<std::ffi::OsString> = args.iter().map(Into::into).collect();
    limited::dualsph_limited(&args, MEMORY_KIB)
}

/// The shipped scenes, by file name.
fn scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    out.sort();
    out
}

/// One case: a scene, the plugin's place in its list, the field and the value as RON.
struct Case {
    scene: PathBuf,
    path: String,
    value: String,
}

/// For every registered plugin, the smallest shipped scene that uses it, and its number
/// fields at the extremes.
fn cases() -> Vec<Case> {
    let registry = dualsph::default_registry();
    let mut loaded: Vec<(PathBuf, dualsph::scene::Scene)> = scenes()
        .into_iter()
        .filter_map(|p| Some((p.clone(), dualsph::scene::Scene::load(&p, &registry).ok()?)))
        .collect();
    loaded.sort_by_key(|(_, s)| s.generate().len());
    let mut out = Vec::new();
    for entry in registry.entries() {
        let Some((path, scene, k)) = loaded.iter().find_map(|(p, s)| {
            let k = s.plugins.iter().position(|q| q.name() == entry.name)?;
            Some((p, s, k))
        }) else {
            continue;
        };
        let schema = (entry.schema)();
        for f in fields(schema.as_value(), schema.as_value()) {
            let item = f.schema.get("items");
            let values: Vec<String> = if is_number(&f.schema) {
                ["1e308", "-1e308", "1e-308"].map(String::from).to_vec()
            } else if item.is_some_and(is_number) {
                ["1e308", "-1e308"]
                    .map(|v| format!("[{}]", vec![v; scene.dimension].join(", ")))
                    .to_vec()
            } else {
                continue;
            };
            for value in values {
                out.push(Case {
                    scene: path.clone(),
                    path: format!("plugins[{k}].{}", f.name),
                    value,
                });
            }
        }
    }
    out
}

#[test]
fn every_plugin_number_at_its_extremes_is_refused_by_name_or_runs_cleanly() {
    let cases = cases();
    assert!(cases.len() >= 100, "{} cases", cases.len());
    let dir = tempfile::tempdir().unwrap();
    let (mut refused, mut ran, mut stopped) = (0, 0, 0);
    let mut wrong = Vec::new();
    for (n, c) in cases.iter().enumerate() {
        let set = format!("{}={}", c.path, c.value);
        let scene = c.scene.display().to_string();
        let what = format!("{scene} --set {set}");
        let (code, err) = dualsph(&["check".into(), scene.clone(), "--set".into(), set.clone()]);
        let field = c.path.rsplit('.').next().unwrap();
        match code {
            Some(2) if err.contains(field) => {
                refused += 1;
                continue;
            }
            Some(0) => {}
            other => {
                wrong.push(format!("{what}: check exited {other:?}: {}", tail(&err)));
                continue;
            }
        }
        let out = dir.path().join(n.to_string());
        let (code, err) = dualsph(&[
            "run".into(),
            scene,
            "--set".into(),
            set,
            "--set".into(),
            "max_steps=5".into(),
            "--out".into(),
            out.display().to_string(),
        ]);
        match code {
            Some(0) => ran += 1,
            Some(2 | 3) if err.contains("error:") => stopped += 1,
            other => wrong.push(format!("{what}: run exited {other:?}: {}", tail(&err))),
        }
        let _ = std::fs::remove_dir_all(&out);
    }
    eprintln!(
        "{} cases: {refused} refused by check naming the field, {ran} ran 5 steps, \
         {stopped} stopped with a message",
        cases.len()
    );
    assert!(
        wrong.is_empty(),
        "{} of {} cases:\n{}",
        wrong.len(),
        cases.len(),
        wrong.join("\n")
    );
}

/// The line of a message that says what failed (a panic's, an abort's, an error's).
fn tail(err: &str) -> &str {
    err.lines()
        .find(|l| l.contains("panicked") || l.contains("error") || l.contains("failed"))
        .unwrap_or_else(|| err.lines().last().unwrap_or(""))
}
