//! `InitialPressure(field: TaylorGreen(speed: U, wavelength: L))`: the fluid starts with a
//! given pressure field, each particle's density set from it by the inverse of its body's
//! equation of state (and its mass scaled with it, `m ← m ρ/ρ_gen`, so that its volume stays
//! the lattice cell it was generated in, as for `HydrostaticStart`).
//!
//! A weakly compressible flow started from the right velocity but a uniform pressure is not
//! in its own equilibrium: the missing pressure gradient launches sound waves of amplitude
//! `≈ ρU²` that ring through the run. Peers start the Taylor–Green vortex from its pressure
//! (TrixiParticles.jl's `taylor_green_vortex_2d.jl`; Adami, Hu & Adams 2013, §4.2).
//!
//! **`TaylorGreen`**: the pressure of the vortex `u = U sin(kx) cos(ky)`,
//! `v = −U cos(kx) sin(ky)` (`k = 2π/L`, the scene's `TaylorGreen` velocity), from the steady
//! Euler balance `∇p = −ρ(u·∇)u`:
//!
//! `p = (ρ0 U²/4) (cos(2kx) + cos(2ky))`
//!
//! (Taylor & Green 1937, *Proc. R. Soc. Lond. A* 158, 499), with `ρ0` the body's reference
//! density. The state is set once, in the initial evaluation before any density pass (a
//! resumed run takes its state from the checkpoint); bodies that are not fluid are left as
//! generated.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::Bodies;
use dualsph_fluid::prelude::*;
use dualsph_fluid::{BodyEos, Liquid};
use serde::{Deserialize, Serialize};

/// A pressure field given in closed form (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub enum PressureField {
    /// The Taylor–Green vortex's pressure (module docs).
    TaylorGreen {
        /// `U`, the vortex's velocity scale (m/s).
        speed: Real,
        /// `L`, its wavelength (m).
        wavelength: Real,
    },
}

impl PressureField {
    /// The pressure at `x` in a liquid of reference density `rho0`.
    pub fn at<V: Vector>(&self, x: V, rho0: Real) -> Real {
        match *self {
            PressureField::TaylorGreen { speed, wavelength } => {
                let k2 = 4.0 * std::f64::consts::PI / wavelength;
                let (x, y) = (x.get(0), if V::DIM > 1 { x.get(1) } else { 0.0 });
                0.25 * rho0 * speed * speed * (libm::cos(k2 * x) + libm::cos(k2 * y))
            }
        }
    }
}

/// The fluid starts with a given pressure (module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InitialPressure {
    /// The field.
    pub field: PressureField,
}

/// The field as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct StartPressure(pub PressureField);

/// Sets the density and mass of the fluid from the field (module docs), in the initial
/// evaluation only.
pub fn pressure_start<V: Vector>(
    clock: Res<SimClock>,
    field: Res<StartPressure>,
    laws: Res<BodyEos>,
    bodies: Res<Bodies>,
    mut q: Query<(&Position<V>, &BodyId, &mut Density, &mut Mass)>,
) {
    if !clock.initializing {
        return;
    }
    crate::start_from_pressure(&bodies, &laws, &mut q, |r, eos| {
        let rho0 = eos.reference_density()?;
        Some(field.0.at(r, rho0))
    });
}

impl SimPlugin for InitialPressure {
    const NAME: &'static str = "InitialPressure";
    const SUMMARY: &'static str =
        "the fluid starts with a given pressure field (its density from the equation of state)";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        match self.field {
            PressureField::TaylorGreen { speed, wavelength } => {
                if info.dimension != 2 {
                    return Err(format!(
                        "field: TaylorGreen is a 2-D vortex, the scene has dimension {}",
                        info.dimension
                    ));
                }
                if !speed.is_finite() {
                    return Err(format!("field.speed: must be finite, got {speed}"));
                }
                if !(wavelength.is_finite() && wavelength > 0.0) {
                    return Err(format!("field.wavelength: must be > 0, got {wavelength}"));
                }
            }
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require::<Liquid>("InitialPressure needs a liquid (TaitEos)");
        sim.world.insert_resource(StartPressure(self.field));
        // Before any density pass of the initial evaluation (the Density set follows).
        sim.add_system(
            StepSet::Neighbours,
            "initial_pressure (rho from the equation of state)",
            pressure_start::<V>,
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// The field balances the vortex's convective acceleration: `∇p = −ρ(u·∇)u`, checked by
    /// central differences at a few points.
    #[test]
    fn taylor_green_pressure_balances_the_vortex() {
        let (u0, l, rho0) = (1.5, 0.8, 2.0);
        let f = PressureField::TaylorGreen {
            speed: u0,
            wavelength: l,
        };
        let k = 2.0 * std::f64::consts::PI / l;
        let vel = |x: DVec2| {
            DVec2::new(
                u0 * libm::sin(k * x.x) * libm::cos(k * x.y),
                -u0 * libm::cos(k * x.x) * libm::sin(k * x.y),
            )
        };
        let e = 1e-6;
        for x in [
            DVec2::new(0.1, 0.3),
            DVec2::new(0.37, 0.05),
            DVec2::new(0.6, 0.7),
        ] {
            let (dx, dy) = (DVec2::new(e, 0.0), DVec2::new(0.0, e));
            let grad_p = DVec2::new(
                f.at(x + dx, rho0) - f.at(x - dx, rho0),
                f.at(x + dy, rho0) - f.at(x - dy, rho0),
            ) / (2.0 * e);
            let u = vel(x);
            let du_dx = (vel(x + dx) - vel(x - dx)) / (2.0 * e);
            let du_dy = (vel(x + dy) - vel(x - dy)) / (2.0 * e);
            let convective = du_dx * u.x + du_dy * u.y;
            let residual = grad_p + convective * rho0;
            assert!(residual.length() < 1e-7, "{x}: {residual}");
        }
    }
}
