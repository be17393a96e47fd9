//! Shared helpers for the end-to-end tests: random particle clouds built in code, runs with
//! checkpoints, files read or the test fails.
#![allow(dead_code)]

pub mod channel;

use dualsph::core::sim::{Domain, SimConfig, TimeStepping};
use dualsph::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Tait's equation of state for water (ρ0 = 1000, γ = 7) with sound speed 20.
pub fn tait() -> dualsph::plugins::TaitEos {
    dualsph::plugins::TaitEos {
        rho0: 1000.0,
        gamma: 7.0,
        c0: Some(20.0.into()),
        p0: None,
        min_pressure: None,
        cavitation: false,
        background: 0.0,
        materials: Vec::new(),
    }
}

/// A jittered lattice of `side^d` particles with random velocity, density, internal energy
/// and h varying log-uniformly over `[h_lo, h_hi]` (in units of the spacing 1).
pub fn cloud<V: Vector>(side: usize, h_lo: Real, h_hi: Real, seed: u64) -> Vec<ParticleInit<V>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = side.pow(V::DIM as u32);
    (0..n)
        .map(|k| {
            let mut pos = V::zero();
            let mut vel = V::zero();
            let mut rest = k;
            for d in 0..V::DIM {
                let idx = rest % side;
                rest /= side;
                pos.set(d, idx as Real + rng.random_range(-0.3..0.3) + 0.5);
                vel.set(d, rng.random_range(-1.0..1.0));
            }
            let h = h_lo * libm::pow(h_hi / h_lo, rng.random_range(0.0..1.0));
            ParticleInit {
                pos,
                vel,
                mass: rng.random_range(0.8..1.2),
                density: 1000.0 * rng.random_range(0.98..1.02),
                h,
                internal_energy: rng.random_range(1.0..3.0),
                body: 0,
            }
        })
        .collect()
}

/// A simulation over a cloud with the given plugins (built in order), cubic spline kernel.
pub fn sim_with<V: Vector>(
    particles: &[ParticleInit<V>],
    formulation: Formulation,
    plugins: &[&dyn PluginConfig],
) -> Sim<V> {
    sim_with_kernel(particles, KernelKind::CubicSpline, formulation, plugins)
}

/// [`sim_with`] with the given kernel.
pub fn sim_with_kernel<V: Vector>(
    particles: &[ParticleInit<V>],
    kernel: KernelKind,
    formulation: Formulation,
    plugins: &[&dyn PluginConfig],
) -> Sim<V> {
    let mut max = V::zero();
    for k in 0..V::DIM {
        max.set(k, 1.0e3);
    }
    let mut sim = Sim::<V>::new(SimConfig {
        kernel,
        formulation,
        domain: Domain::closed(-max, max),
        skin: 0.1,
        skin_rule: SkinRule::Fixed,
        time_stepping: TimeStepping::Fixed(1e-4),
    });
    sim.spawn_particles(particles).expect("fresh particle ids");
    // an integrator or diagnostics in the list replaces the default, and is built first
    let (roles, physics): (Vec<&dyn PluginConfig>, Vec<&dyn PluginConfig>) =
        plugins.iter().partition(|p| p.role() != Role::Physics);
    let defaults: [&dyn PluginConfig; 2] = [
        &dualsph::plugins::LeapfrogPC::default(),
        &dualsph::plugins::DiagnosticsPlugin {},
    ];
    for d in defaults {
        if !roles.iter().any(|p| p.role() == d.role()) {
            sim.build_plugin(d).expect("default plugin builds");
        }
    }
    for p in roles.into_iter().chain(physics) {
        sim.build_plugin(p).expect("plugin builds");
    }
    // a random cloud is no flow: its h and densities move far from their initial ranges
    // within a few steps, so only a value that is not finite (or not positive) fails a step
    if let Some(mut b) = sim
        .world
        .get_resource_mut::<dualsph::diagnostics::HealthBounds>()
    {
        b.density = (Real::INFINITY, Real::INFINITY);
        b.h = (Real::INFINITY, Real::INFINITY);
    }
    sim.initialize().expect("initial evaluation");
    sim
}

/// Per-particle `(m, r, v, a, ε̇)` in id order.
pub fn rates<V: Vector>(sim: &mut Sim<V>) -> Vec<(Real, V, V, V, Real)> {
    let mut q = sim.world.query::<(
        &ParticleId,
        &Mass,
        &Position<V>,
        &Velocity<V>,
        &Acceleration<V>,
        Option<&EnergyRate>,
    )>();
    let mut rows: Vec<_> = q
        .iter(&sim.world)
        .map(|(id, m, r, v, a, e)| (id.0, (m.0, r.0, v.0, a.0, e.map_or(0.0, |e| e.rate))))
        .collect();
    rows.sort_by_key(|r| r.0);
    rows.into_iter().map(|r| r.1).collect()
}

/// Relative imbalances `(momentum, angular momentum, energy)` of the instantaneous rates.
pub fn imbalances<V: Vector>(rows: &[(Real, V, V, V, Real)]) -> (Real, Real, Real) {
    let (mut p, mut p_scale) = (glam::DVec3::ZERO, 0.0);
    let (mut l, mut l_scale) = (glam::DVec3::ZERO, 0.0);
    let (mut e, mut e_scale) = (0.0, 0.0);
    for &(m, r, v, a, edot) in rows {
        let ma = glam::DVec3::from_array((a * m).to_xyz());
        p += ma;
        p_scale += ma.length();
        let t = V::cross3(r, a * m);
        l += t;
        l_scale += t.length();
        let w = m * v.dot(a);
        e += w + m * edot;
        e_scale += w.abs() + (m * edot).abs();
    }
    (
        p.length() / p_scale,
        l.length() / l_scale.max(1e-300),
        e.abs() / e_scale,
    )
}

/// Runs `scene` into `out` with a checkpoint every `every` steps, from `resume` if given.
pub fn run(
    scene: &dualsph::scene::Scene,
    out: &std::path::Path,
    every: u64,
    resume: Option<std::path::PathBuf>,
) -> dualsph::runner::RunSummary {
    use dualsph::runner::{self, Progress, RestartOptions, RunOptions};
    let opts = RunOptions {
        out: out.to_path_buf(),
        progress: Progress::Silent,
        profile: false,
    };
    let restart = RestartOptions {
        checkpoint_every: Some(every),
        resume,
    };
    runner::run_with(scene, &opts, &restart).unwrap()
}

/// Runs `scene` on a pool of `threads` threads into a new temporary directory, silently; a
/// failed run fails the test.
pub fn run_on_threads(
    scene: &dualsph::scene::Scene,
    threads: usize,
) -> (tempfile::TempDir, dualsph::runner::RunSummary) {
    use dualsph::runner::{self, Progress, RunOptions};
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions {
        out: dir.path().to_path_buf(),
        progress: Progress::Silent,
        profile: false,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let summary = pool.install(|| runner::run(scene, &opts).unwrap());
    (dir, summary)
}

/// The bytes of `path`; a missing file fails the test with its path.
pub fn read(path: &std::path::Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The `.ron` files of `dir` (relative to the package root), sorted.
pub fn ron_files(dir: &str) -> Vec<std::path::PathBuf> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(root.join(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    files
}

/// Asserts that each of `files` has the same bytes in the run directories `a` and `b`; a
/// difference fails naming the file and `how` the runs differ ("on 2 threads", "after the
/// resume").
pub fn assert_same_files(a: &std::path::Path, b: &std::path::Path, files: &[&str], how: &str) {
    for f in files {
        assert!(read(&a.join(f)) == read(&b.join(f)), "{f} differs {how}");
    }
}

/// The rows of a particle CSV as maps from column name to value.
pub fn particle_rows(path: &std::path::Path) -> Vec<std::collections::HashMap<String, f64>> {
    let text = String::from_utf8(read(path)).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            let values = l.split(',').map(|v| v.parse::<f64>().unwrap());
            header.iter().cloned().zip(values).collect()
        })
        .collect()
}

/// The snapshots of a run in `dir`, `(t, CSV path)` in time order, from its `particles.pvd`.
pub fn snapshots(dir: &std::path::Path) -> Vec<(f64, std::path::PathBuf)> {
    let pvd = String::from_utf8(read(&dir.join("particles.pvd"))).unwrap();
    let attr = |line: &str, name: &str| -> Option<String> {
        let start = line.find(&format!("{name}=\""))? + name.len() + 2;
        let len = line[start..].find('"')?;
        Some(line[start..start + len].to_string())
    };
    pvd.lines()
        .filter_map(|l| {
            let t: f64 = attr(l, "timestep")?.parse().ok()?;
            let file = attr(l, "file")?.replace(".vtp", ".csv");
            Some((t, dir.join(file)))
        })
        .collect()
}

/// Asserts that the documentation quotes a figure as a deterministic run gives it: the
/// paragraph (or table row) of `doc` (a path from the repository's root) that holds `anchor`
/// must also hold `figure` (both read with runs of white space as one space), so that a
/// change of arithmetic fails here until the doc is updated in the same commit.
pub fn assert_doc_quotes(doc: &str, anchor: &str, figure: &str) {
    let flat = |t: &str| t.split_whitespace().collect::<Vec<_>>().join(" ");
    let (anchor, figure) = (flat(anchor), flat(figure));
    let units = doc_units(&doc_text(doc));
    let unit = units
        .iter()
        .map(|u| flat(u))
        .find(|u| u.contains(&anchor))
        .unwrap_or_else(|| panic!("{doc} has no paragraph or table row with `{anchor}`"));
    assert!(
        unit.contains(&figure),
        "{doc}: the paragraph of `{anchor}` should quote `{figure}`, as the run gives it: \
         update the doc if the arithmetic changed on purpose"
    );
}

/// The paragraphs of a markdown text, each table row on its own.
fn doc_units(text: &str) -> Vec<String> {
    let mut units = vec![String::new()];
    for line in text.lines() {
        let row = line.trim_start().starts_with('|');
        if row || line.trim().is_empty() {
            units.push(if row { line.to_owned() } else { String::new() });
            if row {
                units.push(String::new());
            }
        } else {
            let last = units.last_mut().expect("one unit at least");
            last.push(' ');
            last.push_str(line);
        }
    }
    units.retain(|u| !u.trim().is_empty());
    units
}

/// `n` with a comma between thousands, as the docs write counts (`42,004`).
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The text of `doc`, a path from the repository's root.
pub fn doc_text(doc: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .find(|d| d.join("Cargo.lock").exists())
        .expect("the workspace root")
        .join(doc);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{doc}: {e}"))
}

/// The columns of a run's `diagnostics.csv` by name.
pub fn diagnostics(dir: &std::path::Path) -> std::collections::HashMap<String, Vec<f64>> {
    let (header, rows) = dualsph::io::read_diagnostics_csv(&dir.join("diagnostics.csv")).unwrap();
    let column = |k: usize| rows.iter().map(|r| r[k]).collect();
    (0..header.len())
        .map(|k| (header[k].clone(), column(k)))
        .collect()
}
