//! `HydrostaticStart(surface: H)`: the fluid starts at rest in hydrostatic equilibrium under
//! the scene's gravity, below a free surface at height `H` (measured along `−g`: `y = H` in
//! 2-D with `g = [0, −9.81]`).
//!
//! The equilibrium of a weakly compressible liquid at depth `s` below the surface is
//! `dp/ds = ρ(p) |g|`, with `ρ(p)` the inverse of the Tait equation (Eq. 7.5 with the
//! background pressure), `ρ = ρ0 u^{1/γ}`, `u = 1 + (p − p_b)/p0`. Separating variables,
//! `u^{−1/γ} du = (ρ0 |g| / p0) ds`, gives the pressure in closed form
//!
//! `p(s) = p_b + p0 [(1 + ((γ − 1)/γ) ρ0 |g| s / p0)^{γ/(γ−1)} − 1]`
//!
//! (`p_b + p0 (exp(ρ0 |g| s / p0) − 1)` for γ = 1), which tends to `ρ0 |g| s` as `c0 → ∞`.
//! Every particle of a fluid body below the surface takes the density `ρ(p(s))`, and its
//! mass is scaled with it (`m ← m ρ/ρ_gen`, with `ρ_gen` the density it was generated at),
//! so that its volume `m/ρ` stays the lattice cell it was generated in. Without the mass
//! scaling the particle volumes would sum to less than the space the lattice fills, by the
//! compression `ρ/ρ0 − 1 ≈ |g| s / c0²`, and the discrete pressure gradient would carry
//! the column's weight only at a pressure higher by that much: the fluid then rocks and
//! settles at a pressure above the hydrostatic one.
//!
//! The state is set once, in the initial evaluation before any density pass (a resumed run
//! takes its state from the checkpoint instead). Particles above the surface, and those of
//! fixed or prescribed bodies (whose density a wall model sets, or which evolve their own),
//! are left as generated.

use crate::Eos;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::Bodies;
use dualsph_fluid::BodyEos;
use dualsph_fluid::prelude::*;
use dualsph_fluid::{GravityField, Liquid};
use dualsph_gravity::GravityAccel;
use serde::{Deserialize, Serialize};

/// The fluid starts hydrostatic below a free surface (module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HydrostaticStart {
    /// The height `H` of the free surface along `−g` (m).
    pub surface: Real,
}

/// `H` as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct SurfaceLevel(pub Real);

impl Eos {
    /// The pressure at depth `s` below a free surface at rest under gravity `|g|` (module
    /// docs), for a liquid; `None` for a gas, whose equilibrium depends on its temperature
    /// profile (the law's `EosLaw::hydrostatic_pressure`).
    pub fn hydrostatic_pressure(&self, g: Real, s: Real) -> Option<Real> {
        match *self {
            Eos::Tait {
                rho0,
                gamma,
                p0,
                p_b,
                ..
            } => {
                let head = rho0 * g * s / p0;
                let u = if gamma == 1.0 {
                    libm::exp(head)
                } else {
                    libm::pow(1.0 + (gamma - 1.0) / gamma * head, gamma / (gamma - 1.0))
                };
                Some(p_b + p0 * (u - 1.0))
            }
            Eos::Ideal { .. } => None,
        }
    }
}

/// Sets the hydrostatic density and mass of the fluid below the surface (module docs), in
/// the initial evaluation only.
pub fn hydrostatic_start<V: Vector>(
    clock: Res<SimClock>,
    level: Res<SurfaceLevel>,
    gravity: Res<GravityAccel<V>>,
    laws: Res<BodyEos>,
    bodies: Res<Bodies>,
    mut q: Query<(&Position<V>, &BodyId, &mut Density, &mut Mass)>,
) {
    if !clock.initializing {
        return;
    }
    let g = gravity.0.length();
    let down = gravity.0 * (1.0 / g);
    crate::start_from_pressure(&bodies, &laws, &mut q, |r, eos| {
        let depth = level.0 + r.dot(down);
        if depth <= 0.0 {
            return None;
        }
        eos.hydrostatic_pressure(g, depth)
    });
}

impl SimPlugin for HydrostaticStart {
    const NAME: &'static str = "HydrostaticStart";
    const SUMMARY: &'static str =
        "the fluid starts at rest in hydrostatic equilibrium below a free surface";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !self.surface.is_finite() {
            return Err(format!("surface: must be finite, got {}", self.surface));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require::<GravityField>("HydrostaticStart needs Gravity");
        sim.require::<Liquid>("HydrostaticStart needs a liquid (TaitEos)");
        sim.world.insert_resource(SurfaceLevel(self.surface));
        // Before any density pass of the initial evaluation (the Density set follows).
        sim.add_system(
            StepSet::Neighbours,
            "hydrostatic_start (dp/ds = rho(p) g)",
            hydrostatic_start::<V>,
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn water(c0: Real) -> Eos {
        let (rho0, gamma) = (1000.0, 7.0);
        Eos::Tait {
            rho0,
            gamma,
            p0: c0 * c0 * rho0 / gamma,
            c0,
            p_min: Real::NEG_INFINITY,
            p_b: 0.0,
            rho_min: Real::NEG_INFINITY,
        }
    }

    /// The closed form against a fine RK4 integration of `dp/ds = ρ(p) g`.
    #[test]
    fn closed_form_solves_the_equilibrium() {
        let (eos, g, depth) = (water(20.0), 9.81, 0.6);
        let steps = 4000;
        let ds = depth / steps as Real;
        let f = |p: Real| eos.density_at(p).unwrap() * g;
        let mut p = 0.0;
        for _ in 0..steps {
            let k1 = f(p);
            let k2 = f(p + 0.5 * ds * k1);
            let k3 = f(p + 0.5 * ds * k2);
            let k4 = f(p + ds * k3);
            p += ds / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        let closed = eos.hydrostatic_pressure(g, depth).unwrap();
        assert!((closed - p).abs() < 1e-9 * p, "{closed} vs {p}");
        // and it is above the incompressible ρ0 g s by about half the compression
        let incompressible = 1000.0 * g * depth;
        let excess = closed / incompressible - 1.0;
        let half_compression = 0.5 * g * depth / (20.0 * 20.0);
        assert!((excess / half_compression - 1.0).abs() < 0.1, "{excess}");
    }

    /// γ = 1 takes the exponential limit; a gas has no closed form.
    #[test]
    fn isothermal_and_gas() {
        let eos = Eos::Tait {
            rho0: 1.0,
            gamma: 1.0,
            p0: 10.0,
            c0: 10.0_f64.sqrt(),
            p_min: Real::NEG_INFINITY,
            p_b: 2.0,
            rho_min: Real::NEG_INFINITY,
        };
        let p = eos.hydrostatic_pressure(1.0, 3.0).unwrap();
        assert!((p - (2.0 + 10.0 * (libm::exp(0.3_f64) - 1.0))).abs() < 1e-12);
        assert!(
            Eos::Ideal { gamma: 1.4 }
                .hydrostatic_pressure(9.81, 1.0)
                .is_none()
        );
    }

    #[test]
    fn surface_must_be_finite() {
        let info = SceneInfo::of_dimension(2);
        let bad = HydrostaticStart { surface: Real::NAN };
        assert!(
            SimPlugin::validate(&bad, &info)
                .unwrap_err()
                .contains("surface")
        );
    }
}
