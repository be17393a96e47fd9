//! Periodic boundaries: a uniform stream crosses the period unchanged, and the Taylor–Green
//! vortex decays at its analytic rate while it stays ordered; pairs across the period conserve
//! momentum to round-off, and the run is bitwise the same on 1 and 2 threads.

use crate::common;

use dualsph::scene::Scene;
use dualsph_validation::report::walls::taylor_green::{RATE_BOUND, decay_rate, mode_amplitude};
use std::f64::consts::PI;
use std::path::Path;

/// `scenes/taylor_green_2d.ron` at Δx = 0.02 (2,500 particles, a quarter of the scene's)
/// with its plugins replaced by `plugins`, run to `end` with a snapshot every `every` seconds.
fn taylor_green(plugins: &str, velocity: &str, end: f64, every: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/taylor_green_2d.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let start = text.find("    plugins: [").unwrap();
    let stop = start + text[start..].find("    ],\n").unwrap() + 7;
    let text = format!(
        "{}    plugins: [{plugins}],\n{}",
        &text[..start],
        &text[stop..]
    )
    .replace("spacing: 0.01", "spacing: 0.02")
    .replace("TaylorGreen(speed: 1.0, wavelength: 1.0)", velocity)
    .replace("end_time: 1.0", &format!("end_time: {end}"))
    .replace(
        "snapshot_dt: 0.1)",
        &format!("snapshot_dt: {every}, formats: [Csv])"),
    );
    Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap()
}

const PHYSICS: &str = "ContinuityDensity(form: Pairwise), TaitEos(rho0: 1.0, gamma: 7.0, \
                       c0: 10.0), PressureForce(), PhysicalViscosity(mu: 0.01)";

/// The projection of the velocity on the vortex mode (the report's `mode_amplitude`) at
/// every snapshot of a run in `dir`: `(t, A)`.
fn mode_amplitudes(dir: &Path) -> Vec<(f64, f64)> {
    let index = std::fs::read_to_string(dir.join("snapshots.csv")).unwrap();
    index
        .lines()
        .skip(1)
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let t: f64 = f[1].parse().unwrap();
            let rows = particles(&dir.join(f[2]));
            let a = mode_amplitude(
                rows.iter()
                    .map(|r| (r["x"], r["y"], r["vx"], r["vy"], r["m"])),
            );
            (t, a)
        })
        .collect()
}

/// The scene as it is, to t = 1 s: over 0.1–1 s (the amplitude falls to 0.49 of itself) the
/// vortex mode decays at `2νk²` to 2 % (measured: 1.6 % slow; with the paper's viscous
/// regularisation `eta_factor: 0.1`, 6.4 % slow).
#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): a second of Taylor-Green flow"]
fn the_taylor_green_vortex_keeps_its_decay_rate_to_one_second() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/taylor_green_2d.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace("snapshot_dt: 0.1)", "snapshot_dt: 0.1, formats: [Csv])");
    let scene = Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap();
    let (dir, _) = run(&scene, 2);
    let amplitudes: Vec<(f64, f64)> = mode_amplitudes(dir.path())
        .into_iter()
        .filter(|&(t, _)| t >= 0.1 - 1e-9)
        .collect();
    assert_eq!(amplitudes.len(), 10, "{amplitudes:?}");
    let (rate, exact) = (decay_rate(&amplitudes), 2.0 * 0.01 * (2.0 * PI).powi(2));
    println!("decay rate over 0.1-1 s: {rate}, exact {exact}");
    assert!(
        (rate / exact - 1.0).abs() < RATE_BOUND,
        "decay rate {rate}, exact {exact}"
    );
}

fn run(scene: &Scene, threads: usize) -> (tempfile::TempDir, dualsph::runner::RunSummary) {
    common::run_on_threads(scene, threads)
}

fn particles(path: &Path) -> Vec<std::collections::HashMap<String, f64>> {
    common::particle_rows(path)
}

/// A uniform stream (0.7, 0.3) m/s through the periodic box for 2 s: every particle crosses
/// the period at least once along x; velocities and densities stay exactly what they were
/// (under a background pressure, a uniform lattice moving as a whole feels no force if, and
/// only if, every pair across the period is found at its nearest image: with the images left
/// out of the search, this test fails), and every particle is written inside the box.
#[test]
fn a_uniform_stream_crosses_the_period_unchanged() {
    let physics = PHYSICS.replace("c0: 10.0)", "c0: 10.0, background: 1.0)");
    let scene = taylor_green(&physics, "Uniform([0.7, 0.3])", 2.0, 1.0);
    let (dir, s) = run(&scene, 2);
    assert!(s.steps > 1000, "{} steps", s.steps);
    let rows = particles(&dir.path().join("final.csv"));
    assert_eq!(rows.len(), 2500);
    for r in &rows {
        assert!(
            (r["vx"] - 0.7).abs() < 1e-12 && (r["vy"] - 0.3).abs() < 1e-12,
            "{r:?}"
        );
        assert!((r["rho"] - 1.0).abs() < 1e-12, "{r:?}");
        assert!(
            (0.0..1.0).contains(&r["x"]) && (0.0..1.0).contains(&r["y"]),
            "{r:?}"
        );
    }
}

/// The Taylor–Green vortex at Re = 100 to t = 0.1 s, before the particles disorder: the
/// velocity's projection on the vortex mode, `A(t) = Σ m v·û / Σ m |û|²` with
/// `û = (sin kx cos ky, −cos kx sin ky)`, against `e^{−2νk²t}` (Taylor & Green 1937).
/// Measured at Δx = 0.02 (and 0.01): A within 0.18 % (0.17 %) of it at every 0.01 s — the
/// acoustic transient of a start without the vortex's pressure field, the same at both
/// resolutions — and the fitted decay rate 0.55 % (0.41 %) low. Thresholds: 0.25 % and 0.8 %.
/// A pair missed or mislaid across the period deforms the vortex near the faces and fails
/// both (the uniform-stream test shows the search alone). Momentum stays zero to round-off;
/// 1 and 2 threads agree bitwise.
#[test]
fn the_taylor_green_vortex_decays_at_its_analytic_rate() {
    let scene = taylor_green(
        PHYSICS,
        "TaylorGreen(speed: 1.0, wavelength: 1.0)",
        0.1,
        0.01,
    );
    let (dir, s) = run(&scene, 2);
    let (nu, k) = (0.01, 2.0 * PI);
    let amplitudes = mode_amplitudes(dir.path());
    for &(t, a) in &amplitudes {
        let exact = libm::exp(-2.0 * nu * k * k * t);
        assert!(
            (a / exact - 1.0).abs() < 2.5e-3,
            "t = {t}: A = {a}, exact {exact}"
        );
    }
    assert!(amplitudes.len() >= 10, "{} snapshots", amplitudes.len());
    let rate = decay_rate(&amplitudes);
    let exact = 2.0 * nu * k * k;
    assert!(
        (rate / exact - 1.0).abs() < 0.008,
        "decay rate {rate}, exact {exact}"
    );
    let p = s.last.momentum;
    assert!(p[0].abs() < 1e-15 && p[1].abs() < 1e-15, "momentum {p:?}");
    let (one, _) = run(&scene, 1);
    let final_of = |d: &tempfile::TempDir| std::fs::read(d.path().join("final.csv")).unwrap();
    assert!(final_of(&one) == final_of(&dir), "1 and 2 threads differ");
}

/// `scenes/taylor_green_2d_tvf.ron` (transport velocity, Δx = 0.01) to t = 2 s, measured as
/// PySPH and TrixiParticles.jl measure the vortex every 0.1 s: the peak speed against
/// `U e^{bt}`, `b = −8π²/Re`, and the mean error of the speed over the particles (PySPH's L1),
/// both over `U e^{bt}`. Measured: at most 0.88 % and 0.76 %; the bound is 1 % for both.
/// The run's first 0.2 s are bitwise the same on 1 and 2 threads.
#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): two seconds of Taylor-Green flow"]
fn the_transport_velocity_keeps_the_vortex_within_one_percent_to_two_seconds() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/taylor_green_2d_tvf.ron");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("snapshot_dt: 0.1)", "snapshot_dt: 0.1, formats: [Csv])");
    let scene = Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap();
    let (dir, _) = run(&scene, 2);
    let (b, k) = (-8.0 * PI * PI / 100.0, 2.0 * PI);
    let index = std::fs::read_to_string(dir.path().join("snapshots.csv")).unwrap();
    let (mut peak_worst, mut mean_worst, mut snapshots) = (0.0f64, 0.0f64, 0);
    for line in index.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let t: f64 = f[1].parse().unwrap();
        let scale = libm::exp(b * t);
        let rows = particles(&dir.path().join(f[2]));
        let (mut peak, mut mean) = (0.0f64, 0.0);
        for r in &rows {
            let speed = libm::hypot(r["vx"], r["vy"]);
            let ((sx, cx), (sy, cy)) = (libm::sincos(k * r["x"]), libm::sincos(k * r["y"]));
            let exact = scale * libm::hypot(sx * cy, cx * sy);
            peak = peak.max(speed);
            mean += (speed - exact).abs() / rows.len() as f64;
        }
        let (peak_err, mean_err) = ((peak - scale).abs() / scale, mean / scale);
        println!(
            "t = {t:.2}: peak {:.3} %, mean {:.3} %",
            100.0 * peak_err,
            100.0 * mean_err
        );
        peak_worst = peak_worst.max(peak_err);
        mean_worst = mean_worst.max(mean_err);
        snapshots += 1;
    }
    assert_eq!(snapshots, 21);
    assert!(peak_worst < 0.01, "peak speed off by {peak_worst}");
    assert!(mean_worst < 0.01, "mean speed error {mean_worst}");
    // bitwise the same on 1 and 2 threads, over the first 0.2 s
    let text = text.replace("end_time: 2.0,", "end_time: 0.2,");
    let short = Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap();
    let final_of = |d: &tempfile::TempDir| std::fs::read(d.path().join("final.csv")).unwrap();
    let (one, two) = (run(&short, 1).0, run(&short, 2).0);
    assert!(final_of(&one) == final_of(&two), "1 and 2 threads differ");
}
