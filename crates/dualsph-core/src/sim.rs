//! The simulation: a `bevy_ecs` [`World`] plus one ordered `Step` schedule of named sets.
//!
//! Systems are added to a [`StepSet`] with a label; the schedule is a total order — sets in
//! the order below, systems within a set in the order they were added — so a run is
//! deterministic and [`Sim::plan`] can print exactly what will execute.

use crate::columns::Columns;
use crate::math::Vector;
use crate::order::{Placement, SystemGroup};
use crate::store::ParticleData;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::{ScheduleLabel, SingleThreadedExecutor};
use bevy_ecs::system::ScheduleSystem;
use std::any::TypeId;

pub use crate::names::short_type_name;

mod plan;
mod state;
pub use crate::phase::{RatesStale, StepPhase};
pub use plan::Plan;
pub use state::{
    Domain, Formulation, InitialInternalEnergy, IntegratorName, KernelRes, MaxViscosity,
    ParticleInit, SimClock, SimConfig, StepFailure, TimeStepping,
};
use std::marker::PhantomData;

/// Errors from building or running a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A plugin could not be built (message says why).
    #[error("build error: {0}")]
    Build(String),
    /// The state became unphysical; the message names step, time, particle and quantity.
    #[error("blow-up: {0}")]
    BlowUp(String),
}

/// The ordered stages of one time step.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum StepSet {
    /// Particles added and removed by plugins (inflow, outflow), applied at the end of the
    /// set (see [`crate::population`]).
    Population,
    /// Choose dt (fixed or CFL/force/viscous).
    TimeStep,
    /// The integrator's first stage (the leapfrog's predictor, §6 step 1).
    Predict,
    /// Smoothing-length update every m steps (Eq. 6.1).
    SmoothingLength,
    /// Neighbour-list rebuild (when the skin rule requires it).
    Neighbours,
    /// Own-support pass: summation density.
    Density,
    /// Own-support pass: kernel-gradient correction matrices (Eq. 2.10).
    Correction,
    /// Own-support pass: velocity gradients (Eq. 7.4).
    Gradients,
    /// Equation of state: pressure and sound speed.
    Eos,
    /// The support/dual-support pair sweep and other rates (continuity).
    Forces,
    /// Body forces (gravity).
    BodyForces,
    /// The integrator's last stage (the leapfrog's corrector, §6 step 3).
    Correct,
    /// Boundary conditions (specular walls).
    Boundary,
    /// Advance the clock.
    Advance,
    /// Conservation diagnostics and checks.
    Diagnostics,
}

impl StepSet {
    /// Every set in schedule order.
    pub const ALL: [StepSet; 15] = [
        StepSet::Population,
        StepSet::TimeStep,
        StepSet::Predict,
        StepSet::SmoothingLength,
        StepSet::Neighbours,
        StepSet::Density,
        StepSet::Correction,
        StepSet::Gradients,
        StepSet::Eos,
        StepSet::Forces,
        StepSet::BodyForces,
        StepSet::Correct,
        StepSet::Boundary,
        StepSet::Advance,
        StepSet::Diagnostics,
    ];

    /// Sets skipped by the initial evaluation (which only computes rates at t = 0).
    pub fn advances_state(self) -> bool {
        matches!(
            self,
            StepSet::Population
                | StepSet::TimeStep
                | StepSet::Predict
                | StepSet::SmoothingLength
                | StepSet::Correct
                | StepSet::Boundary
                | StepSet::Advance
        )
    }
}

/// Whether the systems of `set` run in `phase` (`initializing`: the initial evaluation,
/// which skips the sets that advance the state): [`StepSet::Population`] in its phase only;
/// the diagnostics and the sets that advance the state in the step only; the rates' sets in
/// the rates phase and the step.
fn runs_in(phase: StepPhase, set: StepSet, initializing: bool) -> bool {
    match set {
        StepSet::Population => phase == StepPhase::Population && !initializing,
        StepSet::Diagnostics => phase == StepPhase::Step,
        s if s.advances_state() => phase == StepPhase::Step && !initializing,
        _ => phase != StepPhase::Population,
    }
}

/// The step schedule's label.
#[derive(ScheduleLabel, Debug, Clone, PartialEq, Eq, Hash)]
pub struct Step;

#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct Slot(usize);

/// The profiling marker after slot `k` (see [`crate::profile`]); `None` is the one before the
/// first slot.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct Mark(Option<usize>);

type Adder = Box<dyn FnOnce(&mut Schedule, Slot) + Send + Sync>;

struct SystemEntry {
    set: StepSet,
    place: Placement,
    add: Option<Adder>,
}

/// The system just added, to join groups and constrain its place in its set (see
/// [`crate::order`]): `sim.add_system(StepSet::Eos, "wall_pressure", f).after::<EquationOfState>()`.
pub struct SystemOrder<'a> {
    place: &'a mut Placement,
}

impl SystemOrder<'_> {
    /// Joins the group `G`, so that systems placed against `G` are placed against it.
    pub fn in_group<G: SystemGroup>(self) -> Self {
        self.place.groups.push(TypeId::of::<G>());
        self
    }

    /// Runs after every system of its set in group `G` (none, when no such system is in the
    /// scene).
    pub fn after<G: SystemGroup>(self) -> Self {
        self.place.after.push(TypeId::of::<G>());
        self
    }

    /// Runs before every system of its set in group `G` (see [`SystemOrder::after`]).
    pub fn before<G: SystemGroup>(self) -> Self {
        self.place.before.push(TypeId::of::<G>());
        self
    }
}

/// A simulation: world, schedule under construction or built, and its requirements.
pub struct Sim<V: Vector> {
    /// The ECS world: particles are entities, shared state is resources.
    pub world: World,
    systems: Vec<SystemEntry>,
    /// What plugins need present at [`Sim::finish`]: a test of the world and the message.
    requirements: Vec<(fn(&World) -> bool, String)>,
    /// Checks of the scene's particles that plugins ask for (see [`Sim::advise`]).
    advisories: Vec<fn(&mut World) -> Option<String>>,
    notes: Vec<String>,
    /// The plugin being built (systems added now are its own), `core` otherwise.
    building: &'static str,
    schedule: Option<Schedule>,
    /// The systems' labels in schedule order (set when the schedule is built).
    labels: Vec<String>,
    /// The systems' indices in schedule order (set when the schedule is built).
    built_order: Vec<usize>,
    /// Whether a system is in [`StepSet::Population`] (set when the schedule is built).
    has_population: bool,
    /// The threads that run the steps (see [`Sim::step`]); made at the first step.
    pool: Option<rayon::ThreadPool>,
    /// What crates above the core check and add when the simulation is finished, by name
    /// (see [`Sim::add_finish_hook`]).
    finish_hooks: Vec<(&'static str, FinishHook<V>)>,
    _v: PhantomData<V>,
}

/// A check or addition run by [`Sim::finish`] (see [`Sim::add_finish_hook`]).
pub type FinishHook<V> = fn(&mut Sim<V>) -> Result<(), SimError>;

/// Present when every particle's acceleration is set afresh each step by some system (the
/// force sweep writes it, or a system zeroes it); without it, [`Sim::finish`] adds a system
/// that zeroes the accelerations at the end of [`StepSet::Forces`], so that body forces
/// added later in the step do not accumulate.
#[derive(Resource, Debug, Default)]
pub struct AccelerationsSet;

/// Gives bevy's `ComputeTaskPool` (which runs any system's `Query::par_iter_mut` loop) as many
/// threads as the current rayon pool (which runs the neighbour loops), so a run on N threads
/// uses N for both. The pool is global: the first call of a process (normally the first
/// [`Sim::new`]) sets its size; later calls do nothing. The engine's own per-particle updates
/// run over contiguous table slices on rayon (cheaper than bevy's per-entity parallel calls,
/// see [`crate::chunks`]); a plugin's `par_iter_mut` loop must update each particle from its
/// own data only, so that the result does not depend on the number of threads (bitwise).
pub fn init_task_pool() {
    bevy_tasks::ComputeTaskPool::get_or_init(|| {
        bevy_tasks::TaskPoolBuilder::new()
            .num_threads(rayon::current_num_threads())
            .thread_name("dualsph-ecs".to_string())
            .build()
    });
}

impl<V: Vector> Sim<V> {
    /// A simulation of `world` with no systems yet ([`Sim::new`] puts the core's in it).
    pub(crate) fn bare(world: World) -> Self {
        Sim {
            world,
            systems: Vec::new(),
            requirements: Vec::new(),
            advisories: Vec::new(),
            notes: Vec::new(),
            building: "core",
            schedule: None,
            labels: Vec::new(),
            built_order: Vec::new(),
            has_population: false,
            pool: None,
            finish_hooks: Vec::new(),
            _v: PhantomData,
        }
    }

    /// Marks what the marker resource `M` stands for as present (an equation of state,
    /// gravity, the summation density); returns true the first time, so that what it brings
    /// is added once.
    pub fn enable<M: Resource + Default>(&mut self) -> bool {
        if self.world.contains_resource::<M>() {
            return false;
        }
        self.world.init_resource::<M>();
        true
    }

    /// True once [`Sim::enable`]`::<M>` was called.
    pub fn has<M: Resource>(&self) -> bool {
        self.world.contains_resource::<M>()
    }

    /// Declares that some plugin must enable `M` before the run starts; `message` explains
    /// who needs it (checked by [`Sim::finish`]).
    pub fn require<M: Resource>(&mut self, message: impl Into<String>) {
        self.requirements
            .push((World::contains_resource::<M>, message.into()));
    }

    /// Adds a check of the scene as built (its particles and resources) that cannot refuse it
    /// but may warn: `check` returns a warning naming the plugin and the setting, or `None`.
    /// [`Sim::advice`] runs them; the command line prints what they say on `check` and `run`.
    pub fn advise(&mut self, check: fn(&mut World) -> Option<String>) {
        self.advisories.push(check);
    }

    /// The warnings of the checks added with [`Sim::advise`], in the order they were added.
    pub fn advice(&mut self) -> Vec<String> {
        let checks = self.advisories.clone();
        checks.iter().filter_map(|c| c(&mut self.world)).collect()
    }

    /// Records what a plugin derived from the scene as it was built (`c0 = 48.5 m/s, from
    /// …`): the command line prints it on `check` and `run`, so the value a run uses is seen.
    pub fn note(&mut self, text: impl Into<String>) {
        self.notes.push(text.into());
    }

    /// The notes of [`Sim::note`], in the order they were recorded.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Adds a system to a set, after every system already in that set unless the returned
    /// [`SystemOrder`] constrains it otherwise (see [`crate::order`]). The label's first word
    /// is the system's name in messages.
    ///
    /// # Panics
    /// When the schedule is already built ([`Sim::finish`], or the first step): every system
    /// is placed before then (a caller of `dualsph_run::build_sim` adds its own with
    /// `build_sim_with`).
    pub fn add_system<M: 'static>(
        &mut self,
        set: StepSet,
        label: impl Into<String>,
        system: impl IntoScheduleConfigs<ScheduleSystem, M> + Send + Sync + 'static,
    ) -> SystemOrder<'_> {
        let label = label.into();
        assert!(
            self.schedule.is_none(),
            "system {label} added after the schedule was built: add it before Sim::finish"
        );
        let adder: Adder = Box::new(move |schedule: &mut Schedule, slot: Slot| {
            schedule.add_systems(system.in_set(slot));
        });
        self.systems.push(SystemEntry {
            set,
            place: Placement {
                label,
                plugin: self.building.to_string(),
                ..Placement::default()
            },
            add: Some(adder),
        });
        let last = self.systems.len() - 1;
        SystemOrder {
            place: &mut self.systems[last].place,
        }
    }

    /// Runs `f` with the systems it adds attributed to the plugin `name` (`core` for systems
    /// that belong to the engine whichever plugin causes them, such as a pair sweep).
    pub fn as_plugin<T>(&mut self, name: &'static str, f: impl FnOnce(&mut Self) -> T) -> T {
        let outer = std::mem::replace(&mut self.building, name);
        let out = f(self);
        self.building = outer;
        out
    }

    /// The systems in run order: by set, and inside a set by insertion order and the
    /// systems' constraints ([`crate::order`]); the error names a contradiction.
    fn ordered(&self) -> Result<Vec<usize>, SimError> {
        let mut out = Vec::with_capacity(self.systems.len());
        for set in StepSet::ALL {
            let members: Vec<usize> = (0..self.systems.len())
                .filter(|&k| self.systems[k].set == set)
                .collect();
            let places: Vec<Placement> = members
                .iter()
                .map(|&k| self.systems[k].place.clone())
                .collect();
            let inside = crate::order::order(&places)
                .map_err(|e| SimError::Build(format!("{set:?}: {e}")))?;
            out.extend(inside.into_iter().map(|i| members[i]));
        }
        Ok(out)
    }

    /// Runs the finish hooks — the core's (an integrator is set, the plugins' requirements
    /// are met, every column is on the particles, which are one table of the store: see
    /// [`crate::store`]) and then those of the crates above, such as the pair sweeps binding
    /// their terms — and builds the schedule (idempotent).
    pub fn finish(&mut self) -> Result<(), SimError> {
        let hooks = std::mem::take(&mut self.finish_hooks);
        let done = hooks.iter().try_for_each(|(_, hook)| hook(self));
        self.finish_hooks = hooks;
        done?;
        self.build_schedule()
    }

    /// The requirements declared with [`Sim::require`] are met.
    pub(crate) fn check_requirements(&self) -> Result<(), SimError> {
        for (present, message) in &self.requirements {
            if !present(&self.world) {
                return Err(SimError::Build(message.clone()));
            }
        }
        Ok(())
    }

    /// Registers `hook` to run at every [`Sim::finish`], after the core's own checks of the
    /// store and before the schedule is built; a second hook of the same `name` is ignored.
    /// Crates above the core use it for what they own (the pair sweeps bind their terms).
    pub fn add_finish_hook(&mut self, name: &'static str, hook: FinishHook<V>) {
        if self.finish_hooks.iter().all(|(n, _)| *n != name) {
            self.finish_hooks.push((name, hook));
        }
    }

    /// True once the step's schedule is built (by the first [`Sim::finish`]).
    pub fn is_built(&self) -> bool {
        self.schedule.is_some()
    }

    /// The store holds every registered column of every particle in one table.
    pub(crate) fn check_store(&self) -> Result<(), SimError> {
        let unregistered = self.world.resource::<Columns>().unregistered(&self.world);
        if !unregistered.is_empty() {
            return Err(SimError::Build(format!(
                "the particles carry {}, which no plugin declared as a column (Sim::add_column): \
                 it would be neither written nor kept in checkpoints",
                unregistered.join(", ")
            )));
        }
        let tables = crate::store::particle_tables(&self.world);
        if tables > 1 {
            return Err(SimError::Build(format!(
                "the particles carry different sets of components ({tables} tables): a plugin \
                 added a component to only some of them"
            )));
        }
        if tables == 0 {
            return Ok(());
        }
        ParticleData::<V>::of(&self.world)
            .map(|_| ())
            .ok_or_else(|| SimError::Build("the particles lack a core component".into()))
    }

    /// Adds a system that zeroes every acceleration in [`StepSet::Forces`] and marks the
    /// accelerations as set ([`AccelerationsSet`]); the caller places it.
    pub fn add_zero_accelerations(&mut self) -> SystemOrder<'_> {
        self.world.insert_resource(AccelerationsSet);
        self.add_system(
            StepSet::Forces,
            "zero_accelerations",
            zero_accelerations::<V>,
        )
    }

    fn build_schedule(&mut self) -> Result<(), SimError> {
        if self.schedule.is_some() {
            return Ok(());
        }
        if !self.world.contains_resource::<AccelerationsSet>() {
            self.add_zero_accelerations();
        }
        self.world.init_resource::<StepPhase>();
        self.world.init_resource::<RatesStale>();
        self.has_population = self.systems.iter().any(|s| s.set == StepSet::Population);
        let mut schedule = Schedule::new(Step);
        schedule.set_executor(SingleThreadedExecutor::new());
        let order = self.ordered()?;
        for (pos, &k) in order.iter().enumerate() {
            let slot = Slot(pos);
            if pos > 0 {
                schedule.configure_sets(slot.after(Slot(pos - 1)));
            }
            let set = self.systems[k].set;
            schedule.configure_sets(slot.run_if(move |c: Res<SimClock>, p: Res<StepPhase>| {
                runs_in(*p, set, c.initializing)
            }));
            if let Some(add) = self.systems[k].add.take() {
                add(&mut schedule, slot);
            }
        }
        self.built_order = order.clone();
        self.labels = order
            .iter()
            .map(|&k| self.systems[k].place.label.clone())
            .collect();
        self.schedule = Some(schedule);
        Ok(())
    }

    /// Times every system of the step from now on (wall time per system, see
    /// [`crate::profile`]); read with [`Sim::profile`]. Builds the schedule if needed; a second
    /// call does nothing.
    pub fn enable_profile(&mut self) -> Result<(), SimError> {
        use crate::profile::{SystemTimes, begin_step, marker};
        self.finish()?;
        if self.world.contains_resource::<SystemTimes>() {
            return Ok(());
        }
        let n = self.labels.len();
        self.world
            .insert_resource(SystemTimes::new(self.labels.clone()));
        let Some(schedule) = self.schedule.as_mut() else {
            return Ok(());
        };
        schedule.add_systems(begin_step.in_set(Mark(None)));
        if n > 0 {
            schedule.configure_sets(Slot(0).after(Mark(None)));
        }
        for k in 0..n {
            schedule.add_systems(marker(k).in_set(Mark(Some(k))));
            schedule.configure_sets(Mark(Some(k)).after(Slot(k)));
            if k + 1 < n {
                schedule.configure_sets(Slot(k + 1).after(Mark(Some(k))));
            }
        }
        Ok(())
    }

    /// Wall time per system since [`Sim::enable_profile`], or `None` when not profiling.
    pub fn profile(&self) -> Option<&crate::profile::SystemTimes> {
        self.world.get_resource()
    }

    /// Evaluates neighbours, densities and rates at t = 0 without advancing (call once).
    pub fn initialize(&mut self) -> Result<(), SimError> {
        self.finish()?;
        self.world.resource_mut::<SimClock>().initializing = true;
        self.run_schedule();
        self.world.resource_mut::<SimClock>().initializing = false;
        self.failure()
    }

    /// Whether the run has reached its end ([`SimClock::at_end`] with the scene's step limit,
    /// [`StepLimit`](crate::output::StepLimit), when it has one).
    pub fn at_end(&self) -> bool {
        let limit = self.world.get_resource::<crate::output::StepLimit>();
        self.clock().at_end(limit.map(|l| l.0))
    }

    /// The failure a system reported ([`StepFailure`]) as a blow-up naming the step and time.
    fn failure(&self) -> Result<(), SimError> {
        match &self.world.resource::<StepFailure>().0 {
            Some(e) => {
                let c = self.clock();
                Err(SimError::BlowUp(format!(
                    "step {}, t = {:.6e}: {e}",
                    c.step, c.t
                )))
            }
            None => Ok(()),
        }
    }

    /// Advances one time step: the plugins' changes of the particles
    /// ([`StepSet::Population`]), the rates evaluated again if a plugin says they are stale
    /// ([`RatesStale`]), then the rest of the step ([`StepPhase`]).
    pub fn step(&mut self) -> Result<(), SimError> {
        if self.schedule.is_none() {
            self.initialize()?;
        }
        if self.has_population {
            self.run_phase(StepPhase::Population);
            let stale = &mut self.world.resource_mut::<RatesStale>().0;
            if std::mem::take(stale) {
                self.run_phase(StepPhase::Rates);
            }
            *self.world.resource_mut::<StepPhase>() = StepPhase::Step;
        }
        self.run_schedule();
        self.failure()
    }

    /// Runs the step's schedule in `phase` (left set: the caller sets it back).
    fn run_phase(&mut self, phase: StepPhase) {
        *self.world.resource_mut::<StepPhase>() = phase;
        self.run_schedule();
    }

    /// Runs the step's schedule on a thread of a rayon pool. Called from outside any pool,
    /// every parallel loop of the step would be injected into the global pool from outside:
    /// the caller sleeps and a worker wakes, a dozen times per step, and on a VM waking an
    /// idle vCPU takes tens of microseconds (`dualsph run` on 1 thread spent half its wall time
    /// waiting so). The pool is made at the first step with as many threads as the current
    /// pool ([`rayon::current_num_threads`]); a step called from inside a pool runs where it
    /// is. The sums do not depend on the pool (any block length gives the same bits).
    fn run_schedule(&mut self) {
        let Some(schedule) = self.schedule.as_mut() else {
            return;
        };
        let world = &mut self.world;
        if rayon::current_thread_index().is_some() {
            return schedule.run(world);
        }
        if self.pool.is_none() {
            self.pool = rayon::ThreadPoolBuilder::new()
                .num_threads(rayon::current_num_threads())
                .thread_name(|k| format!("dualsph-step-{k}"))
                .build()
                .ok();
        }
        match &self.pool {
            Some(pool) => pool.install(|| schedule.run(world)),
            None => schedule.run(world),
        }
    }

    /// The clock.
    pub fn clock(&self) -> SimClock {
        *self.world.resource::<SimClock>()
    }
}

fn zero_accelerations<V: Vector>(mut q: Query<&mut crate::components::Acceleration<V>>) {
    for mut a in &mut q {
        a.0 = V::zero();
    }
}
