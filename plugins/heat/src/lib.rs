//! `HeatConduction(conductivity: κ, heat_capacity: c_v)`: dual-support heat conduction,
//! Eq. 3.13. With `T = ε / c_v`, for `j ∈ H_i` the heat flow
//! `Q_ij = m_i m_j κ_i/(ρ_iρ_j) · (r_ij·∇_iW_ij)/(r_ij² + η²) · (T_i − T_j)`, `η = 0.1 h_i`,
//! is computed once; i gains `Q_ij` and j loses it, so `Σ m ε` is conserved to round-off for
//! any h field. With equal h the two supports add up to the classical `(κ_i + κ_j)` form.
#![warn(missing_docs)]

use dualsph_core::plugin::positive;
use dualsph_fluid::ensure_energy_equation;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// Heat conduction.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HeatConduction {
    /// Thermal conductivity κ (W/(m K)).
    pub conductivity: Real,
    /// Specific heat c_v (J/(kg K); T = ε / c_v), default 1.
    #[serde(default = "one")]
    pub heat_capacity: Real,
}

fn one() -> Real {
    1.0
}

/// The pair term.
#[derive(Debug, Clone, Copy)]
pub struct HeatTerm {
    /// 1 / c_v.
    pub inv_cv: Real,
}

/// [`HeatTerm`] bound to the columns it reads (`ε` and `κ`) and the power it writes.
#[derive(Clone, Copy, Debug)]
pub struct BoundHeat<'w> {
    inv_cv: Real,
    eps: &'w [InternalEnergy],
    kappa: &'w [Conductivity],
}

impl<V: Vector> PairTerm<V> for HeatTerm {
    type Bound<'w> = BoundHeat<'w>;

    fn name(&self) -> &str {
        "heat conduction (Eq. 3.13)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundHeat<'w>, String> {
        b.power()?;
        Ok(BoundHeat {
            inv_cv: self.inv_cv,
            eps: b.require()?,
            kappa: b.require()?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundHeat<'_> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    /// i gains `Q_ij`, j loses it.
    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i) = (p.data(), p.i());
        let c = T::splat;
        let eta = 0.1 * d.h[i].0;
        let tij = (c(self.eps[i].0) - p.gather(self.eps, |e| e.0)) * c(self.inv_cv);
        let r = p.r();
        let q = c(d.mass[i].0) * p.m_j() * c(self.kappa[i].0) / (c(d.rho[i].0) * p.rho_j())
            * p.rij().dot::<V>(p.grad_raw())
            / (r * r + c(eta * eta))
            * tij;
        out.add_power(q);
        out.react_power(-q);
    }
}

impl SimPlugin for HeatConduction {
    const NAME: &'static str = "HeatConduction";
    const SUMMARY: &'static str = "dual-support heat conduction (Eq. 3.13)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.conductivity.is_finite() && self.conductivity >= 0.0) {
            return Err(format!(
                "conductivity: must be >= 0, got {}",
                self.conductivity
            ));
        }
        positive("heat_capacity", self.heat_capacity)?;
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        ensure_energy_equation(sim)?;
        let kappa = self.conductivity;
        let spec = ColumnSpec::restart_only("conductivity");
        sim.add_column(spec, move |_| Conductivity(kappa))?;
        sim.add_pair_term(HeatTerm {
            inv_cv: 1.0 / self.heat_capacity,
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        dualsph_fluid::checks::check_lanes_2d(&HeatTerm { inv_cv: 0.25 }).unwrap();
    }
}
