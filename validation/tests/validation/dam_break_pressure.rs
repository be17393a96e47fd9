//! The pressure on the far wall in a dam break (`scenes/dam_break_buchner_2d.ron`, H/Δx = 40)
//! against Buchner's (2002) sensor P1, with the δ-SPH results of Marrone et al. (2011) on the
//! same sensor and measure for scale; the measure is the report's
//! (`dualsph_validation::report::walls::wall_pressure`).

use crate::common;

use dualsph::probes::read_probes;
use dualsph::scene::Scene;
use dualsph_validation::report::walls::refinement::buchner_end_time;
use dualsph_validation::report::walls::wall_pressure::{
    BOUNDS, TRIXI_BOUND, grade, sensor, trixi_sensor,
};
use std::path::Path;

/// Over the whole record (t* 2.6–7.0: the first impact, the run-up's plateau and the second
/// impact of the plunging jet) the sensor is within 0.2 of the experiment in mean |Δp*|
/// (measured 0.172); over the first impact (t* 2.6–3.03) within 0.3 (measured 0.230), where
/// Marrone et al.'s δ-SPH is 0.094 at the same H/Δx and 0.053 at twice it: this model rises
/// to the plateau more slowly. The sensor first wets within 0.1 of the experiment's t*
/// (2.506 against 2.491). Measured as TrixiParticles.jl measures its sensor (the scene's
/// `P1_sensor`, t* 2–6.5) the mean |Δp*| is below 0.16 (measured 0.148; TrixiParticles'
/// own WCSPH 0.104), most of it from the late second impact. The run goes on to t* = 8, the
/// end of the walls report's stability cases, and stays water there: no particle's density
/// more than 10 % from ρ0 (measured 0.070: the water cavitates at 0 Pa).
#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): 2 s of dam break"]
fn the_wall_pressure_follows_the_experiment() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/dam_break_buchner_2d.ron");
    let mut scene = Scene::load(&path, &dualsph::default_registry()).unwrap();
    scene.end_time = buchner_end_time();
    let (dir, summary) = common::run_on_threads(&scene, 2);
    assert!(
        summary.t >= scene.end_time * (1.0 - 1e-9),
        "stopped at t = {}",
        summary.t
    );
    let rows = common::particle_rows(&dir.path().join("diagnostics.csv"));
    let rho_var = rows.iter().map(|r| r["rho_var_max"]).fold(0.0, f64::max);
    println!("t* = 8 reached; max |ρ/ρ0 − 1| = {rho_var:.3}");
    assert!(rho_var < 0.1, "max |ρ/ρ0 − 1| = {rho_var}");
    let table = read_probes(dir.path()).unwrap();
    let trixi = trixi_sensor(&table).expect("the scene's P1_sensor");
    let g = grade(sensor(&table), Some(&trixi));
    println!(
        "mean |Δp*|: t* 2.6-7.0 {:.3} ({} points); first impact {:.3} ({} points), Marrone \
         et al. {:.3} (H/40), {:.3} (H/80); wet at t* {:.3} (experiment {:.3}); \
         TrixiParticles' measure {:.3} ({} points)",
        g.whole.0,
        g.whole.1,
        g.first.0,
        g.first.1,
        g.marrone.0,
        g.marrone.1,
        g.wet.0,
        g.wet.1,
        g.trixi.0,
        g.trixi.1
    );
    assert!(g.whole.0 < BOUNDS.0, "t* 2.6-7.0: {}", g.whole.0);
    assert!(g.first.0 < BOUNDS.1, "first impact: {}", g.first.0);
    assert!((g.wet.0 - g.wet.1).abs() < BOUNDS.2, "{:?}", g.wet);
    assert!(
        g.trixi.0 < TRIXI_BOUND,
        "TrixiParticles' measure: {}",
        g.trixi.0
    );
}
