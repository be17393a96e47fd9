//! The default plugin group of `dualsph`: every built-in plugin under the name RON scenes use
//! ([`plugins`]), a registry holding them all ([`default_registry`]) and the fusions of their
//! pair terms ([`fuse_builtin_terms`]).
#![warn(missing_docs)]

use dualsph_fluid::prelude::*;

/// The built-in plugins, by the names used in RON scenes.
pub mod plugins {
    pub use dualsph_density::{
        ContinuityDensity, ContinuityForm, DensityDiffusion, SummationDensity,
    };
    pub use dualsph_diagnostics::DiagnosticsPlugin;
    pub use dualsph_eos::{HydrostaticStart, IdealGas, InitialPressure, TaitEos};
    pub use dualsph_gravity::Gravity;
    pub use dualsph_heat::HeatConduction;
    pub use dualsph_inout::{InflowBoundary, Inlet, OutflowBoundary, Outlet};
    pub use dualsph_integrator::{EnergyUpdate, LeapfrogPC, PositionVerlet};
    pub use dualsph_kernel_correction::KernelCorrection;
    pub use dualsph_motion::Prescribed;
    pub use dualsph_pressure::{ArtificialStress, PressureForce};
    pub use dualsph_probes::{Probe, Probes, Quantity, Vorticity};
    pub use dualsph_refinement::Refinement;
    pub use dualsph_shifting::{ParticleShifting, TransportVelocity};
    pub use dualsph_smoothing_length::SmoothingLengthUpdate;
    pub use dualsph_surface_tension::SurfaceTension;
    pub use dualsph_viscosity::{ArtificialViscosity, NewtonianViscosity, PhysicalViscosity};
    pub use dualsph_walls::{SpecularWalls, WallPressure};
}

/// A registry with every built-in plugin and the scene sections the built-in plugins own
/// (`integrator`: [`IntegratorSettings`](dualsph_integrator::IntegratorSettings), `health`:
/// [`HealthSettings`](dualsph_diagnostics::HealthSettings)); add your own with
/// `register::<YourPlugin>()`.
pub fn default_registry() -> Registry {
    use plugins::*;
    let mut r = Registry::new();
    r.register_body_kind::<dualsph_core::bodies::Fluid>()
        .register_body_kind::<dualsph_core::bodies::Fixed>()
        .register_body_kind::<dualsph_motion::Prescribed>()
        .register_body_kind::<dualsph_inout::Buffer>();
    r.register_section::<dualsph_integrator::IntegratorSettings>()
        .register_section::<dualsph_diagnostics::HealthSettings>()
        .register::<LeapfrogPC>()
        .register::<PositionVerlet>()
        .register::<DiagnosticsPlugin>()
        .register::<SummationDensity>()
        .register::<ContinuityDensity>()
        .register::<DensityDiffusion>()
        .register::<TaitEos>()
        .register::<HydrostaticStart>()
        .register::<InitialPressure>()
        .register::<IdealGas>()
        .register::<PressureForce>()
        .register::<ArtificialStress>()
        .register::<ArtificialViscosity>()
        .register::<PhysicalViscosity>()
        .register::<NewtonianViscosity>()
        .register::<HeatConduction>()
        .register::<KernelCorrection>()
        .register::<SmoothingLengthUpdate>()
        .register::<Gravity>()
        .register::<SpecularWalls>()
        .register::<WallPressure>()
        .register::<Inlet>()
        .register::<Outlet>()
        .register::<InflowBoundary>()
        .register::<OutflowBoundary>()
        .register::<Probes>()
        .register::<Vorticity>()
        .register::<SurfaceTension>()
        .register::<ParticleShifting>()
        .register::<TransportVelocity>()
        .register::<Refinement>();
    r
}

/// Declares the fusions of the built-in terms in the orders the scenes list them (see
/// [`dualsph_sweep::Fused`]): continuity, pressure, then artificial viscosity or the
/// viscous stress, then the density diffusion or the cohesion — each fused chain runs as one
/// compiled row loop. The results do not depend on it.
pub fn fuse_builtin_terms<V: Vector>(sim: &mut Sim<V>) {
    use dualsph_density::ContinuityTerm as C;
    use dualsph_density::diffusion::DiffusionTerm as D;
    use dualsph_pressure::PressureTerm as P;
    use dualsph_surface_tension::CohesionTerm as S;
    use dualsph_sweep::Fused;
    use dualsph_viscosity::{ArtificialViscosityTerm as Av, ViscousStressTerm as Nv};
    type Cp = Fused<C, P>;
    sim.fuse::<C, P>()
        .fuse::<Cp, Av>()
        .fuse::<Cp, Nv>()
        .fuse::<Fused<Cp, Av>, D>()
        .fuse::<Fused<Cp, Nv>, D>()
        .fuse::<Fused<Cp, Av>, S>()
        .fuse::<P, Av>()
        .fuse::<Av, P>()
        .fuse::<P, Nv>()
        .fuse::<Fused<P, Nv>, D>();
}
