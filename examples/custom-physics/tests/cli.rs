//! The user's binary — the whole dualsph CLI plus this crate's plugin — checks, plans, runs
//! and resumes a scene that uses the plugin; its columns reach the CSV and VTK snapshots and
//! a resumed run is bitwise the uninterrupted one (which needs `path_length`, integrated in
//! time, to be checkpointed).

use std::path::{Path, PathBuf};
use std::process::Command;

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("shear.ron")
}

/// Runs the user's binary; panics with its output unless it succeeds.
fn cli(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_custom-physics"))
        .args(args)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{args:?}: {text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

#[test]
fn check_plan_and_plugins_know_the_users_plugin() {
    let s = scene();
    cli(&["check", s.to_str().unwrap()]);
    assert!(cli(&["plugins"]).contains("PairDrag"));
    let plan = cli(&["plan", s.to_str().unwrap()]);
    for want in [
        "pair drag (DPD dissipative force, per-particle γ)",
        "integrate_path_length (PairDrag)",
        "DragGamma (drag_gamma: output gamma; checkpointed)",
        "PathLength (path_length: output s; checkpointed)",
    ] {
        assert!(plan.contains(want), "plan lacks {want:?}:\n{plan}");
    }
}

#[test]
fn its_columns_are_written_and_a_resumed_run_is_bitwise_the_same() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let s = scene();
    let s = s.to_str().unwrap();
    cli(&[
        "run",
        s,
        "--quiet",
        "--out",
        a.to_str().unwrap(),
        "--checkpoint-every",
        "50",
    ]);

    // the columns in the CSV: γ_i as set, and a path no shorter than the chord
    // |r_i(T) − r_i(0)| (to the time discretisation)
    let (h0, first) = csv(&a.join("particles_000000.csv"));
    let (h1, last) = csv(&a.join("final.csv"));
    assert_eq!(h0, h1);
    let col = |name: &str| h1.iter().position(|h| h == name).unwrap();
    let (x, y, gamma, path) = (col("x"), col("y"), col("gamma"), col("s"));
    for (p0, p1) in first.iter().zip(&last) {
        assert_eq!(
            p0[gamma],
            20000.0 + 20000.0 * p0[x],
            "γ_i = γ + ∂γ/∂x x_i(0)"
        );
        assert_eq!(p1[gamma], p0[gamma]);
        assert_eq!(p0[path], 0.0);
        let chord = libm::hypot(p1[x] - p0[x], p1[y] - p0[y]);
        assert!(
            p1[path] >= chord * (1.0 - 1e-3),
            "path {} < chord {chord}",
            p1[path]
        );
    }
    let moved = last.iter().map(|p| p[path]).fold(0.0, f64::max);
    assert!(moved > 0.02, "largest path length {moved}");
    // the drag conserves momentum (the dual-support reaction) and dissipates kinetic energy
    let (h, rows) = csv(&a.join("diagnostics.csv"));
    let (px, py, ek) = (h.iter().position(|c| c == "px").unwrap(), 6, 9);
    assert_eq!((&h[py][..], &h[ek][..]), ("py", "e_kin"));
    for r in &rows {
        assert!(r[px].abs() < 1e-15 && r[py].abs() < 1e-15, "momentum {r:?}");
    }
    assert!(rows.windows(2).all(|w| w[1][ek] < w[0][ek]));
    // and in the VTK file as point data
    let vtp = std::fs::read(a.join("particles_000100.vtp")).unwrap();
    let vtp = String::from_utf8_lossy(&vtp);
    for name in ["drag_gamma", "path_length"] {
        assert!(
            vtp.contains(&format!("Name=\"{name}\"")),
            "{name} not in the VTK file"
        );
    }

    // resume a copy from step 50: every file is byte-identical at the end (but run.json,
    // which records each run's own command line and times)
    std::fs::create_dir(&b).unwrap();
    for f in std::fs::read_dir(&a).unwrap() {
        let f = f.unwrap();
        std::fs::copy(f.path(), b.join(f.file_name())).unwrap();
    }
    for f in [
        "checkpoint_000100.ckpt",
        "final.csv",
        "particles_000100.csv",
    ] {
        std::fs::remove_file(b.join(f)).unwrap();
    }
    let ck = b.join("checkpoint_000050.ckpt");
    let args = [
        "run",
        s,
        "--quiet",
        "--out",
        b.to_str().unwrap(),
        "--checkpoint-every",
        "50",
    ];
    cli(&[&args[..], &["--resume", ck.to_str().unwrap()]].concat());
    for f in std::fs::read_dir(&a).unwrap() {
        let name = f.unwrap().file_name();
        if name == "run.json" {
            continue;
        }
        let (x, y) = (std::fs::read(a.join(&name)), std::fs::read(b.join(&name)));
        assert!(
            x.unwrap() == y.unwrap(),
            "{name:?} differs after the resume"
        );
    }
}

#[test]
fn the_scene_can_choose_the_plugins_column_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene()).unwrap().replace(
        "output: (snapshot_every: 25, diagnostics_every: 10)",
        "output: (snapshot_every: 25, diagnostics_every: 10, columns: [\"drag_gamma\"])",
    );
    let path = tmp.path().join("chosen.ron");
    std::fs::write(&path, text).unwrap();
    let out = tmp.path().join("out");
    cli(&[
        "run",
        path.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    for file in ["particles_000025.csv", "final.csv"] {
        let (header, _) = csv(&out.join(file));
        assert_eq!(header, ["id", "x", "y", "z", "gamma"], "{file}");
    }
}

/// The crate's own equation of state (`LinearEos`) in a tank with walls of particles: the
/// walls' pressure extrapolation and the hydrostatic start follow its law with no edit of
/// theirs, so after 0.5 s the first wall layer under the water and the water itself hold the
/// law's hydrostatic pressure `ρ0 c0² (exp(g (H − y)/c0²) − 1)` to 2 % of `ρ0 g H` (1.8 %
/// measured at Δx = H/10).
#[test]
fn the_walls_follow_the_users_equation_of_state() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("tank");
    let s = Path::new(env!("CARGO_MANIFEST_DIR")).join("tank.ron");
    cli(&[
        "run",
        s.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (h, rows) = csv(&out.join("final.csv"));
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (x, y, body, p) = (col("x"), col("y"), col("body"), col("p"));
    let (rho0, c0, g, depth) = (1000.0_f64, 25.0_f64, 9.81, 0.5);
    let exact = |y: f64| rho0 * c0 * c0 * libm::expm1(g * (depth - y) / (c0 * c0));
    let scale = rho0 * g * depth;
    let floor = |r: &Vec<f64>| r[body] == 0.0 && r[y] > -0.05 && (0.1..0.9).contains(&r[x]);
    let water =
        |r: &Vec<f64>| r[body] == 1.0 && (0.1..0.4).contains(&r[y]) && (0.2..0.8).contains(&r[x]);
    for (what, pick) in [
        ("floor", &floor as &dyn Fn(&Vec<f64>) -> bool),
        ("water", &water),
    ] {
        let errors: Vec<f64> = rows
            .iter()
            .filter(|r| pick(r))
            .map(|r| (r[p] - exact(r[y])) / scale)
            .collect();
        let worst = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
        println!(
            "{what}: {} particles, largest |Δp|/(ρ0 g H) = {worst:.4}",
            errors.len()
        );
        assert!(errors.len() > 10, "{what}: too few particles");
        assert!(worst < 0.02, "{what}: |Δp|/(ρ0 g H) = {worst}");
    }
}

/// The crate's own column `drag_power`, summed by the sweep through its second scalar
/// register, is the heat the drag dissipates: `Σ_i m_i drag_power_i` at the end equals the
/// loss of kinetic energy `−dE_kin/dt` (the drag is the only force) to the backward difference
/// over the last ten steps (0.7 % measured); and a `Probes` line samples the column like a
/// built-in one (non-negative: the drag only dissipates, and positive in the sheared block).
#[test]
fn the_users_column_holds_the_dissipated_power_and_can_be_probed() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("shear");
    cli(&[
        "run",
        scene().to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (h, rows) = csv(&out.join("final.csv"));
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (m, power) = (col("m"), col("drag_power"));
    let heat: f64 = rows.iter().map(|r| r[m] * r[power]).sum();
    let (h, diag) = csv(&out.join("diagnostics.csv"));
    let (t, ek) = (0, h.iter().position(|c| c == "e_kin").unwrap());
    let [.., a, b] = &diag[..] else {
        panic!("too few diagnostics rows")
    };
    let loss = -(b[ek] - a[ek]) / (b[t] - a[t]);
    println!("Σ m drag_power = {heat:.6e}, −dE_kin/dt = {loss:.6e}");
    assert!((heat - loss).abs() < 0.01 * loss, "{heat} against {loss}");
    let (h, samples) = csv(&out.join("probes.csv"));
    assert_eq!(h.len(), 2 + 9, "{h:?}");
    assert!(h[2..].iter().all(|c| c.starts_with("drag_power[")), "{h:?}");
    for s in &samples {
        assert!(s[2..].iter().all(|&x| x.is_finite() && x >= 0.0), "{s:?}");
        assert!(s[2..].iter().any(|&x| x > 1e-3), "{s:?}");
    }
}
