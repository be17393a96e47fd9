//! `SmoothingLengthUpdate(every: m, n: n)`: every m steps `h_i = n (m_i/ρ_i)^{1/d}` (Eq. 6.1).
//! The neighbour lists are marked for rebuild after an update.
#![warn(missing_docs)]

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::neighbours::Neighbours;
use dualsph_core::prelude::*;
use serde::Deserialize;

/// The h-update of §6.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SmoothingLengthUpdate {
    /// Update period m in steps (paper: about 50).
    pub every: u64,
    /// h in units of the particle size (paper: 1.5 to 3).
    pub n: Real,
}

/// Settings as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct HUpdate {
    /// Period.
    pub every: u64,
    /// Factor.
    pub n: Real,
}

/// Applies Eq. 6.1 when `step % every == 0`.
#[inline(never)] // a frame of its own in profiles
pub fn update_h<V: Vector>(
    clock: Res<SimClock>,
    set: Res<HUpdate>,
    mut nb: ResMut<Neighbours<V>>,
    mut q: Query<(&Mass, &Density, &mut SmoothingLength)>,
) {
    if clock.step == 0 || !clock.step.is_multiple_of(set.every) {
        return;
    }
    let inv_d = 1.0 / V::DIM as Real;
    for (m, rho, mut h) in &mut q {
        h.0 = set.n * (m.0 / rho.0).powf(inv_d);
    }
    nb.dirty = true;
}

impl SimPlugin for SmoothingLengthUpdate {
    const NAME: &'static str = "SmoothingLengthUpdate";
    const SUMMARY: &'static str = "h_i = n (m_i/rho_i)^(1/d) every m steps (Eq. 6.1)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if self.every == 0 {
            return Err("every: must be at least 1".into());
        }
        if !(self.n.is_finite() && self.n > 0.0) {
            return Err(format!("n: must be positive, got {}", self.n));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if *sim.world.resource::<Formulation>() == Formulation::ConstantH {
            return Err(SimError::Build(
                "SmoothingLengthUpdate cannot be used with formulation ConstantH".into(),
            ));
        }
        sim.world.insert_resource(HUpdate {
            every: self.every,
            n: self.n,
        });
        sim.add_system(
            StepSet::SmoothingLength,
            format!(
                "smoothing_length_update (Eq. 6.1, every {} steps)",
                self.every
            ),
            update_h::<V>,
        );
        Ok(())
    }
}
