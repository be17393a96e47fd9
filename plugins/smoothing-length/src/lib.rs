//! `SmoothingLengthUpdate(every: m, n: n)`: every m steps `h_i = n (m_i/ρ_i)^{1/d}` (Eq. 6.1).
//! The neighbour lists are marked for rebuild after an update. Two optional steps may then
//! only raise h: [`isotropy`] (h from the particle distribution: each support populated in
//! every direction) and the h-ratio limiter ([`limit_ratio`]), in this order.
//!
//! With the grad-h formulation the same relation holds at every step with the density summed
//! at the same h, solved together ([`grad_h`]); `every` is then not used.
#![warn(missing_docs)]

pub mod grad_h;
pub mod isotropy;
pub use isotropy::Isotropy;

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::math::particle_size;
use dualsph_core::neighbours::Neighbours;
use dualsph_core::plugin::positive;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// The h-update of §6.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SmoothingLengthUpdate {
    /// Update period m in steps (paper: about 50).
    pub every: u64,
    /// h in units of the particle size (dimensionless; paper: 1.5 to 3).
    pub n: Real,
    /// Largest ratio `h_j/h_i` (dimensionless) allowed between a particle i and a neighbour j whose support
    /// holds it (`|r_ij| < h_j`): after Eq. 6.1, `h_i ← max(h_i, max_j h_j/R)`. None (the
    /// default) applies Eq. 6.1 alone. Where the particle spacing jumps by more than R (a
    /// 1:4 or 1:8 refinement interface), the small particles next to the interface would
    /// otherwise see no large particle inside their own support — the coarse spacing exceeds
    /// their h — and their own-support sums (density, kernel correction, velocity gradient)
    /// would be those of a free surface inside the fluid. Any h field keeps the dual-support
    /// sweep's exact conservation.
    #[serde(default)]
    pub max_ratio: Option<Real>,
    /// h from the particle distribution, not the density alone: after Eq. 6.1, raise `h_i`
    /// until the second moment of its support is isotropic to `min`,
    /// `det S_i / (tr S_i/d)^d ≥ min` with `S_i = Σ_j V_j W(r_ij, h_i) r_ij ⊗ r_ij`, at most
    /// to `max_growth` times the Eq. 6.1 value (see [`isotropy`]). None (the default)
    /// leaves Eq. 6.1 alone.
    #[serde(default)]
    pub isotropy: Option<Isotropy>,
}

/// Settings as a resource.
#[derive(Resource, Clone, Copy, Debug)]
pub struct HUpdate {
    /// Period.
    pub every: u64,
    /// Factor.
    pub n: Real,
    /// See [`SmoothingLengthUpdate::max_ratio`].
    pub max_ratio: Option<Real>,
    /// See [`SmoothingLengthUpdate::isotropy`].
    pub isotropy: Option<Isotropy>,
}

/// Applies Eq. 6.1 when `step % every == 0`.
#[inline(never)] // a frame of its own in profiles
pub fn update_h<V: Vector>(
    clock: Res<SimClock>,
    set: Res<HUpdate>,
    kernel: Res<KernelRes>,
    mut nb: ResMut<Neighbours<V>>,
    mut q: Query<(
        &ParticleId,
        &Mass,
        &Density,
        &Position<V>,
        &mut SmoothingLength,
    )>,
) {
    if clock.step == 0 || !clock.step.is_multiple_of(set.every) {
        return;
    }
    if set.max_ratio.is_none() && set.isotropy.is_none() {
        let h: Vec<Real> = q
            .iter_mut()
            .map(|(_, m, rho, _, mut h)| {
                h.0 = set.n * particle_size(V::DIM, m.0, rho.0);
                h.0
            })
            .collect();
        nb.h_changed(&h);
        return;
    }
    let n = q.iter().len();
    let (mut h_new, mut pos, mut vol) = (vec![0.0; n], vec![V::zero(); n], vec![0.0; n]);
    // by row: the index of the neighbour lists (the query walks the one table in row order)
    for (row, (_, m, rho, r, _)) in q.iter().enumerate() {
        h_new[row] = set.n * particle_size(V::DIM, m.0, rho.0);
        pos[row] = r.0;
        vol[row] = m.0 / rho.0;
    }
    if let Some(iso) = set.isotropy {
        h_new = iso.enlarge(&kernel.0, &h_new, (&pos, nb.period.as_ref()), &vol);
    }
    let limited = match set.max_ratio {
        Some(ratio) => limit_ratio(&h_new, &pos, &nb, ratio),
        None => h_new,
    };
    for ((_, _, _, _, mut h), &hl) in q.iter_mut().zip(&limited) {
        h.0 = hl;
    }
    nb.h_changed(&limited);
}

/// `h_i ← max(h_i, max_j h_j/R)` over the j whose candidate support lists hold i (the dual
/// lists of the last build) and whose support really does (`|r_ij| < h_j`). One pass over
/// the old h, so the result does not depend on the order of the particles. Without lists for
/// these particles (particles were added or removed at the start of this step, which drops
/// the lists) the h of this update are left unlimited.
pub fn limit_ratio<V: Vector>(h: &[Real], pos: &[V], nb: &Neighbours<V>, ratio: Real) -> Vec<Real> {
    if nb.dual.rows() != h.len() {
        return h.to_vec();
    }
    (0..h.len())
        .map(|i| {
            nb.dual.row(i).iter().fold(h[i], |hi, &j| {
                let j = j as usize;
                if nb.separation(pos[i], pos[j]).length_squared() < h[j] * h[j] {
                    hi.max(h[j] / ratio)
                } else {
                    hi
                }
            })
        })
        .collect()
}

impl SimPlugin for SmoothingLengthUpdate {
    const NAME: &'static str = "SmoothingLengthUpdate";
    const SUMMARY: &'static str = "h_i = n (m_i/rho_i)^(1/d) every m steps (Eq. 6.1)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if self.every == 0 {
            return Err("every: must be at least 1".into());
        }
        positive("n", self.n)?;
        if let Some(r) = self.max_ratio
            && !(r.is_finite() && r >= 1.0)
        {
            return Err(format!("max_ratio: must be at least 1, got {r}"));
        }
        if let Some(iso) = &self.isotropy {
            iso.validate()?;
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if *sim.world.resource::<Formulation>() == Formulation::ConstantH {
            return Err(SimError::Build(
                "SmoothingLengthUpdate cannot be used with formulation ConstantH".into(),
            ));
        }
        if *sim.world.resource::<Formulation>() == Formulation::GradH {
            return self.build_grad_h(sim);
        }
        sim.world.insert_resource(HUpdate {
            every: self.every,
            n: self.n,
            max_ratio: self.max_ratio,
            isotropy: self.isotropy,
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

impl SmoothingLengthUpdate {
    /// The grad-h formulation's h: solved with the summation density at every step
    /// ([`grad_h`]), η = `n`; Ω on every particle.
    fn build_grad_h<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if self.max_ratio.is_some() || self.isotropy.is_some() {
            return Err(SimError::Build(
                "SmoothingLengthUpdate: max_ratio and isotropy raise h off the density; the \
                 grad-h formulation ties h to it (remove them, or choose another formulation)"
                    .into(),
            ));
        }
        sim.require::<dualsph_fluid::DensitySummation>(
            "the grad-h formulation needs SummationDensity() (h is solved with the summed density)",
        );
        sim.world.insert_resource(grad_h::GradHSettings {
            eta: self.n,
            tolerance: 1e-10,
            max_iterations: 50,
        });
        sim.world.insert_resource(grad_h::GradHStats::default());
        sim.add_column(
            ColumnSpec::scratch("grad_h_omega").with_output("omega"),
            |_| GradHFactor(1.0),
        )?;
        sim.add_system(
            StepSet::Density,
            "grad_h (h and summation density solved together, Ω)",
            grad_h::grad_h::<V>,
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_limiter_lifts_only_particles_inside_a_larger_support() {
        // j: h = 1 at 0; i: h = 0.1 at 0.5 (inside j's support); k: h = 0.1 at 1.5 (outside)
        let pos = [Vec1(0.0), Vec1(0.5), Vec1(1.5)];
        let h = [1.0, 0.1, 0.1];
        let mut nb = Neighbours::<Vec1>::new(0.1);
        nb.rebuild(&pos, &h);
        let limited = limit_ratio(&h, &pos, &nb, 2.0);
        assert_eq!(limited, vec![1.0, 0.5, 0.1]);
        // a ratio already within the bound changes nothing
        assert_eq!(limit_ratio(&h, &pos, &nb, 20.0), h.to_vec());
    }
}
