//! The pressure on the far wall in a dam break (`scenes/dam_break_buchner_2d.ron`, H/Δx = 40)
//! against Buchner's (2002) sensor P1, with the δ-SPH results of Marrone et al. (2011) on the
//! same sensor and measure for scale (`dualsph_reference::wall_pressure`): the simulated
//! sensor (the mean of the probe line over the sensor, averaged over a box of width 0.05 in t*)
//! against the experiment by the mean absolute difference in p*.

mod common;

use dualsph::probes::read_probes;
use dualsph::scene::Scene;
use dualsph_reference::norms::interpolate;
use dualsph_reference::wall_pressure::{box_mean, buchner_p1, marrone_p1, mean_abs_difference};
use std::path::Path;

const H: f64 = 0.6;
const G: f64 = 9.81;
/// The box the simulated sensor is averaged over, in t*.
const BOX: f64 = 0.05;

/// The simulated sensor `(t*, p*)`: the mean of the probe line "P1" (a dry point reads 0).
fn sensor(dir: &Path) -> Vec<(f64, f64)> {
    let table = read_probes(dir).unwrap();
    let cols: Vec<usize> = (0..table.columns.len())
        .filter(|&c| table.columns[c].starts_with("P1["))
        .collect();
    assert_eq!(cols.len(), 7);
    (0..table.t.len())
        .map(|k| {
            let p: f64 = cols
                .iter()
                .map(|&c| table.values[k][c])
                .map(|p| if p.is_nan() { 0.0 } else { p })
                .sum::<f64>()
                / cols.len() as f64;
            (table.t[k] * (G / H).sqrt(), p / (1000.0 * G * H))
        })
        .collect()
}

/// Over the whole record (t* 2.6–7.0: the first impact, the run-up's plateau and the second
/// impact of the plunging jet) the sensor is within 0.2 of the experiment in mean |Δp*|
/// (measured 0.17); over the first impact (t* 2.6–3.03) it is within 0.3 (measured 0.245),
/// where Marrone et al.'s δ-SPH is 0.094 at the same H/Δx and 0.053 at twice it: this model
/// rises to the plateau more slowly. The first wetting of the sensor comes within 0.1 of the
/// experiment's (t* 2.48 against 2.45).
#[test]
#[ignore = "second tier (cargo test --release -- --ignored): 1.8 s of dam break"]
fn the_wall_pressure_follows_the_experiment() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/dam_break_buchner_2d.ron");
    let scene = Scene::load(&path, &dualsph::default_registry()).unwrap();
    let (dir, _) = common::run_on_threads(&scene, 2);
    let sim = sensor(dir.path());
    let model = |t| box_mean(&sim, t, BOX);
    let exp = buchner_p1();
    let (whole, n_whole) = mean_abs_difference(model, &exp, (2.6, 7.0));
    let (first, n_first) = mean_abs_difference(model, &exp, (2.6, 3.03));
    let m = marrone_p1();
    let marrone =
        |s: &[(f64, f64)]| mean_abs_difference(|t| interpolate(s, t), &m.experiment, (2.6, 3.03)).0;
    let (m40, m80) = (marrone(&m.sph_40), marrone(&m.sph_80));
    let wet = |s: &[(f64, f64)]| s.iter().find(|p| p.1 > 0.1).map(|p| p.0).unwrap();
    let (wet_sim, wet_exp) = (wet(&sim), wet(&exp));
    println!(
        "mean |Δp*|: t* 2.6-7.0 {whole:.3} ({n_whole} points); first impact {first:.3} \
         ({n_first} points), Marrone et al. {m40:.3} (H/40), {m80:.3} (H/80); \
         wet at t* {wet_sim:.3} (experiment {wet_exp:.3})"
    );
    assert!(whole < 0.2, "t* 2.6-7.0: {whole}");
    assert!(first < 0.3, "first impact: {first}");
    assert!((wet_sim - wet_exp).abs() < 0.1, "{wet_sim} vs {wet_exp}");
}
