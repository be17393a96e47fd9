//! The lid-driven cavity at Re = 100 (`scenes/cavity_2d.ron`, Δx = 0.02: 50 × 50 fluid
//! particles) and at Re = 1000 (`scenes/cavity_2d_re1000.ron`, Δx = 0.01: 100 × 100) against
//! the centreline velocities of Ghia, Ghia & Shin (1982) (`dualsph_reference::cavity`). The
//! four walls are wall particles with the no-slip velocity of Adami, Hu & Adams (2012), the
//! lid slides; the probes sample the fluid's velocity on the two centrelines, averaged once
//! the flow is steady (Re = 100: t = 16–20 s; Re = 1000: t = 30–40 s).
//!
//! The measure: the largest difference, in units of the lid speed U, between the simulated
//! and Ghia's velocity at Ghia's interior points (u on x = 0.5, v on y = 0.5; the probe
//! lines linearly interpolated to the points).

use crate::common;

use dualsph::probes::read_probes;
use dualsph::scene::Scene;
use dualsph_validation::report::walls::cavity::{BOUND, CentreLines, Ghia, RE100};
use std::path::Path;

fn cavity(viscous: &str) -> Scene {
    scene("cavity_2d.ron", viscous)
}

fn scene(file: &str, viscous: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace("viscous: NoSlip", &format!("viscous: {viscous}"));
    Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap()
}

/// `(largest |u − u_Ghia|, largest |v − v_Ghia|)` over Ghia's interior points, in units of U,
/// with the probe lines averaged over the samples at t ≥ `reference.from` (the report's
/// measure, `CentreLines`).
fn centreline_errors(scene: &Scene, reference: Ghia) -> (f64, f64) {
    let (dir, _) = common::run_on_threads(scene, 2);
    let lines = CentreLines::of(&read_probes(dir.path()).unwrap(), reference).unwrap();
    assert!(
        lines.samples >= 6,
        "{} samples after {} s",
        lines.samples,
        reference.from
    );
    for (label, points) in [("u", lines.u_points()), ("v", lines.v_points())] {
        for (s, got, expect) in points {
            println!("{label} at {s:.4}: {got:+.5} (Ghia {expect:+.5})");
        }
    }
    lines.errors()
}

/// With no-slip walls both centrelines are within 3 % of U of Ghia's table at every point
/// (measured: 2.4 % in u, 1.8 % in v).
#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): 20 s of cavity flow"]
fn no_slip_walls_match_ghia_at_re_100() {
    let (u, v) = centreline_errors(&cavity("NoSlip"), RE100);
    println!("largest error: u {u:.4} U, v {v:.4} U");
    assert!(u < BOUND && v < BOUND, "u {u}, v {v}");
}

/// The long tier: the cavity at Re = 1000 (`dualsph-validation report cavity` runs it too), and
/// the wrong wall model at Re = 100, which shows that the second tier's check can fail.
mod long {
    use dualsph_validation::report::walls::cavity::{BOUND, RE100, RE1000};

    /// At Re = 1000 the wall jets are thin (the backflow along the floor peaks 0.17 off it) and
    /// both centrelines are within 3 % of U of Ghia's table at every point over t = 30–40 s
    /// (measured: 2.2 % in u, 1.2 % in v). The scene's kernel-gradient correction is what reaches
    /// it: without it the jets along the floor and the right wall run 15–20 % slow and the lines
    /// miss by 5.7 % and 5.0 % of U (`docs/parameters.md`, "Transport velocity").
    #[test]
    #[ignore = "long tier (cargo test --release -p dualsph-validation --test validation -- --ignored long::): 40 s of a 10,000-particle cavity"]
    fn no_slip_walls_match_ghia_at_re_1000() {
        let (u, v) =
            super::centreline_errors(&super::scene("cavity_2d_re1000.ron", "NoSlip"), RE1000);
        println!("largest error: u {u:.4} U, v {v:.4} U");
        assert!(u < BOUND && v < BOUND, "u {u}, v {v}");
    }

    /// The walls' own velocities in the viscous terms (the fixed walls at rest, the lid at U)
    /// let the fluid slip: the u centreline is then 10 % of U off (measured 9.95 %) — the second tier's
    /// check at Re = 100 tells a wrong wall model apart.
    #[test]
    #[ignore = "long tier (cargo test --release -p dualsph-validation --test validation -- --ignored long::): 20 s of cavity flow"]
    fn walls_at_their_own_velocity_miss_ghia() {
        let (u, v) = super::centreline_errors(&super::cavity("Own"), RE100);
        println!("largest error: u {u:.4} U, v {v:.4} U");
        assert!(u > 0.08, "u {u}, v {v}");
    }
}
