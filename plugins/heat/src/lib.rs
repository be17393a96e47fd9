//! `HeatConduction(conductivity: κ, heat_capacity: c_v)`: dual-support heat conduction,
//! Eq. 3.13. With `T = ε / c_v`, for `j ∈ H_i` the heat flow
//! `Q_ij = m_i m_j κ_i/(ρ_iρ_j) · (r_ij·∇_iW_ij)/(r_ij² + η²) · (T_i − T_j)`, `η = 0.1 h_i`,
//! is computed once; i gains `Q_ij` and j loses it, so `Σ m ε` is conserved to round-off for
//! any h field. With equal h the two supports add up to the classical `(κ_i + κ_j)` form.
#![warn(missing_docs)]

use dualsph_core::integrator::ensure_energy_equation;
use dualsph_core::prelude::*;
use serde::Deserialize;

/// Heat conduction.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeatConduction {
    /// Thermal conductivity κ.
    pub conductivity: Real,
    /// Specific heat c_v (T = ε / c_v), default 1.
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

/// [`HeatTerm`] bound to the columns it reads: `ε` and `κ`.
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

    fn bind<'w>(&'w self, data: &ParticleData<'w, V>) -> Result<BoundHeat<'w>, String> {
        let name = PairTerm::<V>::name(self);
        Ok(BoundHeat {
            inv_cv: self.inv_cv,
            eps: data.require(name)?,
            kappa: data.require(name)?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundHeat<'_> {
    #[inline(always)]
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        let d = p.data;
        let (i, j) = (p.i, p.j);
        let eta = 0.1 * d.h[i].0;
        let tij = (self.eps[i].0 - self.eps[j].0) * self.inv_cv;
        let q = d.mass[i].0 * d.mass[j].0 * self.kappa[i].0 / (d.rho[i].0 * d.rho[j].0)
            * p.rij.dot(p.grad_raw)
            / (p.r * p.r + eta * eta)
            * tij;
        out.power_i += q;
        out.power_j -= q;
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
        if !(self.heat_capacity.is_finite() && self.heat_capacity > 0.0) {
            return Err(format!(
                "heat_capacity: must be positive, got {}",
                self.heat_capacity
            ));
        }
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
