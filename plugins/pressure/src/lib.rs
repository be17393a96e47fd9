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

use dualsph_fluid::ensure_energy_equation;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// Pressure force.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PressureForce {}

/// The pair term.
#[derive(Debug, Clone, Copy)]
pub struct PressureTerm;

/// The owner's factor of a pressure-like pair coefficient for the stress `s_i` of particle i:
/// `m_i s_i/ρ_i²`, or `m_i s_i/ρ_i` with the kernel correction (then the neighbour's factor,
/// [`neighbour_lanes`], is `m_j/ρ_j`, otherwise `m_j`; §5.2).
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

/// True when the scene applies the kernel-gradient correction (Eq. 2.10).
pub(crate) fn is_corrected<V: Vector>(b: &Binder<'_, '_, V>) -> bool {
    b.column::<GradientCorrection<V>>().is_some()
}

/// The neighbour's factor in every lane (see [`owner_factor`]): `m_j/ρ_j` with the kernel
/// correction, `m_j` without (the pairs say which: [`PairLanes::corrected`], fixed for the
/// row loop, so nothing is tested per pair).
#[inline(always)]
pub(crate) fn neighbour_lanes<T: Lanes, V: Vector>(p: &PairLanes<'_, T, V>) -> T {
    if p.corrected() {
        p.m_j() / p.rho_j()
    } else {
        p.m_j()
    }
}

/// `f_ij = −c ∇̃_iW_ij` on i and `c v_ij·∇̃_iW_ij` to `m_i ε̇_i`, for the pair coefficient `c`.
#[inline(always)]
pub(crate) fn add_pressure_like<T: Lanes, V: Vector>(
    p: &PairLanes<'_, T, V>,
    coef: T,
    out: &mut Out<'_, T>,
) {
    let g = p.grad();
    out.add_force::<V>(g.scale::<V>(-coef));
    out.add_power(coef * p.vij().dot::<V>(g));
}

/// [`PressureTerm`] bound to the pressure column and its sums.
#[derive(Clone, Copy, Debug)]
pub struct BoundPressure<'w, V: Vector> {
    data: ParticleData<'w, V>,
    pressure: &'w [Pressure],
    corrected: bool,
    /// Ω of the grad-h formulation, which divides the owner's factor.
    omega: Option<&'w [GradHFactor]>,
}

impl<V: Vector> PairTerm<V> for PressureTerm {
    type Bound<'w> = BoundPressure<'w, V>;

    fn name(&self) -> &str {
        "pressure (Eq. 4.19)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundPressure<'w, V>, String> {
        b.force()?;
        b.power()?;
        Ok(BoundPressure {
            data: b.data(),
            pressure: b.require()?,
            corrected: is_corrected(b),
            omega: b.column(),
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundPressure<'_, V> {
    /// `m_i p_i/ρ_i²` (`m_i p_i/ρ_i` with the kernel correction; `m_i p_i/(Ω_i ρ_i²)` with
    /// the grad-h formulation, Springel & Hernquist 2002).
    type Owner = Real;

    #[inline(always)]
    fn owner(&self, i: usize) -> Real {
        let f = owner_factor(&self.data, self.corrected, i, self.pressure[i].0);
        match self.omega {
            Some(o) => f / o[i].0,
            None => f,
        }
    }

    #[inline(always)]
    fn interact<T: Lanes>(&self, owner: &Real, p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let coef = T::splat(*owner) * neighbour_lanes(p);
        add_pressure_like(p, coef, out);
    }
}

impl SimPlugin for PressureForce {
    const NAME: &'static str = "PressureForce";
    const SUMMARY: &'static str =
        "dual-support pressure force (Eq. 4.19) with consistent energy (Eq. 4.15)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require::<dualsph_fluid::EquationOfState>(
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
    fn two_lanes_equal_one_lane_bitwise() {
        dualsph_fluid::checks::check_lanes_2d(&PressureTerm).unwrap();
        dualsph_fluid::checks::check_block_loop_2d(std::sync::Arc::new(PressureTerm)).unwrap();
    }
}
