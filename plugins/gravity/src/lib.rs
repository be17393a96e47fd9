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
use dualsph_core::prelude::*;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Uniform gravity.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Gravity {
    /// Acceleration vector, one component per dimension.
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
            let rows = a.par_iter_mut().with_min_len(MIN_LEN);
            rows.for_each(|a| a.0 += g);
        } else {
            let rows = (body, &mut *a).into_par_iter().with_min_len(MIN_LEN);
            rows.for_each(|(b, a)| {
                if fluid.get(b.0 as usize).copied().unwrap_or(true) {
                    a.0 += g;
                }
            });
        }
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

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let g = V::from_slice(&self.g)
            .ok_or_else(|| SimError::Build(format!("Gravity.g needs {} components", V::DIM)))?;
        sim.world.insert_resource(GravityAccel(g));
        let mut pots = sim.world.resource_mut::<ExternalPotentials>();
        pots.terms.push(potential);
        pots.params.push(g.to_xyz());
        sim.add_system(StepSet::BodyForces, "gravity", apply_gravity::<V>);
        Ok(())
    }
}
