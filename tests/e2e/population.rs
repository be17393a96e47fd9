//! A particle count that changes: the inlet and outlet of `scenes/channel_inflow_2d.ron`.
//! Ids stay unique and are never reused, the inlet adds exactly the layers due by each step,
//! the outlet removes exactly the particles inside it, mass follows the count, snapshots (CSV
//! and VTK) hold the varying count, a resumed run is bitwise the uninterrupted one, and 1 and
//! 2 threads give the same bits.

use crate::common::{read, run};

use dualsph::checkpoint::{Checkpoint, checkpoint_file_name};
use dualsph::prelude::*;
use dualsph::scene::Scene;
use dualsph_core::population::Population;
use glam::DVec2;
use std::collections::BTreeSet;
use std::path::Path;

const SCENE: &str = "scenes/channel_inflow_2d.ron";
/// Particles per inlet layer (0.1 m / 0.005 m) and the layer period Δx / U.
const LAYER: usize = 20;
const PERIOD: Real = 0.005;
const MASS: Real = 1000.0 * 0.005 * 0.005;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The channel scene, stopped after `steps` steps.
fn scene_text(steps: u64) -> String {
    let text = std::fs::read_to_string(root().join(SCENE)).unwrap();
    assert!(!text.contains("max_steps"));
    text.replacen(
        "    end_time:",
        &format!("    max_steps: {steps},\n    end_time:"),
        1,
    )
}

fn scene(steps: u64) -> Scene {
    Scene::from_str(
        &scene_text(steps),
        Path::new(SCENE),
        &dualsph::default_registry(),
    )
    .unwrap()
}

/// (id, position, body) of every particle, in row order.
fn particles(sim: &mut Sim<DVec2>) -> Vec<(u32, DVec2)> {
    sim.world
        .query::<(&ParticleId, &Position<DVec2>)>()
        .iter(&sim.world)
        .map(|(id, r)| (id.0, r.0))
        .collect()
}

#[test]
fn the_inlet_and_outlet_change_the_count_exactly_and_ids_are_never_reused() {
    let mut sim = dualsph::build_sim::<DVec2>(&scene(400)).unwrap();
    sim.initialize().unwrap();
    let mut before = particles(&mut sim);
    let n0 = before.len();
    let mut ever: BTreeSet<u32> = before.iter().map(|p| p.0).collect();
    let mut gone: BTreeSet<u32> = BTreeSet::new();
    let (mut added, mut removed) = (0usize, 0usize);
    for _ in 0..400 {
        let t = sim.clock().t;
        // what the step must do at its start: remove the particles inside the outlet box,
        // add the layers due by t (layer k at t_k = k Δx/U, the first at t = 0)
        let doomed: BTreeSet<u32> = before
            .iter()
            .filter(|(_, r)| r.x >= 0.99 && r.x <= 1.2 && r.y >= 0.0 && r.y <= 0.1)
            .map(|p| p.0)
            .collect();
        let layers_due = (0..).find(|&k| k as Real * PERIOD > t).unwrap();
        let new_ids = layers_due * LAYER - added;
        sim.step().unwrap();
        let now = particles(&mut sim);
        let ids: BTreeSet<u32> = now.iter().map(|p| p.0).collect();
        assert_eq!(ids.len(), now.len(), "an id appears twice");
        let old: BTreeSet<u32> = before.iter().map(|p| p.0).collect();
        let fresh: Vec<u32> = ids.difference(&old).copied().collect();
        let left: BTreeSet<u32> = old.difference(&ids).copied().collect();
        assert_eq!(left, doomed, "step {}: removed", sim.clock().step);
        assert_eq!(fresh.len(), new_ids, "step {}: added", sim.clock().step);
        let max_ever = *ever.last().unwrap();
        assert!(
            fresh.iter().all(|&id| id > max_ever),
            "a new id is not above every id given before"
        );
        gone.extend(left);
        ever.extend(&fresh);
        assert!(ids.is_disjoint(&gone), "a removed id came back");
        added += fresh.len();
        removed += doomed.len();
        assert_eq!(now.len(), n0 + added - removed);
        let d = sim.diagnostics();
        assert_eq!(d.n as usize, now.len());
        assert!(
            (d.mass - MASS * now.len() as Real).abs() < 1e-12 * d.mass,
            "mass {} for {} particles",
            d.mass,
            now.len()
        );
        before = now;
    }
    // the test must exercise both: the stream (1 m/s) carries the block's last column into
    // the outlet within the first steps, and the inlet adds layers every 5 ms
    let p = sim.world.resource::<Population<DVec2>>();
    assert_eq!((p.spawned as usize, p.removed as usize), (added, removed));
    assert!(
        added >= 4 * LAYER && removed >= 2 * LAYER,
        "{added} added, {removed} removed"
    );
    // a uniform stream stays uniform through the inlet and the outlet: every velocity
    // difference is zero, so continuity keeps ρ = ρ0, the Tait pressure is 0 and no force
    // acts — exactly, as long as every added particle carries the stream's velocity and
    // density
    let worst = sim
        .world
        .query::<(&Velocity<DVec2>, &Density)>()
        .iter(&sim.world)
        .map(|(v, rho)| (v.0 - DVec2::X).length() + (rho.0 - 1000.0).abs())
        .fold(0.0, Real::max);
    assert_eq!(worst, 0.0, "the stream is disturbed");
}

#[test]
fn a_run_whose_count_changed_resumes_bitwise_and_its_snapshots_hold_the_varying_count() {
    let scene = scene(300);
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let whole = run(&scene, &a, 150, None);
    assert_eq!(whole.steps, 300);
    let half = Checkpoint::read(&a.join(checkpoint_file_name(150))).unwrap();
    let n0 = scene.generate().len();
    // the resume must restore particles that are not the scene's
    assert!(half.ids.len() != n0 || half.ids.iter().zip(0..).any(|(&id, k)| id != k));
    assert!(half.next_id as usize > n0);
    std::fs::create_dir_all(&b).unwrap();
    for e in std::fs::read_dir(&a).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), b.join(e.file_name())).unwrap();
    }
    std::fs::remove_file(b.join(checkpoint_file_name(300))).unwrap();
    std::fs::remove_file(b.join("final.csv")).unwrap();
    let resumed = run(&scene, &b, 150, Some(b.join(checkpoint_file_name(150))));
    assert_eq!(resumed.last, whole.last, "final diagnostics");
    for e in std::fs::read_dir(&a).unwrap() {
        let name = e.unwrap().file_name();
        let name = name.to_string_lossy();
        assert!(
            read(&a.join(&*name)) == read(&b.join(&*name)),
            "{name} differs after the resume"
        );
    }
    // snapshots every 100 steps (the scene's 2000, cut here): CSV rows and VTK points are
    // the count the diagnostics report for that step
    let text = scene_text(300).replace("snapshot_every: 2000", "snapshot_every: 100");
    let scene = Scene::from_str(&text, Path::new(SCENE), &dualsph::default_registry()).unwrap();
    let c = tmp.path().join("c");
    run(&scene, &c, 1000, None);
    let diag = std::fs::read_to_string(c.join("diagnostics.csv")).unwrap();
    let mut counts = BTreeSet::new();
    for step in [0u64, 100, 200, 300] {
        let csv = std::fs::read_to_string(c.join(format!("particles_{step:06}.csv"))).unwrap();
        let rows = csv.lines().count() - 1;
        let n = diagnostics_n(&diag, step);
        assert_eq!(rows, n, "step {step}: CSV rows");
        let vtp = std::fs::read(c.join(format!("particles_{step:06}.vtp"))).unwrap();
        let vtp = String::from_utf8_lossy(&vtp);
        assert!(
            vtp.contains(&format!("NumberOfPoints=\"{n}\"")),
            "step {step}: VTK point count"
        );
        counts.insert(n);
    }
    assert!(counts.len() > 1, "the count never changed: {counts:?}");
}

/// The particle count the diagnostics report at `step`.
fn diagnostics_n(csv: &str, step: u64) -> usize {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (s, n) = (col("step"), col("n"));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|f| f[s].parse::<u64>() == Ok(step))
        .map(|f| f[n].parse().unwrap())
        .unwrap_or_else(|| panic!("no diagnostics row for step {step}"))
}

#[test]
fn a_run_with_an_inlet_and_an_outlet_is_bitwise_the_same_on_1_and_2_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("channel.ron");
    // the channel twice as high (7,960 particles), so the per-particle loops split over both
    // threads
    let text = scene_text(200).replace(", 0.1]", ", 0.2]");
    assert_eq!(text.matches(", 0.2]").count(), 4);
    std::fs::write(&path, text).unwrap();
    let run = |threads: &str| {
        let out = tmp.path().join(format!("t{threads}"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_dualsph"))
            .args(["run", "--quiet", "--checkpoint-every", "200", "--out"])
            .arg(&out)
            .arg(&path)
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let (one, two) = (run("1"), run("2"));
    let ckpt = checkpoint_file_name(200);
    for f in [ckpt.as_str(), "final.csv", "diagnostics.csv"] {
        let (x, y) = (read(&one.join(f)), read(&two.join(f)));
        assert!(
            !x.is_empty() && x == y,
            "{f} differs between 1 and 2 threads"
        );
    }
}
