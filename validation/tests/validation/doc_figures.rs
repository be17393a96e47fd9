//! Figures the docs quote from deterministic runs — step counts and neighbour-list builds — are
//! the runs': each scene is stepped in this process to the time the doc names, and the doc's
//! paragraph or table row is asserted to quote the count the run gives (the runs are bitwise
//! reproducible on any thread count, `tests/e2e/determinism.rs`). A change of arithmetic fails
//! here until the doc is updated in the same commit.

use crate::common::{assert_doc_quotes, thousands};
use dualsph::core::neighbours::Neighbours;
use dualsph::prelude::*;
use dualsph::run_loop::run_to_end;
use dualsph::scene::Scene;
use std::path::Path;

/// Runs `scenes/FILE` (to `end_time` when given) with `plugins` appended to its plugin list
/// (RON), in `V`'s dimension: (steps, neighbour-list builds).
fn steps_and_builds<V: Vector>(file: &str, end_time: Option<f64>, plugins: &str) -> (u64, u64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes").join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let text = if plugins.is_empty() {
        text
    } else {
        let at = text.find("plugins: [").expect("a plugin list") + "plugins: [".len();
        format!("{}{plugins}, {}", &text[..at], &text[at..])
    };
    let mut scene = Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap();
    if let Some(t) = end_time {
        scene.end_time = t;
    }
    let mut sim = dualsph::build_sim::<V>(&scene).unwrap();
    sim.initialize().unwrap();
    run_to_end(&mut sim, &mut []).unwrap();
    let builds = sim.world.resource::<Neighbours<V>>().builds;
    (sim.clock().step, builds)
}

#[test]
fn the_gas_tube_rebuilds_its_lists_as_often_as_the_doc_says() {
    let (steps, builds) = steps_and_builds::<Vec1>("sod_1d_uniform.ron", None, "");
    let quoted = format!(
        "{} builds in {} steps",
        thousands(builds),
        thousands(steps)
    );
    assert_doc_quotes("docs/internals.md", "`scenes/sod_1d_uniform.ron`:", &quoted);
}

#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): four dam breaks, about 2.5 CPU-minutes"]
fn the_dam_breaks_take_the_steps_the_docs_say() {
    let doc = "docs/performance.md";
    let (walls, _) = steps_and_builds::<glam::DVec2>("dam_break_2d_walls_fine.ron", Some(0.5), "");
    let row = "| walls of particles against the specular box";
    assert_doc_quotes(doc, row, &format!("{} steps", thousands(walls)));
    let (box_, _) = steps_and_builds::<glam::DVec2>("dam_break_2d_uniform.ron", Some(0.5), "");
    assert_doc_quotes(doc, row, &format!("{} steps at its CFL", thousands(box_)));
    let (main, _) = steps_and_builds::<glam::DVec2>("dam_break_2d.ron", None, "");
    let row = "| the README's main job";
    assert_doc_quotes(doc, row, &format!("{} steps", thousands(main)));
    let (pc, _) = steps_and_builds::<glam::DVec2>("dam_break_2d.ron", Some(0.4), "");
    let (verlet, _) =
        steps_and_builds::<glam::DVec2>("dam_break_2d.ron", Some(0.4), "PositionVerlet()");
    let doc = "docs/parameters.md";
    let anchor = "with `PositionVerlet()` added to its plugins;";
    assert_eq!(pc, verlet, "the doc says both schemes take the same steps");
    assert_doc_quotes(doc, anchor, &format!("{} steps either way", thousands(pc)));
}
