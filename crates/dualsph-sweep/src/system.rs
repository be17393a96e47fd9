//! The step's pair sweeps: each has a name, a place in the step ([`StepSet`]) and its terms,
//! and runs as one scheduled system that evaluates its terms and writes its accumulators'
//! columns ([`crate::accum`]). The force sweep ([`FORCES`]) is where the momentum and energy
//! terms go; a plugin can add a sweep of its own (a correction matrix, a gradient, a
//! summation density) at its own place.

use crate::erased::DynPairTerm;
use crate::fuse::{Fusions, apply_fusions};
use crate::pair::{PairTerm, ParticleData};
use crate::{Formulation, SweepBuffers, SweepCtx, evaluate};
use bevy_ecs::prelude::*;
use dualsph_core::components::Acceleration;
use dualsph_core::kernels::Kernel;
use dualsph_core::math::Vector;
use dualsph_core::neighbours::Neighbours;
use dualsph_core::order::SystemGroup;
use dualsph_core::sim::{AccelerationsSet, KernelRes, Sim, SimError, StepSet};
use std::sync::Arc;

/// The name of the step's force sweep (in [`StepSet::Forces`]).
pub const FORCES: &str = "pair_sweep";

/// The step's force sweep ([`FORCES`]) as a group of systems: what must see its sums runs
/// after it, what its sums must not overwrite before it.
pub struct ForceSweep;

impl SystemGroup for ForceSweep {}

/// One sweep of the step.
pub struct PairSweep<V: Vector> {
    /// Its name (the system's name in order constraints).
    pub name: &'static str,
    /// Its place in the step.
    pub set: StepSet,
    /// Its terms, in the order they were added.
    pub terms: Vec<Arc<dyn DynPairTerm<V>>>,
    buffers: SweepBuffers,
}

/// Every pair sweep of the step, in the order they were added.
#[derive(Resource)]
pub struct PairSweeps<V: Vector> {
    /// The sweeps.
    pub sweeps: Vec<PairSweep<V>>,
}

impl<V: Vector> Default for PairSweeps<V> {
    fn default() -> Self {
        PairSweeps { sweeps: Vec::new() }
    }
}

impl<V: Vector> PairSweeps<V> {
    /// The sweep named `name`.
    pub fn get(&self, name: &str) -> Option<&PairSweep<V>> {
        self.sweeps.iter().find(|s| s.name == name)
    }

    /// True when some sweep's terms write column `C` (bound to `data`).
    pub fn writes<C: 'static>(&self, data: ParticleData<'_, V>, kernel: &Kernel) -> bool {
        self.sweeps.iter().any(|s| {
            crate::bind(&s.terms, data, kernel).is_ok_and(|(_, layout)| layout.writes::<C>())
        })
    }
}

/// Runs sweep `index` over `world`'s particles and writes its columns.
fn run_sweep<V: Vector>(world: &mut World, index: usize) {
    world.resource_scope(|world, mut sweeps: Mut<PairSweeps<V>>| {
        let sweep = &mut sweeps.sweeps[index];
        sweep_into(world, &sweep.terms, &mut sweep.buffers);
        sweep.buffers.layout.write(world, &sweep.buffers.sums);
    });
}

/// Evaluates `terms` over `world`'s particles into `buf` (nothing without particles).
pub fn sweep_into<V: Vector>(
    world: &World,
    terms: &[Arc<dyn DynPairTerm<V>>],
    buf: &mut SweepBuffers,
) {
    let Some(data) = ParticleData::of(world) else {
        return;
    };
    let ctx = SweepCtx::new(
        data,
        world.resource::<Neighbours<V>>(),
        &world.resource::<KernelRes>().0,
        *world.resource::<Formulation>(),
    );
    if let Err(e) = evaluate(&ctx, terms, buf) {
        unreachable!("pair terms were bound when the simulation was built: {e}")
    }
}

/// What the pair layer adds to a [`Sim`]: pair terms in sweeps, and their fusions.
pub trait SimSweeps<V: Vector> {
    /// Adds a term to the step's force sweep ([`FORCES`], in [`StepSet::Forces`]).
    fn add_pair_term(&mut self, term: impl PairTerm<V>);

    /// Adds a term to the sweep `name` at `set`, which is created (as a system named `name`)
    /// by its first term; the error names a sweep of that name at another place.
    fn add_pair_term_to(
        &mut self,
        name: &'static str,
        set: StepSet,
        term: impl PairTerm<V>,
    ) -> Result<(), SimError>;

    /// Declares that a term `A` followed by a term `B` in a sweep run as one
    /// ([`crate::Fused<A, B>`]); chains fuse left to right, so `A, B, C` needs this for
    /// `(A, B)` and for `(Fused<A, B>, C)`.
    fn fuse<A: PairTerm<V>, B: PairTerm<V>>(&mut self) -> &mut Self;

    /// The pair terms as `sweep: term`, sweep by sweep, in order (fused terms are joined by
    /// `+` once the simulation is finished).
    fn pair_terms(&self) -> Vec<String>;
}

impl<V: Vector> SimSweeps<V> for Sim<V> {
    fn add_pair_term(&mut self, term: impl PairTerm<V>) {
        self.add_pair_term_to(FORCES, StepSet::Forces, term)
            .expect("the force sweep is in the Forces set");
    }

    fn add_pair_term_to(
        &mut self,
        name: &'static str,
        set: StepSet,
        term: impl PairTerm<V>,
    ) -> Result<(), SimError> {
        install::<V>(self);
        let mut sweeps = self.world.resource_mut::<PairSweeps<V>>();
        if let Some(s) = sweeps.sweeps.iter_mut().find(|s| s.name == name) {
            if s.set != set {
                return Err(SimError::Build(format!(
                    "pair sweep {name} is in {:?}, not {set:?}",
                    s.set
                )));
            }
            s.terms.push(Arc::new(term));
            return Ok(());
        }
        let index = sweeps.sweeps.len();
        sweeps.sweeps.push(PairSweep {
            name,
            set,
            terms: vec![Arc::new(term)],
            buffers: SweepBuffers::default(),
        });
        let label = if name == FORCES {
            format!("{FORCES} (support + dual-support)")
        } else {
            format!("{name} (pair sweep)")
        };
        // the sweep is the engine's, whichever plugin's term comes first
        self.as_plugin("core", |sim| {
            let order = sim.add_system(set, label, move |world: &mut World| {
                run_sweep::<V>(world, index)
            });
            if name == FORCES {
                order.in_group::<ForceSweep>();
            }
        });
        Ok(())
    }

    fn fuse<A: PairTerm<V>, B: PairTerm<V>>(&mut self) -> &mut Self {
        install::<V>(self);
        self.world.init_resource::<Fusions<V>>();
        self.world.resource_mut::<Fusions<V>>().declare::<A, B>();
        self
    }

    fn pair_terms(&self) -> Vec<String> {
        let Some(sweeps) = self.world.get_resource::<PairSweeps<V>>() else {
            return Vec::new();
        };
        sweeps
            .sweeps
            .iter()
            .flat_map(|s| s.terms.iter().map(|t| format!("{}: {}", s.name, t.name())))
            .collect()
    }
}

/// The sweeps' resource and their finish hook, once per simulation.
fn install<V: Vector>(sim: &mut Sim<V>) {
    sim.world.init_resource::<PairSweeps<V>>();
    sim.add_finish_hook("pair sweeps", finish_sweeps::<V>);
}

/// At [`Sim::finish`]: applies the declared fusions, binds every sweep's terms to the
/// particles (the error names what a term lacks) and, before the schedule is built, marks the
/// accelerations as set when a sweep writes them, or else zeroes them before the force sweep.
fn finish_sweeps<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    apply_fusions(sim);
    let kernel = &sim.world.resource::<KernelRes>().0;
    let sweeps = sim.world.resource::<PairSweeps<V>>();
    let data = ParticleData::<V>::of(&sim.world);
    if let Some(data) = data {
        for sweep in &sweeps.sweeps {
            crate::bind(&sweep.terms, data, kernel).map_err(SimError::Build)?;
        }
    }
    if sim.is_built() || sim.world.contains_resource::<AccelerationsSet>() {
        return Ok(());
    }
    let writes = data.is_some_and(|d| sweeps.writes::<Acceleration<V>>(d, kernel));
    if writes {
        sim.world.insert_resource(AccelerationsSet);
    } else {
        sim.add_zero_accelerations().before::<ForceSweep>();
    }
    Ok(())
}
