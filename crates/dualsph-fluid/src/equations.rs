//! The energy and continuity equations as integrated scalars: each is added once, by the
//! first plugin that needs it, with its columns and its declaration to the scene's scheme
//! (`SimIntegrate::integrate`).

use crate::components::{DensityRate, Dissipated, DissipationRate, EnergyRate, InternalEnergy};
use bevy_ecs::prelude::Resource;
use dualsph_core::columns::ColumnSpec;
use dualsph_core::components::Density;
use dualsph_core::math::Vector;
use dualsph_core::sim::{Sim, SimError};
use dualsph_integrate::SimIntegrate;

/// The name under which [`ensure_energy_equation`] declares the internal energy (what a
/// scheme sees as `ScalarEquation::name`).
pub const INTERNAL_ENERGY: &str = "internal_energy";

/// The name of the dissipated energy as an integrated scalar ([`ensure_dissipation`]).
pub const DISSIPATED: &str = "dissipated";

/// Present once the energy equation is solved ([`ensure_energy_equation`]).
#[derive(Resource, Debug, Default)]
pub struct EnergyEquation;

/// Present once the dissipated energy is tracked apart ([`ensure_dissipation`]).
#[derive(Resource, Debug, Default)]
pub struct Dissipation;

/// Present once the density is integrated by the continuity equation
/// ([`ensure_density_integration`]).
#[derive(Resource, Debug, Default)]
pub struct DensityIntegration;

/// Adds the internal-energy equation once: [`InternalEnergy`] (initial ε from the scene) and
/// [`EnergyRate`] on every particle, and declares `dε/dt` integrated.
pub fn ensure_energy_equation<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if !sim.enable::<EnergyEquation>() {
        return Ok(());
    }
    let spec = ColumnSpec::state("internal_energy", "e");
    sim.add_column(spec, |seed| InternalEnergy(seed.init.internal_energy))?;
    let spec = ColumnSpec::restart_only("energy_rate");
    sim.add_column(spec, move |_| EnergyRate { rate: 0.0 })?;
    sim.integrate::<InternalEnergy, EnergyRate>(INTERNAL_ENERGY)?;
    Ok(())
}

/// Adds the dissipated-energy channel once (with the energy equation): [`Dissipated`] (0 at
/// the start; written to snapshots as `dissipated` and kept in checkpoints) and
/// [`DissipationRate`] on every particle, and declares `dd/dt` integrated by the scene's
/// scheme with the same rule as the internal energy's rates. A dissipative pair term sums its
/// heat into `DissipationRate` as well as into the power
/// ([`crate::FluidSums::dissipation`]).
pub fn ensure_dissipation<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    ensure_energy_equation(sim)?;
    if !sim.enable::<Dissipation>() {
        return Ok(());
    }
    let spec = ColumnSpec::state(DISSIPATED, "e_diss");
    sim.add_column(spec, |_| Dissipated(0.0))?;
    let spec = ColumnSpec::restart_only("dissipation_rate");
    sim.add_column(spec, move |_| DissipationRate { rate: 0.0 })?;
    sim.integrate::<Dissipated, DissipationRate>(DISSIPATED)?;
    Ok(())
}

/// Adds the integrated density (continuity) once: [`DensityRate`] on every particle, and
/// declares `dρ/dt` integrated into the core's [`Density`].
pub fn ensure_density_integration<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if !sim.enable::<DensityIntegration>() {
        return Ok(());
    }
    let spec = ColumnSpec::restart_only("density_rate");
    sim.add_column(spec, move |_| DensityRate { rate: 0.0 })?;
    sim.integrate::<Density, DensityRate>("density")?;
    Ok(())
}
