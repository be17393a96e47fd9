//! `Gravity(g: [gx, gy])`: a uniform body force `b = g` (Eq. 4.2) and its potential energy
//! `φ(x) = −g·x`, so that the diagnostics' total energy includes `Σ m φ`.
#![warn(missing_docs)]

use dualsph_core::bevy_ecs::prelude::*;
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

/// Adds `g` to every particle's acceleration (after the pair sweep).
#[inline(never)] // a frame of its own in profiles
pub fn apply_gravity<V: Vector>(g: Res<GravityAccel<V>>, mut q: Query<&mut Acceleration<V>>) {
    let g = g.0;
    for mut a in q.contiguous_iter_mut().expect(DENSE) {
        let rows = a.par_iter_mut().with_min_len(MIN_LEN);
        rows.for_each(|a| a.0 += g);
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
        sim.enable_feature("gravity");
        sim.world.insert_resource(GravityAccel(g));
        let mut pots = sim.world.resource_mut::<ExternalPotentials>();
        pots.terms.push(potential);
        pots.params.push(g.to_xyz());
        sim.add_system(StepSet::BodyForces, "gravity", apply_gravity::<V>);
        Ok(())
    }
}
