//! Criterion benches of the three costs of a step — neighbour rebuild (with kiddo's k-d tree and
//! with the cell grid), the support/dual-support
//! pair sweep, one whole `Sim::step` — on the dam-break physics (`dualsph_validation::perf`, a
//! dev-dependency), for 2-D and 3-D columns of ~10^4 and ~10^5 particles, uniform and two-level h, on 1 and 2 threads (a
//! local rayon pool). `DUALSPH_BENCH_LARGE=1` adds ~10^6 particles.
//!
//! Besides criterion's wall-clock statistics each case prints CPU-time throughput (user +
//! system time of the process, `/proc/self/stat`, over a loop of at least 1 CPU-second):
//! * **pair interactions** = `Σ_i |H_i|`, the `(i, j ∈ H_i)` with `|r_ij| < h_i` that the sweep
//!   evaluates (all terms of the sweep for one pair count once; candidates inside the Verlet
//!   skin but outside `h_i` are skipped and not counted);
//! * **particle-steps** = particles × steps of `Sim::step` (everything the scene runs);
//! * the rebuild lines time each neighbour index (`NeighbourIndex::KdTree`, `CellGrid`; the
//!   engine's default `Auto` picks one of them) and the grid line its ratio to kiddo;
//! * the 2-thread lines also give the wall-clock speed-up over 1 thread.
//!
//! The systems' per-particle loops run on bevy's task pool, which is sized once per process
//! (like rayon's global pool) when the first simulation is built. `DUALSPH_BENCH_THREADS=N`
//! runs only N threads and sizes that pool to N; without it the bench runs 1 then 2 threads in
//! one process with the task pool at 2, so its 1-thread step lines include 2-thread ECS loops.
//! For clean figures run each count in its own process (as `docs/performance.md` does):
//! `DUALSPH_BENCH_THREADS=1 cargo bench --bench throughput`, then `=2`.
//!
//! ```sh
//! CARGO_TARGET_DIR=target cargo bench --bench throughput
//! CARGO_TARGET_DIR=target cargo bench --bench throughput -- 2d-uniform-12800
//! CARGO_TARGET_DIR=target cargo bench --bench throughput -- rebuild   # rebuild lines only
//! ```

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use dualsph::core::neighbours::{NeighbourIndex, Neighbours};
use dualsph::prelude::*;
use dualsph::sweep::SweepBuffers;
use dualsph_validation::perf::{Case, Layout, cpu_seconds, run_sweep, support_pairs};
use std::time::{Duration, Instant};

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("rayon pool")
}

/// Runs `f` until at least `min_cpu` CPU-seconds have passed; returns (reps, CPU-s, wall-s).
fn measure(min_cpu: f64, mut f: impl FnMut()) -> (usize, f64, f64) {
    let (c0, w0) = (cpu_seconds(), Instant::now());
    let mut reps = 0;
    while cpu_seconds() - c0 < min_cpu || reps < 3 {
        f();
        reps += 1;
    }
    (reps, cpu_seconds() - c0, w0.elapsed().as_secs_f64())
}

fn cases() -> Vec<Case> {
    let mut sizes = vec![12_800, 100_000];
    if std::env::var("DUALSPH_BENCH_LARGE").is_ok_and(|v| v == "1") {
        sizes.push(1_000_000);
    }
    let mut out = Vec::new();
    for n in sizes {
        for dim in [2, 3] {
            for layout in [Layout::Uniform, Layout::TwoLevel] {
                out.push(if n == 12_800 && dim == 2 && layout == Layout::Uniform {
                    Case::dam_column_2d()
                } else {
                    Case::with_particles(dim, layout, n)
                });
            }
        }
    }
    out
}

/// `cargo bench --bench throughput -- rebuild`: only the rebuild lines (the sweep and step
/// timing loops, which run outside criterion's filter, are skipped).
fn rebuild_only() -> bool {
    std::env::args().skip(1).any(|a| a == "rebuild")
}

/// The 2-thread lines report the wall-time speed-up over the 1-thread line of the same kind.
struct Speedup([f64; 4]);

impl Speedup {
    fn note(&mut self, kind: usize, threads: usize, wall_per_rep: f64) -> String {
        if threads == 1 {
            self.0[kind] = wall_per_rep;
            String::new()
        } else if self.0[kind] == 0.0 {
            String::new() // no 1-thread line in this process
        } else {
            format!(
                ", {:.2}x the 1-thread wall rate",
                self.0[kind] / wall_per_rep
            )
        }
    }
}

fn bench_dim<V: Vector>(c: &mut Criterion, case: Case) {
    let mut sim = case.sim::<V>();
    let n = sim.particle_count();
    let pairs = support_pairs(&sim) as f64;
    let name = case.name(n);
    let min_cpu = 1.0;
    let mut speedup = Speedup([0.0; 4]);

    let mut group = c.benchmark_group(name.clone());
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for threads in thread_counts() {
        let pool = pool(threads);

        // neighbour rebuild (search + CSR + transpose) with each index; the grid line also
        // gives its CPU-time ratio to the kiddo line just before it (same run, same load)
        let (pos, h, skin) = {
            let d = ParticleData::<V>::of(&sim.world).expect("particles");
            let nb = sim.world.resource::<Neighbours<V>>();
            let pos: Vec<V> = d.pos.iter().map(|x| x.0).collect();
            let h: Vec<Real> = d.h.iter().map(|x| x.0).collect();
            (pos, h, nb.skin)
        };
        let mut kd_rate = 0.0;
        for (kind, index, label) in [
            (0, NeighbourIndex::KdTree, "kiddo"),
            (3, NeighbourIndex::CellGrid, "grid "),
        ] {
            let mut nb = Neighbours::<V>::new(skin);
            nb.index = index;
            let (reps, cpu, wall) = measure(min_cpu, || pool.install(|| nb.rebuild(&pos, &h)));
            let rate = (n * reps) as f64 / cpu;
            let vs_kd = if index == NeighbourIndex::KdTree {
                kd_rate = rate;
                String::new()
            } else {
                format!(", {:.2}x kiddo", rate / kd_rate)
            };
            println!(
                "{name} rebuild {label} {threads}T: {rate:.3e} particles/CPU-s ({:.1} candidates/particle){vs_kd}{}",
                nb.support.indices.len() as f64 / n as f64,
                speedup.note(kind, threads, wall / reps as f64)
            );
            group.throughput(Throughput::Elements(n as u64));
            group.bench_function(
                BenchmarkId::new(format!("rebuild-{}", label.trim()), format!("{threads}T")),
                |b| b.iter(|| pool.install(|| nb.rebuild(&pos, &h))),
            );
        }
        if rebuild_only() {
            continue;
        }

        // pair sweep (pressure + artificial viscosity, support + dual-support)
        {
            let mut buf = SweepBuffers::default();
            let (reps, cpu, wall) = measure(min_cpu, || pool.install(|| run_sweep(&sim, &mut buf)));
            println!(
                "{name} sweep   {threads}T: {:.3e} pair interactions/CPU-s ({:.1} pairs/particle){}",
                pairs * reps as f64 / cpu,
                pairs / n as f64,
                speedup.note(1, threads, wall / reps as f64)
            );
            group.throughput(Throughput::Elements(pairs as u64));
            group.bench_function(BenchmarkId::new("sweep", format!("{threads}T")), |b| {
                b.iter(|| pool.install(|| run_sweep(&sim, &mut buf)))
            });
        }

        // one whole step
        let (reps, cpu, wall) = measure(min_cpu, || {
            pool.install(|| sim.step().expect("step"));
        });
        println!(
            "{name} step    {threads}T: {:.3e} particle-steps/CPU-s, {:.3e} pair interactions/CPU-s{}",
            (n * reps) as f64 / cpu,
            pairs * reps as f64 / cpu,
            speedup.note(2, threads, wall / reps as f64)
        );
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::new("step", format!("{threads}T")), |b| {
            b.iter(|| pool.install(|| sim.step().expect("step")))
        });
    }
    group.finish();
}

/// `DUALSPH_BENCH_THREADS=N` → `[N]`; otherwise `[1, 2]`.
fn thread_counts() -> Vec<usize> {
    match std::env::var("DUALSPH_BENCH_THREADS").map(|v| v.parse::<usize>()) {
        Ok(Ok(n)) if n >= 1 => vec![n],
        _ => vec![1, 2],
    }
}

fn benches(c: &mut Criterion) {
    // size the ECS task pool before any simulation exists (see the module docs)
    let most = thread_counts().into_iter().max().unwrap_or(1);
    pool(most).install(dualsph::core::sim::init_task_pool);
    for case in cases() {
        match case.dim {
            2 => bench_dim::<glam::DVec2>(c, case),
            _ => bench_dim::<glam::DVec3>(c, case),
        }
    }
}

criterion_group!(throughput, benches);
criterion_main!(throughput);
