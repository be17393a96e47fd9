//! The grad-h formulation (Springel & Hernquist 2002; Price 2012) beside DualSupport and
//! SingleSupport: h tied to the summation density at every step, exact conservation of its
//! pair sums on a cloud whose h varies by a factor of 8, and the Sod tube against the exact
//! Riemann solution.

use crate::common::*;
use dualsph::plugins::*;
use dualsph::prelude::*;
use dualsph_validation::report::{ReportOptions, sod};
use glam::{DVec2, DVec3};

/// The rates' imbalances of a grad-h cloud with pressure and artificial viscosity.
fn cloud_imbalances<V: Vector>(side: usize) -> (Real, Real, Real) {
    let particles = cloud::<V>(side, 1.5, 12.0, 42);
    let av = ArtificialViscosity {
        alpha: 1.0,
        beta: 2.0,
        eta_factor: 0.1,
        materials: Vec::new(),
        dissipation: true,
    };
    let h = SmoothingLengthUpdate {
        every: 1,
        n: 2.0,
        max_ratio: None,
        isotropy: None,
    };
    let plugins: [&dyn PluginConfig; 5] = [
        &SummationDensity {},
        &IdealGas { gamma: 1.4 },
        &PressureForce {},
        &av,
        &h,
    ];
    let mut sim = sim_with::<V>(&particles, Formulation::GradH, &plugins);
    imbalances(&rates(&mut sim))
}

#[test]
fn grad_h_pair_sums_conserve_momentum_angular_momentum_and_energy_2d_3d() {
    for (dim, (p, l, e)) in [
        (2, cloud_imbalances::<DVec2>(24)),
        (3, cloud_imbalances::<DVec3>(9)),
    ] {
        println!("{dim}-D grad-h: momentum {p:.2e}, angular {l:.2e}, energy {e:.2e}");
        // the same bounds as the dual-support sweep's (tests/e2e/conservation.rs)
        assert!(p <= 1e-12, "{dim}-D momentum imbalance {p:e}");
        assert!(l <= 1e-12, "{dim}-D angular momentum imbalance {l:e}");
        assert!(e <= 1e-12, "{dim}-D energy imbalance {e:e}");
    }
}

#[test]
fn grad_h_runs_the_sod_tube_with_h_tied_to_its_density_and_conserving() {
    let opts = report_options(1.0, None);
    let cases = opts
        .run_graded(
            &sod::cases(&opts).unwrap(),
            &ReportOptions::every_ten_steps(),
            sod::grade,
        )
        .unwrap();
    for c in &cases {
        let d = &c.run.diagnostics;
        println!(
            "{}: L1 {:?}, ΔE/E {:e}, {} steps, {:.2} CPU-s",
            c.run.label,
            c.l1,
            (d.last().unwrap().e_tot - d[0].e_tot) / d[0].e_tot,
            c.run.steps,
            c.run.cpu_seconds
        );
    }
    let (dual, grad_h) = (&cases[0], &cases[2]);
    assert_eq!(grad_h.run.label, "grad-h, variable h");
    assert!((grad_h.run.final_diagnostics().t - 0.2).abs() < 1e-9);
    // largest |h/(η m/ρ) − 1| over the particles at the end (η = 2, the scene's n; 1-D)
    let off_density = |c: &sod::SodCase| {
        let rows = c.run.last.rows();
        rows.map(|p| (p.h() / (2.0 * p.mass() / p.rho()) - 1.0).abs())
            .fold(0.0, f64::max)
    };
    // h = η (m/ρ)^{1/d} with the density summed at that h, on every particle at the end
    // (the solve stops at a density residual of 1e-10)
    let worst = off_density(grad_h);
    println!("grad-h: largest |h/(η m/ρ) − 1| = {worst:e}");
    assert!(worst <= 1e-9, "h off its density by {worst:e}");
    // DualSupport applies Eq. 6.1 to the density of the step before: not tied
    let dual_off = off_density(dual);
    println!("DualSupport: largest |h/(η m/ρ) − 1| = {dual_off:e}");
    assert!(dual_off > 1e-6, "DualSupport's h: {dual_off:e}");
    // as accurate as DualSupport within 10 % on every quantity (measured: ρ 0.00342 vs
    // 0.00350, u 0.0155 vs 0.0165, p 0.00452 vs 0.00434, e 0.0167 vs 0.0182)
    for k in 0..4 {
        assert!(
            grad_h.l1[k] <= 1.1 * dual.l1[k],
            "L1[{k}] grad-h {} vs DualSupport {}",
            grad_h.l1[k],
            dual.l1[k]
        );
    }
    assert!(grad_h.l1[0] <= 0.0036, "density L1 {}", grad_h.l1[0]);
    // exact conservation for its own h: momentum and, with the work-consistent update, energy
    let d = &grad_h.run.diagnostics;
    let de = (d.last().unwrap().e_tot - d[0].e_tot).abs() / d[0].e_tot;
    assert!(de <= 5e-14, "grad-h ΔE/E {de:e}");
    let p = d.last().unwrap().momentum[0].abs() / d.last().unwrap().momentum_scale;
    assert!(p <= 1e-14, "grad-h momentum {p:e}");
}

#[test]
fn grad_h_is_bitwise_the_same_on_one_and_two_threads() {
    let opts = report_options(1.0, None);
    let spec = &sod::cases(&opts).unwrap()[2];
    let rec = dualsph_validation::report::Recording::default();
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| opts.run(spec, &rec).unwrap())
    };
    let (one, two) = (on(1), on(2));
    assert!(one.steps > 1000 && one.steps == two.steps);
    let bits = |r: &dualsph_validation::report::CaseRun| {
        r.last
            .rows()
            .flat_map(|p| [p.pos()[0], p.vel()[0], p.rho(), p.h(), p.e()])
            .map(f64::to_bits)
            .collect::<Vec<_>>()
    };
    assert!(
        bits(&one) == bits(&two),
        "grad-h differs between 1 and 2 threads"
    );
}
