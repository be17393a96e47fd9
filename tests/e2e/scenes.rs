//! Shipped scenes run end to end in every dimension, and a free-flying drop conserves
//! momentum over 1000 steps with variable h under the dual-support formulation.

use dualsph::io::{read_diagnostics_csv, read_particles};
use dualsph::runner::{self, Progress, RunOptions};
use dualsph::scene::{Formulation, Scene};
use std::path::Path;

fn load(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    Scene::load(&path, &dualsph::default_registry()).unwrap()
}

/// Runs a scene silently into a fresh temporary directory.
fn run_in_tempdir(scene: &Scene) -> (tempfile::TempDir, runner::RunSummary) {
    let dir = tempfile::tempdir().unwrap();
    let summary = runner::run(
        scene,
        &RunOptions {
            out: dir.path().to_path_buf(),
            progress: Progress::Silent,
            profile: false,
        },
    )
    .unwrap();
    (dir, summary)
}

/// Largest momentum change over the run, relative to Σ|m v| at t = 0.
fn momentum_drift(s: &runner::RunSummary) -> f64 {
    (0..3)
        .map(|k| (s.last.momentum[k] - s.initial.momentum[k]).abs())
        .fold(0.0, f64::max)
        / s.initial.momentum_scale
}

fn run_short(name: &str, steps: u64) -> (tempfile::TempDir, runner::RunSummary) {
    let mut scene = load(name);
    scene.max_steps = Some(steps);
    scene.output.snapshot_every = steps / 2;
    run_in_tempdir(&scene)
}

#[test]
fn scenes_of_each_dimension_run_and_write_outputs() {
    for (name, dim) in [
        ("heat_1d.ron", 1),
        ("sod_1d.ron", 1),
        ("dam_break_2d.ron", 2),
        ("column_3d.ron", 3),
    ] {
        let (dir, s) = run_short(name, 20);
        assert_eq!(s.steps, 20, "{name}");
        let parts = read_particles(&dir.path().join("final.csv")).unwrap();
        assert_eq!(parts.len() as u64, s.particles, "{name}");
        assert!(
            parts.rows().all(|p| p.pos().iter().all(|x| x.is_finite())),
            "{name}"
        );
        if dim < 3 {
            assert!(
                parts.rows().all(|p| p.pos()[2] == 0.0),
                "{name}: unused z must be 0"
            );
        }
        let (header, rows) = read_diagnostics_csv(&dir.path().join("diagnostics.csv")).unwrap();
        assert_eq!(
            &header[..13],
            &[
                "t", "step", "dt", "n", "mass", "px", "py", "pz", "lz", "e_kin", "e_int", "e_pot",
                "e_tot"
            ]
        );
        assert!(rows.len() >= 2, "{name}");
        assert!(
            dir.path().join("particles_000010.vtp").is_file()
                && dir.path().join("particles.pvd").is_file(),
            "{name}"
        );
    }
}

#[test]
fn free_drop_conserves_momentum_with_dual_support_and_variable_h() {
    let mut scene = load("drop_2d.ron");
    scene.max_steps = Some(1000);
    scene.end_time = 1.0;
    scene.output.snapshot_every = 0;
    let (_dir, s) = run_in_tempdir(&scene);
    assert_eq!(s.steps, 1000);
    let rel = momentum_drift(&s);
    let l_drift = (s.last.angular_momentum[2] - s.initial.angular_momentum[2]).abs();
    println!(
        "DualSupport drop: momentum drift {rel:.2e} (relative to Σ|m v|), Lz drift {l_drift:.2e}"
    );
    assert!(rel <= 1e-12, "momentum drift {rel:e}");

    scene.formulation = Formulation::SingleSupport;
    scene.max_steps = Some(200);
    let (_dir, s) = run_in_tempdir(&scene);
    let rel_single = momentum_drift(&s);
    println!("SingleSupport drop: momentum drift {rel_single:.2e} after 200 steps");
    assert!(
        rel_single > 1e-8,
        "SingleSupport should drift, got {rel_single:e}"
    );
}

#[test]
fn heat_conduction_conserves_energy_with_a_refined_band() {
    let (_dir, s) = run_short("heat_1d.ron", 400);
    let rel = (s.last.e_int - s.initial.e_int).abs() / s.initial.e_int;
    println!("1-D heat, DualSupport: ΔE/E = {rel:.2e}");
    assert!(rel <= 1e-13, "ΔE/E = {rel:e}");
    assert!(
        (s.initial.e_int - 0.75).abs() < 1e-12,
        "E_total = {}",
        s.initial.e_int
    );
}

/// `scenes/tank_obstacle_2d.ron`, built from shapes: the particle count of each body, the walls
/// held in place and every particle still in the domain after 100 steps of the collapse.
#[test]
fn tank_of_particle_walls_with_obstacles_from_shapes() {
    let mut scene = load("tank_obstacle_2d.ron");
    let first = scene.generate();
    let count = |b: u16| first.iter().filter(|p| p.body == b).count();
    // water: 20 × 30 − the 32 lattice points within the post's radius 0.06 (3Δx)
    // tank: (80 + 6)(50 + 6) − 80·50; cylinder: rings of round(2π r/Δx) = 28, 22, 16;
    // post: 16 + 9
    assert_eq!(
        [count(0), count(1), count(2), count(3)],
        [600 - 32, 86 * 56 - 4000, 28 + 22 + 16, 16 + 9]
    );
    scene.max_steps = Some(100);
    scene.output.snapshot_every = 0;
    let (dir, s) = run_in_tempdir(&scene);
    assert_eq!(s.steps, 100);
    let last = read_particles(&dir.path().join("final.csv")).unwrap();
    assert_eq!(last.len(), first.len());
    for (p0, p) in first.iter().zip(last.rows()) {
        if p0.body > 0 {
            assert_eq!(p.pos().map(f64::to_bits), p0.pos.map(f64::to_bits));
        }
        assert!(p.pos()[0] > -0.06 && p.pos()[0] < 1.66 && p.pos()[1] > -0.06 && p.pos()[1] < 1.06);
    }
}
