//! The sweep's fused loop for the built-in terms (`PressureForce`, `ArtificialViscosity`, with
//! the continuity sum) against the general path that runs the plugins' own pair terms: bitwise
//! the same force, power and dρ/dt on every particle, for every order of the terms, in 2-D and
//! 3-D, with a strongly varying h, for three kernels (the fused loop evaluates pairs two at a
//! time); and the general path is what a scene with any other term (here heat conduction) or
//! the kernel correction uses.

mod common;

use common::*;
use dualsph::core::sweep::{Formulation, PairTerms, SweepBuffers, fused_loop_applies};
use dualsph::perf::{run_sweep, sweep_ctx};
use dualsph::plugins::*;
use dualsph::prelude::*;
use glam::{DVec2, DVec3};

fn av() -> ArtificialViscosity {
    ArtificialViscosity {
        alpha: 1.0,
        beta: 2.0,
        eta_factor: 0.1,
    }
}

/// True when `sim`'s sweep takes the fused loop.
fn fused<V: Vector>(sim: &Sim<V>) -> bool {
    fused_loop_applies(&sweep_ctx(sim), &sim.world.resource::<PairTerms<V>>().terms)
}

/// Force, power and dρ/dt of one sweep of `sim`'s state, through the fused loop when it
/// applies (`general_only = false`) or the general path.
fn sweep<V: Vector>(sim: &Sim<V>, general_only: bool) -> (Vec<V>, Vec<Real>, Vec<Real>) {
    let mut buf = SweepBuffers::<V>::default();
    buf.with_density_rate = true;
    buf.general_only = general_only;
    run_sweep(sim, &mut buf);
    (buf.force, buf.power, buf.density_rate)
}

/// Asserts the two paths agree bitwise on `sim` after a few steps (so pressures, densities
/// and velocities all vary), and that the work is not trivially zero.
fn assert_paths_agree<V: Vector>(mut sim: Sim<V>, what: &str) {
    assert!(fused(&sim), "{what}: the fused loop applies");
    for _ in 0..3 {
        sim.step().unwrap();
    }
    let (fa, pa, da) = sweep(&sim, false);
    let (fb, pb, db) = sweep(&sim, true);
    assert!(fa.iter().any(|f| f.length() > 0.0), "{what}: no force");
    for i in 0..fa.len() {
        let bits = |v: V| v.to_xyz().map(f64::to_bits);
        assert_eq!(bits(fa[i]), bits(fb[i]), "{what}: force on {i}");
        assert_eq!(pa[i].to_bits(), pb[i].to_bits(), "{what}: power of {i}");
        assert_eq!(da[i].to_bits(), db[i].to_bits(), "{what}: dρ/dt of {i}");
    }
}

fn orders() -> Vec<(&'static str, Vec<Box<dyn PluginConfig>>)> {
    let cont = || {
        Box::new(ContinuityDensity {
            form: ContinuityForm::Pairwise,
        }) as Box<dyn PluginConfig>
    };
    let e = || Box::new(tait()) as Box<dyn PluginConfig>;
    let p = || Box::new(PressureForce {}) as Box<dyn PluginConfig>;
    let v = || Box::new(av()) as Box<dyn PluginConfig>;
    vec![
        ("pressure, viscosity", vec![cont(), e(), p(), v()]),
        ("viscosity, pressure", vec![cont(), e(), v(), p()]),
        ("pressure", vec![cont(), e(), p()]),
        ("viscosity", vec![cont(), e(), v()]),
    ]
}

/// Both paths on a cloud of `side^d` particles with h varying over `[h_lo, h_hi]`, with the
/// cubic spline for every order of the terms, and with Wendland C2 and the quintic spline (whose
/// pieces are selected per lane) for the dam break's order.
fn check_every_order<V: Vector>(side: usize, h_lo: Real, h_hi: Real, seed: u64) {
    let particles = cloud::<V>(side, h_lo, h_hi, seed);
    let dual = Formulation::DualSupport;
    for (what, plugins) in orders() {
        let refs: Vec<&dyn PluginConfig> = plugins.iter().map(|b| b.as_ref()).collect();
        assert_paths_agree(sim_with::<V>(&particles, dual, &refs), what);
    }
    let (_, plugins) = orders().swap_remove(0);
    let refs: Vec<&dyn PluginConfig> = plugins.iter().map(|b| b.as_ref()).collect();
    for kind in [KernelKind::WendlandC2, KernelKind::QuinticSpline] {
        let sim = sim_with_kernel::<V>(&particles, kind, dual, &refs);
        assert_paths_agree(sim, &format!("{kind:?}"));
    }
}

#[test]
fn fused_loop_equals_the_plugins_terms_bitwise_2d() {
    check_every_order::<DVec2>(24, 1.2, 4.0, 7);
}

#[test]
fn fused_loop_equals_the_plugins_terms_bitwise_3d() {
    check_every_order::<DVec3>(9, 1.2, 3.0, 8);
}

/// Any other pair term, the kernel correction or another formulation keeps the general path.
#[test]
fn other_terms_take_the_general_path() {
    let particles = cloud::<DVec2>(8, 1.2, 3.0, 9);
    let (cont, e, p, v) = (
        ContinuityDensity {
            form: ContinuityForm::Pairwise,
        },
        tait(),
        PressureForce {},
        av(),
    );
    let heat = HeatConduction {
        conductivity: 0.7,
        heat_capacity: 1.0,
    };
    let cases: [(&str, Formulation, Vec<&dyn PluginConfig>); 3] = [
        (
            "heat conduction is not built in",
            Formulation::DualSupport,
            vec![&cont, &e, &p, &v, &heat],
        ),
        (
            "the corrected pressure force is not fused",
            Formulation::DualSupport,
            vec![&cont, &e, &KernelCorrection {}, &p, &v],
        ),
        (
            "the averaged kernel is not a dual-support sweep",
            Formulation::AveragedKernel,
            vec![&cont, &e, &p, &v],
        ),
    ];
    for (what, formulation, plugins) in cases {
        let mut sim = sim_with::<DVec2>(&particles, formulation, &plugins);
        // after a step every field the sweep reads is filled (the correction matrices too)
        sim.step().unwrap();
        assert!(!fused(&sim), "{what}");
    }
}
