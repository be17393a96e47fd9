//! Plane Poiseuille flow started from rest (`scenes/poiseuille_2d.ron`, the case of Morris,
//! Fox & Zhu 1997, §4.1): the velocity profile across the channel against the series solution
//! (`dualsph_reference::poiseuille`) at every snapshot, from the start-up to the steady state.
//! The plates are walls of particles; with the no-slip wall velocity of Adami, Hu & Adams
//! (2012) the profile follows the series, with the walls' own (zero) velocity it slips.

use crate::common;

use dualsph::scene::Scene;
use dualsph_validation::report::walls::poiseuille::{L2_BOUND, profile_error};
use std::path::Path;

/// The scene with its `WallPressure(viscous: NoSlip)` set to `viscous`.
fn channel(viscous: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/poiseuille_2d.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace("viscous: NoSlip", &format!("viscous: {viscous}"));
    Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap()
}

/// `(t, relative L2 error of v_x over the water)` at every snapshot after the start
/// (the report's measure, `profile_error`).
fn profile_errors(scene: &Scene) -> Vec<(f64, f64)> {
    let (dir, _) = common::run_on_threads(scene, 2);
    common::snapshots(dir.path())
        .into_iter()
        .filter(|&(t, _)| t > 0.0)
        .map(|(t, csv)| {
            let rows = common::particle_rows(&csv);
            let water = rows
                .iter()
                .filter(|r| r["body"] == 1.0)
                .map(|r| (r["y"], r["vx"]));
            (t, profile_error(water, t))
        })
        .collect()
}

/// With no-slip walls the profile is within 0.6 % (relative L2) of the series at every
/// snapshot from t = 0.0225 s to 1 s (the slowest mode has then decayed to 5e-5 of itself:
/// the steady state). Measured: at most 0.48 %, 0.48 % at the end.
#[test]
fn no_slip_walls_follow_the_series_solution() {
    let errors = profile_errors(&channel("NoSlip"));
    println!("t, L2 error: {errors:?}");
    assert!(errors.len() >= 40, "{} snapshots", errors.len());
    assert!((errors.last().unwrap().0 - 1.0).abs() < 1e-9);
    for (t, e) in errors {
        assert!(e < L2_BOUND, "t = {t}: relative L2 error {e}");
    }
}

/// The same walls with their own velocity (zero) in the viscous terms: the fluid slips at
/// the plates and the steady profile is 8.5 % off — the check above tells the two apart.
#[test]
fn walls_at_their_own_velocity_slip() {
    let (t, e) = *profile_errors(&channel("Own")).last().unwrap();
    println!("t = {t}: relative L2 error {e}");
    assert!(e > 0.05, "t = {t}: relative L2 error {e}");
}
