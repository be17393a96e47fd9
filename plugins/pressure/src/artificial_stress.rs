//! `ArtificialStress(epsilon, exponent)`: Monaghan's (2000) cure for the tensile instability,
//! written as a dual-support pair term.
//!
//! Under tension (`p_i < 0`) SPH particles attract and clump: the mode grows at a rate of
//! order `c/h` and, once two particles nearly coincide, the continuity equation drives their
//! density negative within a few dozen steps. The artificial stress adds a short-range
//! repulsion to the pressure force of a particle under tension:
//!
//! `f_ij = −m_i m_j R_i F_ij^n ∇_iW_ij`,  `R_i = ε |p_i|/ρ_i²` for `p_i < 0` (else 0),
//! `F_ij = W(r_ij, h_i) / W(Δp_i, h_i)`,  `Δp_i = (m_i/ρ_i)^{1/d}` (the particle's size),
//!
//! evaluated once per pair with the owner's kernel like the pressure term (Eq. 4.19), the
//! reaction going to j, so linear momentum is exact. `F^n` (n = 4) is ≈ 1 at the particle
//! spacing and falls off fast beyond it, so the repulsion acts only on pairs closer than the
//! spacing. The pair's work is credited to i's internal energy
//! (`m_i ε̇_i += m_i m_j R_i F^n v_ij·∇_iW_ij`), so total energy stays exact too. With the
//! kernel correction active the same forms as the pressure term are used (`1/(ρ_iρ_j)`,
//! `L_i ∇_iW`). Monaghan, J. J. (2000), SPH without a tensile instability, J. Comput. Phys.
//! 159, 290–311.

use crate::{add_pressure_like, is_corrected, neighbour_lanes, owner_factor};
use dualsph_fluid::ensure_energy_equation;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// Artificial stress settings.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ArtificialStress {
    /// ε (dimensionless): the strength of the repulsion relative to the tension (Monaghan: 0.2 for fluids).
    #[serde(default = "default_epsilon")]
    pub epsilon: Real,
    /// n: the exponent of `F_ij` (Monaghan: 4).
    #[serde(default = "default_exponent")]
    pub exponent: u32,
}

fn default_epsilon() -> Real {
    0.2
}

fn default_exponent() -> u32 {
    4
}

/// The pair term.
#[derive(Debug, Clone)]
pub struct ArtificialStressTerm {
    /// ε.
    pub epsilon: Real,
    /// n.
    pub exponent: i32,
}

/// [`ArtificialStressTerm`] bound to the pressure column and its sums.
#[derive(Clone, Copy, Debug)]
pub struct BoundStress<'w> {
    term: &'w ArtificialStressTerm,
    pressure: &'w [Pressure],
    corrected: bool,
}

impl BoundStress<'_> {
    /// `m_i R_i` in the pressure term's form ([`owner_factor`] with `s_i = ε max(−p_i, 0)`):
    /// zero unless particle i is under tension.
    #[inline(always)]
    fn owner<V: Vector>(&self, d: &ParticleData<'_, V>, i: usize) -> Real {
        let s_i = (-self.pressure[i].0).max(0.0) * self.term.epsilon;
        owner_factor(d, self.corrected, i, s_i)
    }

    /// `W(Δp_i, h_i)` with `Δp_i = (m_i/ρ_i)^{1/d}`.
    #[inline(always)]
    fn w_spacing<V: Vector>(d: &ParticleData<'_, V>, i: usize, kernel: &OwnerKernel) -> Real {
        let dp = dualsph_core::math::particle_size(V::DIM, d.mass[i].0, d.rho[i].0);
        kernel.w(dp)
    }
}

impl<V: Vector> PairTerm<V> for ArtificialStressTerm {
    type Bound<'w> = BoundStress<'w>;

    fn name(&self) -> &str {
        "artificial stress (Monaghan 2000)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundStress<'w>, String> {
        b.force()?;
        b.power()?;
        Ok(BoundStress {
            term: self,
            pressure: b.require()?,
            corrected: is_corrected(b),
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundStress<'_> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i) = (p.data(), p.i());
        let owner = self.owner(d, i);
        if owner == 0.0 {
            return;
        }
        let inv_w0 = 1.0 / Self::w_spacing(d, i, &p.kernel());
        let ratio = p.w() * T::splat(inv_w0);
        let n = self.term.exponent;
        let fn_ = T::from_fn(|l| ratio.lane(l).powi(n));
        let coef = T::splat(owner) * neighbour_lanes(p) * fn_;
        add_pressure_like(p, coef, out);
    }
}

impl SimPlugin for ArtificialStress {
    const NAME: &'static str = "ArtificialStress";
    const SUMMARY: &'static str =
        "Monaghan (2000) artificial stress against the tensile instability (p < 0)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.epsilon.is_finite() && self.epsilon > 0.0 && self.epsilon <= 1.0) {
            return Err(format!("epsilon: must lie in (0, 1], got {}", self.epsilon));
        }
        if !(1..=8).contains(&self.exponent) {
            return Err(format!(
                "exponent: must lie in 1..=8, got {}",
                self.exponent
            ));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require::<dualsph_fluid::EquationOfState>(
            "ArtificialStress needs an equation of state (TaitEos or IdealGas)",
        );
        ensure_energy_equation(sim)?;
        sim.add_pair_term(ArtificialStressTerm {
            epsilon: self.epsilon,
            exponent: self.exponent as i32,
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        let term = ArtificialStressTerm {
            epsilon: 0.2,
            exponent: 4,
        };
        dualsph_fluid::checks::check_lanes_2d(&term).unwrap();
    }
}
