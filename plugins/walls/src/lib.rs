//! `SpecularWalls(clearance: κ)`: the faces of the domain box (on its axes that are not
//! periodic) reflect particles specularly
//! (Eq. 7.7): `v' = v − 2 (v·n) n` if `v·n < 0`, with n the inward normal, for a particle
//! closer to a face than `κ h_i` (its own support radius; κ = 0, the default, means on or
//! beyond the face). Reflection leaves |v| unchanged, so the kinetic energy — and the total
//! energy — are untouched. A particle found beyond a face (it overshot by `|v|Δt`) is also
//! mirrored back inside, which lifts it by at most `2|v|Δt`.
//!
//! With κ = 0 particles come to rest on the face itself, inside each other's kernels at
//! a fraction of the spacing, under the tension the truncated support gives there; in the
//! dam break that wall layer is where the tensile instability starts (docs/validation).
//! κ = 0.25 keeps them off the face by half a spacing (h = 2Δx), where the initial lattice
//! puts the first layer.
#![warn(missing_docs)]

pub mod pressure;
pub mod velocity;
pub use pressure::WallPressure;
pub use velocity::ViscousWall;

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::chunks::{DENSE, MIN_LEN};
use dualsph_fluid::prelude::*;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Which bodies are walls, by `BodyId` (set by [`WallPressure`]).
#[derive(Resource, Clone, Debug)]
pub struct WallBodies(pub Vec<bool>);

/// Specular reflection on the domain box.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpecularWalls {
    /// κ (dimensionless): a particle closer to a face than `κ h_i` and approaching it is reflected.
    #[serde(default)]
    pub clearance: Real,
}

/// κ as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct WallClearance(pub Real);

/// Reflects positions and velocities at the domain faces.
#[inline(never)] // a frame of its own in profiles
pub fn reflect<V: Vector>(
    domain: Res<Domain<V>>,
    clearance: Res<WallClearance>,
    mut q: Query<(&mut Position<V>, &mut Velocity<V>, &SmoothingLength)>,
) {
    let (lo, hi) = (domain.min, domain.max);
    let kappa = clearance.0;
    let walled = domain.periodic.map(|p| !p);
    for (mut r, mut v, h) in q.contiguous_iter_mut().expect(DENSE) {
        let (r, v) = (r.bypass_change_detection(), v.bypass_change_detection());
        let rows = (r, v, h).into_par_iter().with_min_len(MIN_LEN);
        rows.for_each(|(r, v, h)| reflect_one(&mut r.0, &mut v.0, kappa * h.0, (lo, hi), walled));
    }
}

/// One particle of [`reflect`], at distance `gap` from the faces `lo`, `hi` of the axes
/// marked in `walled`.
#[inline(always)]
fn reflect_one<V: Vector>(r: &mut V, v: &mut V, gap: Real, (lo, hi): (V, V), walled: [bool; 3]) {
    for k in (0..V::DIM).filter(|&k| walled[k]) {
        let (x, u) = (r.get(k), v.get(k));
        if x <= lo.get(k) + gap {
            if x < lo.get(k) {
                r.set(k, (2.0 * lo.get(k) - x).min(hi.get(k)));
            }
            if u < 0.0 {
                v.set(k, -u);
            }
        } else if x >= hi.get(k) - gap {
            if x > hi.get(k) {
                r.set(k, (2.0 * hi.get(k) - x).max(lo.get(k)));
            }
            if u > 0.0 {
                v.set(k, -u);
            }
        }
    }
}

impl SimPlugin for SpecularWalls {
    const NAME: &'static str = "SpecularWalls";
    const SUMMARY: &'static str = "specular reflection on the domain box (Eq. 7.7)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.clearance.is_finite() && (0.0..=0.5).contains(&self.clearance)) {
            return Err(format!(
                "clearance: must lie in [0, 0.5] (a fraction of h), got {}",
                self.clearance
            ));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.world.insert_resource(WallClearance(self.clearance));
        sim.add_system(StepSet::Boundary, "specular_walls (Eq. 7.7)", reflect::<V>);
        Ok(())
    }
}
