//! What every simulation starts with ([`Sim::new`]): the core resources, the core columns,
//! the neighbour and clock systems, and the core's finish hooks. The hub ([`crate::sim`])
//! knows none of the modules installed here; they extend it.

use crate::bodies::Bodies;
use crate::chunks::{DENSE, MIN_LEN};
use crate::columns::Columns;
use crate::components::{Position, SmoothingLength};
use crate::kernels::Kernel;
use crate::math::{Real, Vector};
use crate::neighbours::Neighbours;
use crate::population::{ColumnInits, NextId};
use crate::potentials::ExternalPotentials;
use crate::sim::{
    InitialInternalEnergy, IntegratorName, KernelRes, MaxViscosity, Sim, SimClock, SimConfig,
    SimError, StepFailure, StepSet, init_task_pool,
};
use crate::store::single_table;
use bevy_ecs::prelude::*;
use rayon::prelude::*;

impl<V: Vector> Sim<V> {
    /// A simulation with the core resources and no particles yet.
    pub fn new(config: SimConfig<V>) -> Self {
        init_task_pool();
        let mut world = World::new();
        world.insert_resource(SimClock {
            t: 0.0,
            step: 0,
            dt: 0.0,
            initializing: false,
            t_end: Real::INFINITY,
        });
        world.insert_resource(KernelRes(Kernel::new(config.kernel, V::DIM)));
        world.insert_resource(config.formulation);
        world.insert_resource(config.domain);
        world.insert_resource(config.time_stepping);
        let period = config.domain.period();
        world.insert_resource(
            Neighbours::<V>::with_rule(config.skin, config.skin_rule).with_period(period),
        );
        world.insert_resource(MaxViscosity::default());
        world.insert_resource(InitialInternalEnergy::default());
        world.insert_resource(ExternalPotentials::default());
        world.insert_resource(Columns::default());
        world.insert_resource(crate::output::DiagnosticColumns::default());
        world.insert_resource(crate::output::DerivedColumns::default());
        world.insert_resource(NextId::default());
        world.insert_resource(ColumnInits::<V>::default());
        world.insert_resource(Bodies::default());
        world.insert_resource(IntegratorName::default());
        world.insert_resource(StepFailure::default());
        let mut sim = Sim::bare(world);
        add_core_systems(&mut sim);
        sim.register_core_columns();
        // in this order: the first failing check is the one reported
        sim.add_finish_hook("integrator", check_integrator::<V>);
        sim.add_finish_hook("requirements", |sim| sim.check_requirements());
        sim.add_finish_hook("pending columns", |sim| {
            sim.insert_pending_columns();
            Ok(())
        });
        sim.add_finish_hook("store", |sim| sim.check_store());
        sim
    }
}

/// At [`Sim::finish`]: an integrator is set ([`IntegratorName`]).
fn check_integrator<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    match sim.world.resource::<IntegratorName>().0 {
        Some(_) => Ok(()),
        None => Err(SimError::Build(
            "no integrator: the state would not advance; add a time-integration plugin \
             (e.g. `dualsph_integrator::LeapfrogPC`, which a scene gets by default)"
                .into(),
        )),
    }
}

/// Rebuilds the neighbour lists when the skin rule requires it.
#[inline(never)] // a frame of its own in profiles
pub fn update_neighbours<V: Vector>(
    mut nb: ResMut<Neighbours<V>>,
    q: Query<(&Position<V>, &SmoothingLength)>,
) {
    let (pos, h) = single_table(q.contiguous_iter().expect(DENSE)).unwrap_or((&[], &[]));
    nb.update_with(
        pos.len(),
        |i| pos[i].0,
        |p, r| {
            p.extend(pos.iter().map(|x| x.0));
            r.extend(h.iter().map(|x| x.0));
        },
    );
}

/// Moves every particle that left the box across a periodic face back by whole periods
/// (see [`crate::neighbours::Period::wrap`]); the pair separations are minimum images, so the
/// move changes no force, only where the particle is written.
#[inline(never)] // a frame of its own in profiles
pub fn wrap_periodic<V: Vector>(nb: Res<Neighbours<V>>, mut q: Query<&mut Position<V>>) {
    let Some(period) = nb.period else { return };
    for mut r in q.contiguous_iter_mut().expect(DENSE) {
        r.bypass_change_detection()
            .par_iter_mut()
            .with_min_len(MIN_LEN)
            .for_each(|r| r.0 = period.wrap(r.0));
    }
}

/// Advances the clock after a completed step.
pub fn advance_clock(mut clock: ResMut<SimClock>) {
    clock.t += clock.dt;
    clock.step += 1;
}

/// The systems of every simulation, whatever its plugins: the neighbour lists and the clock.
fn add_core_systems<V: Vector>(sim: &mut Sim<V>) {
    sim.add_system(
        StepSet::Neighbours,
        "update_neighbours (Verlet skin)",
        update_neighbours::<V>,
    );
    if sim.world.resource::<Neighbours<V>>().period.is_some() {
        sim.add_system(
            StepSet::Boundary,
            "wrap_periodic (positions into the box)",
            wrap_periodic::<V>,
        );
    }
    sim.add_system(StepSet::Advance, "advance_clock", advance_clock);
}
