//! Bad input never panics: every malformed scene in `tests/bad_scenes/` makes `dualsph check`
//! and `dualsph run` exit non-zero with exactly one error message, the one its header
//! announces, with `file:line:column` for parse errors, and without writing any output.
//!
//! Header of each file (line 3): `// expect: TEXT` (TEXT must appear in the message) or
//! `// expect: TEXT @ L:C` / `// expect: @ L:C` (a parse error at line L, column C).

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn corpus() -> Vec<PathBuf> {
    common::ron_files("tests/bad_scenes")
}

/// `(text that must appear, optional (line, column))` from the file's header.
fn expectation(path: &Path) -> (String, Option<(usize, usize)>) {
    let bytes = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("// expect: "))
        .unwrap_or_else(|| panic!("{}: no `// expect:` header", path.display()));
    match line.split_once('@') {
        None => (line.trim().to_string(), None),
        Some((want, pos)) => {
            let (l, c) = pos.trim().split_once(':').unwrap();
            (
                want.trim().to_string(),
                Some((l.parse().unwrap(), c.parse().unwrap())),
            )
        }
    }
}

#[test]
fn every_bad_scene_gives_one_clear_error_and_no_panic() {
    let files = corpus();
    assert!(files.len() >= 45, "the corpus has {} files", files.len());
    let tmp = tempfile::tempdir().unwrap();
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let (want, pos) = expectation(path);
        let out_dir = tmp.path().join(&name);
        let runs = [
            Command::new(env!("CARGO_BIN_EXE_dualsph"))
                .arg("check")
                .arg(path)
                .output()
                .unwrap(),
            Command::new(env!("CARGO_BIN_EXE_dualsph"))
                .arg("run")
                .arg(path)
                .arg("--quiet")
                .arg("--out")
                .arg(&out_dir)
                .output()
                .unwrap(),
        ];
        for (cmd, o) in ["check", "run"].iter().zip(&runs) {
            let err = String::from_utf8_lossy(&o.stderr);
            let ctx = format!("{name} ({cmd}): {err}");
            assert!(!o.status.success(), "{ctx}: exited 0");
            assert!(!err.contains("panicked"), "{ctx}");
            let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
            assert_eq!(errors.len(), 1, "{ctx}: expected exactly one error line");
            assert!(
                errors[0].contains(&name),
                "{ctx}: the message must name the file"
            );
            assert!(errors[0].contains(&want), "{ctx}: expected {want:?}");
            if let Some((l, c)) = pos {
                let at = format!("{name}:{l}:{c}: ");
                assert!(errors[0].contains(&at), "{ctx}: expected position {at}");
            }
        }
        assert!(
            !out_dir.join("final.csv").exists() && !out_dir.join("diagnostics.csv").exists(),
            "{name}: run wrote output"
        );
    }
}
