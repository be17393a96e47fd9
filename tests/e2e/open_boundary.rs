//! Open boundaries with buffer zones (`scenes/channel_open_2d.ron`: a plane channel between
//! walls of particles, a parabolic inflow on the left, an outflow at pressure 0 on the right):
//! the fluid's mass and momentum balance closes to round-off at every step with the columns
//! the boundaries add to `diagnostics.csv`; the run is bitwise the same on 1 and 2 threads and
//! across a resume; in the second tier, the outlet's velocity profile against Poiseuille's.

use crate::common;

use crate::common::channel::{balance, off_poiseuille, scene};
use dualsph::checkpoint::checkpoint_file_name;

/// Two seconds (about 380 steps): particles enter and leave; every step closes the balance.
/// Measured: momentum residual 2e-15 of M ū, mass 1e-16 of M; without the buffers' impulse
/// the residual is 1e-2 of M ū.
#[test]
fn the_fluid_balance_closes_at_every_step_through_open_boundaries() {
    let s = scene(2.0, "diagnostics_every: 1, snapshot_every: 0");
    let (dir, summary) = common::run_on_threads(&s, 1);
    let d = common::diagnostics(dir.path());
    let last = d["dt"].len() - 1;
    assert!(summary.steps > 300, "{} steps", summary.steps);
    // particles crossed both ways
    assert!(
        d["mass_in[inflow]"][last] > 0.5,
        "{}",
        d["mass_in[inflow]"][last]
    );
    assert!(
        d["mass_out[outflow]"][last] > 0.5,
        "{}",
        d["mass_out[outflow]"][last]
    );
    // the particles the buffers create and delete wait for the lists' own rebuilds
    // (plugins/inout/src/open/owed.rs): measured 42 builds in 391 steps; applied at once,
    // every step on which one crosses rebuilds them (89)
    eprintln!(
        "open channel: {} list builds in {} steps, {} added, {} removed",
        summary.list_builds, summary.steps, summary.added, summary.removed
    );
    assert!(
        summary.list_builds * 7 < summary.steps,
        "{} builds in {} steps",
        summary.list_builds,
        summary.steps
    );
    let (p, m, without_j) = balance(&d);
    eprintln!(
        "open channel balance: momentum {p:.2e} of M u, mass {m:.2e} of M; {without_j:.2e} without j"
    );
    assert!(p < 1e-12, "momentum residual {p:e} of M u");
    assert!(m < 1e-13, "mass residual {m:e} of M");
    assert!(
        without_j > 1e3 * p.max(1e-16),
        "the impulse is needed: {without_j:e}"
    );
    // bitwise on two threads
    let (dir2, _) = common::run_on_threads(&s, 2);
    for f in ["diagnostics.csv", "final.csv"] {
        let (a, b) = (dir.path().join(f), dir2.path().join(f));
        assert!(
            common::read(&a) == common::read(&b),
            "{f} differs on 2 threads"
        );
    }
}

/// A resumed run writes the bytes of an uninterrupted one: the buffers' particles, their
/// state and the boundaries' ledger are in the checkpoint.
#[test]
fn a_channel_with_open_boundaries_resumes_bitwise() {
    let s = scene(1.0, "diagnostics_every: 10, snapshot_every: 0");
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let whole = common::run(&s, &a, 100, None);
    assert!(whole.steps > 150, "{}", whole.steps);
    std::fs::create_dir_all(&b).unwrap();
    for e in std::fs::read_dir(&a).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), b.join(e.file_name())).unwrap();
    }
    std::fs::remove_file(b.join("final.csv")).unwrap();
    for e in std::fs::read_dir(&b).unwrap() {
        let p = e.unwrap().path();
        if p.file_name() != Some(checkpoint_file_name(100).as_ref())
            && p.to_string_lossy().contains("checkpoint")
        {
            std::fs::remove_file(p).unwrap();
        }
    }
    let resumed = common::run(&s, &b, 100, Some(b.join(checkpoint_file_name(100))));
    assert_eq!(resumed.last, whole.last, "final diagnostics");
    for f in ["diagnostics.csv", "final.csv"] {
        let (x, y) = (a.join(f), b.join(f));
        assert!(
            common::read(&x) == common::read(&y),
            "{f} differs after the resume"
        );
    }
}

/// Six flow-through times (150 s), the velocity profile averaged over the last 25 s against
/// plane Poiseuille flow. Measured: within 0.45 % of U over x ∈ [0.1, 0.35) (upstream of the
/// outlet plane at 0.5), the bound 0.6 %; within 0.84 % over the last 0.1 m before the outlet
/// plane (1.0 % in the rows next to the walls of the last 0.05 m), the bound 1 %. (With the
/// outflow's pressure held instead of non-reflecting the channel rings at its quarter-wave
/// period, and the profiles are 1.6 % and 4.0 % off; relaxed over 10 s instead of 40 s, 0.3 %
/// and 6.5 %.)
#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): 150 s of an open channel, about 2 minutes"]
fn the_open_channel_keeps_poiseuilles_profile_upstream_of_the_outlet() {
    let s = scene(150.0, "diagnostics_every: 1000, snapshot_dt: 2.5");
    let (dir, summary) = common::run_on_threads(&s, 2);
    assert!(summary.last.t >= 150.0 - 1e-9);
    let interior = off_poiseuille(dir.path(), 125.0, (0.1, 0.35));
    let outlet = off_poiseuille(dir.path(), 125.0, (0.4, 0.5));
    eprintln!("off Poiseuille: interior {interior:.4} of U, last 0.1 m {outlet:.4}");
    assert!(
        interior < 0.006,
        "the profile is {interior:.4} of U off Poiseuille's"
    );
    assert!(
        outlet < 0.01,
        "by the outlet, {outlet:.4} of U off Poiseuille's"
    );
}
