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

use dualsph_core::integrator::ensure_energy_equation;
use dualsph_core::passes::ensure_velocity_gradient;
use dualsph_core::prelude::*;
use dualsph_core::sim::MaxViscosity;
use dualsph_core::sweep::{BuiltinTerm, artificial_viscosity_parts};
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

/// The owner's values used by [`ArtificialViscosityTerm`].
#[derive(Clone, Copy, Debug)]
struct AvOwner {
    m: Real,
    h: Real,
    c: Real,
    rho: Real,
}

/// [`ArtificialViscosityTerm`] bound to the sound-speed column.
#[derive(Clone, Copy, Debug)]
pub struct BoundAv<'w> {
    term: ArtificialViscosityTerm,
    sound: &'w [SoundSpeed],
}

impl BoundAv<'_> {
    #[inline(always)]
    fn owner<V: Vector>(&self, d: &ParticleData<'_, V>, i: usize) -> AvOwner {
        AvOwner {
            m: d.mass[i].0,
            h: d.h[i].0,
            c: self.sound[i].0,
            rho: d.rho[i].0,
        }
    }

    /// `Π_ij` of Eq. 4.17 (0 for receding pairs).
    #[inline]
    pub fn pi<V: Vector>(&self, p: &Pair<'_, V>) -> Real {
        let a = self.owner(p.data, p.i);
        self.pi_of(&a, p.data, p.j, p.vij().dot(p.rij), p.r)
    }

    /// `Π_ij` from the owner's values, j, `v_ij·r_ij` and `r_ij`: with `D = r² + η²` and
    /// `x = h̄ min(v_ij·r_ij, 0)` (so `μ_ij = x/D`),
    /// `Π_ij = μ(−α c̄ + β μ)/ρ̄ = 2 x (β x − α c̄ D) / (D² (ρ_i + ρ_j))` — one division, and
    /// no branch: a receding pair has `x = 0`, hence `Π_ij = 0`.
    #[inline(always)]
    fn pi_of<V: Vector>(
        &self,
        a: &AvOwner,
        d: &ParticleData<'_, V>,
        j: usize,
        vr: Real,
        r: Real,
    ) -> Real {
        let (num, den) = self.pi_parts(a, d, j, vr, r);
        2.0 * num / den
    }

    /// `(x (β x − α c̄ D), D² (ρ_i + ρ_j))`: `Π_ij = 2 num/den` (see [`Self::pi_of`]); the
    /// formula is the core's [`artificial_viscosity_parts`], which the sweep's fused loop uses
    /// too.
    #[inline(always)]
    fn pi_parts<V: Vector>(
        &self,
        a: &AvOwner,
        d: &ParticleData<'_, V>,
        j: usize,
        vr: Real,
        r: Real,
    ) -> (Real, Real) {
        let t = &self.term;
        artificial_viscosity_parts(
            (t.alpha, t.beta, t.eta_factor),
            (a.h, a.c, a.rho),
            (d.h[j].0, self.sound[j].0, d.rho[j].0),
            vr,
            r,
        )
    }

    /// Adds the pair's force `−m_i m_j (Π_ij/2) ∇_iW_ij` and heat (Eqs. 4.17, 4.20); a
    /// receding pair adds zeros.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // the pair's data, passed unpacked to stay in registers
    fn add<V: Vector>(
        &self,
        a: &AvOwner,
        d: &ParticleData<'_, V>,
        j: usize,
        rij: V,
        r: Real,
        vij: V,
        grad_raw: V,
        out: &mut PairOut<V>,
    ) {
        let (num, den) = self.pi_parts(a, d, j, vij.dot(rij), r);
        // m_i m_j Π/2 = m_i m_j num/den
        let coef = a.m * d.mass[j].0 * num / den;
        out.force += grad_raw * (-coef);
        let heat = 0.5 * coef * vij.dot(grad_raw);
        out.power_i += heat;
        out.power_j += heat;
    }
}

impl<V: Vector> PairTerm<V> for ArtificialViscosityTerm {
    type Bound<'w> = BoundAv<'w>;

    fn name(&self) -> &str {
        "artificial viscosity (Eq. 4.17)"
    }

    fn bind<'w>(&'w self, data: &ParticleData<'w, V>) -> Result<BoundAv<'w>, String> {
        Ok(BoundAv {
            term: *self,
            sound: data.require(PairTerm::<V>::name(self))?,
        })
    }

    fn builtin(&self) -> Option<BuiltinTerm> {
        Some(BuiltinTerm::ArtificialViscosity {
            alpha: self.alpha,
            beta: self.beta,
            eta_factor: self.eta_factor,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundAv<'_> {
    #[inline(always)]
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        let a = self.owner(p.data, p.i);
        self.add(&a, p.data, p.j, p.rij, p.r, p.vij(), p.grad_raw, out);
    }

    /// The same arithmetic as [`BoundTerm::interact`] with the owner's values loaded once.
    fn interact_row(&self, row: &Row<'_, V>, out: &mut [PairOut<V>]) {
        let a = self.owner(row.data, row.i);
        let geom = row
            .j
            .iter()
            .zip(row.rij)
            .zip(row.r)
            .zip(row.vij)
            .zip(row.grad_raw);
        for (o, ((((&j, &rij), &r), &vij), &g)) in out.iter_mut().zip(geom) {
            self.add(&a, row.data, j as usize, rij, r, vij, g, o);
        }
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

impl<V: Vector> PairTerm<V> for PhysicalViscosityTerm {
    type Bound<'w> = PhysicalViscosityTerm;

    fn name(&self) -> &str {
        "physical viscosity (Eq. 4.23)"
    }

    /// Reads only the core columns.
    fn bind<'w>(&'w self, _: &ParticleData<'w, V>) -> Result<PhysicalViscosityTerm, String> {
        Ok(*self)
    }
}

impl<V: Vector> BoundTerm<V> for PhysicalViscosityTerm {
    #[inline(always)]
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        let d = p.data;
        let (i, j) = (p.i, p.j);
        let eta = 0.1 * d.h[i].0;
        let rho_i = d.rho[i].0;
        let coef = d.mass[i].0 * d.mass[j].0 * self.mu / (rho_i * rho_i) * p.rij.dot(p.grad_raw)
            / (p.r * p.r + eta * eta);
        let vij = p.vij();
        out.force += vij * coef;
        let heat = -0.5 * coef * vij.length_squared();
        out.power_i += heat;
        out.power_j += heat;
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

/// [`ViscousStressTerm`] bound to the velocity-gradient column.
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

    fn bind<'w>(&'w self, data: &ParticleData<'w, V>) -> Result<BoundStress<'w, V>, String> {
        Ok(BoundStress {
            term: *self,
            grad: data.require(PairTerm::<V>::name(self))?,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundStress<'_, V> {
    #[inline(always)]
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        let d = p.data;
        let (i, j) = (p.i, p.j);
        let (mu, lambda) = (self.term.mu, self.term.lambda);
        let g = self.grad[i].0;
        let tau = (g + g.transpose()) * mu + V::Mat::identity() * (lambda * g.trace());
        let coef = d.mass[i].0 * d.mass[j].0 / (d.rho[i].0 * d.rho[j].0);
        let force = tau.mul_vec(p.grad) * coef;
        out.force += force;
        out.power_i -= force.dot(p.vij());
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
    fn interact_row_matches_interact_bitwise() {
        dualsph_core::sweep::check_row_override_2d(&ArtificialViscosityTerm {
            alpha: 1.0,
            beta: 2.0,
            eta_factor: 0.1,
        })
        .unwrap();
    }

    /// Π_ij (one division, no branch) against Eq. 4.17 written out as in the paper:
    /// `μ = h̄ v·r/(r² + η²)`, `Π = (−α c̄ μ + β μ²)/ρ̄` for `v·r < 0`, else 0.
    #[test]
    fn pi_matches_eq_4_17_as_written() {
        use dualsph_core::glam::DVec2;
        let term = ArtificialViscosityTerm {
            alpha: 1.0,
            beta: 2.0,
            eta_factor: 0.1,
        };
        use dualsph_core::store::{Cloud, insert_column};
        let mut c = Cloud::<DVec2>::new(2);
        (c.h[0], c.h[1], c.rho[0], c.rho[1]) = (0.05, 0.08, 1003.0, 991.0);
        (c.mass[0], c.mass[1]) = (0.1, 0.2);
        c.pos[1] = DVec2::new(0.03, -0.01);
        let mut checked = 0;
        for (vx, vy) in [
            (-2.0, 1.0),
            (3.0, -0.5),
            (0.0, 0.0),
            (-0.01, 0.2),
            (-40.0, 3.0),
        ] {
            c.vel[1] = DVec2::new(vx, vy);
            let mut world = c.spawn();
            insert_column(&mut world, |i| SoundSpeed([100.0, 103.0][i]));
            let data = ParticleData::<DVec2>::of(&world).unwrap();
            let bound = PairTerm::<DVec2>::bind(&term, &data).unwrap();
            let f = &c;
            let rij = f.pos[0] - f.pos[1];
            let r = rij.length();
            let pair = Pair {
                i: 0,
                j: 1,
                rij,
                r,
                w: 0.0,
                grad_raw: rij,
                grad: rij,
                data: &data,
            };
            let vr = (f.vel[0] - f.vel[1]).dot(rij);
            let hbar = 0.5 * (f.h[0] + f.h[1]);
            let eta = 0.1 * hbar;
            let expect = if vr < 0.0 {
                let mu = hbar * vr / (r * r + eta * eta);
                let (alpha, beta, cbar, rhobar) = (1.0, 2.0, 101.5, 997.0);
                (-alpha * cbar * mu + beta * mu * mu) / rhobar
            } else {
                0.0
            };
            let got = bound.pi(&pair);
            assert!(
                (got - expect).abs() <= 1e-14 * expect.abs(),
                "v = ({vx}, {vy}): {got} vs {expect}"
            );
            checked += (expect > 0.0) as usize;
        }
        assert_eq!(checked, 3, "three approaching pairs");
    }
}
