//! `Gravity(g: [gx, gy])`: a uniform body force `b = g` (Eq. 4.2) and its potential energy
//! `φ(x) = −g·x`, so that the diagnostics' total energy includes `Σ m φ`.
//!
//! Gravity acts on the particles of fluid bodies only. A fixed or prescribed body's motion is
//! given (the integrator's update of its particles is replaced by the body's law), so g on
//! them would move nothing; leaving it out keeps their `Acceleration` the pair force on them
//! over their mass, `a_i = f_i/m_i`, which is what the load on the body sums
//! (`dualsph_diagnostics::totals::BodyLoad`), with no body force to take off again. Likewise
//! the potential energy counts the fluid bodies only (the diagnostics sum the potentials over
//! them). A scene of fluid bodies only is unchanged by this, bitwise.
#![warn(missing_docs)]

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Bodies, BodyId};
use dualsph_core::chunks::{DENSE, MIN_LEN};
use dualsph_core::potentials::ExternalPotentials;
use dualsph_fluid::prelude::*;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Uniform gravity.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Gravity {
    /// Acceleration vector (m/s²), one component per dimension.
    pub g: Vec<Real>,
}

/// The body-force acceleration, as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct GravityAccel<V: Vector>(pub V);

fn potential(x: &[Real; 3], g: &[Real; 3]) -> Real {
    -(x[0] * g[0] + x[1] * g[1] + x[2] * g[2])
}

/// Adds `g` to the acceleration of every particle of a fluid body (after the pair sweep).
#[inline(never)] // a frame of its own in profiles
pub fn apply_gravity<V: Vector>(
    g: Res<GravityAccel<V>>,
    bodies: Res<Bodies>,
    mut q: Query<(&BodyId, &mut Acceleration<V>)>,
) {
    let g = g.0;
    let fluid: Vec<bool> = bodies.0.iter().map(|b| b.is_fluid()).collect();
    let all_fluid = fluid.iter().all(|&f| f);
    for (body, mut a) in q.contiguous_iter_mut().expect(DENSE) {
        if all_fluid {
            let rows = a.bypass_change_detection().par_iter_mut();
            let rows = rows.with_min_len(MIN_LEN);
            rows.for_each(|a| a.0 += g);
        } else {
            let rows = (body, a.bypass_change_detection())
                .into_par_iter()
                .with_min_len(MIN_LEN);
            rows.for_each(|(b, a)| {
                if fluid.get(b.0 as usize).copied().unwrap_or(true) {
                    a.0 += g;
                }
            });
        }
    }
}

impl Gravity {
    /// `g` as a vector of the simulation's dimension.
    fn vector<V: Vector>(&self) -> Result<V, SimError> {
        V::from_slice(&self.g)
            .ok_or_else(|| SimError::Build(format!("Gravity.g needs {} components", V::DIM)))
    }
}

impl SimPlugin for Gravity {
    const NAME: &'static str = "Gravity";
    const SUMMARY: &'static str = "uniform body force g with potential energy -g·x";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        if self.g.len() != info.dimension {
            return Err(format!(
                "g: expected {} components, got {}",
                info.dimension,
                self.g.len()
            ));
        }
        if self.g.iter().any(|x| !x.is_finite()) {
            return Err("g: components must be finite".into());
        }
        Ok(())
    }

    /// Publishes `g` ([`GravityAccel`]) before any plugin builds: the sound speed's `Auto`,
    /// the hydrostatic start and the walls read it whatever the plugin list's order.
    fn prepare<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.world.insert_resource(GravityAccel(self.vector::<V>()?));
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let g = self.vector::<V>()?;
        sim.enable::<dualsph_fluid::GravityField>();
        sim.world.insert_resource(GravityAccel(g));
        let mut pots = sim.world.resource_mut::<ExternalPotentials>();
        pots.terms.push(potential);
        pots.params.push(g.to_xyz());
        sim.add_system(StepSet::BodyForces, "gravity", apply_gravity::<V>);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::bodies::{Body, install_bodies};
    use dualsph_core::sim::{Domain, ParticleInit, SimConfig};
    use glam::DVec2;

    /// After the initial evaluation (no pair force), the particle of the fluid body has
    /// acceleration g and those of a fixed and a prescribed body none.
    #[test]
    fn gravity_acts_on_fluid_bodies_only() {
        let mut sim = Sim::<DVec2>::new(SimConfig {
            kernel: KernelKind::CubicSpline,
            formulation: Formulation::DualSupport,
            domain: Domain::closed(DVec2::splat(-10.0), DVec2::splat(10.0)),
            skin: 0.1,
            skin_rule: SkinRule::Fixed,
            time_stepping: TimeStepping::Fixed(1e-3),
        });
        let p = |x: f64, body: u16| ParticleInit {
            pos: DVec2::new(x, 0.0),
            vel: DVec2::ZERO,
            mass: 1.0,
            density: 1000.0,
            h: 0.1,
            internal_energy: 0.0,
            body,
        };
        sim.spawn_particles(&[p(-3.0, 0), p(0.0, 1), p(3.0, 2)])
            .unwrap();
        let lid = dualsph_motion::Law::Translate {
            velocity: [1.0, 0.0, 0.0],
        };
        let bodies = vec![
            Body::fluid("water"),
            Body::fixed("floor"),
            Body::moved_by("lid", std::sync::Arc::new(lid)),
        ];
        install_bodies(&mut sim, Bodies(bodies)).unwrap();
        let integrator: &dyn PluginConfig = &dualsph_integrator::LeapfrogPC::default();
        sim.build_plugin(integrator).unwrap();
        let gravity = Gravity {
            g: vec![0.0, -9.81],
        };
        sim.build_plugin(&gravity).unwrap();
        sim.initialize().unwrap();
        let mut q = sim.world.query::<(&ParticleId, &Acceleration<DVec2>)>();
        let mut a: Vec<_> = q.iter(&sim.world).map(|(id, a)| (id.0, a.0)).collect();
        a.sort_by_key(|r| r.0);
        let want = [DVec2::new(0.0, -9.81), DVec2::ZERO, DVec2::ZERO];
        assert_eq!(a.iter().map(|r| r.1).collect::<Vec<_>>(), want);
    }
}
