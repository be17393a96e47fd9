//! The resources and settings a simulation is made of: its clock, kernel, domain, dt rule,
//! the particles' initial state and the static configuration.

use crate::kernels::{Kernel, KernelKind};
use crate::math::{Real, Vector};
use crate::neighbours::SkinRule;
use bevy_ecs::prelude::*;
use serde::{Deserialize, Serialize};

/// Time, step counter and dt.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct SimClock {
    /// Simulated time.
    pub t: Real,
    /// Completed steps.
    pub step: u64,
    /// Time step of the current (or last) step.
    pub dt: Real,
    /// True during the initial evaluation of rates at t = 0.
    pub initializing: bool,
    /// End time: the last dt is shortened to land on it exactly.
    pub t_end: Real,
}

impl SimClock {
    /// Whether a run has reached its end: the end time (to a relative 1e-12, the last dt
    /// having landed on it) or `max_steps` steps. The one stop condition of every run loop and
    /// of the samplers that record the last state.
    pub fn at_end(&self, max_steps: Option<u64>) -> bool {
        self.t >= self.t_end * (1.0 - 1e-12) || max_steps.is_some_and(|m| self.step >= m)
    }
}

/// The kernel of the scene, normalised for its dimension.
#[derive(Resource, Clone, Copy, Debug)]
pub struct KernelRes(pub Kernel);

/// The computational box.
#[derive(Resource, Clone, Copy, Debug)]
pub struct Domain<V: Vector> {
    /// Lower corner.
    pub min: V,
    /// Upper corner.
    pub max: V,
    /// The axes on which the box is periodic (see [`crate::neighbours::Period`]); the first
    /// `V::DIM` are read.
    pub periodic: [bool; 3],
}

impl<V: Vector> Domain<V> {
    /// The box `[min, max]` with no periodic axis.
    pub fn closed(min: V, max: V) -> Self {
        Domain {
            min,
            max,
            periodic: [false; 3],
        }
    }

    /// The period of the box, when an axis is periodic.
    pub fn period(&self) -> Option<crate::neighbours::Period<V>> {
        crate::neighbours::Period::new(self.min, self.max, self.periodic)
    }
}

/// How dt is chosen.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub enum TimeStepping {
    /// A fixed dt.
    Fixed(Real),
    /// `dt = min(C_cfl h_i/(c_i + |v_i|), C_f sqrt(h_i/|a_i|), C_v ρ_i h_i²/μ)`, capped by `max_dt`.
    Adaptive {
        /// Courant number (on the support radius h).
        courant: Real,
        /// Force criterion coefficient.
        force: Real,
        /// Viscous criterion coefficient.
        viscous: Real,
        /// Upper bound on dt.
        max_dt: Real,
    },
}

/// Largest kinematic viscosity source `μ` in the scene (set by viscosity plugins, used by dt).
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct MaxViscosity(pub Real);

/// Initial state of one particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParticleInit<V: Vector> {
    /// Position.
    pub pos: V,
    /// Velocity.
    pub vel: V,
    /// Mass.
    pub mass: Real,
    /// Density.
    pub density: Real,
    /// Support radius.
    pub h: Real,
    /// Specific internal energy (used only if an energy equation is added).
    pub internal_energy: Real,
    /// The body it belongs to (an index into [`crate::bodies::Bodies`]).
    pub body: u16,
}

/// The initial internal energies of the particles spawned before [`Sim::finish`](super::Sim::finish), by id:
/// their seeds' energies when the columns are put on them (dropped after).
#[derive(Resource, Clone, Debug, Default)]
pub struct InitialInternalEnergy(Vec<Real>);

impl InitialInternalEnergy {
    /// Records particle `id`'s energy.
    pub fn set(&mut self, id: u32, e: Real) {
        let i = id as usize;
        if self.0.len() <= i {
            self.0.resize(i + 1, 0.0);
        }
        self.0[i] = e;
    }

    /// Particle `id`'s energy (0 when none was recorded).
    pub fn get(&self, id: u32) -> Real {
        self.0.get(id as usize).copied().unwrap_or(0.0)
    }
}

/// Static settings of a simulation.
#[derive(Clone, Copy, Debug)]
pub struct SimConfig<V: Vector> {
    /// Kernel profile.
    pub kernel: KernelKind,
    /// Support/dual-support formulation.
    pub formulation: Formulation,
    /// Domain box.
    pub domain: Domain<V>,
    /// Verlet skin (fraction of h): of every build, or of the first with a tuned rule.
    pub skin: Real,
    /// How the skin of later builds is chosen.
    pub skin_rule: SkinRule,
    /// dt rule.
    pub time_stepping: TimeStepping,
}

/// How pair interactions are summed: the method and the paper's comparison cases (the pair
/// sweep of `dualsph-sweep` describes each). A scene names it by its variant
/// (`formulation: DualSupport`).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Formulation {
    /// Dual-support SPH: every pair interacts through the support of one particle and the
    /// dual-support of the other, once with its reaction, so momentum and energy are
    /// conserved exactly (§5 of Ren, Dai, Zhuang & Rabczuk, *Dual-support Smoothed Particle
    /// Hydrodynamics*, preprint; RenDSSPH in docs/references.md). The default.
    #[default]
    DualSupport,
    /// Variable-h SPH that uses only each particle's own support, without the reaction (not
    /// exactly conservative).
    SingleSupport,
    /// Classical SPH with one common smoothing length for all particles.
    ConstantH,
    /// Variable-h SPH symmetrised by averaging the two kernels of a pair over the union of
    /// support and dual-support (Eq. 2.13).
    AveragedKernel,
    /// Grad-h SPH (Springel & Hernquist 2002; Price 2012): h tied to the summation density at
    /// every step, `h_i = n (m_i/ρ_i)^{1/d}` with `ρ_i = Σ_j m_j W(r_ij, h_i)` solved together
    /// (n from the scene's `SmoothingLengthUpdate`), and the Ω terms in the pressure and
    /// viscous forces. Its pair forces are support/dual-support pairs (the owner's pressure
    /// with the owner's kernel, the reaction to the neighbour), so it runs on the
    /// dual-support sweep; the h solve and Ω come from the smoothing-length plugin. Needs
    /// `SummationDensity()` and `SmoothingLengthUpdate(...)`.
    GradH,
}

impl Formulation {
    /// Every formulation, in declaration order.
    pub const ALL: [Formulation; 5] = [
        Formulation::DualSupport,
        Formulation::SingleSupport,
        Formulation::ConstantH,
        Formulation::AveragedKernel,
        Formulation::GradH,
    ];

    /// The name a scene gives it (`DualSupport`, `GradH`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Formulation::DualSupport => "DualSupport",
            Formulation::SingleSupport => "SingleSupport",
            Formulation::ConstantH => "ConstantH",
            Formulation::AveragedKernel => "AveragedKernel",
            Formulation::GradH => "GradH",
        }
    }
}

impl std::fmt::Display for Formulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Formulation {
    type Err = String;
    /// The formulation of a scene name (`DualSupport`).
    fn from_str(s: &str) -> Result<Self, String> {
        Formulation::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Formulation::ALL.iter().map(|f| f.name()).collect();
                format!(
                    "unknown formulation `{s}`, expected one of {}",
                    names.join(", ")
                )
            })
    }
}

/// Why the last step failed, as reported by one of its systems — the health check (an
/// unphysical value), the fixed time step's CFL check, the population when the id space is
/// exhausted, a refinement that cannot split: [`Sim::step`](crate::sim::Sim::step) (and
/// [`Sim::initialize`](crate::sim::Sim::initialize)) return it as a blow-up naming the step
/// and time. The one failure channel of a step: the first failure a step reports stands
/// ([`StepFailure::fail`]).
#[derive(Resource, Debug, Default)]
pub struct StepFailure(pub Option<String>);

impl StepFailure {
    /// Records `why` unless a failure is already recorded (the first cause stands).
    pub fn fail(&mut self, why: impl FnOnce() -> String) {
        if self.0.is_none() {
            self.0 = Some(why());
        }
    }
}

/// The name of the simulation's one time-integration scheme, once its plugin has set it
/// (through `dualsph_integrate::SimIntegrate::set_integrator`, which holds the scheme); at
/// [`Sim::finish`](crate::sim::Sim::finish) a simulation without one is refused, as its state
/// would not advance.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct IntegratorName(pub Option<&'static str>);

#[cfg(test)]
mod tests {
    use super::Formulation;

    #[test]
    fn every_formulation_is_listed_once_and_parses_from_its_name() {
        for (k, f) in Formulation::ALL.into_iter().enumerate() {
            // declaration order: the index is the variant's (its serialized form)
            assert_eq!(f as usize, k);
            assert_eq!(f.name().parse::<Formulation>(), Ok(f));
        }
        let e = "single-support".parse::<Formulation>().unwrap_err();
        assert!(
            e.contains("expected one of DualSupport, SingleSupport"),
            "{e}"
        );
    }
}
