//! `SpecularWalls()`: the faces of the domain box reflect particles specularly (Eq. 7.7):
//! `v' = v − 2 (v·n) n` if `v·n < 0`, with n the inward normal, for a particle on or beyond a
//! face. Positions are not moved: a particle that overshot a face by `|v|Δt` comes back on
//! its own with the reflected velocity. (Mirroring the position instead would lift it in a
//! gravity field and inject potential energy at every bounce.) Reflection leaves |v|
//! unchanged, so the kinetic energy — and the total energy — are untouched.
#![warn(missing_docs)]

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::prelude::*;
use serde::Deserialize;

/// Specular reflection on the domain box.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpecularWalls {}

/// Reflects positions and velocities at the domain faces.
#[inline(never)] // a frame of its own in profiles
pub fn reflect<V: Vector>(
    domain: Res<Domain<V>>,
    mut q: Query<(&mut Position<V>, &mut Velocity<V>)>,
) {
    let (lo, hi) = (domain.min, domain.max);
    q.par_iter_mut().for_each(|(mut r, mut v)| {
        for k in 0..V::DIM {
            let (x, u) = (r.0.get(k), v.0.get(k));
            if x <= lo.get(k) {
                r.0.set(k, (2.0 * lo.get(k) - x).min(hi.get(k)));
                if u < 0.0 {
                    v.0.set(k, -u);
                }
            } else if x >= hi.get(k) {
                r.0.set(k, (2.0 * hi.get(k) - x).max(lo.get(k)));
                if u > 0.0 {
                    v.0.set(k, -u);
                }
            }
        }
    });
}

impl SimPlugin for SpecularWalls {
    const NAME: &'static str = "SpecularWalls";
    const SUMMARY: &'static str = "specular reflection on the domain box (Eq. 7.7)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.add_system(StepSet::Boundary, "specular_walls (Eq. 7.7)", reflect::<V>);
        Ok(())
    }
}
