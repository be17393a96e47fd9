//! Figures the docs quote from deterministic runs — step counts and neighbour-list builds — are
//! the runs': each scene is stepped in this process to its end, and the doc's
//! paragraph is asserted to quote the count the run gives (the runs are bitwise
//! reproducible on any thread count, `tests/e2e/determinism.rs`). A change of arithmetic fails
//! here until the doc is updated in the same commit.

use crate::common::{assert_doc_quotes, thousands};
use dualsph::core::neighbours::Neighbours;
use dualsph::prelude::*;
use dualsph::run_loop::run_to_end;
use dualsph::scene::Scene;
use std::path::Path;

/// Runs `scenes/FILE` to its end in `V`'s dimension: (steps, neighbour-list builds).
fn steps_and_builds<V: Vector>(file: &str) -> (u64, u64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(file);
    let scene = Scene::load(&path, &dualsph::default_registry()).unwrap();
    let mut sim = dualsph::build_sim::<V>(&scene).unwrap();
    sim.initialize().unwrap();
    run_to_end(&mut sim, &mut []).unwrap();
    let builds = sim.world.resource::<Neighbours<V>>().builds;
    (sim.clock().step, builds)
}

#[test]
fn the_gas_tube_rebuilds_its_lists_as_often_as_the_doc_says() {
    let (steps, builds) = steps_and_builds::<Vec1>("sod_1d_uniform.ron");
    let quoted = format!("{} builds in {} steps", thousands(builds), thousands(steps));
    assert_doc_quotes("docs/internals.md", "`scenes/sod_1d_uniform.ron`:", &quoted);
}
