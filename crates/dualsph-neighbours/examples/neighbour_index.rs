//! Times the two neighbour indexes (kiddo k-d tree, cell grid) and the transpose on
//! dam-break-like columns (`[0,1]×[0,2]`, `[0,1]²×[0,2]`, h = 2Δx, skin 0.15; two-level: the lower
//! quarter at Δx/2), without building the whole engine.
//!
//! ```sh
//! cargo run --release -p dualsph-neighbours --example neighbour_index -- [n] [threads] [cells/radius...]
//! ```
//! prints, per case, particles per CPU-second of each search and of the transpose, and the
//! grid/kiddo ratio measured in the same run (interleaved repetitions).

use dualsph_math::{Real, Vector};
use dualsph_neighbours::{GridPlan, kd_radius_csr};
use glam::{DVec2, DVec3};
use std::time::Instant;

/// CPU seconds of the process, all threads (NaN where the platform cannot tell).
fn cpu_seconds() -> f64 {
    cpu_time::ProcessTime::try_now().map_or(f64::NAN, |t| t.as_duration().as_secs_f64())
}

/// A staggered lattice column with spacing `dx` on `z ∈ [z0, z1)`, h = 2·spacing.
fn block<V: Vector>(dx: Real, z0: Real, z1: Real, pos: &mut Vec<V>, h: &mut Vec<Real>) {
    let nx = (1.0 / dx).round() as usize;
    let nz = ((z1 - z0) / dx).round() as usize;
    let ny = if V::DIM == 3 { nx } else { 1 };
    for kz in 0..nz {
        for ky in 0..ny {
            for kx in 0..nx {
                let shift = if kz % 2 == 1 { 0.5 * dx } else { 0.0 };
                let mut p = V::zero();
                p.set(0, (kx as Real + 0.25) * dx + shift * 0.5);
                if V::DIM == 3 {
                    p.set(1, (ky as Real + 0.25) * dx + shift * 0.5);
                }
                p.set(V::DIM - 1, z0 + (kz as Real + 0.5) * dx);
                pos.push(p);
                h.push(2.0 * dx);
            }
        }
    }
}

fn column<V: Vector>(n: usize, two_level: bool) -> (Vec<V>, Vec<Real>) {
    let d = V::DIM as i32;
    let vol = if two_level {
        1.5 + 0.5 * (1 << d) as Real
    } else {
        2.0
    };
    let dx = 1.0 / (1.0 / libm::pow(vol / n as Real, 1.0 / d as Real)).round();
    let (mut pos, mut h) = (Vec::new(), Vec::new());
    if two_level {
        block::<V>(0.5 * dx, 0.0, 0.5, &mut pos, &mut h);
        block::<V>(dx, 0.5, 2.0, &mut pos, &mut h);
    } else {
        block::<V>(dx, 0.0, 2.0, &mut pos, &mut h);
    }
    (pos, h)
}

fn time(f: &mut dyn FnMut()) -> f64 {
    let c0 = cpu_seconds();
    let mut reps = 0;
    while cpu_seconds() - c0 < 0.5 || reps < 2 {
        f();
        reps += 1;
    }
    (cpu_seconds() - c0) / reps as f64
}

fn case<V: Vector>(name: &str, n: usize, two_level: bool, cprs: &[Real], spread: Real) {
    let (pos, h) = column::<V>(n, two_level);
    // spread > 1: h_i scaled by a pseudo-random factor in [1, spread]
    let radii: Vec<Real> = h
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let u =
                ((i as u64).wrapping_mul(0x9e3779b97f4a7c15) >> 11) as Real / (1u64 << 53) as Real;
            x * 1.15 * (1.0 + (spread - 1.0) * u)
        })
        .collect();
    let n = pos.len() as f64;
    let kd = kd_radius_csr(&pos, &radii);
    let mut line = format!(
        "{name:<14} n={:>7} cand/p={:5.1}",
        pos.len(),
        kd.indices.len() as f64 / n
    );
    let mut t_kd = 0.0;
    let mut t_grid = vec![0.0; cprs.len()];
    for _ in 0..2 {
        t_kd += time(&mut || drop(kd_radius_csr(&pos, &radii)));
        for (t, &cpr) in t_grid.iter_mut().zip(cprs) {
            let plan = GridPlan::new(&pos, &radii, cpr).expect("grid");
            assert_eq!(plan.radius_csr(&pos, &radii), kd);
            *t += time(&mut || {
                let plan = GridPlan::new(&pos, &radii, cpr).expect("grid");
                drop(plan.radius_csr(&pos, &radii));
            });
        }
    }
    let t_tr = time(&mut || drop(kd.transpose_with_slots())) * 2.0;
    line += &format!("  kd {:.2e} p/CPU-s", 2.0 * n / t_kd);
    for (t, cpr) in t_grid.iter().zip(cprs) {
        line += &format!("  grid(c=r/{cpr}) {:.2e} ({:.1}x)", 2.0 * n / t, t_kd / t);
    }
    line += &format!("  transpose {:.2e} p/CPU-s", 2.0 * n / t_tr);
    println!("{line}");
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|s| s.parse().ok()).unwrap_or(12_800);
    let threads: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let mut cprs: Vec<Real> = args.iter().skip(2).filter_map(|s| s.parse().ok()).collect();
    if cprs.is_empty() {
        cprs = vec![1.0, 2.0];
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    if let Ok(reps) = std::env::var("NB_PROFILE") {
        // one search only, for a profiler: NB_2D, NB_TWO (layout), NB_KD (kiddo, not the grid)
        let reps = reps.parse::<usize>().unwrap_or(20);
        if std::env::var("NB_2D").is_ok() {
            profile::<DVec2>(n, reps, cprs[0]);
        } else {
            profile::<DVec3>(n, reps, cprs[0]);
        }
        return;
    }
    let w0 = Instant::now();
    pool.install(|| {
        if let Ok(s) = std::env::var("NB_SPREAD") {
            let s: Real = s.parse().expect("NB_SPREAD");
            case::<DVec2>(&format!("2d-h×[1,{s}]"), n, false, &cprs, s);
            case::<DVec3>(&format!("3d-h×[1,{s}]"), n, false, &cprs, s);
            return;
        }
        case::<DVec2>("2d-uniform", n, false, &cprs, 1.0);
        case::<DVec2>("2d-two-level", n, true, &cprs, 1.0);
        case::<DVec3>("3d-uniform", n, false, &cprs, 1.0);
        case::<DVec3>("3d-two-level", n, true, &cprs, 1.0);
    });
    println!(
        "{threads} thread(s), {:.1} s wall",
        w0.elapsed().as_secs_f64()
    );
}

fn profile<V: Vector>(n: usize, reps: usize, cpr: Real) {
    let (pos, h) = column::<V>(n, std::env::var("NB_TWO").is_ok());
    let radii: Vec<Real> = h.iter().map(|x| x * 1.15).collect();
    for _ in 0..reps {
        if std::env::var("NB_KD").is_ok() {
            drop(kd_radius_csr(&pos, &radii));
        } else {
            let plan = GridPlan::new(&pos, &radii, cpr).expect("grid");
            drop(plan.radius_csr(&pos, &radii));
        }
    }
}
