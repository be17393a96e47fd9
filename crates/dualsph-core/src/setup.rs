//! What every simulation starts with ([`Sim::new`]): the core resources, the core columns,
//! the neighbour and clock systems, and the core's finish hooks. The hub ([`crate::sim`])
//! knows none of the modules installed here; they extend it.

use crate::bodies::Bodies;
use crate::columns::Columns;
use crate::integrate::{Integration, add_core_systems, check_integrator};
use crate::kernels::Kernel;
use crate::math::{Real, Vector};
use crate::neighbours::Neighbours;
use crate::population::{ColumnInits, NextId};
use crate::potentials::ExternalPotentials;
use crate::sim::{
    InitialInternalEnergy, KernelRes, MaxViscosity, Sim, SimClock, SimConfig, StepFailure,
    init_task_pool,
};
use bevy_ecs::prelude::*;

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
        world.insert_resource(NextId::default());
        world.insert_resource(ColumnInits::<V>::default());
        world.insert_resource(Bodies::default());
        world.insert_resource(Integration::<V>::default());
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
