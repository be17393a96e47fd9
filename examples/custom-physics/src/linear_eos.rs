//! A user's own equation of state, which the built-in plugins follow with no edit of theirs:
//! the linear (acoustic) law of a weakly compressible liquid,
//!
//! `p = c0² (ρ − ρ0)`,  `c = c0`
//!
//! (the first-order expansion of any barotropic law about ρ0; e.g. Morris, Fox & Zhu 1997,
//! *J. Comput. Phys.* 136, 214, Eq. 9, with `p = c² ρ` shifted by its rest pressure). It
//! sets every particle's pressure and sound speed in the step's equation-of-state group
//! (`EquationOfState`), so the walls' pressure extrapolation and the pressure force run after
//! it, and it publishes its law per body (`BodyEos`), so the walls turn their extrapolated
//! pressure into a density with it (`ρ = ρ0 + p/c0²`) and a hydrostatic start fills the tank
//! with its profile: `dp/ds = ρ(p) g` gives `p(s) = ρ0 c0² (exp(g s / c0²) − 1)`.

use bevy_ecs::prelude::*;
use dualsph::core::chunks::DENSE;
use dualsph::fluid::{BodyEos, EosLaw, EquationOfState, Liquid};
use dualsph::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The settings, as written in a scene: `LinearEos(rho0: 1000.0, c0: 25.0)`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LinearEos {
    /// Rest density ρ0 (kg/m^d).
    pub rho0: Real,
    /// Sound speed c0 (m/s).
    pub c0: Real,
}

/// The law of one body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearLaw {
    /// ρ0.
    pub rho0: Real,
    /// c0.
    pub c0: Real,
}

impl EosLaw for LinearLaw {
    fn eval(&self, rho: Real, _eps: Real) -> (Real, Real) {
        (self.c0 * self.c0 * (rho - self.rho0), self.c0)
    }

    fn density_at(&self, p: Real) -> Option<Real> {
        let rho = self.rho0 + p / (self.c0 * self.c0);
        (rho > 0.0).then_some(rho)
    }

    fn reference_density(&self) -> Option<Real> {
        Some(self.rho0)
    }

    fn hydrostatic_pressure(&self, g: Real, s: Real) -> Option<Real> {
        let c2 = self.c0 * self.c0;
        Some(self.rho0 * c2 * libm::expm1(g * s / c2))
    }
}

/// Sets every particle's pressure and sound speed from its density.
pub fn apply_linear_eos(
    law: Res<LinearEosLaw>,
    mut q: Query<(&Density, &mut Pressure, &mut SoundSpeed)>,
) {
    let law = law.0;
    for (rho, mut p, mut c) in q.contiguous_iter_mut().expect(DENSE) {
        for ((rho, p), c) in rho.iter().zip(p.iter_mut()).zip(c.iter_mut()) {
            (p.0, c.0) = law.eval(rho.0, 0.0);
        }
    }
}

/// The scene's law, as the system reads it.
#[derive(Resource, Debug, Clone, Copy)]
pub struct LinearEosLaw(pub LinearLaw);

impl SimPlugin for LinearEos {
    const NAME: &'static str = "LinearEos";
    const SUMMARY: &'static str = "linear equation of state p = c0^2 (rho - rho0) (a user crate)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        for (name, x) in [("rho0", self.rho0), ("c0", self.c0)] {
            if !(x.is_finite() && x > 0.0) {
                return Err(format!("{name}: must be finite and > 0, got {x}"));
            }
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if !sim.enable::<EquationOfState>() {
            return Err(SimError::Build(
                "only one equation of state may be used".into(),
            ));
        }
        sim.enable::<Liquid>();
        let law = LinearLaw {
            rho0: self.rho0,
            c0: self.c0,
        };
        sim.add_column(ColumnSpec::state("pressure", "p"), |_| Pressure(0.0))?;
        sim.add_column(ColumnSpec::restart_only("sound_speed"), |_| SoundSpeed(0.0))?;
        let bodies = sim
            .world
            .resource::<dualsph::core::bodies::Bodies>()
            .0
            .len();
        let laws = (0..bodies).map(|_| Arc::new(law) as Arc<dyn EosLaw>);
        sim.world.insert_resource(BodyEos(laws.collect()));
        sim.world.insert_resource(LinearEosLaw(law));
        sim.add_system(StepSet::Eos, "linear_eos (a user crate)", apply_linear_eos)
            .in_group::<EquationOfState>();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hydrostatic profile solves `dp/ds = ρ(p) g` with `p(0) = 0`: against a fine
    /// midpoint integration, and the law's inverse gives back the density.
    #[test]
    fn the_hydrostatic_profile_solves_its_equation() {
        let law = LinearLaw {
            rho0: 1000.0,
            c0: 10.0,
        };
        let (g, depth, n) = (9.81, 2.0, 20_000);
        let ds = depth / n as Real;
        let mut p: Real = 0.0;
        for _ in 0..n {
            let half = p + 0.5 * ds * g * law.density_at(p).unwrap();
            p += ds * g * law.density_at(half).unwrap();
        }
        let exact = law.hydrostatic_pressure(g, depth).unwrap();
        assert!((p - exact).abs() < 1e-9 * exact, "{p} against {exact}");
        let rho = law.density_at(exact).unwrap();
        assert!((law.eval(rho, 0.0).0 - exact).abs() < 1e-9 * exact);
    }
}
