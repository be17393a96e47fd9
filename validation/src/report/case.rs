//! One case of a benchmark: a scene (possibly with its formulation overridden and its
//! resolution coarsened), run in-process while time series and snapshots are recorded.

use dualsph::prelude::*;
use dualsph::run_loop::{EveryStep, Flow, run_to_end};
use dualsph::runner::column_table;
use dualsph::{build_sim, with_dimension};
use dualsph_diagnostics::{Diagnostics, SimDiagnostics};
use dualsph_io::ParticleTable;
use dualsph_scene::{Formulation as SceneFormulation, Generator, Scene};
use std::time::Instant;

/// What to record while a case runs.
#[derive(Clone, Debug, Default)]
pub struct Recording {
    /// Record diagnostics (and the front) every this many steps (0: only first and last).
    pub every: u64,
    /// Snapshot the particles at the first step at or after each of these times.
    pub snapshot_times: Vec<Real>,
    /// Record the water front: the largest x of a fluid particle that is not alone in its
    /// support (a dam-break water front).
    pub front: bool,
    /// Where plugins that write files of their own (probes) put them; in memory when `None`.
    pub output_dir: Option<std::path::PathBuf>,
}

/// A finished case.
#[derive(Clone, Debug)]
pub struct CaseRun {
    /// Label used in tables and legends.
    pub label: String,
    /// Particle count.
    pub particles: u64,
    /// Steps taken.
    pub steps: u64,
    /// Wall-clock seconds of the stepping loop.
    pub wall_seconds: f64,
    /// CPU seconds (user + system, all threads) of the stepping loop.
    pub cpu_seconds: f64,
    /// Diagnostics at t = 0, every `Recording::every` steps, and at the end.
    pub diagnostics: Vec<Diagnostics>,
    /// `(t, largest x)` when `Recording::front` is set.
    pub front: Vec<(Real, Real)>,
    /// The particles at t = 0.
    pub initial: ParticleTable,
    /// `(requested time, actual time, particles)`.
    pub snapshots: Vec<(Real, Real, ParticleTable)>,
    /// The particles at the end.
    pub last: ParticleTable,
    /// Why the run stopped before its end time (a blow-up), if it did; the series above
    /// then end at the last good step.
    pub failure: Option<String>,
}

impl CaseRun {
    /// Particle-steps per CPU second.
    pub fn particle_steps_per_cpu_second(&self) -> f64 {
        (self.particles * self.steps) as f64 / self.cpu_seconds.max(1e-9)
    }

    /// The last diagnostics row.
    pub fn final_diagnostics(&self) -> &Diagnostics {
        self.diagnostics
            .last()
            .expect("a run records at least its initial state")
    }

    /// Largest relative total-energy variation `max |E(t) − E(0)| / |E(0)|` over the rows.
    pub fn max_energy_variation(&self) -> Real {
        let e0 = self.diagnostics[0].e_tot;
        self.diagnostics
            .iter()
            .map(|d| (d.e_tot - e0).abs() / e0.abs())
            .fold(0.0, Real::max)
    }

    /// Largest density variation over the recorded rows.
    pub fn max_density_variation(&self) -> Real {
        self.diagnostics
            .iter()
            .map(|d| d.max_density_variation)
            .fold(0.0, Real::max)
    }
}

/// A scene as one case of a benchmark.
#[derive(Debug)]
pub struct CaseSpec {
    /// Label used in tables and legends.
    pub label: String,
    /// The scene to run.
    pub scene: Scene,
}

impl CaseSpec {
    /// A case from a scene, with the formulation replaced when `formulation` is given.
    pub fn new(
        label: impl Into<String>,
        mut scene: Scene,
        formulation: Option<SceneFormulation>,
    ) -> Self {
        if let Some(f) = formulation {
            scene.formulation = f;
        }
        CaseSpec {
            label: label.into(),
            scene,
        }
    }
}

/// Multiplies every generator's particle spacing by `factor` (> 1 coarsens), keeping the
/// ratio of spacings, h = h_factor Δx, densities and the physics; the plugins' settings that
/// follow the resolution (a refinement's sizes, an inlet's layers) scale with it
/// ([`dualsph_core::plugin::SimPlugin::scale_spacing`]). Used to run the paper's
/// benchmarks at a resolution that fits CI, and for the speed-against-error study.
pub fn coarsen(scene: &mut Scene, factor: Real) {
    for g in &mut scene.particles {
        match g {
            Generator::Block(b) => b.spacing *= factor,
            Generator::Disk(d) => d.spacing *= factor,
            Generator::Shape(s) => s.spacing *= factor,
            // particles read from a file keep their resolution
            Generator::File(_) => {}
        }
    }
    for p in &mut scene.plugins {
        p.scale_spacing(factor);
    }
}

pub use crate::perf::cpu_seconds as process_cpu_seconds;

/// The water front: the largest x of a particle of a fluid body that has another fluid
/// particle within its support radius — the leading edge of the water, not a droplet thrown
/// ahead of it (nor the walls of a tank).
fn largest_x<V: Vector>(sim: &mut Sim<V>) -> Real {
    let fluid: Vec<bool> = match sim.world.get_resource::<dualsph_core::bodies::Bodies>() {
        Some(b) => b.0.iter().map(|b| b.is_fluid()).collect(),
        None => Vec::new(),
    };
    let mut q = sim
        .world
        .query::<(&Position<V>, &SmoothingLength, &BodyId)>();
    let mut water: Vec<(V, Real)> = q
        .iter(&sim.world)
        .filter(|(_, _, b)| fluid.get(b.0 as usize).copied().unwrap_or(true))
        .map(|(p, h, _)| (p.0, h.0))
        .collect();
    water.sort_by(|a, b| b.0.get(0).total_cmp(&a.0.get(0)));
    // the particles within h of particle k in x are next to it in the sorted order
    let attached = |k: usize| {
        let (x, h) = water[k];
        let close = |j: &usize| (water[*j].0 - x).length() < h;
        let ahead = (0..k)
            .rev()
            .take_while(|&j| water[j].0.get(0) - x.get(0) < h);
        let behind = (k + 1..water.len()).take_while(|&j| x.get(0) - water[j].0.get(0) < h);
        ahead.chain(behind).any(|j| close(&j))
    };
    (0..water.len())
        .find(|&k| attached(k))
        .map_or(Real::NEG_INFINITY, |k| water[k].0.get(0))
}

fn run_dim<V: Vector>(spec: &CaseSpec, rec: &Recording) -> Result<CaseRun, SimError> {
    let scene = &spec.scene;
    let mut sim = build_sim::<V>(scene)?;
    if let Some(dir) = &rec.output_dir {
        std::fs::create_dir_all(dir)
            .map_err(|e| SimError::Build(format!("{}: {e}", dir.display())))?;
        sim.world
            .insert_resource(dualsph_core::output::RunOutputDir(dir.clone()));
    }
    sim.initialize()
        .map_err(|e| SimError::BlowUp(format!("case {}: {e}", spec.label)))?;
    let initial = column_table(&mut sim);
    let mut run = CaseRun {
        label: spec.label.clone(),
        particles: sim.particle_count() as u64,
        steps: 0,
        wall_seconds: 0.0,
        cpu_seconds: 0.0,
        diagnostics: vec![sim.diagnostics()],
        front: Vec::new(),
        initial,
        snapshots: Vec::new(),
        last: ParticleTable::default(),
        failure: None,
    };
    if rec.front {
        run.front.push((0.0, largest_x(&mut sim)));
    }
    let mut pending: Vec<Real> = rec.snapshot_times.clone();
    pending.sort_by(Real::total_cmp);
    pending.reverse();
    let (cpu0, wall0) = (process_cpu_seconds(), Instant::now());
    let mut record = EveryStep(|sim: &mut Sim<V>| {
        let c = sim.clock();
        if rec.every > 0 && c.step.is_multiple_of(rec.every) {
            run.diagnostics.push(sim.diagnostics());
            if rec.front {
                run.front.push((c.t, largest_x(sim)));
            }
        }
        while pending.last().is_some_and(|&t| c.t >= t * (1.0 - 1e-12)) {
            let t = pending.pop().unwrap_or(c.t);
            run.snapshots.push((t, c.t, column_table(sim)));
        }
        Ok(Flow::Continue)
    });
    if let Err(e) = run_to_end(&mut sim, &mut [&mut record]) {
        run.failure = Some(format!("case {}: {e}", spec.label));
    }
    run.cpu_seconds = process_cpu_seconds() - cpu0;
    run.wall_seconds = wall0.elapsed().as_secs_f64();
    let last = sim.diagnostics();
    run.steps = last.step;
    if run.diagnostics.last().is_none_or(|d| d.step != last.step) {
        run.diagnostics.push(last);
        if rec.front {
            run.front.push((sim.clock().t, largest_x(&mut sim)));
        }
    }
    run.last = column_table(&mut sim);
    Ok(run)
}

/// Builds and runs a case in its scene's dimension.
pub fn run_case(spec: &CaseSpec, rec: &Recording) -> Result<CaseRun, SimError> {
    with_dimension!(spec.scene.dimension, V => run_dim::<V>(spec, rec))
}
