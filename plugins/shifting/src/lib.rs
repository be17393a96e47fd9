//! `ParticleShifting(coefficient: 2.0)`: after every step the fluid particles move a little
//! down the gradient of their own concentration, so that they keep an even spacing where the
//! flow would line them up (along stagnation lines, in a shear layer) or clump them. This is
//! the Fickian shifting of Lind, Xu, Stansby & Rogers (2012), *Incompressible smoothed
//! particle hydrodynamics for free-surface flows: a generalised diffusion-based algorithm for
//! stability and validations for impulsive flows and propagating waves*, J. Comput. Phys.
//! 231, 1499, Eq. 19–20, with the diffusion coefficient of Skillen, Lind, Stansby & Rogers
//! (2013), *Incompressible smoothed particle hydrodynamics (SPH) with reduced temporal noise
//! and generalised Fickian smoothing applied to body–water slam and efficient wave–body
//! interaction*, Comput. Methods Appl. Mech. Engrg. 265, 163 (as DualSPHysics uses it):
//!
//! `δr_i = −D_i ∇C_i`,  `∇C_i = Σ_j V_j ∇_iW_ij`,  `D_i = A (h_i/2) |v_i| Δt`,
//!
//! over i's support (its own kernel, all bodies' particles, so a wall of particles pushes
//! the fluid off it), with `V_j = m_j/ρ_j` and `h_i/2` the smoothing length of the usual
//! notation (whose kernels reach `2h`: `h_i` here is the support radius). `A` is
//! `coefficient` (Skillen et al. take 1–6; DualSPHysics 2).
//!
//! **The free surface** is detected by the divergence of position,
//! `∇·r_i = −Σ_j V_j r_ij·∇_iW_ij`, which is the dimension d in the bulk and falls towards half
//! of it at a free surface (Lind et al. 2012, §3.3): where it is below `surface` (default
//! 1.5 in 2-D, 2.75 in 3-D, 0.75 in 1-D) the shift keeps only its part along the surface,
//! `δr_i − (δr_i·n_i) n_i` with `n_i = ∇C_i/|∇C_i|`, so the particles there do not move out
//! of the fluid.
//!
//! **What is conserved.** The shift moves positions and nothing else: mass, velocities and
//! densities are untouched, so the linear momentum `Σ m v` and the kinetic and internal
//! energies are exactly what they were (the dual-support pair forces of the next step are
//! computed at the new positions and stay exactly opposite). The angular momentum `Σ m r × v`
//! changes by `Σ m δr × v`, and a potential energy (gravity) by `Σ m g·δr`; no velocity or
//! density correction for the moved positions (the ALE terms) is made, which would cost the
//! exact momentum. Only the particles of fluid bodies move.
#![warn(missing_docs)]

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Bodies, DriveBodies};
use dualsph_core::chunks::DENSE;
use dualsph_core::neighbours::Neighbours;
use dualsph_fluid::prelude::*;
use dualsph_sweep::Support;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Particle shifting (module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ParticleShifting {
    /// `A` in `D_i = A (h_i/2) |v_i| Δt` (dimensionless; default 2).
    #[serde(default = "two")]
    pub coefficient: Real,
    /// The free-surface threshold on `∇·r` (dimensionless; default 1.5 in 2-D, 2.75 in 3-D, 0.75 in 1-D).
    #[serde(default)]
    pub surface: Option<Real>,
}

fn two() -> Real {
    2.0
}

impl Default for ParticleShifting {
    fn default() -> Self {
        ParticleShifting {
            coefficient: two(),
            surface: None,
        }
    }
}

/// The settings as the system reads them.
#[derive(Resource, Clone, Copy, Debug)]
pub struct Shifting {
    /// `A`.
    pub coefficient: Real,
    /// The threshold on `∇·r`.
    pub surface: Real,
}

impl Shifting {
    /// The default threshold of dimension `d` (Lind et al. 2012; DualSPHysics).
    pub fn default_surface(d: usize) -> Real {
        match d {
            1 => 0.75,
            2 => 1.5,
            _ => 2.75,
        }
    }
}

/// `(∇C_i, ∇·r_i)` of particle i over its support (module docs).
pub fn concentration_gradient<V: Vector>(
    support: &Support<'_, V>,
    volume: &[Real],
    i: usize,
) -> (V, Real) {
    let (mut grad, mut div) = (V::zero(), 0.0);
    support.for_each_neighbour(i, |j, rij, _r, _w, g| {
        grad += g * volume[j];
        div -= volume[j] * rij.dot(g);
    });
    (grad, div)
}

/// The shift of one particle: `−D ∇C`, its part along the surface where `∇·r < surface`.
pub fn shift<V: Vector>(grad: V, div: Real, d: Real, surface: Real) -> V {
    let dr = grad * -d;
    let g2 = grad.length_squared();
    if div < surface && g2 > 0.0 {
        dr - grad * (dr.dot(grad) / g2)
    } else {
        dr
    }
}

/// Each fluid particle's shift `f(i)` (zero for the particles of other bodies), in parallel:
/// the loop both regularisers share.
pub fn fluid_shifts<V: Vector>(
    bodies: &Bodies,
    body: &[BodyId],
    f: impl Fn(usize) -> V + Sync + Send,
) -> Vec<V> {
    let fluid: Vec<bool> = bodies.0.iter().map(|b| b.is_fluid()).collect();
    (0..body.len())
        .into_par_iter()
        .with_min_len(256)
        .map(|i| {
            if fluid[body[i].0 as usize] {
                f(i)
            } else {
                V::zero()
            }
        })
        .collect()
}

/// `V_i = m_i/ρ_i` of every particle.
pub fn volumes(m: &[Mass], rho: &[Density]) -> Vec<Real> {
    m.iter().zip(rho).map(|(m, r)| m.0 / r.0).collect()
}

/// A free-surface threshold, when given, is a positive number.
pub fn check_surface(surface: Option<Real>) -> Result<(), String> {
    match surface {
        Some(s) if !(s.is_finite() && s > 0.0) => Err(format!("surface: must be > 0, got {s}")),
        _ => Ok(()),
    }
}

/// Moves every fluid particle by its shift (module docs), after the corrector.
#[allow(clippy::too_many_arguments)] // one system, its resources
#[inline(never)] // a frame of its own in profiles
pub fn shift_particles<V: Vector>(
    settings: Res<Shifting>,
    bodies: Res<Bodies>,
    clock: Res<SimClock>,
    kernel: Res<KernelRes>,
    nb: Res<Neighbours<V>>,
    formulation: Res<Formulation>,
    mut q: Query<(
        &mut Position<V>,
        &Velocity<V>,
        &SmoothingLength,
        &Mass,
        &Density,
        &BodyId,
    )>,
) {
    let Some((mut pos, vel, h, m, rho, body)) =
        dualsph_core::store::single_table(q.contiguous_iter_mut().expect(DENSE))
    else {
        return;
    };
    // the engine reads no change ticks (`dualsph_core::chunks`)
    let pos = pos.bypass_change_detection();
    let volume = volumes(m, rho);
    let support = Support {
        pos,
        h,
        neighbours: &nb,
        kernel: &kernel.0,
        formulation: *formulation,
    };
    let (a, dt) = (settings.coefficient, clock.dt);
    let shifts = fluid_shifts(&bodies, body, |i| {
        let (grad, div) = concentration_gradient(&support, &volume, i);
        let d = a * 0.5 * h[i].0 * vel[i].0.length() * dt;
        shift(grad, div, d, settings.surface)
    });
    for (r, dr) in pos.iter_mut().zip(shifts) {
        r.0 += dr;
    }
}

impl SimPlugin for ParticleShifting {
    const NAME: &'static str = "ParticleShifting";
    const SUMMARY: &'static str =
        "fluid particles shifted down their concentration gradient (Lind et al. 2012)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.coefficient.is_finite() && self.coefficient > 0.0 && self.coefficient <= 10.0) {
            return Err(format!(
                "coefficient: must be in (0, 10], got {}",
                self.coefficient
            ));
        }
        check_surface(self.surface)
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.world.insert_resource(Shifting {
            coefficient: self.coefficient,
            surface: self
                .surface
                .unwrap_or_else(|| Shifting::default_surface(V::DIM)),
        });
        sim.add_system(
            StepSet::Correct,
            "particle_shifting (Lind et al. 2012)",
            shift_particles::<V>,
        )
        .after::<DriveBodies>();
        Ok(())
    }
}

pub mod transport;
pub use transport::{TransportOffset, TransportVelocity};

#[cfg(test)]
mod tests;
