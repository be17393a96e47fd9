//! Benchmark cases and process-time measurement, shared by `benches/` and the `perf` example.
//!
//! Every case is the physics of `scenes/dam_break_2d.ron` — cubic spline, DualSupport,
//! continuity density (Eq. 4.9, pairwise), Tait EOS (Eq. 7.5), pressure (Eq. 4.19) +
//! artificial viscosity (Eq. 4.17), gravity, specular walls, h-update every 200 steps
//! (Eq. 6.1), skin 0.15, adaptive dt — on a water column `[0,1] × [0,2]` (2-D) or
//! `[0,1] × [0,1] × [0,2]` (3-D), with h = 2Δx:
//! * **uniform**: one block at spacing Δx;
//! * **two-level**: the lower quarter (height 0.5) at Δx/2, the rest at Δx (the dam-break
//!   Case II layout with the refinement at the bottom), h = 2Δx locally.
//!
//! Δx is chosen from the requested particle count; the generated count is what the
//! benches report. `dam_column_2d()` is the reference case of docs/performance.md: 12,800
//! particles, Δx = 0.0125.

pub use dualsph::runner::cpu_seconds;

use dualsph::prelude::*;
use dualsph::{build_sim, default_registry};
use dualsph_scene::Scene;
use std::path::Path;

/// The resolution layout of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// One spacing everywhere.
    Uniform,
    /// The lower quarter of the column at half the spacing.
    TwoLevel,
}

/// A benchmark case: dimension, layout and spacing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// 2 or 3.
    pub dim: usize,
    /// Uniform or two-level.
    pub layout: Layout,
    /// Coarse spacing Δx (the fine part uses Δx/2).
    pub dx: Real,
}

impl Case {
    /// The uniform 2-D dam-break column, the reference case of docs/performance.md: 12,800
    /// particles, Δx = 0.0125.
    pub fn dam_column_2d() -> Self {
        Case {
            dim: 2,
            layout: Layout::Uniform,
            dx: 0.0125,
        }
    }

    /// A case with about `n` particles: `n ≈ 2/Δx^d` (uniform; column volume 2) or
    /// `(1.5 + 0.5·2^d)/Δx^d` (two-level: the fine quarter holds `2^d` times more), with Δx
    /// rounded to `1/k`.
    pub fn with_particles(dim: usize, layout: Layout, n: usize) -> Self {
        let cells = match layout {
            Layout::Uniform => 2.0,
            Layout::TwoLevel => 1.5 + 0.5 * (1 << dim) as Real,
        };
        // snap Δx to 1/k so every block holds whole cells (lattice points stay inside)
        let dx = libm::pow(cells / n as Real, 1.0 / dim as Real);
        Case {
            dim,
            layout,
            dx: 1.0 / (1.0 / dx).round().max(1.0),
        }
    }

    /// A short name such as `2d-uniform-12800`.
    pub fn name(&self, particles: usize) -> String {
        let l = match self.layout {
            Layout::Uniform => "uniform",
            Layout::TwoLevel => "two-level",
        };
        format!("{}d-{l}-{particles}", self.dim)
    }

    /// The case as RON scene text (the same format as `scenes/*.ron`).
    pub fn scene_text(&self) -> String {
        let dx = self.dx;
        // a point of the column at horizontal position x (all horizontal axes) and height z
        let at = |x: Real, z: Real| {
            if self.dim == 2 {
                format!("[{x:?}, {z:?}]")
            } else {
                format!("[{x:?}, {x:?}, {z:?}]")
            }
        };
        let block = |lo: String, hi: String, spacing: Real| {
            format!(
                "Block(min: {lo}, max: {hi}, spacing: {spacing:?}, lattice: Staggered, \
                 density: 1000.0, h_factor: 2.0),"
            )
        };
        let blocks = match self.layout {
            Layout::Uniform => block(at(0.0, 0.0), at(1.0, 2.0), dx),
            Layout::TwoLevel => {
                block(at(0.0, 0.0), at(1.0, 0.5), 0.5 * dx) + &block(at(0.0, 0.5), at(1.0, 2.0), dx)
            }
        };
        let (domain_max, g) = if self.dim == 2 {
            ("[4.0, 3.0]", "[0.0, -9.81]")
        } else {
            ("[4.0, 1.0, 3.0]", "[0.0, 0.0, -9.81]")
        };
        format!(
            "Scene(
    name: \"bench\",
    dimension: {dim},
    domain: (min: {domain_min}, max: {domain_max}),
    kernel: CubicSpline,
    formulation: DualSupport,
    neighbours: (skin: 0.15),
    particles: [ {blocks} ],
    plugins: [
        ContinuityDensity(form: Pairwise),
        TaitEos(rho0: 1000.0, gamma: 7.0, c0: 100.0),
        PressureForce(),
        ArtificialViscosity(alpha: 1.0, beta: 1.0),
        Gravity(g: {g}),
        SpecularWalls(),
        SmoothingLengthUpdate(every: 200, n: 2.0),
    ],
    integrator: (dt: Adaptive(courant: 0.1, force: 0.25, viscous: 0.125)),
    end_time: 1.0,
    output: (diagnostics_every: 20, snapshot_every: 0, formats: []),
)",
            dim = self.dim,
            domain_min = at(0.0, 0.0),
        )
    }

    /// The parsed and validated scene.
    pub fn scene(&self) -> Scene {
        Scene::from_str(
            &self.scene_text(),
            Path::new("<bench case>"),
            &default_registry(),
        )
        .expect("bench case scene is valid")
    }

    /// The simulation of this case, initialised (rates at t = 0 exist), in a state where
    /// every term works: hydrostatic density (Tait, Eq. 7.5, inverted for
    /// `p = ρ0 |g| (2 − z)`) and a deterministic velocity noise of 0.05 m/s per component, so
    /// pairs approach and recede as in a flow (a column at rest in free fall would evaluate
    /// pressure and viscosity on zeros).
    pub fn sim<V: Vector>(&self) -> Sim<V> {
        assert_eq!(V::DIM, self.dim, "case dimension");
        let mut sim = build_sim::<V>(&self.scene()).expect("bench case builds");
        let (rho0, gamma, c0, g, top) = (1000.0, 7.0, 100.0, 9.81, 2.0);
        let p0 = c0 * c0 * rho0 / gamma;
        let mut q = sim
            .world
            .query::<(&ParticleId, &Position<V>, &mut Velocity<V>, &mut Density)>();
        for (id, r, mut v, mut rho) in q.iter_mut(&mut sim.world) {
            let z = r.0.get(V::DIM - 1);
            rho.0 = rho0 * libm::pow(1.0 + rho0 * g * (top - z) / p0, 1.0 / gamma);
            let mut h = (id.0 as u64).wrapping_mul(0x9e3779b97f4a7c15);
            for k in 0..V::DIM {
                h ^= h >> 29;
                h = h.wrapping_mul(0xbf58476d1ce4e5b9);
                let u = (h >> 11) as Real / (1u64 << 53) as Real; // [0, 1)
                v.0.set(k, 0.1 * (u - 0.5));
            }
        }
        sim.initialize().expect("bench case initialises");
        sim
    }
}

/// Pair interactions of the current lists: `Σ_i |H_i|`, the `(i, j ∈ H_i)` with
/// `|r_ij| < h_i` that the sweep evaluates (candidates inside the Verlet skin but outside
/// `h_i` are skipped by the sweep and not counted).
pub fn support_pairs<V: Vector>(sim: &Sim<V>) -> usize {
    let Some(d) = ParticleData::<V>::of(&sim.world) else {
        return 0;
    };
    let nb = sim
        .world
        .resource::<dualsph_core::neighbours::Neighbours<V>>();
    (0..d.len())
        .map(|i| {
            let (x, h) = (d.pos[i].0, d.h[i].0);
            nb.support
                .row(i)
                .iter()
                .filter(|&&j| (x - d.pos[j as usize].0).length_squared() < h * h)
                .count()
        })
        .sum()
}

/// Peak resident set size of this process in bytes (`VmHWM` of `/proc/self/status`).
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The force sweep of the simulation's current state, as the Forces set runs it
/// (`sweep::sweep_into` over the terms of the sweep `FORCES`: the momentum, energy and
/// density rates), into `buf` — what the benches and the `perf` example time on their own.
pub fn run_sweep<V: Vector>(sim: &Sim<V>, buf: &mut dualsph::sweep::SweepBuffers) {
    use dualsph::sweep::{FORCES, PairSweeps, sweep_into};
    let sweeps = sim.world.resource::<PairSweeps<V>>();
    let terms = sweeps.get(FORCES).map_or(&[][..], |s| &s.terms[..]);
    sweep_into(&sim.world, terms, buf);
}

/// The steps after which docs/performance.md quotes the reference case's fingerprint.
pub const REFERENCE_STEPS: usize = 500;

/// FNV-1a over the bits of every particle's position, velocity and density, in id order:
/// equal fingerprints mean bitwise-equal states. The `perf` example prints it, and
/// docs/performance.md quotes it for [`REFERENCE_STEPS`] steps of [`Case::dam_column_2d`]
/// (checked by a test, so the quote follows the arithmetic).
pub fn state_fingerprint<V: Vector>(sim: &mut Sim<V>) -> u64 {
    let mut q = sim
        .world
        .query::<(&ParticleId, &Position<V>, &Velocity<V>, &Density)>();
    let mut rows: Vec<_> = q.iter(&sim.world).collect();
    rows.sort_by_key(|r| r.0.0);
    let mut h: u64 = 0xcbf29ce484222325;
    let mut mix = |x: f64| {
        h ^= x.to_bits();
        h = h.wrapping_mul(0x100000001b3);
    };
    for (_, r, v, rho) in rows {
        for k in 0..V::DIM {
            mix(r.0.get(k));
            mix(v.0.get(k));
        }
        mix(rho.0);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dam_column_has_12800_particles() {
        assert_eq!(Case::dam_column_2d().scene().generate().len(), 12_800);
    }

    #[test]
    fn bench_cases_are_valid_scenes() {
        for n in [12_800, 100_000] {
            for dim in [2, 3] {
                for layout in [Layout::Uniform, Layout::TwoLevel] {
                    let got = Case::with_particles(dim, layout, n)
                        .scene()
                        .generate()
                        .len();
                    assert!(got > n / 2 && got < 2 * n, "{dim}-D {layout:?} {n}: {got}");
                }
            }
        }
    }

    #[test]
    fn two_level_case_builds_in_3d() {
        let c = Case::with_particles(3, Layout::TwoLevel, 3000);
        let n = c.scene().generate().len();
        assert!((2000..4500).contains(&n), "{n}");
        let mut sim = c.sim::<glam::DVec3>();
        sim.step().unwrap();
    }
}
