//! The step's pair sweeps: each has a name, a place in the step ([`StepSet`]) and its terms,
//! and runs as one scheduled system that evaluates its terms and writes its accumulators'
//! columns ([`crate::accum`]). The force sweep ([`FORCES`]) is where the momentum and energy
//! terms go; a plugin can add a sweep of its own (a correction matrix, a gradient, a
//! summation density) at its own place.

use super::{Formulation, SweepBuffers, SweepCtx, evaluate};
use crate::components::Acceleration;
use crate::kernels::Kernel;
use crate::math::Vector;
use crate::neighbours::Neighbours;
use crate::pair::{DynPairTerm, PairTerm, ParticleData};
use crate::sim::{KernelRes, Sim, SimError, StepSet};
use bevy_ecs::prelude::*;
use std::sync::Arc;

/// The name of the step's force sweep (in [`StepSet::Forces`]).
pub const FORCES: &str = "pair_sweep";

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
            super::bind(&s.terms, data, kernel).is_ok_and(|(_, layout)| layout.writes::<C>())
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

impl<V: Vector> Sim<V> {
    /// Adds a term to the step's force sweep ([`FORCES`], in [`StepSet::Forces`]).
    pub fn add_pair_term(&mut self, term: impl PairTerm<V>) {
        self.add_pair_term_to(FORCES, StepSet::Forces, term)
            .expect("the force sweep is in the Forces set");
    }

    /// Adds a term to the sweep `name` at `set`, which is created (as a system named `name`)
    /// by its first term; the error names a sweep of that name at another place.
    pub fn add_pair_term_to(
        &mut self,
        name: &'static str,
        set: StepSet,
        term: impl PairTerm<V>,
    ) -> Result<(), SimError> {
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
            sim.add_system(set, label, move |world: &mut World| {
                run_sweep::<V>(world, index)
            });
        });
        Ok(())
    }
}

fn zero_accelerations<V: Vector>(mut q: Query<&mut Acceleration<V>>) {
    for mut a in &mut q {
        a.0 = V::zero();
    }
}

/// Adds a system that zeroes every acceleration at the start of the force stage, for scenes
/// whose sweeps write none.
pub(crate) fn add_zero_acceleration_system<V: Vector>(sim: &mut Sim<V>) {
    sim.add_system(
        StepSet::Forces,
        "zero_accelerations",
        zero_accelerations::<V>,
    )
    .before(FORCES);
}
