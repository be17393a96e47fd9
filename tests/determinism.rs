//! Bitwise-identical results on 1 and 2 threads.

mod common;

use common::*;
use dualsph::plugins::*;
use dualsph::prelude::*;
use glam::DVec2;

fn run_steps(threads: usize) -> Vec<(Real, DVec2, DVec2, DVec2, Real)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let particles = cloud::<DVec2>(20, 1.5, 12.0, 3);
        let (eos, pf, av, heat, cont, hup) = (
            TaitEos {
                rho0: 1000.0,
                gamma: 7.0,
                c0: Some(20.0),
                p0: None,
                min_pressure: None,
            },
            PressureForce {},
            ArtificialViscosity {
                alpha: 1.0,
                beta: 2.0,
                eta_factor: 0.1,
            },
            HeatConduction {
                conductivity: 0.7,
                heat_capacity: 1.0,
            },
            ContinuityDensity {
                form: ContinuityForm::Pairwise,
            },
            SmoothingLengthUpdate {
                every: 5,
                n: 2.0,
                max_ratio: None,
            },
        );
        let mut sim = sim_with::<DVec2>(
            &particles,
            Formulation::DualSupport,
            &[&cont, &eos, &pf, &av, &heat, &hup],
        );
        for _ in 0..20 {
            sim.step().unwrap();
        }
        rates(&mut sim)
    })
}

#[test]
fn one_and_two_threads_give_bitwise_identical_states() {
    let a = run_steps(1);
    let b = run_steps(2);
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            x.1.to_array().map(f64::to_bits),
            y.1.to_array().map(f64::to_bits)
        );
        assert_eq!(
            x.2.to_array().map(f64::to_bits),
            y.2.to_array().map(f64::to_bits)
        );
        assert_eq!(
            x.3.to_array().map(f64::to_bits),
            y.3.to_array().map(f64::to_bits)
        );
        assert_eq!(x.4.to_bits(), y.4.to_bits());
    }
}
