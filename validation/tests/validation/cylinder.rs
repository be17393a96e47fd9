//! Flow past a cylinder in a channel between open boundaries: the DFG benchmark 2D-1
//! (`scenes/cylinder_dfg_2d1.ron`, Schäfer & Turek 1996; the reference intervals in
//! `dualsph_reference::cylinder`). The drag and lift from the cylinder's exact load in
//! `bodies.csv`, the pressure difference and the recirculation length from the scene's probes
//! (`probes.csv`), averaged over a window at the end of the run.

use crate::common;

use dualsph::cli::forces::{coefficients, summarise, upward_crossings};
use dualsph::io::read_body_loads;
use dualsph::scene::Scene;
use dualsph_reference::cylinder::{self, midpoint, setup};
use std::path::Path;

/// The shipped scene `file` at its own resolution, to `end_time`, without snapshots.
fn scene(file: &str, end_time: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(file);
    let mut scene = Scene::load(&path, &dualsph::default_registry()).unwrap();
    scene.end_time = end_time;
    scene.output.snapshot_dt = None;
    scene.output.snapshot_every = 0;
    scene
}

/// What the benchmark measures, averaged over `t ≥ from`: c_D, c_L, Δp and L_a.
#[derive(Debug)]
struct Measured {
    drag: f64,
    lift: f64,
    pressure_drop: f64,
    recirculation: Option<f64>,
}

/// The end of reversed flow on the centreline behind the cylinder, `x_r − 0.25`, from the
/// time-averaged `wake[k]` samples over `[0.25, 0.45]`: the first upward crossing of zero,
/// linear between the samples either side (the forces command's `upward_crossings`), or
/// `None` without reversed flow.
fn recirculation_length(mean: &[f64]) -> Option<f64> {
    let dx = 0.2 / (mean.len() - 1) as f64;
    let signal: Vec<(f64, f64)> = (mean.iter().enumerate())
        .map(|(k, &u)| (k as f64 * dx, u))
        .collect();
    upward_crossings(&signal, 0.0).first().copied()
}

fn measure(dir: &Path, from: f64) -> Measured {
    let loads = read_body_loads(&dir.join("bodies.csv"), "cylinder").unwrap();
    let ubar = 2.0 / 3.0 * setup::U_MAX_2D1;
    // ½ρŪ²D, the scale of the benchmark's coefficients
    let dynamic = 1.0 / cylinder::coefficient(1.0, setup::RHO, ubar, setup::DIAMETER);
    let s = summarise(&coefficients(&loads, dynamic), from).expect("rows in the window");
    let probes: Vec<_> = common::particle_rows(&dir.join("probes.csv"))
        .into_iter()
        .filter(|r| r["t"] >= from)
        .collect();
    let n = probes.len() as f64;
    let pressure_drop = probes.iter().map(|r| r["front"] - r["back"]).sum::<f64>() / n;
    let samples = (0..).take_while(|k| probes[0].contains_key(&format!("wake[{k}]")));
    let wake: Vec<f64> = samples
        .map(|k| probes.iter().map(|r| r[&format!("wake[{k}]")]).sum::<f64>() / n)
        .collect();
    Measured {
        drag: s.mean[0],
        lift: s.mean[1],
        pressure_drop,
        recirculation: recirculation_length(&wake),
    }
}

#[test]
fn the_recirculation_length_is_read_where_the_centreline_flow_turns() {
    // reversed flow up to a quarter of the way, then forward: x_r − 0.25 = 0.05
    let mean: Vec<f64> = (0..101).map(|k| k as f64 * 0.002 - 0.05).collect();
    assert!((recirculation_length(&mean).unwrap() - 0.05).abs() < 1e-12);
    assert_eq!(recirculation_length(&[0.1, 0.2, 0.3]), None);
}

/// The bounds the benchmark is held to (Schäfer & Turek's intervals' midpoints): `drag`,
/// `pressure_drop` and `recirculation` as fractions of them, `lift` in units of c_L off the
/// edge of its interval.
struct Bounds {
    drag: f64,
    pressure_drop: f64,
    recirculation: f64,
    lift: f64,
}

/// DFG 2D-1 at the scene's D/Δx = 20 to `end`, averaged over `t ≥ from`, against `bounds`.
fn dfg_2d1(end: f64, from: f64, bounds: Bounds) {
    let (dir, _) = common::run_on_threads(&scene("cylinder_dfg_2d1.ron", end), 2);
    let m = measure(dir.path(), from);
    println!("DFG 2D-1, D/dx = 20, t in [{from}, {end}]: {m:?}");
    let off = |x: f64, reference| x / midpoint(reference) - 1.0;
    assert!(
        off(m.drag, cylinder::DRAG_2D1).abs() < bounds.drag,
        "c_D {}",
        m.drag
    );
    assert!(
        off(m.pressure_drop, cylinder::PRESSURE_DROP_2D1).abs() < bounds.pressure_drop,
        "Δp {}",
        m.pressure_drop
    );
    let l = m
        .recirculation
        .expect("no reversed flow behind the cylinder");
    assert!(
        off(l, cylinder::RECIRCULATION_2D1).abs() < bounds.recirculation,
        "L_a {l}"
    );
    let (lo, hi) = cylinder::LIFT_2D1;
    let lift_off = (lo - m.lift).max(m.lift - hi).max(0.0);
    assert!(lift_off < bounds.lift, "c_L {}", m.lift);
}

/// DFG 2D-1 at the scene's D/Δx = 20 (38,600 particles, the fluid shifted) to t = 6 s,
/// averaged over its last second (the loads every 10 steps, as the scene writes them: their
/// noise is acoustic). The wake is still growing then; measured over t = 5–6 s: c_D 5.563
/// (−0.3 % of the reference's midpoint 5.58), Δp 0.1198 Pa (+2.0 % of 0.1174), L_a 0.0809 m
/// (−4.5 % of 0.0847), c_L −0.003 (its means over single seconds range over ±0.03). The
/// long tier's test below runs on to the steady wake. About 750 CPU-s on two threads.
#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): DFG 2D-1 at D/Δx = 20 to 6 s, about 6 minutes"]
fn dfg_2d1_drag_pressure_drop_and_wake_against_schafer_and_turek() {
    let bounds = Bounds {
        drag: 0.01,
        pressure_drop: 0.04,
        recirculation: 0.07,
        lift: 0.03,
    };
    dfg_2d1(6.0, 5.0, bounds);
}

/// The long tier: DFG 2D-1 once its wake is steady.
mod long {
    use super::{Bounds, dfg_2d1};

    /// DFG 2D-1 at D/Δx = 20 to t = 14 s, averaged over t = 10–14 s, held to what the
    /// benchmark asks (c_D within 1 % and L_a within 3 % of the intervals' midpoints, c_L
    /// within 0.005 of its interval). Measured: c_D 5.585 (+0.09 %), Δp 0.1174 Pa (−0.02 %),
    /// L_a 0.0843 m (−0.48 %), c_L 0.0151 (0.0041 above 0.0110). 2,190 CPU-s on one thread.
    #[test]
    #[ignore = "long tier (cargo test --release -p dualsph-validation --test validation -- --ignored long::): DFG 2D-1 at D/Δx = 20 to 14 s, about 25 minutes on two threads"]
    fn dfg_2d1_meets_the_benchmark_once_the_wake_is_steady() {
        let bounds = Bounds {
            drag: 0.01,
            pressure_drop: 0.02,
            recirculation: 0.03,
            lift: 0.005,
        };
        dfg_2d1(14.0, 10.0, bounds);
    }
}
