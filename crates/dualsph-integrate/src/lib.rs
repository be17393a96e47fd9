//! What is integrated in time, as data: the registry of integrated quantities and the slot of
//! the one time-integration scheme, added to [`Sim`] by [`SimIntegrate`] (the core keeps only
//! the scheme's name, `IntegratorName`, and refuses a simulation without one). The schemes themselves are plugins (the `dualsph-integrator`
//! crate: the leapfrog predictor–corrector of §6 and a position Verlet); the core holds no
//! update formula.
//!
//! **Quantities.** Position (advanced by the velocity) and velocity (by the acceleration) are
//! integrated in every simulation: a scheme updates `Position`, `Velocity` and
//! `Acceleration` itself. Any other per-particle scalar `x` with `dx/dt = ẋ` is declared by
//! the plugin that needs it, [`SimIntegrate::integrate`]`::<S, R>()`: the column `S` is advanced by the
//! rate `R` that the step's systems compute (the continuity equation's `Density` by
//! `DensityRate`, the energy equation's `InternalEnergy` by `EnergyRate`: see
//! `dualsph_fluid::ensure_density_integration` and `ensure_energy_equation`).
//!
//! **Schemes.** A scheme is a [`Scheme`] set once per simulation ([`SimIntegrate::set_integrator`]; a
//! second one is an error naming both). It adds its own systems for the kinematics, and for
//! every declared scalar — declared before or after it is set — it is handed a
//! [`ScalarEquation`], through which it adds systems that run a per-block kernel
//! ([`ScalarKernel`]) over the scalar's values, rates and two registers per particle
//! ([`Registers`], a column the scheme adds and owns: its start-of-step values).
//!
//! An integrated scalar and its rate are `#[repr(transparent)]` wrappers of one real, so the
//! scalar systems hand the scheme's kernel the columns themselves as slices of reals, a
//! block of up to [`BLOCK`] particles at a time: the scheme's loop is a plain array loop,
//! compiled once, whatever the column's type, and no value is copied. Each particle is
//! updated from its own data, so the result does not depend on the number of threads.

#![warn(missing_docs)]

use bevy_ecs::component::Mutable;
use bevy_ecs::prelude::*;
use bytemuck::TransparentWrapper;
use dualsph_core::chunks::{DENSE, MIN_LEN};
use dualsph_core::columns::{ColumnSpec, ColumnValue, Shape};
use dualsph_core::components::Density;
use dualsph_core::math::{Real, Vector};
use dualsph_core::sim::{IntegratorName, Sim, SimClock, SimError, StepSet, SystemOrder};
use rayon::prelude::*;
use std::any::TypeId;
use std::marker::PhantomData;
use std::sync::Arc;

/// A per-particle scalar that can be integrated in time (the `x` of `dx/dt = ẋ`): a
/// `#[repr(transparent)]` wrapper of one real, so that a column of it is a slice of reals
/// (the schemes' kernels run on the column itself, with no copy).
pub trait ScalarState: Component<Mutability = Mutable> + TransparentWrapper<Real> {}

/// A per-particle rate `ẋ` of an integrated scalar, written by the step's systems: a
/// `#[repr(transparent)]` wrapper of one real, like [`ScalarState`].
pub trait ScalarRate: Component + TransparentWrapper<Real> {}

impl ScalarState for Density {}

/// A scheme's two reals of one particle (see [`Registers`]).
pub type Pair = [Real; 2];

/// Two reals per particle that a scheme keeps for the integrated scalar `S` (e.g. its value
/// and rate at the start of the step). Added, as a column, by the scheme that uses them
/// ([`ScalarEquation::add_registers`]); no other system reads them.
#[derive(Component, TransparentWrapper)]
#[repr(transparent)]
#[transparent(Pair)]
pub struct Registers<S: Send + Sync + 'static> {
    /// The values, in the scheme's own meaning.
    pub values: Pair,
    _of: PhantomData<fn() -> S>,
}

impl<S: Send + Sync + 'static> Default for Registers<S> {
    fn default() -> Self {
        Registers {
            values: [0.0; 2],
            _of: PhantomData,
        }
    }
}

impl<S: Send + Sync + 'static> std::fmt::Debug for Registers<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Registers({:?})", self.values)
    }
}

impl<V: Vector, S: Send + Sync + 'static> ColumnValue<V> for Registers<S> {
    const SHAPE: Shape = Shape::Record;
    fn width() -> usize {
        2
    }
    fn put(&self, out: &mut Vec<Real>) {
        out.extend(self.values);
    }
    fn take(&mut self, values: &[Real]) {
        self.values = [values[0], values[1]];
    }
}

/// Particles updated per call of a [`ScalarKernel`] (the last block of a table may be
/// shorter).
pub const BLOCK: usize = 512;

/// One block of particles of an integrated scalar, as arrays of reals of equal length.
#[derive(Debug)]
pub struct ScalarRows<'a> {
    /// The values `x_i`; what the kernel leaves here is the new value.
    pub value: &'a mut [Real],
    /// The rates `ẋ_i` from the last evaluation.
    pub rate: &'a [Real],
    /// The scheme's [`Registers`] of each particle, kept from step to step.
    pub registers: &'a mut [[Real; 2]],
}

/// A scheme's update of one block of an integrated scalar (the clock gives dt).
pub type ScalarKernel = Arc<dyn Fn(&SimClock, ScalarRows<'_>) + Send + Sync>;

/// An integrated scalar with its types erased: what a [`Scheme`] needs to update it.
pub trait ScalarEquation<V: Vector>: Send + Sync {
    /// The name of the quantity (`density`, `internal_energy`), for system labels.
    fn name(&self) -> &'static str;
    /// Adds the [`Registers`] column of this scalar to every particle (zeros), named
    /// `<name>_registers`: kept in checkpoints when `restart` (values that a step reads before
    /// it writes them), scratch otherwise.
    fn add_registers(&self, sim: &mut Sim<V>, restart: bool) -> Result<(), SimError>;
    /// Adds a system to `set` that runs `kernel` over every block of particles.
    fn add_system<'s>(
        &self,
        sim: &'s mut Sim<V>,
        set: StepSet,
        label: String,
        kernel: ScalarKernel,
    ) -> SystemOrder<'s>;
}

/// The equation `dS/dt = R`.
struct Equation<S, R> {
    name: &'static str,
    registers: &'static str,
    _types: PhantomData<fn() -> (S, R)>,
}

impl<V: Vector, S: ScalarState, R: ScalarRate> ScalarEquation<V> for Equation<S, R> {
    fn name(&self) -> &'static str {
        self.name
    }

    fn add_registers(&self, sim: &mut Sim<V>, restart: bool) -> Result<(), SimError> {
        let spec = match restart {
            true => ColumnSpec::restart_only(self.registers),
            false => ColumnSpec::scratch(self.registers),
        };
        sim.add_column(spec, |_| Registers::<S>::default())
    }

    fn add_system<'s>(
        &self,
        sim: &'s mut Sim<V>,
        set: StepSet,
        label: String,
        kernel: ScalarKernel,
    ) -> SystemOrder<'s> {
        let system = move |clock: Res<SimClock>, q: Query<(&mut S, &R, &mut Registers<S>)>| {
            run_blocks(&clock, q, &*kernel)
        };
        sim.add_system(set, label, system).in_group::<Updates<S>>()
    }
}

/// The systems a scheme adds to update the integrated scalar `S` (see
/// [`ScalarEquation::add_system`]): what must see `S` updated in a set runs after them.
pub struct Updates<S>(PhantomData<fn() -> S>);

impl<S: 'static> dualsph_core::order::SystemGroup for Updates<S> {}

/// Runs `kernel` over the particles in blocks of [`BLOCK`], in parallel over blocks, on the
/// columns themselves (their reals: see [`ScalarState`]).
#[inline(never)] // a frame of its own in profiles
fn run_blocks<S: ScalarState, R: ScalarRate>(
    clock: &SimClock,
    mut q: Query<(&mut S, &R, &mut Registers<S>)>,
    kernel: &(dyn Fn(&SimClock, ScalarRows<'_>) + Send + Sync),
) {
    for (mut s, r, mut regs) in q.contiguous_iter_mut().expect(DENSE) {
        // the engine reads no change ticks (see `dualsph_core::chunks`)
        let value = S::peel_slice_mut(s.bypass_change_detection());
        let rate = R::peel_slice(r);
        let registers = Registers::<S>::peel_slice_mut(regs.bypass_change_detection());
        let blocks = value.par_chunks_mut(BLOCK).zip(rate.par_chunks(BLOCK));
        let blocks = blocks.zip(registers.par_chunks_mut(BLOCK));
        let blocks = blocks.with_min_len(MIN_LEN.div_ceil(BLOCK));
        blocks.for_each(|((value, rate), registers)| {
            let rows = ScalarRows {
                value,
                rate,
                registers,
            };
            kernel(clock, rows)
        });
    }
}

/// `s` as a `&'static str`, leaked once per distinct string of the process (column names are
/// static; a scalar's registers are named after it).
fn intern(s: String) -> &'static str {
    use std::collections::BTreeSet;
    use std::sync::{Mutex, OnceLock};
    static NAMES: OnceLock<Mutex<BTreeSet<&'static str>>> = OnceLock::new();
    let mut names = NAMES
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    if let Some(known) = names.get(s.as_str()) {
        return known;
    }
    let name: &'static str = Box::leak(s.into_boxed_str());
    names.insert(name);
    name
}

/// A time-integration scheme: the one plugin of a simulation that advances its state.
pub trait Scheme<V: Vector>: Send + Sync + 'static {
    /// The plugin's name (`LeapfrogPC`), for messages and the plan.
    fn name(&self) -> &'static str;
    /// Adds the scheme's systems for one declared scalar (called once per scalar, whenever
    /// it is declared; the systems are attributed to the scheme's plugin).
    fn integrate_scalar(
        &self,
        sim: &mut Sim<V>,
        equation: &dyn ScalarEquation<V>,
    ) -> Result<(), SimError>;
}

/// The integrated scalars and the scheme of a simulation.
#[derive(Resource)]
struct Integration<V: Vector> {
    /// The declared scalars, in declaration order, with the type of their column.
    equations: Vec<(TypeId, Arc<dyn ScalarEquation<V>>)>,
    /// The scheme, once set.
    scheme: Option<Arc<dyn Scheme<V>>>,
}

impl<V: Vector> Default for Integration<V> {
    fn default() -> Self {
        Integration {
            equations: Vec::new(),
            scheme: None,
        }
    }
}

/// The simulation's [`Integration`], added empty the first time it is asked for.
fn integration<V: Vector>(sim: &mut Sim<V>) -> Mut<'_, Integration<V>> {
    sim.world.get_resource_or_init::<Integration<V>>()
}

/// What a [`Sim`] integrates in time, and its scheme.
pub trait SimIntegrate<V: Vector> {
    /// Declares that column `S` is advanced in time by the rate `R` (`name` labels the
    /// scheme's systems). Declaring the same `S` again does nothing; returns true the first
    /// time. The columns themselves are added by the caller (`Sim::add_column`).
    fn integrate<S: ScalarState, R: ScalarRate>(
        &mut self,
        name: &'static str,
    ) -> Result<bool, SimError>;
    /// The names of the declared scalars, in declaration order.
    fn integrated_scalars(&self) -> Vec<&'static str>;
    /// Sets the time-integration scheme (called by its plugin's `build`) and lets it add its
    /// systems for the scalars declared so far. A simulation has one scheme: a second is an
    /// error that names both.
    fn set_integrator(&mut self, scheme: impl Scheme<V>) -> Result<(), SimError>;
    /// The name of the scheme, once set.
    fn integrator(&self) -> Option<&'static str>;
}

impl<V: Vector> SimIntegrate<V> for Sim<V> {
    fn integrate<S: ScalarState, R: ScalarRate>(
        &mut self,
        name: &'static str,
    ) -> Result<bool, SimError> {
        let id = TypeId::of::<S>();
        if integration(self).equations.iter().any(|(t, _)| *t == id) {
            return Ok(false);
        }
        let equation: Arc<dyn ScalarEquation<V>> = Arc::new(Equation::<S, R> {
            name,
            registers: intern(format!("{name}_registers")),
            _types: PhantomData,
        });
        let mut integration = integration(self);
        integration.equations.push((id, equation.clone()));
        if let Some(scheme) = integration.scheme.clone() {
            self.as_plugin(scheme.name(), |sim| {
                scheme.integrate_scalar(sim, &*equation)
            })?;
        }
        Ok(true)
    }

    fn integrated_scalars(&self) -> Vec<&'static str> {
        let eqs = self.world.get_resource::<Integration<V>>();
        eqs.map_or(Vec::new(), |i| {
            i.equations.iter().map(|(_, e)| e.name()).collect()
        })
    }

    fn set_integrator(&mut self, scheme: impl Scheme<V>) -> Result<(), SimError> {
        if let Some(first) = &integration(self).scheme {
            return Err(SimError::Build(format!(
                "two integrators, {} and {}: a simulation is advanced by one (remove one of them)",
                first.name(),
                scheme.name()
            )));
        }
        let scheme: Arc<dyn Scheme<V>> = Arc::new(scheme);
        let mut integration = integration(self);
        integration.scheme = Some(scheme.clone());
        let equations: Vec<_> = integration.equations.to_vec();
        self.world.resource_mut::<IntegratorName>().0 = Some(scheme.name());
        self.as_plugin(scheme.name(), |sim| {
            for (_, equation) in &equations {
                scheme.integrate_scalar(sim, &**equation)?;
            }
            Ok(())
        })
    }

    fn integrator(&self) -> Option<&'static str> {
        self.world.resource::<IntegratorName>().0
    }
}
