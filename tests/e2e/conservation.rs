//! Exact conservation of the dual-support sweep (§5 of Ren, Dai, Zhuang & Rabczuk,
//! *Dual-support Smoothed Particle Hydrodynamics*, preprint; RenDSSPH in docs/references.md),
//! measured on the instantaneous rates of random clouds whose support radii vary by a factor of
//! 8 between neighbours.

use crate::common::*;
use dualsph::plugins::*;
use dualsph::prelude::*;
use glam::{DVec2, DVec3};

fn pressure_av_heat_case<V: Vector>(f: Formulation, side: usize) -> (Real, Real, Real) {
    imbalances(&pressure_av_heat_rates::<V>(f, side))
}

fn pressure_av_heat_rates<V: Vector>(f: Formulation, side: usize) -> Vec<(Real, V, V, V, Real)> {
    let particles = cloud::<V>(side, 1.5, 12.0, 42);
    let (eos, pf, av, heat, cont) = (
        tait(),
        PressureForce {},
        ArtificialViscosity {
            alpha: 1.0,
            beta: 2.0,
            eta_factor: 0.1,
            materials: Vec::new(),
            dissipation: true,
        },
        HeatConduction {
            conductivity: 0.7,
            heat_capacity: 1.0,
        },
        ContinuityDensity {
            form: ContinuityForm::Pairwise,
        },
    );
    let mut sim = sim_with::<V>(&particles, f, &[&cont, &eos, &pf, &av, &heat]);
    rates(&mut sim)
}

#[test]
fn dual_support_conserves_momentum_angular_momentum_and_energy_2d_3d() {
    for (dim, (p, l, e)) in [
        (
            2,
            pressure_av_heat_case::<DVec2>(Formulation::DualSupport, 24),
        ),
        (
            3,
            pressure_av_heat_case::<DVec3>(Formulation::DualSupport, 9),
        ),
    ] {
        println!("{dim}-D DualSupport: momentum {p:.2e}, angular {l:.2e}, energy {e:.2e}");
        assert!(p <= 1e-12, "{dim}-D momentum imbalance {p:e}");
        assert!(l <= 1e-12, "{dim}-D angular momentum imbalance {l:e}");
        assert!(e <= 1e-12, "{dim}-D energy imbalance {e:e}");
    }
}

#[test]
fn single_support_violates_conservation_by_orders_of_magnitude() {
    for (dim, (p, _l, e)) in [
        (
            2,
            pressure_av_heat_case::<DVec2>(Formulation::SingleSupport, 24),
        ),
        (
            3,
            pressure_av_heat_case::<DVec3>(Formulation::SingleSupport, 9),
        ),
    ] {
        println!("{dim}-D SingleSupport: momentum {p:.2e}, energy {e:.2e}");
        assert!(
            p > 1e-6,
            "{dim}-D SingleSupport momentum imbalance only {p:e}"
        );
        assert!(
            e > 1e-6,
            "{dim}-D SingleSupport energy imbalance only {e:e}"
        );
    }
}

#[test]
fn averaged_kernel_conserves_momentum_but_is_a_different_operator() {
    let avg = pressure_av_heat_rates::<DVec2>(Formulation::AveragedKernel, 20);
    let (p, _, _) = imbalances(&avg);
    assert!(p <= 1e-12, "averaged kernel momentum imbalance {p:e}");
    // A different operator: on the same cloud (support radii varying 8 : 1 between neighbours)
    // its rates differ from the dual-support ones by far more than round-off.
    let ds = pressure_av_heat_rates::<DVec2>(Formulation::DualSupport, 20);
    let scale_a = ds.iter().map(|r| r.3.length()).fold(0.0, Real::max);
    let scale_e = ds.iter().map(|r| r.4.abs()).fold(0.0, Real::max);
    let pairs = || ds.iter().zip(&avg);
    let da = pairs()
        .map(|(a, b)| (a.3 - b.3).length())
        .fold(0.0, Real::max)
        / scale_a;
    let de = pairs().map(|(a, b)| (a.4 - b.4).abs()).fold(0.0, Real::max) / scale_e;
    println!(
        "AveragedKernel vs DualSupport: max |Δa|/max|a| = {da:.3e}, max |Δε̇|/max|ε̇| = {de:.3e}"
    );
    // Measured on this cloud (fixed seed, bitwise reproducible): 4.02e-2 and 4.41e-2; at equal
    // h the two agree to 2.6e-16 (equal_h_formulations_agree_to_round_off). The bounds sit 25 %
    // and 32 % below the measured values: a change of the cloud or the plugin constants may
    // move them by that much without the operators becoming alike.
    assert!(da >= 0.03, "accelerations differ by only {da:e}");
    assert!(de >= 0.03, "energy rates differ by only {de:e}");
}

fn stress_case<V: Vector>(f: Formulation, side: usize) -> (Real, Real, Real) {
    let particles = cloud::<V>(side, 1.5, 12.0, 7);
    let (eos, pf, visc, corr, cont) = (
        tait(),
        PressureForce {},
        NewtonianViscosity {
            mu: 0.5,
            lambda: 0.0,
        },
        KernelCorrection {},
        ContinuityDensity {
            form: ContinuityForm::VelocityDivergence,
        },
    );
    let mut sim = sim_with::<V>(&particles, f, &[&corr, &cont, &eos, &pf, &visc]);
    imbalances(&rates(&mut sim))
}

#[test]
fn newtonian_stress_with_gradient_correction_conserves_angular_momentum() {
    for (dim, (p, l, e)) in [
        (2, stress_case::<DVec2>(Formulation::DualSupport, 20)),
        (3, stress_case::<DVec3>(Formulation::DualSupport, 8)),
    ] {
        println!(
            "{dim}-D Newtonian + correction: momentum {p:.2e}, angular {l:.2e}, energy {e:.2e}"
        );
        assert!(p <= 1e-12, "momentum {p:e}");
        assert!(l <= 1e-12, "angular momentum {l:e}");
        assert!(e <= 1e-12, "energy {e:e}");
    }
    let (_, l_single, _) = stress_case::<DVec2>(Formulation::SingleSupport, 20);
    assert!(
        l_single > 1e-6,
        "SingleSupport angular momentum imbalance only {l_single:e}"
    );
}

#[test]
fn physical_viscosity_conserves_momentum_and_energy() {
    let particles = cloud::<DVec2>(20, 1.5, 12.0, 9);
    let (eos, pf, visc, cont) = (
        tait(),
        PressureForce {},
        PhysicalViscosity {
            mu: 0.3,
            eta_factor: 0.1,
            materials: Vec::new(),
        },
        ContinuityDensity {
            form: ContinuityForm::Pairwise,
        },
    );
    let mut sim = sim_with::<DVec2>(
        &particles,
        Formulation::DualSupport,
        &[&cont, &eos, &pf, &visc],
    );
    let (p, _l, e) = imbalances(&rates(&mut sim));
    assert!(p <= 1e-12 && e <= 1e-12, "momentum {p:e} energy {e:e}");
}

fn equal_h_rates(f: Formulation) -> Vec<(Real, DVec2, DVec2, DVec2, Real)> {
    let particles = cloud::<DVec2>(18, 2.6, 2.6, 5);
    let (eos, pf, av, heat, cont) = (
        tait(),
        PressureForce {},
        ArtificialViscosity {
            alpha: 1.0,
            beta: 2.0,
            eta_factor: 0.1,
            materials: Vec::new(),
            dissipation: true,
        },
        HeatConduction {
            conductivity: 0.7,
            heat_capacity: 1.0,
        },
        ContinuityDensity {
            form: ContinuityForm::Pairwise,
        },
    );
    let mut sim = sim_with::<DVec2>(&particles, f, &[&cont, &eos, &pf, &av, &heat]);
    rates(&mut sim)
}

#[test]
fn equal_h_formulations_agree_to_round_off() {
    let ds = equal_h_rates(Formulation::DualSupport);
    let scale_a = ds.iter().map(|r| r.3.length()).fold(0.0, Real::max);
    let scale_e = ds.iter().map(|r| r.4.abs()).fold(0.0, Real::max);
    for f in [
        Formulation::SingleSupport,
        Formulation::ConstantH,
        Formulation::AveragedKernel,
    ] {
        let other = equal_h_rates(f);
        let da = ds
            .iter()
            .zip(&other)
            .map(|(a, b)| (a.3 - b.3).length())
            .fold(0.0, Real::max);
        let de = ds
            .iter()
            .zip(&other)
            .map(|(a, b)| (a.4 - b.4).abs())
            .fold(0.0, Real::max);
        println!(
            "{f:?}: max |Δa|/max|a| = {:.2e}, max |Δε̇|/max|ε̇| = {:.2e}",
            da / scale_a,
            de / scale_e
        );
        assert!(
            da <= 1e-12 * scale_a,
            "{f:?} acceleration differs by {da:e} (scale {scale_a:e})"
        );
        assert!(
            de <= 1e-12 * scale_e,
            "{f:?} energy rate differs by {de:e} (scale {scale_e:e})"
        );
    }
}

#[test]
fn artificial_stress_keeps_dual_support_conservation_exact() {
    fn case<V: Vector>(side: usize, stress: bool) -> Vec<(Real, V, V, V, Real)> {
        // ρ within ±2 % of ρ0: about half the particles are under tension (p < 0)
        let particles = cloud::<V>(side, 1.5, 12.0, 7);
        let (eos, pf, cont) = (
            tait(),
            PressureForce {},
            ContinuityDensity {
                form: ContinuityForm::Pairwise,
            },
        );
        let st = ArtificialStress {
            epsilon: 0.2,
            exponent: 4,
        };
        let mut plugins: Vec<&dyn PluginConfig> = vec![&cont, &eos, &pf];
        if stress {
            plugins.push(&st);
        }
        let mut sim = sim_with::<V>(&particles, Formulation::DualSupport, &plugins);
        rates(&mut sim)
    }
    let (with, without) = (case::<DVec2>(24, true), case::<DVec2>(24, false));
    let changed = with
        .iter()
        .zip(&without)
        .filter(|(a, b)| a.3 != b.3)
        .count();
    assert!(
        changed > with.len() / 4,
        "the term acted on only {changed} particles"
    );
    for (dim, (p, l, e)) in [
        (2, imbalances(&with)),
        (3, imbalances(&case::<DVec3>(9, true))),
    ] {
        println!("{dim}-D artificial stress: momentum {p:.2e}, angular {l:.2e}, energy {e:.2e}");
        assert!(p <= 1e-12, "{dim}-D momentum imbalance {p:e}");
        assert!(l <= 1e-12, "{dim}-D angular momentum imbalance {l:e}");
        assert!(e <= 1e-12, "{dim}-D energy imbalance {e:e}");
    }
}
