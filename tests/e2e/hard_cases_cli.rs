//! Hard cases (scenes/hard/) that `dualsph run` must refuse: each scene states what it tests
//! and its pass criterion; these tests run the binary and assert it (the other hard cases run
//! in-process in validation/tests/validation/hard_cases.rs). Results and figures:
//! docs/validation/hard_cases.md.

use crate::common::assert_doc_quotes;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The doc of the hard cases, whose table quotes each run's figures.
const DOC: &str = "docs/validation/hard_cases.md";

fn hard(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/hard")
        .join(name)
}

/// Runs `dualsph run SCENE --quiet` into a temporary directory: (success, stderr, out dir).
fn run(scene: &Path) -> (bool, String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_dualsph"))
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(dir.path())
        .arg("--quiet")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    (out.status.success(), stderr, dir)
}

/// The number after `key` in `text` (e.g. "t = 1.5e-1" → 0.15).
fn number_after(text: &str, key: &str) -> f64 {
    let rest = &text[text
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in {text}"))
        + key.len()..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || "+-.e".contains(c)))
        .unwrap_or(rest.len());
    rest[..end].parse().unwrap()
}

#[test]
fn fixed_dt_at_one_and_a_half_times_the_cfl_limit_is_refused_before_the_first_step() {
    // the reference limit from the scene's left state: 0.25 h/c with h = 2Δx, c = sqrt(γp/ρ)
    let (gamma, p, rho, dx): (f64, f64, f64, f64) = (5.0 / 3.0, 1.0, 1.0, 0.00125);
    let limit = 0.25 * 2.0 * dx / (gamma * p / rho).sqrt();
    let (ok, err, _dir) = run(&hard("sod_dt_above_cfl.ron"));
    assert!(!ok, "a dt of 1.5 × the CFL limit ran");
    assert!(err.contains("above the CFL limit"), "{err}");
    assert!(
        err.contains("step 0,"),
        "not refused before the first step: {err}"
    );
    let reported = number_after(&err, "the CFL limit ");
    // summation density on the lattice moves ρ (and so h, c) by well under 1 %
    assert!(
        (reported / limit - 1.0).abs() < 0.01,
        "limit {reported:e}, expected {limit:e}"
    );
    let dt = number_after(&err, "fixed dt = ");
    assert!((dt / limit - 1.5).abs() < 0.01, "dt/limit = {}", dt / limit);
    let row = "| `sod_dt_above_cfl.ron` |";
    assert_doc_quotes(
        DOC,
        row,
        &format!("{dt:.3e} is above the CFL limit {reported:.3e}"),
    );
    assert_doc_quotes(
        DOC,
        row,
        &format!("computed by hand from the left state: {limit:.3e}"),
    );
}

#[test]
fn fixed_dt_that_drifts_above_the_cfl_limit_is_stopped_mid_run() {
    let (ok, err, _dir) = run(&hard("dam_break_dt_drifts_above_cfl.ron"));
    assert!(!ok, "the run kept a dt above the CFL limit: {err}");
    assert!(err.contains("above the CFL limit"), "{err}");
    let step = number_after(&err, "step ");
    let t = number_after(&err, "t = ");
    assert!(
        step > 0.0,
        "refused at the start, but dt is within the limit at rest: {err}"
    );
    // Measured: stopped at step 295, t = 0.0723 s (fixed dt: bitwise reproducible); the bound
    // is that + 10 %, i.e. about 30 steps.
    assert!(t < 0.08, "detected late, at t = {t}");
    // the limit it reports is below dt and is 0.25 h/(c + |v|) with h = 0.1 m: c + |v| > c0
    let limit = number_after(&err, "the CFL limit ");
    assert!(limit < 2.45e-4 && limit > 0.25 * 0.1 / 150.0, "{limit:e}");
    let row = "| `dam_break_dt_drifts_above_cfl.ron` |";
    let quoted = format!("stopped at step {step}, t = {t:.4} s: limit {limit:.3e}");
    assert_doc_quotes(DOC, row, &quoted);
}
