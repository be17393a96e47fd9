//! Adaptive resolution end to end (`Refinement`): what splits and merges conserve in a run,
//! in 1, 2 and 3 dimensions, read from `diagnostics.csv` at every step; the same bytes on 1
//! and 2 threads.
//!
//! The scene: a spinning, stretching water drop (`tests/restart/refine_drop.ron`) whose
//! particles split inside a box that sweeps across it and merge where the box has passed.
//! With the artificial viscosity the particles carry an internal energy, so the total energy
//! is exact; a merge's kinetic energy becomes heat, and the angular momentum of its pair's
//! relative motion is reported (`merge_lz`).

use crate::common::{read, run_on_threads};

use dualsph::scene::Scene;
use std::collections::HashMap;
use std::path::Path;

fn drop_text() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/restart/refine_drop.ron");
    std::fs::read_to_string(path).unwrap()
}

fn load(text: &str) -> Scene {
    Scene::from_str(text, Path::new("refine.ron"), &dualsph::default_registry()).unwrap()
}

/// The rows of the CSV file `name` in `dir` (`diagnostics.csv`, `final.csv`), by column label.
fn csv_rows(dir: &Path, name: &str) -> Vec<HashMap<String, f64>> {
    let text = String::from_utf8(read(&dir.join(name))).unwrap();
    let mut lines = text.lines();
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            names
                .iter()
                .zip(l.split(','))
                .map(|(n, v)| (n.to_string(), v.parse().unwrap()))
                .collect()
        })
        .collect()
}

/// The rows of `diagnostics.csv` in `dir`, by column name.
fn diagnostics(dir: &Path) -> Vec<HashMap<String, f64>> {
    csv_rows(dir, "diagnostics.csv")
}

/// The largest departures over the run, each relative to its scale: mass (`M`), momentum
/// (`M U`), angular momentum plus what the merges removed (`M U R`), total energy (`E(0)`);
/// and the final counts of splits and merges.
struct Residuals {
    mass: f64,
    momentum: f64,
    angular: f64,
    energy: f64,
    splits: f64,
    merges: f64,
}

impl Residuals {
    /// Asserts that `label`'s run split and merged at least `least` times each (or, with
    /// `merges` false, split and never merged), and kept mass, momentum and total energy to
    /// round-off.
    fn assert_exact(&self, label: &str, least: f64, merges: bool) {
        assert!(self.splits > least, "{label}: {} splits", self.splits);
        match merges {
            true => assert!(self.merges > least, "{label}: {} merges", self.merges),
            false => assert_eq!(self.merges, 0.0, "{label}: merges"),
        }
        assert!(self.mass < 1e-14, "{label}: mass {}", self.mass);
        assert!(self.momentum < 1e-14, "{label}: momentum {}", self.momentum);
        assert!(self.energy < 1e-14, "{label}: energy {}", self.energy);
    }
}

/// Runs `text` and measures it (module docs); `u` and `r` are the velocity and length scales.
fn residuals(text: &str, u: f64, r: f64) -> Residuals {
    let (dir, _) = run_on_threads(&load(text), 1);
    let rows = diagnostics(dir.path());
    let first = &rows[0];
    let (m0, e0) = (first["mass"], first["e_tot"]);
    let l = |x: &HashMap<String, f64>, k: &str| {
        x.get(k).copied().unwrap_or(0.0) + x.get(&format!("merge_{k}")).copied().unwrap_or(0.0)
    };
    let worst = |f: &dyn Fn(&HashMap<String, f64>) -> f64| rows.iter().map(f).fold(0.0, f64::max);
    let last = rows.last().unwrap();
    Residuals {
        mass: worst(&|x| (x["mass"] - m0).abs() / m0),
        momentum: worst(&|x| (x["px"].abs() + x["py"].abs() + x["pz"].abs()) / (m0 * u)),
        angular: worst(&|x| {
            ["lx", "ly", "lz"]
                .iter()
                .map(|k| (l(x, k) - l(first, k)).abs())
                .sum::<f64>()
                / (m0 * u * r)
        }),
        energy: worst(&|x| (x["e_tot"] - e0).abs() / e0),
        splits: last["splits"],
        merges: last["merges"],
    }
}

#[test]
fn splits_conserve_mass_momentum_angular_momentum_and_energy_to_round_off() {
    // the box stands over the left half of the drop, and nothing merges
    let text = drop_text()
        .replace("buffer: 0.0", "buffer: 100.0")
        .replace("velocity: [4000.0, 0.0]", "velocity: [0.0, 0.0]")
        .replace(
            "min: [-1.6, -2.0], max: [-0.8, 2.0]",
            "min: [-2.0, -2.0], max: [0.0, 2.0]",
        )
        .replace("max_steps: 40", "max_steps: 200");
    let r = residuals(&text, 100.0, 1.0);
    assert!(
        r.splits > 100.0 && r.merges == 0.0,
        "{} {}",
        r.splits,
        r.merges
    );
    assert!(r.mass < 1e-14, "mass {}", r.mass);
    assert!(r.momentum < 1e-14, "momentum {}", r.momentum);
    assert!(r.angular < 1e-14, "angular momentum {}", r.angular);
    assert!(r.energy < 1e-14, "energy {}", r.energy);
}

#[test]
fn merges_conserve_mass_momentum_and_energy_and_report_the_angular_momentum_they_remove() {
    let r = residuals(
        &drop_text().replace("max_steps: 40", "max_steps: 200"),
        100.0,
        1.0,
    );
    r.assert_exact("2-D", 100.0, true);
    // the rates are evaluated again after a merge, so the angular momentum the run keeps
    // plus what the merges report is exact
    assert!(r.angular < 1e-14, "angular momentum {}", r.angular);
}

/// The drop in 1-D (a segment) or 3-D (a cube), its box sweeping along x.
fn drop_in(dim: usize) -> String {
    let (domain, block, velocity, region) = match dim {
        1 => (
            "(min: [-4.0], max: [4.0])",
            "Block(min: [-1.0], max: [1.0], spacing: 0.02, density: 1000.0, h_factor: 2.6, \
             velocity: Linear([[-100.0]]))",
            "[4000.0]",
            "min: [-1.6], max: [-0.8]",
        ),
        _ => (
            "(min: [-4.0, -4.0, -4.0], max: [4.0, 4.0, 4.0])",
            "Block(min: [-0.5, -0.5, -0.5], max: [0.5, 0.5, 0.5], spacing: 0.125, \
             density: 1000.0, h_factor: 2.6, velocity: Linear([[-100.0, -40.0, 0.0], \
             [40.0, 100.0, 0.0], [0.0, 0.0, 0.0]]))",
            "[2000.0, 0.0, 0.0]",
            "min: [-1.2, -2.0, -2.0], max: [-0.4, 2.0, 2.0]",
        ),
    };
    let text = drop_text();
    let disk_start = text.find("Disk(").unwrap();
    let disk_end = disk_start + text[disk_start..].find("])),").unwrap() + 3;
    let coarse = if dim == 1 { "0.02" } else { "0.125" };
    let fine = if dim == 1 { "0.01" } else { "0.0625" };
    format!("{}{block}{}", &text[..disk_start], &text[disk_end..])
        .replace("dimension: 2", &format!("dimension: {dim}"))
        .replace("(min: [-4.0, -4.0], max: [4.0, 4.0])", domain)
        .replace("velocity: [4000.0, 0.0]", &format!("velocity: {velocity}"))
        .replace("min: [-1.6, -2.0], max: [-0.8, 2.0]", region)
        .replace(
            "finest: 0.05, coarsest: 0.1",
            &format!("finest: {fine}, coarsest: {coarse}"),
        )
        .replace(
            "spacing: 0.05, velocity",
            &format!("spacing: {fine}, velocity"),
        )
        .replace("max_steps: 40", "max_steps: 300")
}

#[test]
fn splits_and_merges_conserve_in_1_and_3_d() {
    for (dim, r_scale) in [(1, 1.0), (3, 0.5)] {
        let text = drop_in(dim);
        let r = residuals(&text, 100.0, r_scale);
        r.assert_exact(&format!("{dim}-D"), 10.0, true);
        assert!(r.angular < 1e-14, "{dim}-D angular momentum {}", r.angular);
    }
}

/// Runs `scene` on 1 and on 2 threads, asserts that the final diagnostics, `final.csv` and
/// `diagnostics.csv` are the same bytes, and returns the 1-thread run's directory.
fn same_on_1_and_2_threads(scene: &Scene) -> tempfile::TempDir {
    let (one, s1) = run_on_threads(scene, 1);
    let (two, s2) = run_on_threads(scene, 2);
    assert_eq!(s1.last, s2.last);
    for f in ["final.csv", "diagnostics.csv"] {
        assert!(
            read(&one.path().join(f)) == read(&two.path().join(f)),
            "{f} differs"
        );
    }
    one
}

#[test]
fn a_refined_run_is_bitwise_the_same_on_1_and_2_threads() {
    let scene = load(&drop_text().replace("max_steps: 40", "max_steps: 150"));
    let one = same_on_1_and_2_threads(&scene);
    let rows = diagnostics(one.path());
    let last = rows.last().unwrap();
    assert!(last["splits"] > 100.0 && last["merges"] > 100.0);
}

#[test]
fn a_refined_gas_is_bitwise_the_same_on_1_and_2_threads() {
    // the adaptive Sod tube to t = 0.05 (about 860 steps): splits at the shock and the contact
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sod_1d_adaptive.ron");
    let text = std::fs::read_to_string(path)
        .unwrap()
        .replace("end_time: 0.2,", "end_time: 0.05,");
    let one = same_on_1_and_2_threads(&load(&text));
    let last = diagnostics(one.path()).pop().unwrap();
    assert!(last["splits"] > 50.0, "{} splits", last["splits"]);
}

#[test]
fn only_a_region_splits_a_particle_larger_than_coarsest() {
    // the gas's end particles grow to about nine times `coarsest`; no region reaches them
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/refinement/expanding_gas.ron");
    let (dir, _) = run_on_threads(&load(&std::fs::read_to_string(path).unwrap()), 1);
    let last = diagnostics(dir.path()).pop().unwrap();
    assert_eq!((last["splits"], last["merges"]), (0.0, 0.0));
    let largest = csv_rows(dir.path(), "final.csv")
        .iter()
        .map(|p| p["m"] / p["rho"])
        .fold(0.0, f64::max);
    assert!(
        largest > 4.0 * 0.02,
        "the largest particle is only {largest} m"
    );
}

/// The expanding gas refined everywhere to `finest` (a quarter of its particles' size), its
/// sizes read on the ladder at `ladder`: the final masses of its particles.
fn expanding_gas_masses(ladder: &str) -> Vec<f64> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/refinement/expanding_gas.ron");
    let text = std::fs::read_to_string(path).unwrap().replace(
        "every: 5, regions: [\n            Box(min: [3.0], max: [3.5], spacing: 0.005),",
        &format!(
            "every: 5, ladder: {ladder}, regions: [\n            Box(min: [-4.0], max: [4.0], spacing: 0.005),"
        ),
    );
    assert!(
        text.contains("Box(min: [-4.0]"),
        "the scene's region was not replaced"
    );
    let (dir, _) = run_on_threads(&load(&text), 1);
    csv_rows(dir.path(), "final.csv")
        .iter()
        .map(|p| p["m"])
        .collect()
}

#[test]
fn a_gas_read_at_its_nominal_density_splits_to_finest_once_and_no_further() {
    // every particle is split twice, to a quarter of the scene's mass 0.02 × 1.0, however far
    // the gas has expanded
    let nominal = expanding_gas_masses("Nominal");
    assert_eq!(nominal.len(), 4 * 100);
    assert!(nominal.iter().all(|&m| m == 0.005), "{nominal:?}");
    // read at its density now, an end particle grows past its ladder size as the gas expands
    // and splits again, below the mass of `finest`
    let current = expanding_gas_masses("Current");
    let lightest = current.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(lightest < 0.005, "the lightest particle is {lightest}");
}

#[test]
fn snapshots_carry_each_particles_size_and_level_and_a_scene_may_choose_them() {
    let text = drop_text()
        .replace("max_steps: 40", "max_steps: 150")
        .replace(
            "snapshot_every: 100000)",
            "snapshot_every: 100000, columns: [\"level\"])",
        );
    let (dir, _) = run_on_threads(&load(&text), 1);
    let rows = csv_rows(dir.path(), "final.csv");
    assert!(rows[0].contains_key("level") && !rows[0].contains_key("size"));
    // the levels are those diagnostics.csv counts at the same step
    let last = diagnostics(dir.path()).pop().unwrap();
    let mut counts: HashMap<String, f64> = HashMap::new();
    for p in &rows {
        *counts.entry(format!("n_level{}", p["level"])).or_default() += 1.0;
    }
    assert!(counts.len() > 1, "one level only: {counts:?}");
    for (name, n) in &counts {
        assert_eq!(last[name], *n, "{name}");
    }
    // every written column by default, the size among them: (m/ρ)^{1/2} in 2-D
    let (dir, _) = run_on_threads(&load(&drop_text()), 1);
    for p in csv_rows(dir.path(), "final.csv") {
        let size = (p["m"] / p["rho"]).sqrt();
        assert!(
            (p["size"] - size).abs() <= 1e-12 * size,
            "{} vs {size}",
            p["size"]
        );
    }
}
