//! Criterion bench of the support/dual-support pair sweep on the uniform 2-D dam-break column
//! (12,800 particles, Δx = 0.0125, h = 2Δx) with pressure + artificial viscosity, for 1 and 2
//! threads. Besides criterion's wall-clock statistics it prints pair interactions per
//! CPU-second (user + system time of the process from /proc/self/stat over a fixed loop).

use criterion::{Criterion, criterion_group, criterion_main};
use dualsph::core::neighbours::Neighbours;
use dualsph::core::sim::{Domain, KernelRes, SimConfig, TimeStepping};
use dualsph::core::sweep::{PairTerms, SweepBuffers, evaluate};
use dualsph::plugins::*;
use dualsph::prelude::*;
use glam::DVec2;
use std::time::Instant;

fn column() -> Sim<DVec2> {
    let dx = 0.0125;
    let mut particles = Vec::new();
    for b in 0..160 {
        for a in 0..80 {
            let off = if b % 2 == 0 { 0.25 } else { 0.75 };
            particles.push(ParticleInit {
                pos: DVec2::new((a as f64 + off) * dx, (b as f64 + 0.5) * dx),
                vel: DVec2::new(0.01 * (a as f64).sin(), 0.0),
                mass: 1000.0 * dx * dx,
                density: 1000.0 * (1.0 + 1e-4 * (b as f64)),
                h: 2.0 * dx,
                internal_energy: 0.0,
            });
        }
    }
    let mut sim = Sim::<DVec2>::new(SimConfig {
        kernel: KernelKind::CubicSpline,
        formulation: Formulation::DualSupport,
        domain: Domain {
            min: DVec2::ZERO,
            max: DVec2::new(4.0, 3.0),
        },
        skin: 0.0,
        time_stepping: TimeStepping::Fixed(1e-5),
    });
    sim.spawn_particles(&particles);
    let plugins: [&dyn PluginConfig; 4] = [
        &ContinuityDensity {
            form: ContinuityForm::Pairwise,
        },
        &TaitEos {
            rho0: 1000.0,
            gamma: 7.0,
            c0: Some(100.0),
            p0: None,
        },
        &PressureForce {},
        &ArtificialViscosity {
            alpha: 1.0,
            beta: 1.0,
            eta_factor: 0.1,
        },
    ];
    for p in plugins {
        p.build_into(&mut sim).unwrap();
    }
    sim.initialize().unwrap();
    sim
}

fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit(')')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect();
    let ticks = |k: usize| {
        fields
            .get(k)
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

fn bench_sweep(c: &mut Criterion) {
    let sim = column();
    let w = &sim.world;
    let (fields, nb, terms, kernel) = (
        w.resource::<Fields<DVec2>>(),
        w.resource::<Neighbours<DVec2>>(),
        w.resource::<PairTerms<DVec2>>(),
        w.resource::<KernelRes>(),
    );
    let ctx = SweepCtx {
        fields,
        neighbours: nb,
        kernel: &kernel.0,
        formulation: Formulation::DualSupport,
    };
    let pairs = nb.support.indices.len() as f64;
    let mut group = c.benchmark_group("pair_sweep_dam_column_12800");
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut buf = SweepBuffers::<DVec2>::default();
        // CPU-time throughput over a fixed loop
        let (cpu0, wall0) = (cpu_seconds(), Instant::now());
        let reps = 200;
        pool.install(|| {
            for _ in 0..reps {
                evaluate(&ctx, &terms.terms, &mut buf);
            }
        });
        let (cpu, wall) = (cpu_seconds() - cpu0, wall0.elapsed().as_secs_f64());
        println!(
            "pair sweep, {threads} thread(s): {:.0} pairs, {:.3e} pair interactions per CPU-second, {:.3e} per wall-second",
            pairs,
            pairs * reps as f64 / cpu.max(1e-9),
            pairs * reps as f64 / wall
        );
        group.throughput(criterion::Throughput::Elements(pairs as u64));
        group.bench_function(format!("{threads}_threads"), |b| {
            b.iter(|| pool.install(|| evaluate(&ctx, &terms.terms, &mut buf)))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = bench_sweep
}
criterion_main!(benches);
