//! `PressureForce()`: the dual-support pressure force, Eq. 4.19 (pressure part).
//!
//! For `j ∈ H_i`, evaluated once with i's kernel: `f_ij = −m_i m_j (p_i/ρ_i²) ∇_iW_ij` acts on
//! i and `−f_ij` on j (the `H'_j` term of Eq. 4.19). The pair's work `−f_ij·v_ij` goes into i's
//! internal energy: `m_i ε̇_i += m_i m_j (p_i/ρ_i²) v_ij·∇_iW_ij`, the `σ_i`-term of Eq. 4.15,
//! so that `Σ(m v·a + m ε̇) = 0` exactly and `dε_i = (p_i/ρ_i²) dρ_i` with the continuity
//! equation (4.9). (Eq. 4.20 splits this work ½/½ instead; that also balances but is not
//! consistent with `dε = p/ρ² dρ`.) With the kernel correction active, `1/ρ_i²` becomes
//! `1/(ρ_iρ_j)` and `∇_iW_ij` becomes `L_i ∇_iW_ij` (§5.2), which keeps angular momentum exact.

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

impl<V: Vector> PairTerm<V> for PressureTerm {
    fn name(&self) -> &str {
        "pressure (Eq. 4.19)"
    }

    #[inline]
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        let f = p.fields;
        let (i, j) = (p.i, p.j);
        let denom = if f.correction.is_empty() {
            f.rho[i] * f.rho[i]
        } else {
            f.rho[i] * f.rho[j]
        };
        let coef = f.mass[i] * f.mass[j] * f.pressure[i] / denom;
        let force = p.grad * (-coef);
        out.force += force;
        out.power_i += coef * p.vij().dot(p.grad);
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
        ensure_energy_equation(sim);
        sim.add_pair_term(PressureTerm);
        Ok(())
    }
}
