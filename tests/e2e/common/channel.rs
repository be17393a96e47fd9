//! The plane channel with an open inflow and outflow (`scenes/channel_open_2d.ron`), shared by
//! the end-to-end tests and the validation's long tier: the scene with its end time and output
//! set, the fluid's balance step by step, and the outlet's profile against Poiseuille's.

use dualsph::scene::Scene;
use std::collections::HashMap;
use std::path::Path;

pub const SCENE: &str = "scenes/channel_open_2d.ron";

/// The scene's text (read from the workspace root, as [`super::doc_text`] reads a doc) with its
/// end time and output section replaced.
pub fn scene_text(end_time: f64, output: &str) -> String {
    let text = super::doc_text(SCENE);
    let text = text.replace("end_time: 2.0,", &format!("end_time: {end_time:?},"));
    let text = text.replace(
        "output: (diagnostics_every: 100, snapshot_dt: 0.5),",
        &format!("output: ({output}),"),
    );
    assert!(text.contains(output), "the scene's output line changed");
    text
}

/// The scene of [`scene_text`], parsed with the built-in plugins.
pub fn scene(end_time: f64, output: &str) -> Scene {
    let text = scene_text(end_time, output);
    Scene::from_str(&text, Path::new(SCENE), &dualsph::default_registry()).unwrap()
}

/// The water's momentum over each step against what crossed, the buffers' impulses and the
/// walls' trapezoidal impulse (the leapfrog's corrector): residual
/// `ΔP − Σ_B Δ(p_in − p_out + j) + Δt/2 (F_w^n + F_w^{n+1})` on each axis, and the mass
/// residual `ΔM − Σ_B Δ(m_in − m_out)`; returns the worst of each relative to `M ū` and to
/// `M`, and the worst residual with the buffers' impulse left out (relative to `M ū`). On
/// z too when the run is 3-D.
pub fn balance(d: &HashMap<String, Vec<f64>>) -> (f64, f64, f64) {
    let steps = d["dt"].len() - 1;
    let mass = d["mass[water]"][0];
    let scale = mass * 0.02;
    let (mut worst_p, mut worst_m, mut without_j) = (0.0f64, 0.0f64, 0.0f64);
    for n in 0..steps {
        let dt = d["dt"][n + 1];
        let delta = |c: &str| d[c][n + 1] - d[c][n];
        let mut r_m = delta("mass[water]");
        for b in ["inflow", "outflow"] {
            r_m -= delta(&format!("mass_in[{b}]")) - delta(&format!("mass_out[{b}]"));
        }
        worst_m = worst_m.max(r_m.abs() / mass);
        let axes: &[&str] = if d.contains_key("jz[inflow]") {
            &["x", "y", "z"]
        } else {
            &["x", "y"]
        };
        for a in axes {
            let walls = &d[&format!("f{a}[walls]")];
            let mut r = delta(&format!("p{a}[water]")) + 0.5 * dt * (walls[n] + walls[n + 1]);
            let mut j = 0.0;
            for b in ["inflow", "outflow"] {
                r -= delta(&format!("p{a}_in[{b}]")) - delta(&format!("p{a}_out[{b}]"));
                j += delta(&format!("j{a}[{b}]"));
            }
            worst_p = worst_p.max((r - j).abs() / scale);
            without_j = without_j.max(r.abs() / scale);
        }
    }
    (worst_p, worst_m, without_j)
}

/// The mean of the water's streamwise velocity over the snapshots at or after `from`, in
/// bins of Δx across the channel, over the section `x ∈ [x0, x1)`.
pub fn profile(dir: &Path, from: f64, (x0, x1): (f64, f64)) -> Vec<(f64, f64)> {
    let (mut sum, mut count) = (vec![0.0; 20], vec![0usize; 20]);
    for (t, path) in super::snapshots(dir) {
        if t < from {
            continue;
        }
        for r in super::particle_rows(&path) {
            let (x, y) = (r["x"], r["y"]);
            if r["body"] == 1.0 && x >= x0 && x < x1 && (0.0..0.1).contains(&y) {
                let k = ((y / 0.005) as usize).min(19);
                sum[k] += r["vx"];
                count[k] += 1;
            }
        }
    }
    (0..20)
        .map(|k| ((k as f64 + 0.5) * 0.005, sum[k] / count[k].max(1) as f64))
        .collect()
}

/// The largest difference of the profile over `window`, averaged over the snapshots at or after
/// `from`, from plane Poiseuille flow `u = 4U (y/H)(1 − y/H)`, U = 0.03 m/s, H = 0.1 m,
/// relative to U.
pub fn off_poiseuille(dir: &Path, from: f64, window: (f64, f64)) -> f64 {
    let (u, h) = (0.03, 0.1);
    let bins = profile(dir, from, window);
    eprintln!("profile over x in {window:?}: {bins:?}");
    bins.iter()
        .map(|&(y, v)| (v - 4.0 * u * (y / h) * (1.0 - y / h)).abs() / u)
        .fold(0.0, f64::max)
}
