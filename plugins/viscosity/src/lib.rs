//! Viscosity plugins for the dual-support sweep.
//!
//! * `ArtificialViscosity(alpha, beta, eta_factor)` — Eq. 4.17 in the dual form of Eq. 4.19:
//!   `f_ij = −m_i m_j (Π_ij/2) ∇_iW_ij` on i, `−f_ij` on j; the dissipated work `−f_ij·v_ij ≥ 0`
//!   is shared ½/½ as internal energy (Eq. 4.20).
//! * `PhysicalViscosity(mu)` — Eq. 4.23: `f_ij = m_i m_j (μ/ρ_i²) (r_ij·∇_iW_ij)/(r_ij²+η²) v_ij`,
//!   `η = 0.1 h_i`, work shared ½/½ (Eq. 4.24).
//! * `NewtonianViscosity(mu, lambda)` — the viscous part of the Newtonian stress (Eq. 4.6),
//!   `τ_i = μ(G_i + G_iᵀ) + λ tr(G_i) I` with the velocity gradient G of Eq. 7.4, in the
//!   general dual form Eq. 4.13 with `1/(ρ_iρ_j)` (§5.2): `f_ij = m_i m_j/(ρ_iρ_j) τ_i·∇̃_iW_ij`
//!   on i, `−f_ij` on j; its work goes to i (Eq. 4.15). With the kernel correction, the stress
//!   being symmetric, angular momentum is conserved exactly.
#![warn(missing_docs)]

use dualsph_core::integrate::ensure_energy_equation;
use dualsph_core::prelude::*;
use dualsph_core::sim::MaxViscosity;
use dualsph_kernel_correction::ensure_velocity_gradient;
use serde::Deserialize;

/// Monaghan artificial viscosity.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArtificialViscosity {
    /// Linear coefficient α.
    pub alpha: Real,
    /// Quadratic coefficient β.
    pub beta: Real,
    /// η = eta_factor · h̄ (default 0.1).
    #[serde(default = "default_eta")]
    pub eta_factor: Real,
}

fn default_eta() -> Real {
    0.1
}

/// The artificial-viscosity pair term.
#[derive(Debug, Clone, Copy)]
pub struct ArtificialViscosityTerm {
    /// α.
    pub alpha: Real,
    /// β.
    pub beta: Real,
    /// η / h̄.
    pub eta_factor: Real,
}

/// One particle's values in the artificial viscosity: `(h, c, ρ)`.
pub type AvSide<T> = (T, T, T);

/// `(num, den)` of Monaghan's `Π_ij` (Eq. 4.17) for `(α, β, η_f)`, the owner's `(h_i, c_i, ρ_i)`,
/// the neighbour's `(h_j, c_j, ρ_j)`, `v_ij·r_ij` and `|r_ij|`: with `h̄ = (h_i + h_j)/2`,
/// `D = r² + (η_f h̄)²`, `x = h̄ min(v_ij·r_ij, 0)` (so `μ_ij = x/D`) and `c̄ = (c_i + c_j)/2`,
/// `Π_ij = μ(−α c̄ + β μ)/ρ̄ = 2 num/den` with `num = x (β x − α c̄ D)` and
/// `den = D² (ρ_i + ρ_j)`: one division, and no branch (a receding pair has `x = 0`).
#[inline(always)]
pub fn pi_parts<T: Lanes>(
    (alpha, beta, eta_factor): (Real, Real, Real),
    (h_i, c_i, rho_i): AvSide<T>,
    (h_j, c_j, rho_j): AvSide<T>,
    vr: T,
    r: T,
) -> (T, T) {
    let c = T::splat;
    let hbar = c(0.5) * (h_i + h_j);
    let eta = c(eta_factor) * hbar;
    let d = r * r + eta * eta;
    let x = hbar * T::if_lt(vr, c(0.0), vr, c(0.0));
    let cbar = c(0.5) * (c_i + c_j);
    (
        x * (c(beta) * x - c(alpha) * cbar * d),
        d * d * (rho_i + rho_j),
    )
}

/// [`ArtificialViscosityTerm`] bound to the sound-speed column and its sums.
#[derive(Clone, Copy, Debug)]
pub struct BoundAv<'w, V: Vector> {
    term: ArtificialViscosityTerm,
    data: ParticleData<'w, V>,
    sound: &'w [SoundSpeed],
}

impl<V: Vector> PairTerm<V> for ArtificialViscosityTerm {
    type Bound<'w> = BoundAv<'w, V>;

    fn name(&self) -> &str {
        "artificial viscosity (Eq. 4.17)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundAv<'w, V>, String> {
        b.force()?;
        b.power()?;
        Ok(BoundAv {
            term: *self,
            data: b.data(),
            sound: b.require()?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundAv<'_, V> {
    /// `(m_i, (h_i, c_i, ρ_i))`.
    type Owner = (Real, AvSide<Real>);

    #[inline(always)]
    fn owner(&self, i: usize) -> Self::Owner {
        let d = &self.data;
        (d.mass[i].0, (d.h[i].0, self.sound[i].0, d.rho[i].0))
    }

    /// The pair's force `−m_i m_j (Π_ij/2) ∇_iW_ij` and its heat, half to each (Eqs. 4.17,
    /// 4.20); a receding pair adds zeros.
    #[inline(always)]
    fn interact<T: Lanes>(&self, o: &Self::Owner, p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, t) = (p.data(), &self.term);
        let c = T::splat;
        let (m_i, (h_i, c_i, rho_i)) = *o;
        let side_j = (
            p.gather(d.h, |h| h.0),
            p.gather(self.sound, |s| s.0),
            p.rho_j(),
        );
        let (vij, g) = (p.vij(), p.grad_raw());
        let coefs = (t.alpha, t.beta, t.eta_factor);
        let side_i = (c(h_i), c(c_i), c(rho_i));
        let (num, den) = pi_parts(coefs, side_i, side_j, vij.dot::<V>(p.rij()), p.r());
        // m_i m_j Π/2 = m_i m_j num/den
        let coef = c(m_i) * p.m_j() * num / den;
        out.add_force::<V>(g.scale::<V>(-coef));
        let heat = c(0.5) * coef * vij.dot::<V>(g);
        out.add_power(heat);
        out.react_power(heat);
    }
}

impl SimPlugin for ArtificialViscosity {
    const NAME: &'static str = "ArtificialViscosity";
    const SUMMARY: &'static str = "Monaghan artificial viscosity (Eq. 4.17) in dual-support form";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        for (n, x) in [
            ("alpha", self.alpha),
            ("beta", self.beta),
            ("eta_factor", self.eta_factor),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!("{n}: must be >= 0, got {x}"));
            }
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require_feature(
            "eos",
            "ArtificialViscosity needs an equation of state for the sound speed",
        );
        ensure_energy_equation(sim)?;
        sim.add_pair_term(ArtificialViscosityTerm {
            alpha: self.alpha,
            beta: self.beta,
            eta_factor: self.eta_factor,
        });
        Ok(())
    }
}

/// Morris-type physical viscosity.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicalViscosity {
    /// Dynamic viscosity μ.
    pub mu: Real,
}

/// The physical-viscosity pair term (Eq. 4.23).
#[derive(Debug, Clone, Copy)]
pub struct PhysicalViscosityTerm {
    /// μ.
    pub mu: Real,
}

/// [`PhysicalViscosityTerm`] bound to its sums.
#[derive(Clone, Copy, Debug)]
pub struct BoundPhysical {
    mu: Real,
}

impl<V: Vector> PairTerm<V> for PhysicalViscosityTerm {
    type Bound<'w> = BoundPhysical;

    fn name(&self) -> &str {
        "physical viscosity (Eq. 4.23)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundPhysical, String> {
        b.force()?;
        b.power()?;
        Ok(BoundPhysical { mu: self.mu })
    }
}

impl<V: Vector> BoundTerm<V> for BoundPhysical {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i) = (p.data(), p.i());
        let c = T::splat;
        let eta = 0.1 * d.h[i].0;
        let rho_i = d.rho[i].0;
        let r = p.r();
        let coef = c(d.mass[i].0) * p.m_j() * c(self.mu) / c(rho_i * rho_i)
            * p.rij().dot::<V>(p.grad_raw())
            / (r * r + c(eta * eta));
        let vij = p.vij();
        out.add_force::<V>(vij.scale::<V>(coef));
        let heat = c(-0.5) * coef * vij.dot::<V>(vij);
        out.add_power(heat);
        out.react_power(heat);
    }
}

impl SimPlugin for PhysicalViscosity {
    const NAME: &'static str = "PhysicalViscosity";
    const SUMMARY: &'static str = "physical viscosity, Morris form in dual-support (Eq. 4.23)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.mu.is_finite() && self.mu >= 0.0) {
            return Err(format!("mu: must be >= 0, got {}", self.mu));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        ensure_energy_equation(sim)?;
        raise_viscosity(sim, self.mu);
        sim.add_pair_term(PhysicalViscosityTerm { mu: self.mu });
        Ok(())
    }
}

/// Newtonian viscous stress.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NewtonianViscosity {
    /// Dynamic viscosity μ.
    pub mu: Real,
    /// Second viscosity coefficient λ (default 0, as in the paper's Eq. 4.6 example).
    #[serde(default)]
    pub lambda: Real,
}

/// The viscous-stress pair term.
#[derive(Debug, Clone, Copy)]
pub struct ViscousStressTerm {
    /// μ.
    pub mu: Real,
    /// λ.
    pub lambda: Real,
}

/// [`ViscousStressTerm`] bound to the velocity-gradient column and its sums.
#[derive(Clone, Copy, Debug)]
pub struct BoundStress<'w, V: Vector> {
    term: ViscousStressTerm,
    grad: &'w [VelocityGradient<V>],
}

impl<V: Vector> PairTerm<V> for ViscousStressTerm {
    type Bound<'w> = BoundStress<'w, V>;

    fn name(&self) -> &str {
        "Newtonian viscous stress (Eqs. 4.6, 4.13, 7.4)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundStress<'w, V>, String> {
        b.force()?;
        b.power()?;
        Ok(BoundStress {
            term: *self,
            grad: b.require()?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundStress<'_, V> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i) = (p.data(), p.i());
        let (mu, lambda) = (self.term.mu, self.term.lambda);
        let g = self.grad[i].0;
        let tau = (g + g.transpose()) * mu + V::Mat::identity() * (lambda * g.trace());
        let coef = T::splat(d.mass[i].0) * p.m_j() / (T::splat(d.rho[i].0) * p.rho_j());
        let grad = p.grad();
        let force = LaneVec::<T>::from_fn(|l| tau.mul_vec(grad.lane::<V>(l)) * coef.lane(l));
        out.add_force::<V>(force);
        out.add_power(-force.dot::<V>(p.vij()));
    }
}

impl SimPlugin for NewtonianViscosity {
    const NAME: &'static str = "NewtonianViscosity";
    const SUMMARY: &'static str =
        "Newtonian viscous stress from the velocity gradient (Eqs. 4.6, 7.4)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.mu.is_finite() && self.mu >= 0.0) {
            return Err(format!("mu: must be >= 0, got {}", self.mu));
        }
        if !self.lambda.is_finite() {
            return Err("lambda: must be finite".into());
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        ensure_energy_equation(sim)?;
        ensure_velocity_gradient(sim)?;
        raise_viscosity(sim, self.mu + self.lambda.abs());
        sim.add_pair_term(ViscousStressTerm {
            mu: self.mu,
            lambda: self.lambda,
        });
        Ok(())
    }
}

fn raise_viscosity<V: Vector>(sim: &mut Sim<V>, mu: Real) {
    let mut m = sim.world.resource_mut::<MaxViscosity>();
    m.0 = m.0.max(mu);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        use dualsph_core::sweep::check_lanes_2d;
        let av = ArtificialViscosityTerm {
            alpha: 1.0,
            beta: 2.0,
            eta_factor: 0.1,
        };
        check_lanes_2d(&av).unwrap();
        check_lanes_2d(&PhysicalViscosityTerm { mu: 1e-3 }).unwrap();
        check_lanes_2d(&ViscousStressTerm {
            mu: 1e-3,
            lambda: 2e-4,
        })
        .unwrap();
    }

    /// Π_ij (one division, no branch) against Eq. 4.17 written out as in the paper:
    /// `μ = h̄ v·r/(r² + η²)`, `Π = (−α c̄ μ + β μ²)/ρ̄` for `v·r < 0`, else 0.
    #[test]
    fn pi_matches_eq_4_17_as_written() {
        use dualsph_core::glam::DVec2;
        let (h, rho, c) = ([0.05, 0.08], [1003.0, 991.0], [100.0, 103.0]);
        let rij = DVec2::new(-0.03, 0.01);
        let r = rij.length();
        let mut checked = 0;
        for (vx, vy) in [
            (-2.0, 1.0),
            (3.0, -0.5),
            (0.0, 0.0),
            (-0.01, 0.2),
            (-40.0, 3.0),
        ] {
            let vij = -DVec2::new(vx, vy);
            let vr = vij.dot(rij);
            let (num, den) = pi_parts::<Real>(
                (1.0, 2.0, 0.1),
                (h[0], c[0], rho[0]),
                (h[1], c[1], rho[1]),
                vr,
                r,
            );
            let got = 2.0 * num / den;
            let hbar = 0.5 * (h[0] + h[1]);
            let eta = 0.1 * hbar;
            let expect = if vr < 0.0 {
                let mu = hbar * vr / (r * r + eta * eta);
                let (alpha, beta, cbar, rhobar) = (1.0, 2.0, 101.5, 997.0);
                (-alpha * cbar * mu + beta * mu * mu) / rhobar
            } else {
                0.0
            };
            assert!(
                (got - expect).abs() <= 1e-14 * expect.abs(),
                "v = ({vx}, {vy}): {got} vs {expect}"
            );
            checked += (expect > 0.0) as usize;
        }
        assert_eq!(checked, 3, "three approaching pairs");
    }
}
