//! Loads on bodies: a water block in a tank of wall particles (a fixed body). The load on the
//! tank is minus the force of the walls on the water, checked against the water's own
//! momentum balance step by step; its moment against a symmetric case and an independent sum;
//! the load columns are bitwise the same on 1 and 2 threads; `bodies.csv` has its columns and
//! rows, and a resumed run continues it byte for byte.

use crate::common;

use dualsph::prelude::*;
use dualsph::scene::Scene;
use glam::DVec2;
use std::collections::HashMap;
use std::path::Path;

const G: f64 = 9.81;

/// The tank: three layers of wall particles (Δx = 0.01 m) under and beside a 0.2 m × 0.1 m
/// water block, symmetric about x = 0; `bodies` declares them (the tank's particles belong
/// to `floor` and `walls`, which may be the same body), `water` is the water's generator
/// extra settings, and the run takes `steps` steps of 1e-4 s.
fn scene(bodies: &str, floor: &str, walls: &str, water: &str, steps: u64) -> Scene {
    let text = format!(
        r#"Scene(
    name: "water in a tank of wall particles",
    dimension: 2,
    domain: (min: [-0.2, -0.05], max: [0.2, 0.3]),
    kernel: CubicSpline,
    formulation: DualSupport,
    bodies: [{bodies}, Body(name: "water")],
    particles: [
        Block(min: [-0.13, -0.03], max: [0.13, 0.0], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "{floor}"),
        Block(min: [-0.13, 0.0], max: [-0.1, 0.15], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "{walls}"),
        Block(min: [0.1, 0.0], max: [0.13, 0.15], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "{walls}"),
        Block(min: [-0.1, 0.0], max: [0.1, 0.1], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "water"{water}),
    ],
    plugins: [
        ContinuityDensity(form: Pairwise),
        TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0),
        Gravity(g: [0.0, -{G}]),
        PressureForce(),
        ArtificialViscosity(alpha: 0.5, beta: 0.0),
    ],
    integrator: (dt: Fixed(1e-4)),
    end_time: {end},
    output: (diagnostics_every: 1, snapshot_every: 0),
)"#,
        end = steps as f64 * 1e-4,
    );
    Scene::from_str(&text, Path::new("tank.ron"), &dualsph::default_registry()).unwrap()
}

/// The tank as one fixed body, its moment about `about`.
fn tank(about: &str, steps: u64) -> Scene {
    let body = format!(r#"Body(name: "tank", kind: Fixed{about})"#);
    scene(&body, "tank", "tank", "", steps)
}

fn run(scene: &Scene, threads: usize) -> (tempfile::TempDir, dualsph::runner::RunSummary) {
    common::run_on_threads(scene, threads)
}

/// The load on the tank is minus the force of the walls on the water: the water's momentum
/// changes over each step by exactly what the leapfrog's trapezoidal rule gives for gravity
/// and that force, `P^{n+1} − P^n = Δt M g − Δt/2 (F^n + F^{n+1})` (the corrector's
/// `v^{n+1} = v^n + Δt/2 (a^n + a^{n+1})` summed over the water, whose pair forces from the
/// tank are the reactions of the tank's). Residual measured: 3.5e-14 of `Δt M g` at worst over
/// 200 steps. Counting gravity in the load would leave `M_tank/M_water` = 0.84 of it.
#[test]
fn the_load_on_the_tank_balances_the_water_momentum_step_by_step() {
    let (dir, s) = run(&tank("", 200), 1);
    let d = common::diagnostics(dir.path());
    let (dt, px, py) = (&d["dt"], &d["px[water]"], &d["py[water]"]);
    let (fx, fy) = (&d["fx[tank]"], &d["fy[tank]"]);
    let (m_water, m_tank) = (d["mass[water]"][0], d["mass[tank]"][0]);
    assert_eq!(dt.len(), 201);
    assert!((m_water - 20.0).abs() < 1e-9 && (m_tank - 16.8).abs() < 1e-9);
    let weight = m_water * G;
    let (mut worst, mut worst_with_gravity) = (0.0f64, 0.0f64);
    for n in 0..200 {
        let h = dt[n + 1];
        let (fx_bar, fy_bar) = (0.5 * (fx[n] + fx[n + 1]), 0.5 * (fy[n] + fy[n + 1]));
        let rx = (px[n + 1] - px[n]) + h * fx_bar;
        let ry = (py[n + 1] - py[n]) - h * (-weight - fy_bar);
        worst = worst.max(libm::hypot(rx, ry) / (h * weight));
        // the same balance with the tank's weight counted in its load
        let ry_g = (py[n + 1] - py[n]) - h * (-weight - (fy_bar - m_tank * G));
        worst_with_gravity = worst_with_gravity.max(ry_g.abs() / (h * weight));
    }
    eprintln!("momentum balance of the water: worst residual {worst:.2e} of dt M g");
    assert!(worst < 1e-12, "residual {worst:e} of dt M g");
    assert!(worst_with_gravity > 0.5, "{worst_with_gravity}");
    // the water pushes down on the floor: the load is downwards and a sizeable part of the
    // weight after 20 ms (the column is still being compressed from uniform density)
    let last = s.last.loads[0];
    assert_eq!(last.body, 0);
    assert!(last.force[1] < -0.2 * weight, "{:?}", last.force);
}

/// The water at rest weighs on the tank. The column, released at uniform density, oscillates
/// in its acoustic mode (period 40 ms here, slowly damped: the load swings between 0.5 and
/// 1.7 times the weight at first); over two periods the mean load is the weight straight
/// down, measured within 0.5 % (1.0046 of it). On the tank, symmetric about x = 0, the sideways force and
/// the moment about the axis of symmetry stay round-off next to the weight and to the moment
/// of the weight about the tank's edge (measured up to 3e-14 and 2e-14; not exactly zero, as
/// the lattice is not bitwise symmetric and the sums run in id order).
#[test]
fn the_water_at_rest_weighs_on_the_tank_with_no_moment_about_its_axis() {
    let steps = 800;
    let (dir, _) = run(&tank("", steps), 2);
    let d = common::diagnostics(dir.path());
    let (fx, fy, mz) = (&d["fx[tank]"], &d["fy[tank]"], &d["mz[tank]"]);
    let weight = d["mass[water]"][0] * G;
    let scale = weight * 0.13;
    let worst_x = fx.iter().map(|f| f.abs()).fold(0.0, f64::max) / weight;
    let worst_m = mz.iter().map(|m| m.abs()).fold(0.0, f64::max) / scale;
    eprintln!("symmetry: |fx| up to {worst_x:.2e} of the weight, |mz| up to {worst_m:.2e}");
    assert!(
        worst_x < 1e-12 && worst_m < 1e-12,
        "{worst_x:e}, {worst_m:e}"
    );
    // the trapezoidal mean, the leapfrog's own quadrature of the load
    let sum: f64 = fy.windows(2).map(|w| 0.5 * (w[0] + w[1])).sum();
    let mean = sum / steps as f64;
    eprintln!("mean load over 80 ms: {:.4} of the weight", -mean / weight);
    assert!(
        (mean + weight).abs() < 0.01 * weight,
        "{mean} N vs {weight} N"
    );
}

/// The moment about a given point is `Σ_i (x_i − c) × m_i a_i` over the tank's particles,
/// summed independently from the simulation's own data, and `M_c = M_0 − c × F`.
#[test]
fn the_moment_about_a_point_is_the_sum_of_the_particle_moments() {
    let c = DVec2::new(0.05, -0.02);
    // the water off the axis, so that the moment is not zero
    let scene = scene(
        r#"Body(name: "tank", kind: Fixed, moment_about: [0.05, -0.02])"#,
        "tank",
        "tank",
        ", cut: [(min: [0.0, 0.05], max: [0.1, 0.1])]",
        40,
    );
    let mut sim = dualsph::build_sim::<DVec2>(&scene).unwrap();
    sim.initialize().unwrap();
    for _ in 0..40 {
        sim.step().unwrap();
    }
    let load = sim.diagnostics().loads[0];
    let mut q = sim.world.query::<(
        &ParticleId,
        &dualsph::core::bodies::BodyId,
        &Position<DVec2>,
        &Mass,
        &Acceleration<DVec2>,
    )>();
    let mut rows: Vec<_> = q.iter(&sim.world).filter(|r| r.1.0 == 0).collect();
    rows.sort_by_key(|r| std::cmp::Reverse(r.0.0));
    let (mut f, mut m0, mut scale) = (DVec2::ZERO, 0.0, 0.0);
    for (_, _, r, m, a) in rows {
        let fi = a.0 * m.0;
        f += fi;
        m0 += r.0.perp_dot(fi);
        scale += r.0.length() * fi.length();
    }
    let mc = m0 - c.perp_dot(f);
    eprintln!(
        "moment about c: {:.6e} N m, independent {mc:.6e}",
        load.moment[2]
    );
    assert!(
        mc.abs() > 1e-3 * scale,
        "a moment to measure: {mc} vs {scale}"
    );
    assert!((load.moment[2] - mc).abs() < 1e-13 * scale);
    assert!((DVec2::from_slice(&load.force[..2]) - f).length() < 1e-13 * scale);
    assert_eq!(load.moment[..2], [0.0, 0.0]);
}

/// The load columns and `bodies.csv` are bitwise the same on 1 and 2 threads.
#[test]
fn the_loads_are_bitwise_the_same_on_one_and_two_threads() {
    let scene = tank(", moment_about: [0.02, 0.01]", 60);
    let (a, _) = run(&scene, 1);
    let (b, _) = run(&scene, 2);
    let (da, db) = (common::diagnostics(a.path()), common::diagnostics(b.path()));
    for col in ["fx[tank]", "fy[tank]", "mz[tank]"] {
        let bits = |d: &HashMap<String, Vec<f64>>| -> Vec<u64> {
            d[col].iter().map(|x| x.to_bits()).collect()
        };
        assert_eq!(bits(&da), bits(&db), "{col}");
    }
    let bodies = |d: &tempfile::TempDir| common::read(&d.path().join("bodies.csv"));
    assert!(bodies(&a) == bodies(&b), "bodies.csv differs");
}

/// With the tank split into two fixed bodies, `bodies.csv` has the columns
/// `t,step,body,fx,fy,fz,mx,my,mz` and one row per diagnostics step and body, in body order,
/// with the values of the load columns of `diagnostics.csv`; the two loads add up to the
/// load on the whole tank (the pair forces between floor and walls cancel), to round-off.
#[test]
fn bodies_csv_has_a_row_per_step_and_body_and_the_parts_add_up() {
    let bodies = r#"Body(name: "floor", kind: Fixed), Body(name: "walls", kind: Fixed)"#;
    let (dir, _) = run(&scene(bodies, "floor", "walls", "", 30), 1);
    let d = common::diagnostics(dir.path());
    let text = std::fs::read_to_string(dir.path().join("bodies.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,step,body,fx,fy,fz,mx,my,mz"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2 * 31);
    let (whole, _) = run(&tank("", 30), 1);
    let w = common::diagnostics(whole.path());
    for (k, pair) in rows.chunks(2).enumerate() {
        let value = |row: &[&str], i: usize| row[i].parse::<f64>().unwrap();
        for (row, name) in pair.iter().zip(["floor", "walls"]) {
            assert_eq!((row[1], row[2]), (k.to_string().as_str(), name));
            assert_eq!(value(row, 0), d["t"][k]);
            assert_eq!(value(row, 3), d[&format!("fx[{name}]")][k]);
            assert_eq!(value(row, 4), d[&format!("fy[{name}]")][k]);
            assert_eq!(value(row, 8), d[&format!("mz[{name}]")][k]);
            assert_eq!([value(row, 5), value(row, 6), value(row, 7)], [0.0; 3]);
        }
        let sum = value(&pair[0], 4) + value(&pair[1], 4);
        let scale = value(&pair[0], 4).abs() + value(&pair[1], 4).abs() + 1e-9;
        assert!((sum - w["fy[tank]"][k]).abs() < 1e-12 * scale, "step {k}");
    }
    assert!(!d.contains_key("fx[water]"), "a fluid body has no load");
}

/// A run resumed from its checkpoint at step 20 writes `bodies.csv` and `diagnostics.csv`
/// byte for byte as the uninterrupted run does, and a fresh run in the same directory starts
/// them again.
#[test]
fn a_resumed_run_continues_bodies_csv() {
    let scene = tank("", 40);
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let s = common::run(&scene, &a, 20, None);
    std::fs::create_dir_all(&b).unwrap();
    let checkpoint = dualsph::checkpoint::checkpoint_file_name(20);
    std::fs::copy(a.join(&checkpoint), b.join(&checkpoint)).unwrap();
    for f in ["bodies.csv", "diagnostics.csv"] {
        // the files as a run stopped at step 30 left them (header and steps 0..=30): rows
        // past the checkpoint, which the resumed run replaces
        let text = std::fs::read_to_string(a.join(f)).unwrap();
        let keep: Vec<&str> = text.lines().take(32).collect();
        std::fs::write(b.join(f), keep.join("\n") + "\n").unwrap();
    }
    let resumed = common::run(&scene, &b, 20, Some(b.join(&checkpoint)));
    assert_eq!(resumed.initial, s.initial);
    assert_eq!(resumed.last, s.last);
    for f in ["bodies.csv", "diagnostics.csv"] {
        assert!(common::read(&a.join(f)) == common::read(&b.join(f)), "{f}");
    }
    let fluid_only = scene_without_walls();
    common::run(&fluid_only, &b, 1000, None);
    assert!(
        !b.join("bodies.csv").exists(),
        "the earlier run's bodies.csv"
    );
}

/// A fluid-only scene in the tank's domain (no load to write).
fn scene_without_walls() -> Scene {
    let text = r#"Scene(
    name: "a water block",
    dimension: 2,
    domain: (min: [-0.2, -0.05], max: [0.2, 0.3]),
    kernel: CubicSpline,
    formulation: DualSupport,
    particles: [Block(min: [-0.1, 0.0], max: [0.1, 0.1], spacing: 0.01, lattice: Square,
                      density: 1000.0, h_factor: 2.0)],
    plugins: [ContinuityDensity(form: Pairwise), TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0),
              PressureForce()],
    integrator: (dt: Fixed(1e-4)),
    end_time: 0.0005,
    output: (snapshot_every: 0),
)"#;
    Scene::from_str(text, Path::new("block.ron"), &dualsph::default_registry()).unwrap()
}
