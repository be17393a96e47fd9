//! `TransportVelocity(gain: 0.12)`: the transport-velocity formulation of Adami, Hu &
//! Adams (2013), *A transport-velocity formulation for smoothed particle hydrodynamics*,
//! J. Comput. Phys. 241, 292–307. The particles are carried by a transport velocity
//! `ṽ_i = v_i + (Δt/2) ã_i` (their Eq. 13 in the kick–drift–kick of their §2.4) that adds to
//! the momentum velocity the acceleration of a uniform background pressure `p_b`,
//!
//! `ã_i = −(p_b/m_i) Σ_j (V_i² + V_j²) ∇_iW_ij`  (their Eq. 12, `V = m/ρ`),
//!
//! which vanishes on an even particle distribution and pushes the particles towards one
//! wherever they bunch or open up. The step's drift with `ṽ` instead of `v` is done here as a
//! shift after the step, `δr_i = Δt (ṽ_i − v_i) = (Δt²/2) ã_i`, over i's support with its own
//! kernel (all bodies' particles, so walls of particles keep the fluid off them).
//!
//! **The momentum equation** gains the divergence of the stress `A = ρ v ⊗ (ṽ − v)` that the
//! difference of the two velocities carries (their Eq. 9–10): as a dual-support pair term,
//! for `j ∈ H_i` with i's kernel,
//!
//! `f_ij = m_i m_j (A_i/ρ_i²)·∇_iW_ij = (m_i m_j/ρ_i) v_i ((ṽ_i − v_i)·∇_iW_ij)`
//!
//! on i and `−f_ij` on j (with the kernel correction `1/ρ_i²` becomes `1/(ρ_iρ_j)` and
//! `∇_iW_ij` becomes `L_i∇_iW_ij`, as for the pressure force), so linear momentum stays
//! exact. Its work `f_ij·v_ij` is taken from the pair's internal energy, half to each, so the
//! total energy stays exact where the scene tracks it. `ṽ − v` is the offset of the last step,
//! kept per particle (`transport_offset`, in checkpoints).
//!
//! **The background pressure.** Adami et al. take `p_b = ρ0 c0²`; a scene may fix it
//! (`background`). By default it is set per particle and step as `p_b = G ρ_i h_i²/Δt²`, so
//! that the shift `δr_i = (G/2)(h_i²/V_i) Σ_j (V_i² + V_j²) ∇_iW_ij` has the same gain `G` on
//! every step whatever the step's length. The shift is a relaxation of the distribution; like
//! an explicit diffusion it overshoots above a gain (measured on the Taylor–Green vortex with
//! Wendland C2, `h = 3Δx`: stable at `G` = 0.14, ringing from the start at 0.21), and the
//! stronger it is below that, the better the flow keeps its order: the default `G` = 0.12 is
//! about `3 ρ0 c0²` at the Courant number 0.2 on `h`. `gain` may be set up to 0.15.
//!
//! **The density** is left to the scene's density plugin, with the momentum velocity: carrying
//! the shift into the continuity equation (the ALE term `Σ_j m_j (ṽ − v)_ij·∇_iW_ij`)
//! measured worse on the Taylor–Green vortex, the density then following the evening-out of
//! the start's jitter (see `docs/parameters.md`).
//!
//! **The free surface.** A background pressure pulls particles out of a free surface; where
//! the divergence of position `∇·r_i` falls below `surface` (as in `ParticleShifting`) only
//! the shift's part along the surface is kept. The formulation is meant for confined flows.
//!
//! **What is conserved.** The shift moves positions, nothing else, so mass, linear momentum and
//! the energies are exactly what they were, and the dual-support pair forces at the new
//! positions stay exactly opposite; the stress term conserves linear momentum and total
//! energy pair by pair (above). The angular momentum changes by `Σ m δr × v` and by the
//! stress term's torque.

use crate::{Shifting, check_surface, fluid_shifts, shift, volumes};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Bodies, DriveBodies};
use dualsph_core::chunks::DENSE;
use dualsph_core::neighbours::Neighbours;
use dualsph_fluid::ensure_energy_equation;
use dualsph_fluid::prelude::*;
use dualsph_sweep::Support;
use serde::{Deserialize, Serialize};

/// The largest `gain` a scene may set: the shift is unstable above about 0.17 (module docs).
pub const MAX_GAIN: Real = 0.15;

/// `ṽ_i − v_i` of the last step (module docs).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct TransportOffset<V: Vector>(pub V);

dualsph_core::vector_column!(TransportOffset);

/// The transport-velocity formulation (module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TransportVelocity {
    /// The background pressure `p_b` (Pa), fixed; by default `p_b = G ρ_i h_i²/Δt²` with
    /// `G` = `gain`.
    #[serde(default)]
    pub background: Option<Real>,
    /// `G` (dimensionless), the shift's gain per step when `background` is not given (default 0.12).
    #[serde(default = "default_gain")]
    pub gain: Real,
    /// The free-surface threshold on `∇·r` (dimensionless; default 1.5 in 2-D, 2.75 in 3-D, 0.75 in 1-D).
    #[serde(default)]
    pub surface: Option<Real>,
    /// Whether the momentum equation carries the stress `A = ρ v ⊗ (ṽ − v)` (default true).
    #[serde(default = "yes")]
    pub stress: bool,
}

fn yes() -> bool {
    true
}

fn default_gain() -> Real {
    0.12
}

impl Default for TransportVelocity {
    fn default() -> Self {
        TransportVelocity {
            background: None,
            gain: default_gain(),
            surface: None,
            stress: true,
        }
    }
}

/// The settings as the system reads them.
#[derive(Resource, Clone, Copy, Debug)]
pub struct Transport {
    /// `p_b`, or `None` for `G ρ_i h_i²/Δt²`.
    pub background: Option<Real>,
    /// `G`.
    pub gain: Real,
    /// The threshold on `∇·r`.
    pub surface: Real,
}

/// The largest fixed background pressure (Pa): 10⁶ bar, about 45 times water's bulk modulus
/// (2.2 GPa). A weakly compressible flow has no use for more; far beyond it the shift
/// `Δt² p_b / ρ` overflows the positions (at `1e308` they wrap to one point, and every pair of
/// particles becomes a neighbour).
pub const MAX_BACKGROUND: Real = 1e11;

/// `(Σ_j (V_i² + V_j²) ∇_iW_ij, ∇·r_i)` over i's support.
pub fn background_sum<V: Vector>(support: &Support<'_, V>, volume: &[Real], i: usize) -> (V, Real) {
    let (mut sum, mut div) = (V::zero(), 0.0);
    let vi2 = volume[i] * volume[i];
    support.for_each_neighbour(i, |j, rij, _r, _w, g| {
        sum += g * (vi2 + volume[j] * volume[j]);
        div -= volume[j] * rij.dot(g);
    });
    (sum, div)
}

/// Moves every fluid particle by `(Δt²/2) ã_i` (module docs), after the corrector.
#[allow(clippy::too_many_arguments)] // one system, its resources
#[inline(never)] // a frame of its own in profiles
pub fn transport_particles<V: Vector>(
    settings: Res<Transport>,
    bodies: Res<Bodies>,
    clock: Res<SimClock>,
    kernel: Res<KernelRes>,
    nb: Res<Neighbours<V>>,
    formulation: Res<Formulation>,
    mut q: Query<(
        &mut Position<V>,
        &mut TransportOffset<V>,
        &SmoothingLength,
        &Mass,
        &Density,
        &BodyId,
    )>,
) {
    // nothing moves in the initial evaluation (no step has been taken)
    if clock.initializing || clock.dt <= 0.0 {
        return;
    }
    let Some((mut pos, mut offset, h, m, rho, body)) =
        dualsph_core::store::single_table(q.contiguous_iter_mut().expect(DENSE))
    else {
        return;
    };
    // the engine reads no change ticks (`dualsph_core::chunks`)
    let pos = pos.bypass_change_detection();
    let offset = offset.bypass_change_detection();
    let volume = volumes(m, rho);
    let support = Support {
        pos,
        h,
        neighbours: &nb,
        kernel: &kernel.0,
        formulation: *formulation,
    };
    let dt = clock.dt;
    let shifts = fluid_shifts(&bodies, body, |i| {
        let (sum, div) = background_sum(&support, &volume, i);
        // δr = −(Δt²/2)(p_b/m_i) Σ: `shift` applies −d to its gradient
        let d = match settings.background {
            Some(pb) => 0.5 * dt * dt * pb / m[i].0,
            // p_b = G ρ_i h_i²/Δt²
            None => 0.5 * settings.gain * h[i].0 * h[i].0 / volume[i],
        };
        shift(sum, div, d, settings.surface)
    });
    for ((r, o), dr) in pos.iter_mut().zip(offset.iter_mut()).zip(shifts) {
        r.0 += dr;
        o.0 = dr * (1.0 / dt);
    }
}

/// The stress term of the transport velocity (module docs).
#[derive(Debug, Clone, Copy)]
pub struct TransportStressTerm;

/// [`TransportStressTerm`] bound to the offsets.
#[derive(Clone, Copy, Debug)]
pub struct BoundTransportStress<'w, V: Vector> {
    data: ParticleData<'w, V>,
    offset: &'w [TransportOffset<V>],
    corrected: bool,
}

impl<V: Vector> PairTerm<V> for TransportStressTerm {
    type Bound<'w> = BoundTransportStress<'w, V>;

    fn name(&self) -> &str {
        "transport-velocity stress (Adami et al. 2013)"
    }

    fn bind<'w>(
        &'w self,
        b: &mut Binder<'_, 'w, V>,
    ) -> Result<BoundTransportStress<'w, V>, String> {
        b.force()?;
        b.power()?;
        Ok(BoundTransportStress {
            data: b.data(),
            offset: b.require()?,
            corrected: b.column::<GradientCorrection<V>>().is_some(),
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundTransportStress<'_, V> {
    /// `(m_i v_i/ρ_i` (`m_i v_i` with the kernel correction), `ṽ_i − v_i)`: `m_i A_i/ρ_i²`
    /// (`m_i A_i/ρ_i`) without its offset.
    type Owner = (V, V);

    #[inline(always)]
    fn owner(&self, i: usize) -> (V, V) {
        let (m, rho) = (self.data.mass[i].0, self.data.rho[i].0);
        let f = if self.corrected { m } else { m / rho };
        (self.data.vel[i].0 * f, self.offset[i].0)
    }

    #[inline(always)]
    fn interact<T: Lanes>(&self, owner: &(V, V), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (a, dv) = *owner;
        let g = p.grad();
        let nbr = if p.corrected() {
            p.m_j() / p.rho_j()
        } else {
            p.m_j()
        };
        let s = LaneVec::<T>::splat::<V>(dv).dot::<V>(g) * nbr;
        let f = LaneVec::<T>::splat::<V>(a).scale::<V>(s);
        out.add_force::<V>(f);
        let heat = T::splat(-0.5) * f.dot::<V>(p.vij());
        out.add_power(heat);
        out.react_power(heat);
    }
}

impl SimPlugin for TransportVelocity {
    const NAME: &'static str = "TransportVelocity";
    const SUMMARY: &'static str =
        "particles carried by a transport velocity with a background pressure (Adami et al. 2013)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.gain.is_finite() && self.gain > 0.0 && self.gain <= MAX_GAIN) {
            return Err(format!(
                "gain: must be in (0, {MAX_GAIN}] (the shift is unstable above about 0.17), got {}",
                self.gain
            ));
        }
        if let Some(p) = self.background
            && !(p.is_finite() && p > 0.0 && p <= MAX_BACKGROUND)
        {
            return Err(format!(
                "background: must be in (0, {MAX_BACKGROUND:e}] Pa, got {p}"
            ));
        }
        check_surface(self.surface)
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.world.insert_resource(Transport {
            background: self.background,
            gain: self.gain,
            surface: self
                .surface
                .unwrap_or_else(|| Shifting::default_surface(V::DIM)),
        });
        sim.add_column(ColumnSpec::restart_only("transport_offset"), |_| {
            TransportOffset(V::zero())
        })?;
        if self.stress {
            ensure_energy_equation(sim)?;
            sim.add_pair_term(TransportStressTerm);
        }
        sim.add_system(
            StepSet::Correct,
            "transport_velocity (Adami et al. 2013)",
            transport_particles::<V>,
        )
        .after::<DriveBodies>();
        Ok(())
    }
}
