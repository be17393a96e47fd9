//! A scene's result does not depend on the order of its plugin list: `DensityDiffusion`, a
//! term of the force sweep, gives the same plan and bitwise the same state wherever it is
//! listed, and a scene without what it needs is refused whatever the order.

use dualsph::core::glam::DVec2;
use dualsph::scene::Scene;
use dualsph::sweep::SimSweeps;
use dualsph::{SimDiagnostics, build_sim};
use std::path::Path;

fn scene(text: &str) -> Result<Scene, String> {
    Scene::from_str(text, Path::new("order.ron"), &dualsph::default_registry())
        .map_err(|e| e.to_string())
}

/// `scenes/hard/drop_stretched.ron` with `plugins` as its plugin list.
fn with_plugins(plugins: &[&str]) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hard/drop_stretched.ron");
    let text = std::fs::read_to_string(path).unwrap();
    let a = text.find("    plugins: [").unwrap();
    let b = a + text[a..].find("    ],").unwrap() + "    ],".len();
    let list = format!("    plugins: [{}],", plugins.join(", "));
    scene(&format!("{}{list}{}", &text[..a], &text[b..])).unwrap()
}

/// The scene with `plugins`: its plan (systems, then the pair terms sorted) and state after
/// 30 steps.
fn run(plugins: &[&str]) -> (Vec<String>, Vec<u64>) {
    let mut sim = build_sim::<DVec2>(&with_plugins(plugins)).unwrap();
    let p = sim.plan();
    // each term by name (terms that run fused are listed joined by " + ")
    let mut terms: Vec<String> = sim
        .pair_terms()
        .iter()
        .flat_map(|t| {
            let (sweep, names) = t.split_once(": ").unwrap();
            names.split(" + ").map(move |n| format!("{sweep}: {n}"))
        })
        .collect();
    terms.sort();
    let plan = p
        .systems
        .iter()
        .map(|(_, l, _)| l.clone())
        .chain(terms)
        .collect();
    sim.initialize().unwrap();
    for _ in 0..30 {
        sim.step().unwrap();
    }
    let d = sim.diagnostics();
    let bits = [
        d.e_kin,
        d.e_int,
        d.momentum[0],
        d.momentum[1],
        d.max_density_variation,
    ];
    (plan, bits.map(f64::to_bits).to_vec())
}

const PLUGINS: [&str; 7] = [
    "KernelCorrection()",
    "ContinuityDensity(form: VelocityDivergence)",
    "TaitEos(rho0: 1000.0, gamma: 7.0, p0: 285.714e6)",
    "PressureForce()",
    "NewtonianViscosity(mu: 0.5)",
    "SmoothingLengthUpdate(every: 50, n: 2.6, isotropy: (min: 0.99, max_growth: 4.0))",
    "DensityDiffusion(delta: 0.1)",
];

#[test]
fn density_diffusion_gives_the_same_state_wherever_it_is_listed() {
    let (plan, last) = run(&PLUGINS);
    let mut first = PLUGINS.to_vec();
    first.rotate_right(1); // DensityDiffusion first
    let (plan_first, state_first) = run(&first);
    assert_eq!(plan, plan_first);
    assert_eq!(last, state_first, "bitwise the same state");
    assert!(
        plan.iter()
            .any(|l| l.starts_with("pair_sweep: density_diffusion")),
        "{plan:?}"
    );
    let at = |name: &str| plan.iter().position(|l| l.starts_with(name)).unwrap();
    assert!(at("velocity_gradient") < at("pair_sweep"), "{plan:?}");
}

#[test]
fn what_density_diffusion_needs_is_checked_whatever_the_order() {
    // without continuity, without an EOS
    for (missing, needs) in [(&[1][..], "ContinuityDensity"), (&[2], "equation of state")] {
        let mut plugins: Vec<&str> = PLUGINS
            .iter()
            .enumerate()
            .filter(|(k, _)| !missing.contains(k))
            .map(|(_, p)| *p)
            .collect();
        plugins.rotate_right(1); // DensityDiffusion first
        let err = build_sim::<DVec2>(&with_plugins(&plugins))
            .err()
            .expect("refused")
            .to_string();
        assert!(
            err.contains("DensityDiffusion") && err.contains(needs),
            "{missing:?}: {err}"
        );
    }
}

/// A caller's own system added with `build_sim_with` (here the pair-balance probe) runs after
/// the force sweep: the probe sees the sweep's accelerations — of a SingleSupport run, whose
/// pair forces do not balance, a clearly non-zero imbalance — and a DualSupport run balances
/// to round-off.
#[test]
fn a_callers_system_runs_after_the_force_sweep() {
    use dualsph::diagnostics::{PairBalance, track_pair_balance};
    let balance = |formulation: &str| {
        let mut s = with_plugins(&[
            "ContinuityDensity(form: Pairwise)",
            "TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0)",
            "PressureForce()",
            "ArtificialViscosity(alpha: 0.1, beta: 0.0)",
            "SmoothingLengthUpdate(every: 10, n: 2.0)",
        ]);
        s.formulation = match formulation {
            "single" => dualsph::scene::Formulation::SingleSupport,
            _ => dualsph::scene::Formulation::DualSupport,
        };
        let mut sim = dualsph::build_sim_with::<DVec2>(&s, |sim| {
            track_pair_balance(sim);
            Ok(())
        })
        .unwrap();
        for _ in 0..5 {
            sim.step().unwrap();
        }
        *sim.world.resource::<PairBalance>()
    };
    let (dual, single) = (balance("dual"), balance("single"));
    println!("pair balance: DualSupport {dual:?}, SingleSupport {single:?}");
    assert!(single.force > 1e-6, "the probe did not run: {single:?}");
    assert!(dual.force < 1e-12 && dual.force > 0.0, "{dual:?}");
}
