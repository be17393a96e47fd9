//! Whole-step driver for profiling and throughput: runs `Sim::step` on a benchmark case
//! (see `dualsph_validation::perf`) and prints particles, pair interactions, CPU time,
//! particle-steps per CPU-second and peak RSS per particle.
//!
//! ```sh
//! cargo run --release -p dualsph-validation --example perf -- [dim] [uniform|two-level] [particles|dam] [steps] [threads]
//! cargo run --release -p dualsph-validation --example perf -- 2 uniform dam 200 1     # the reference 12,800 column
//! cargo run --release -p dualsph-validation --example perf -- 3 uniform 1000000 3 2   # memory per particle at 1e6
//! valgrind --tool=callgrind target/release/examples/perf 2 uniform dam 20 1
//! ```

use dualsph::core::neighbours::Neighbours;
use dualsph::prelude::*;
use dualsph_validation::perf::{
    Case, Layout, cpu_seconds, peak_rss_bytes, run_sweep, state_fingerprint, support_pairs,
};
use std::time::Instant;

/// The measured loop (a frame of its own: `valgrind --tool=callgrind --collect-atstart=no
/// --toggle-collect='*step_loop*'` profiles the steps without the set-up).
/// Returns the shortest wall time of one step: on a shared machine the fastest of many
/// repetitions is the best estimate of the undisturbed cost.
#[inline(never)]
fn step_loop<V: Vector>(sim: &mut Sim<V>, steps: usize) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..steps {
        let t = Instant::now();
        sim.step().expect("step");
        best = best.min(t.elapsed().as_secs_f64());
    }
    best
}

fn run<V: Vector>(case: Case, steps: usize) {
    let (c0, w0) = (cpu_seconds(), Instant::now());
    let mut sim = case.sim::<V>();
    let (setup_cpu, setup_wall) = (cpu_seconds() - c0, w0.elapsed().as_secs_f64());
    let setup_rss = peak_rss_bytes().unwrap_or(0);
    let n = sim.particle_count();
    let pairs = support_pairs(&sim);
    let builds0 = sim.world.resource::<Neighbours<V>>().builds;
    let (c1, w1) = (cpu_seconds(), Instant::now());
    let best = step_loop(&mut sim, steps);
    let builds = sim.world.resource::<Neighbours<V>>().builds - builds0;
    let (cpu, wall) = (cpu_seconds() - c1, w1.elapsed().as_secs_f64());
    let ps = (n * steps) as f64;
    println!(
        "case {} ({} particles, {pairs} pairs = {:.1}/particle), setup {setup_cpu:.2} CPU-s / {setup_wall:.2} s",
        case.name(n),
        n,
        pairs as f64 / n as f64
    );
    println!(
        "{steps} steps: {cpu:.2} CPU-s, {wall:.2} wall-s; {:.3e} particle-steps per CPU-second, {:.3e} per wall-second; {:.3e} pair interactions per CPU-second (whole step)",
        ps / cpu.max(1e-9),
        ps / wall.max(1e-9),
        (pairs * steps) as f64 / cpu.max(1e-9),
    );
    println!(
        "fastest step: {:.3} ms = {:.3e} particle-steps per second",
        best * 1e3,
        n as f64 / best
    );
    println!(
        "neighbour lists built {builds} times in the {steps} steps; {} candidates per pair at the end; skin {:.3}",
        fmt_ratio(&sim),
        sim.world.resource::<Neighbours<V>>().skin
    );
    println!("state fingerprint {:016x}", state_fingerprint(&mut sim));
    if let Some(rss) = peak_rss_bytes() {
        println!(
            "peak RSS {:.1} MiB = {:.0} bytes per particle (peak after set-up: {:.0} bytes per particle)",
            rss as f64 / 1048576.0,
            rss as f64 / n as f64,
            setup_rss as f64 / n as f64
        );
    }
    // after the RSS line: the extra sweep buffers of this measurement are not the engine's
    sweep_only(&sim, steps);
}

/// Candidate slots (inside the Verlet skin) per pair inside `h_i`, on the current lists.
fn fmt_ratio<V: Vector>(sim: &Sim<V>) -> String {
    let slots = sim.world.resource::<Neighbours<V>>().support.indices.len();
    format!("{:.2}", slots as f64 / support_pairs(sim).max(1) as f64)
}

/// The pair sweep alone (`sweep::evaluate`, what the Forces set runs), `steps` times on the
/// final state: pair interactions per CPU-second.
#[inline(never)]
fn sweep_only<V: Vector>(sim: &Sim<V>, steps: usize) {
    use dualsph::sweep::SweepBuffers;
    let mut buf = SweepBuffers::default();
    let pairs = support_pairs(sim);
    let (c0, mut best) = (cpu_seconds(), f64::INFINITY);
    for _ in 0..steps {
        let t = Instant::now();
        run_sweep(sim, &mut buf);
        best = best.min(t.elapsed().as_secs_f64());
    }
    let cpu = cpu_seconds() - c0;
    println!(
        "sweep alone ({steps} times, with continuity): {:.3e} pair interactions per CPU-second; fastest {:.3e} per second",
        (pairs * steps) as f64 / cpu.max(1e-9),
        pairs as f64 / best
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |k: usize, d: &str| args.get(k).cloned().unwrap_or_else(|| d.to_string());
    let dim: usize = arg(0, "2").parse().expect("dim");
    let layout = match arg(1, "uniform").as_str() {
        "uniform" => Layout::Uniform,
        "two-level" => Layout::TwoLevel,
        other => panic!("layout {other}: uniform | two-level"),
    };
    let size = arg(2, "dam");
    let case = if size == "dam" {
        Case::dam_column_2d()
    } else {
        Case::with_particles(dim, layout, size.parse().expect("particles"))
    };
    let steps: usize = arg(3, "100").parse().expect("steps");
    let threads: usize = arg(4, "1").parse().expect("threads");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| match case.dim {
        2 => run::<glam::DVec2>(case, steps),
        3 => run::<glam::DVec3>(case, steps),
        d => panic!("dimension {d}: 2 or 3"),
    });
}
