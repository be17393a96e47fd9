//! A user's own physics in a crate of its own, with no edit of the engine: a pairwise drag
//! (the dissipative force of dissipative particle dynamics, Español & Warren 1995, *Europhys.
//! Lett.* 30, 191, Eq. 4 with the weight `w(r) = (1 − r/h_i)²`),
//!
//! `f_i←j = −γ_ij m_i m_j (1 − r/h_i)² (v_ij · ê) ê`,  `ê = r_ij/|r_ij|`,  `γ_ij = ½(γ_i + γ_j)`,
//!
//! with a drag coefficient per particle (the column `drag_gamma`, read by the pair term) and
//! the distance each particle has travelled (the column `path_length`, integrated by the
//! plugin's own system: `s_i ← s_i + Δt |v_i|` after the corrector). Both columns are
//! written to snapshots (CSV and VTK) and kept in checkpoints, so a resumed run continues
//! bitwise. The sweep evaluates the force once per pair in i's support and applies the
//! reaction to j: momentum is conserved to round-off, and the dissipated work `−f·v_ij` goes
//! to internal energy, half to each particle. The same heat is summed into a column of the
//! crate's own, `drag_power` (`Σ_j −½ f_ij·v_ij / m_i`, W/kg), through the sweep's second scalar
//! register: the sweep then runs on the record layout of the built-in terms (the pressure
//! force's power and the continuity equation's density rate), at their cost per pair. The
//! register is the one the continuity equation's density rate takes, so a scene that
//! integrates the density puts the drag in a sweep of its own (the build says so).
//!
//! The crate also brings an equation of state of its own ([`LinearEos`]), which the walls of
//! particles and the hydrostatic start follow with no edit of theirs.

mod linear_eos;
pub use linear_eos::{LinearEos, LinearEosLaw, LinearLaw, apply_linear_eos};

use bevy_ecs::prelude::*;
use dualsph::core::chunks::DENSE;
use dualsph::prelude::*;
use serde::{Deserialize, Serialize};

/// The settings, as written in a scene: `PairDrag(gamma: 2e4, gamma_gradient: [1e4, 0.0])`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PairDrag {
    /// Drag coefficient γ at the origin (1/(kg·s)).
    pub gamma: Real,
    /// ∂γ/∂x per axis: `γ_i = gamma + gamma_gradient · r_i(0)` (default 0).
    #[serde(default)]
    pub gamma_gradient: Vec<Real>,
}

/// The drag coefficient `γ_i` of a particle (1/(kg·s)).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct DragGamma(pub Real);

/// The distance the particle has travelled since the start (m).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct PathLength(pub Real);

/// The power per unit mass the drag dissipates in the particle, `Σ_j −½ f_ij·v_ij / m_i`
/// (W/kg; summed by the sweep each step).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct DragPower(pub Real);

dualsph::core::scalar_column!(DragGamma, PathLength, DragPower);

/// The sweep's scalar register that carries [`DragPower`].
pub const DRAG_POWER: usize = 1;

/// The pair term, before it is bound to the columns it reads.
#[derive(Debug, Clone, Copy)]
pub struct PairDragTerm;

/// The pair term bound for one sweep: the `drag_gamma` column it reads, the force and power
/// it writes.
#[derive(Debug, Clone, Copy)]
pub struct BoundDrag<'w> {
    gamma: &'w [DragGamma],
}

impl<V: Vector> PairTerm<V> for PairDragTerm {
    type Bound<'w> = BoundDrag<'w>;

    fn name(&self) -> &str {
        "pair drag (DPD dissipative force, per-particle γ)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundDrag<'w>, String> {
        b.force()?;
        b.power()?;
        let per_mass = |d: &mut DragPower, s: &[Real], m: Real| d.0 = s[0] / m;
        b.scalar_register::<DragPower, DRAG_POWER>(Reaction::Separate, per_mass)?;
        Ok(BoundDrag {
            gamma: b.require::<DragGamma>()?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundDrag<'_> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    /// `f_ij = −γ̄ m_i m_j (1 − r/h_i)² (v_ij·e) e` with `e = r_ij/r` (zero for coincident
    /// particles) on i, its reaction on j; the dissipated work `−f_ij·v_ij ≥ 0` to both, ½/½.
    /// Written once over [`Lanes`]: the sweep runs it two pairs at a time.
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i, r) = (p.data(), p.i(), p.r());
        let c = T::splat;
        let inv_r = T::if_gt(r, c(0.0), c(1.0) / r, c(0.0));
        let e = p.rij().scale::<V>(inv_r);
        let w = c(1.0) - r / c(d.h[i].0);
        let gamma = c(0.5) * (c(self.gamma[i].0) + p.gather(self.gamma, |g| g.0));
        let vij = p.vij();
        let mag = -gamma * c(d.mass[i].0) * p.m_j() * w * w * vij.dot::<V>(e);
        let force = e.scale::<V>(mag);
        out.add_force::<V>(force);
        let heat = c(-0.5) * force.dot::<V>(vij);
        out.add_power(heat);
        out.react_power(heat);
        out.add_scalar::<DRAG_POWER>(heat);
        out.react_scalar::<DRAG_POWER>(heat);
    }
}

/// `s_i ← s_i + Δt |v_i|` with the corrected velocity.
pub fn integrate_path_length<V: Vector>(
    clock: Res<SimClock>,
    mut q: Query<(&Velocity<V>, &mut PathLength)>,
) {
    let dt = clock.dt;
    for (v, mut s) in q.contiguous_iter_mut().expect(DENSE) {
        for (v, s) in v.iter().zip(s.iter_mut()) {
            s.0 += dt * v.0.length();
        }
    }
}

impl SimPlugin for PairDrag {
    const NAME: &'static str = "PairDrag";
    const SUMMARY: &'static str =
        "pairwise drag with a per-particle γ and each particle's path length (a user crate)";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        if !(self.gamma.is_finite() && self.gamma >= 0.0) {
            return Err(format!("gamma: must be >= 0, got {}", self.gamma));
        }
        if !(self.gamma_gradient.is_empty() || self.gamma_gradient.len() == info.dimension) {
            return Err(format!(
                "gamma_gradient: expected {} components, got {}",
                info.dimension,
                self.gamma_gradient.len()
            ));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let grad = V::from_slice(&self.gamma_gradient).unwrap_or_else(V::zero);
        let gamma0 = self.gamma;
        let gamma = move |r: V| gamma0 + grad.dot(r);
        let positions = dualsph::core::store::column::<Position<V>>(&sim.world).unwrap_or(&[]);
        if let Some(r) = positions.iter().find(|r| gamma(r.0) < 0.0) {
            return Err(SimError::Build(format!(
                "PairDrag.gamma_gradient: γ = {} < 0 at {:?}",
                gamma(r.0),
                r.0.to_xyz()
            )));
        }
        let spec = ColumnSpec::state("drag_gamma", "gamma");
        sim.add_column(spec, move |seed| DragGamma(gamma(seed.init.pos)))?;
        sim.add_column(ColumnSpec::state("path_length", "s"), |_| PathLength(0.0))?;
        let spec = ColumnSpec::state("drag_power", "drag_power");
        sim.add_column(spec, |_| DragPower(0.0))?;
        sim.add_pair_term(PairDragTerm);
        sim.add_system(
            StepSet::Correct,
            "integrate_path_length (PairDrag)",
            integrate_path_length::<V>,
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph::core::store::insert_column;

    /// The term gives, two pairs at a time, bitwise what it gives one pair at a time: the
    /// check every built-in term passes, on the same lattice, with the drag coefficient
    /// varying from particle to particle.
    #[test]
    fn the_drag_gives_two_lanes_what_each_pair_gives_alone() {
        dualsph::fluid::checks::check_lanes_2d_with(&PairDragTerm, |world| {
            insert_column(world, |i| DragGamma(0.5 + 0.1 * (i % 4) as Real));
            insert_column(world, |_| DragPower(0.0));
        })
        .unwrap();
    }
}
