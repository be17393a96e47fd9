//! `PressureForce()`: the dual-support pressure force, Eq. 4.19 (pressure part).
//!
//! For `j ∈ H_i`, evaluated once with i's kernel: `f_ij = −m_i m_j (p_i/ρ_i²) ∇_iW_ij` acts on
//! i and `−f_ij` on j (the `H'_j` term of Eq. 4.19). The pair's work `−f_ij·v_ij` goes into i's
//! internal energy: `m_i ε̇_i += m_i m_j (p_i/ρ_i²) v_ij·∇_iW_ij`, the `σ_i`-term of Eq. 4.15,
//! so that `Σ(m v·a + m ε̇) = 0` exactly and `dε_i = (p_i/ρ_i²) dρ_i` with the continuity
//! equation (4.9). (Eq. 4.20 splits this work ½/½ instead; that also balances but is not
//! consistent with `dε = p/ρ² dρ`.) With the kernel correction active, `1/ρ_i²` becomes
//! `1/(ρ_iρ_j)` and `∇_iW_ij` becomes `L_i ∇_iW_ij` (§5.2), which keeps angular momentum exact.
#![warn(missing_docs)]

mod artificial_stress;
pub use artificial_stress::{ArtificialStress, ArtificialStressTerm};

use dualsph_core::integrator::ensure_energy_equation;
use dualsph_core::prelude::*;
use serde::Deserialize;

/// Pressure force.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureForce {}

/// The pair term.
#[derive(Debug, Clone, Copy)]
pub struct PressureTerm;

/// The owner's factor of a pressure-like pair coefficient for the stress `s_i` of particle i:
/// `m_i s_i/ρ_i²`, or `m_i s_i/ρ_i` with the kernel correction (then the neighbour's factor,
/// [`neighbour_factor`], is `m_j/ρ_j`, otherwise `m_j`; §5.2).
#[inline(always)]
pub(crate) fn owner_factor<V: Vector>(
    d: &ParticleData<'_, V>,
    corrected: bool,
    i: usize,
    s_i: Real,
) -> Real {
    let (m, rho) = (d.mass[i].0, d.rho[i].0);
    if corrected {
        m * s_i / rho
    } else {
        m * s_i / (rho * rho)
    }
}

/// The neighbour's factor (see [`owner_factor`]).
#[inline(always)]
pub(crate) fn neighbour_factor<V: Vector>(
    d: &ParticleData<'_, V>,
    corrected: bool,
    j: usize,
) -> Real {
    if corrected {
        d.mass[j].0 / d.rho[j].0
    } else {
        d.mass[j].0
    }
}

/// True when the scene applies the kernel-gradient correction (Eq. 2.10).
pub(crate) fn is_corrected<V: Vector>(data: &ParticleData<'_, V>) -> bool {
    data.column::<GradientCorrection<V>>().is_some()
}

/// [`PressureTerm`] bound to the pressure column.
#[derive(Clone, Copy, Debug)]
pub struct BoundPressure<'w> {
    pressure: &'w [Pressure],
    corrected: bool,
}

impl BoundPressure<'_> {
    /// The owner's factor: [`owner_factor`] with `s_i = p_i`.
    #[inline(always)]
    fn owner<V: Vector>(&self, d: &ParticleData<'_, V>, i: usize) -> Real {
        owner_factor(d, self.corrected, i, self.pressure[i].0)
    }

    /// `f_ij = −c ∇̃_iW_ij` on i and `c v_ij·∇̃_iW_ij` to `m_i ε̇_i`, `c = owner · other`.
    #[inline(always)]
    fn add<V: Vector>(coef: Real, vij: V, grad: V, out: &mut PairOut<V>) {
        out.force += grad * (-coef);
        out.power_i += coef * vij.dot(grad);
    }
}

impl<V: Vector> PairTerm<V> for PressureTerm {
    type Bound<'w> = BoundPressure<'w>;

    fn name(&self) -> &str {
        "pressure (Eq. 4.19)"
    }

    fn bind<'w>(&'w self, data: &ParticleData<'w, V>) -> Result<BoundPressure<'w>, String> {
        Ok(BoundPressure {
            pressure: data.require(PairTerm::<V>::name(self))?,
            corrected: is_corrected(data),
        })
    }

    fn builtin(&self) -> Option<dualsph_core::sweep::BuiltinTerm> {
        Some(dualsph_core::sweep::BuiltinTerm::Pressure)
    }
}

impl<V: Vector> BoundTerm<V> for BoundPressure<'_> {
    #[inline(always)]
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        let d = p.data;
        let coef = self.owner(d, p.i) * neighbour_factor(d, self.corrected, p.j);
        Self::add(coef, p.vij(), p.grad, out);
    }

    /// The same arithmetic as [`BoundTerm::interact`] with the owner's values loaded once.
    fn interact_row(&self, row: &Row<'_, V>, out: &mut [PairOut<V>]) {
        let d = row.data;
        let owner = self.owner(d, row.i);
        let mass = d.mass;
        let pairs = out.iter_mut().zip(row.j).zip(row.vij).zip(row.grad);
        if !self.corrected {
            for (((o, &j), &v), &g) in pairs {
                Self::add(owner * mass[j as usize].0, v, g, o);
            }
        } else {
            for (((o, &j), &v), &g) in pairs {
                Self::add(owner * neighbour_factor(d, true, j as usize), v, g, o);
            }
        }
    }
}

impl SimPlugin for PressureForce {
    const NAME: &'static str = "PressureForce";
    const SUMMARY: &'static str =
        "dual-support pressure force (Eq. 4.19) with consistent energy (Eq. 4.15)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require_feature(
            "eos",
            "PressureForce needs an equation of state (TaitEos or IdealGas)",
        );
        ensure_energy_equation(sim)?;
        sim.add_pair_term(PressureTerm);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interact_row_matches_interact_bitwise() {
        dualsph_core::sweep::check_row_override_2d(&PressureTerm).unwrap();
    }
}
