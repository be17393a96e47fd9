//! Viscosity plugins for the dual-support sweep.
//!
//! * `ArtificialViscosity(alpha, beta, eta_factor)` — Eq. 4.17 in the dual form of Eq. 4.19:
//!   `f_ij = −m_i m_j (Π_ij/2) ∇_iW_ij` on i, `−f_ij` on j; the dissipated work `−f_ij·v_ij ≥ 0`
//!   is shared ½/½ as internal energy (Eq. 4.20). The same heat is summed into the particles'
//!   `DissipationRate`, integrated into their `Dissipated` energy (the energy budget's
//!   dissipated part, `dualsph_fluid::ensure_dissipation`) with `dissipation: true`.
//! * `PhysicalViscosity(mu)` — Eq. 4.23: `f_ij = m_i m_j (μ/ρ_i²) (r_ij·∇_iW_ij)/(r_ij²+η²) v_ij`,
//!   `η = 0.1 h_i`, work shared ½/½ (Eq. 4.24).
//!
//! Both take their coefficients per body (`materials: [(body: "oil", …)]`, the others keeping
//! the plugin's own): a pair is evaluated in its owner i's support with i's coefficients (α_i,
//! β_i or μ_i), as Eq. 4.23 already takes i's ρ_i and h_i, and its reaction goes to j through
//! j's dual-support — so momentum and the pair's energy stay exact across a material interface.
//! Next to walls that extrapolate the fluid's velocity (`WallPressure(viscous: NoSlip)`),
//! both read the relative velocity through the walls' offsets, `v̂_ij = v_ij + δ_i − δ_j`
//! ([`WallVelocityOffset`]); the heat stays the work of the force on the pair, so energy is
//! conserved as before.
//! * `NewtonianViscosity(mu, lambda)` — the viscous part of the Newtonian stress (Eq. 4.6),
//!   `τ_i = μ(G_i + G_iᵀ) + λ tr(G_i) I` with the velocity gradient G of Eq. 7.4, in the
//!   general dual form Eq. 4.13 with `1/(ρ_iρ_j)` (§5.2): `f_ij = m_i m_j/(ρ_iρ_j) τ_i·∇̃_iW_ij`
//!   on i, `−f_ij` on j; its work goes to i (Eq. 4.15). With the kernel correction, the stress
//!   being symmetric, angular momentum is conserved exactly.
#![warn(missing_docs)]

use dualsph_core::bodies::WallVelocityOffset;
use dualsph_core::lanes::LaneVec;
use dualsph_core::sim::MaxViscosity;
use dualsph_fluid::prelude::*;
use dualsph_fluid::{ensure_dissipation, ensure_energy_equation};
use dualsph_kernel_correction::ensure_velocity_gradient;
use serde::{Deserialize, Serialize};

/// Monaghan artificial viscosity.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ArtificialViscosity {
    /// Linear coefficient α (dimensionless).
    pub alpha: Real,
    /// Quadratic coefficient β (dimensionless).
    pub beta: Real,
    /// η = eta_factor · h̄ (dimensionless; default 0.1).
    #[serde(default = "default_eta")]
    pub eta_factor: Real,
    /// Other coefficients by body: `materials: [(body: "oil", alpha: 0.1, beta: 0.0)]`.
    #[serde(default)]
    pub materials: Vec<AvMaterial>,
    /// Whether the heat is also integrated apart, as each particle's `Dissipated` energy
    /// (the energy budget's dissipated part; default false). The extra sum takes the force
    /// sweep off its fixed record layout: about half as many instructions again per step on
    /// the dam break (the `perf` example of validation/, callgrind), so it is on only in the scenes that ask.
    #[serde(default)]
    pub dissipation: bool,
}

/// A body's own artificial-viscosity coefficients (see [`ArtificialViscosity::materials`]).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AvMaterial {
    /// The body's name.
    pub body: String,
    /// α (dimensionless).
    pub alpha: Real,
    /// β (dimensionless).
    pub beta: Real,
}

fn default_eta() -> Real {
    0.1
}

/// The artificial-viscosity pair term.
#[derive(Debug, Clone)]
pub struct ArtificialViscosityTerm {
    /// α (dimensionless).
    pub alpha: Real,
    /// β (dimensionless).
    pub beta: Real,
    /// η / h̄.
    pub eta_factor: Real,
    /// `(α, β)` of every body by [`BodyId`] when the bodies differ; empty when every particle
    /// has the plugin's `(alpha, beta)`.
    pub by_body: Vec<(Real, Real)>,
    /// Whether the heat is summed into [`DissipationRate`] too.
    pub dissipation: bool,
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
    term: &'w ArtificialViscosityTerm,
    data: ParticleData<'w, V>,
    sound: &'w [SoundSpeed],
    body: Option<&'w [BodyId]>,
    /// Ω of the grad-h formulation, which divides the owner's mass.
    omega: Option<&'w [GradHFactor]>,
    /// The dissipation-rate sum, when the heat is tracked apart.
    dissipation: Option<Acc>,
    /// The walls' velocity offsets, when a wall model sets them.
    offset: Option<&'w [WallVelocityOffset<V>]>,
}

impl<V: Vector> PairTerm<V> for ArtificialViscosityTerm {
    type Bound<'w> = BoundAv<'w, V>;

    fn name(&self) -> &str {
        "artificial viscosity (Eq. 4.17)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundAv<'w, V>, String> {
        b.force()?;
        b.power()?;
        let body = if self.by_body.is_empty() {
            None
        } else {
            Some(b.require::<BodyId>()?)
        };
        let dissipation = match self.dissipation {
            true => Some(b.dissipation()?),
            false => None,
        };
        Ok(BoundAv {
            term: self,
            data: b.data(),
            sound: b.require()?,
            body,
            omega: b.column(),
            dissipation,
            offset: b.column(),
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundAv<'_, V> {
    /// `(m_i, (h_i, c_i, ρ_i), (α_i, β_i, η_f))` (`η_f` read once per row, not per pair);
    /// `m_i/Ω_i` for the grad-h formulation, whose viscous force on i from its own support is
    /// `−m_i m_j (Π_ij/2) ∇_iW_ij(h_i)/Ω_i` (the viscosity of Price 2012 with the
    /// kernel gradients over Ω, in its dual-support half).
    type Owner = (Real, AvSide<Real>, (Real, Real, Real));

    #[inline(always)]
    fn owner(&self, i: usize) -> Self::Owner {
        let d = &self.data;
        let t = self.term;
        let coefs = match self.body {
            None => (t.alpha, t.beta),
            Some(b) => t.by_body[b[i].0 as usize],
        };
        let coefs = (coefs.0, coefs.1, t.eta_factor);
        let m = match self.omega {
            Some(o) => d.mass[i].0 / o[i].0,
            None => d.mass[i].0,
        };
        (m, (d.h[i].0, self.sound[i].0, d.rho[i].0), coefs)
    }

    /// The pair's force `−m_i m_j (Π_ij/2) ∇_iW_ij` and its heat, half to each (Eqs. 4.17,
    /// 4.20), into the power and, tracked apart, the dissipation rate; a receding pair adds
    /// zeros. The heat `½ m_i m_j (Π_ij/2) v_ij·∇_iW_ij` is never negative: `Π_ij ≥ 0`
    /// (`num ≥ 0` with `x ≤ 0`), and `v_ij·∇_iW_ij = W'(r) v_ij·r_ij/r ≥ 0` when the pair
    /// approaches (`W' ≤ 0`), `Π_ij = 0` otherwise.
    #[inline(always)]
    fn interact<T: Lanes>(&self, o: &Self::Owner, p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let d = p.data();
        let c = T::splat;
        let (m_i, (h_i, c_i, rho_i), coefs) = *o;
        let side_j = (
            p.gather(d.h, |h| h.0),
            p.gather(self.sound, |s| s.0),
            p.rho_j(),
        );
        let (vij, g) = (p.vij(), p.grad_raw());
        let side_i = (c(h_i), c(c_i), c(rho_i));
        let seen = viscous_vij(p, self.offset);
        let (num, den) = pi_parts(coefs, side_i, side_j, seen.dot::<V>(p.rij()), p.r());
        // m_i m_j Π/2 = m_i m_j num/den
        let coef = c(m_i) * p.m_j() * num / den;
        out.add_force::<V>(g.scale::<V>(-coef));
        let heat = c(0.5) * coef * vij.dot::<V>(g);
        out.add_power(heat);
        out.react_power(heat);
        if let Some(acc) = self.dissipation {
            out.add(acc, heat);
            out.react(acc, heat);
        }
    }
}

impl SimPlugin for ArtificialViscosity {
    const NAME: &'static str = "ArtificialViscosity";
    const SUMMARY: &'static str = "Monaghan artificial viscosity (Eq. 4.17) in dual-support form";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        for (n, x) in [
            ("alpha", self.alpha),
            ("beta", self.beta),
            ("eta_factor", self.eta_factor),
        ] {
            non_negative(n, x)?;
        }
        let bodies: Vec<&str> = self.materials.iter().map(|m| m.body.as_str()).collect();
        check_bodies(&bodies, info)?;
        for (k, m) in self.materials.iter().enumerate() {
            non_negative(&format!("materials[{k}].alpha"), m.alpha)?;
            non_negative(&format!("materials[{k}].beta"), m.beta)?;
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require::<dualsph_fluid::EquationOfState>(
            "ArtificialViscosity needs an equation of state for the sound speed",
        );
        ensure_energy_equation(sim)?;
        if self.dissipation {
            ensure_dissipation(sim)?;
        }
        let own = self
            .materials
            .iter()
            .map(|m| (m.body.as_str(), (m.alpha, m.beta)));
        let by_body = by_body(sim, (self.alpha, self.beta), own);
        sim.add_pair_term(ArtificialViscosityTerm {
            alpha: self.alpha,
            beta: self.beta,
            eta_factor: self.eta_factor,
            by_body,
            dissipation: self.dissipation,
        });
        Ok(())
    }
}

/// Morris-type physical viscosity.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PhysicalViscosity {
    /// Dynamic viscosity μ (Pa s).
    pub mu: Real,
    /// `η/h_i` (dimensionless) of the regularisation `r² + η²` (default 0.1, the paper's). It lowers the
    /// Laplacian the term makes: on a square lattice with Wendland C2 and a support of 3Δx,
    /// the sum that should be 1 is 0.950 at 0.1 and 0.997 at 0.01 (see the unit test
    /// `regularisation_lowers_the_laplacian`), so a viscous flow that must be accurate to a
    /// per cent wants 0.01.
    #[serde(default = "default_eta")]
    pub eta_factor: Real,
    /// Other viscosities by body: `materials: [(body: "oil", mu: 0.05)]`.
    #[serde(default)]
    pub materials: Vec<MuMaterial>,
}

/// A body's own dynamic viscosity (see [`PhysicalViscosity::materials`]).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MuMaterial {
    /// The body's name.
    pub body: String,
    /// μ (Pa s).
    pub mu: Real,
}

/// The physical-viscosity pair term (Eq. 4.23).
#[derive(Debug, Clone)]
pub struct PhysicalViscosityTerm {
    /// μ (Pa s).
    pub mu: Real,
    /// `η/h_i`.
    pub eta_factor: Real,
    /// μ of every body by [`BodyId`] when the bodies differ; empty when every particle has
    /// `mu`.
    pub by_body: Vec<Real>,
}

/// [`PhysicalViscosityTerm`] bound to its sums.
#[derive(Clone, Copy, Debug)]
pub struct BoundPhysical<'w, V: Vector> {
    term: &'w PhysicalViscosityTerm,
    body: Option<&'w [BodyId]>,
    /// The walls' velocity offsets, when a wall model sets them.
    offset: Option<&'w [WallVelocityOffset<V>]>,
}

impl<V: Vector> PairTerm<V> for PhysicalViscosityTerm {
    type Bound<'w> = BoundPhysical<'w, V>;

    fn name(&self) -> &str {
        "physical viscosity (Eq. 4.23)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundPhysical<'w, V>, String> {
        b.force()?;
        b.power()?;
        let body = if self.by_body.is_empty() {
            None
        } else {
            Some(b.require::<BodyId>()?)
        };
        Ok(BoundPhysical {
            term: self,
            body,
            offset: b.column(),
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundPhysical<'_, V> {
    /// `μ_i`.
    type Owner = Real;

    #[inline(always)]
    fn owner(&self, i: usize) -> Real {
        match self.body {
            None => self.term.mu,
            Some(b) => self.term.by_body[b[i].0 as usize],
        }
    }

    #[inline(always)]
    fn interact<T: Lanes>(&self, mu: &Real, p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i) = (p.data(), p.i());
        let c = T::splat;
        let eta = self.term.eta_factor * d.h[i].0;
        let rho_i = d.rho[i].0;
        let r = p.r();
        let coef = c(d.mass[i].0) * p.m_j() * c(*mu) / c(rho_i * rho_i)
            * p.rij().dot::<V>(p.grad_raw())
            / (r * r + c(eta * eta));
        let (vij, seen) = (p.vij(), viscous_vij(p, self.offset));
        out.add_force::<V>(seen.scale::<V>(coef));
        // the work of the force on the pair, −coef v̂_ij·v_ij, as heat: half to each
        let heat = c(-0.5) * coef * seen.dot::<V>(vij);
        out.add_power(heat);
        out.react_power(heat);
    }
}

impl SimPlugin for PhysicalViscosity {
    const NAME: &'static str = "PhysicalViscosity";
    const SUMMARY: &'static str = "physical viscosity, Morris form in dual-support (Eq. 4.23)";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        non_negative("mu", self.mu)?;
        if !(self.eta_factor.is_finite() && self.eta_factor > 0.0) {
            return Err(format!(
                "eta_factor: must be a number > 0, got {}",
                self.eta_factor
            ));
        }
        let bodies: Vec<&str> = self.materials.iter().map(|m| m.body.as_str()).collect();
        check_bodies(&bodies, info)?;
        for (k, m) in self.materials.iter().enumerate() {
            non_negative(&format!("materials[{k}].mu"), m.mu)?;
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        ensure_energy_equation(sim)?;
        let own = self.materials.iter().map(|m| (m.body.as_str(), m.mu));
        let by_body = by_body(sim, self.mu, own);
        raise_viscosity(sim, by_body.iter().copied().fold(self.mu, Real::max));
        sim.add_pair_term(PhysicalViscosityTerm {
            mu: self.mu,
            eta_factor: self.eta_factor,
            by_body,
        });
        Ok(())
    }
}

/// Newtonian viscous stress.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NewtonianViscosity {
    /// Dynamic viscosity μ (Pa s).
    pub mu: Real,
    /// Second viscosity coefficient λ (Pa s) (default 0, as in the paper's Eq. 4.6 example).
    #[serde(default)]
    pub lambda: Real,
}

/// The viscous-stress pair term.
#[derive(Debug, Clone, Copy)]
pub struct ViscousStressTerm {
    /// μ (Pa s).
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

/// `x` finite and `>= 0`, or the error naming `field`.
/// The relative velocity a viscous term sees, `v̂_ij = v_ij + δ_i − δ_j` with `δ` the walls'
/// [`WallVelocityOffset`] (zero on fluid particles), or `v_ij` when no wall model sets it.
#[inline(always)]
fn viscous_vij<T: Lanes, V: Vector>(
    p: &PairLanes<'_, T, V>,
    offset: Option<&[WallVelocityOffset<V>]>,
) -> LaneVec<T> {
    match offset {
        None => p.vij(),
        Some(d) => {
            let d_i = LaneVec::splat::<V>(d[p.i()].0);
            p.vij().plus::<V>(d_i).minus::<V>(p.gather_vec(d, |x| x.0))
        }
    }
}

fn non_negative(field: &str, x: Real) -> Result<(), String> {
    if x.is_finite() && x >= 0.0 {
        Ok(())
    } else {
        Err(format!("{field}: must be >= 0, got {x}"))
    }
}

/// Every body named in `materials` (`bodies`, in order) exists, and none twice.
fn check_bodies(bodies: &[&str], info: &SceneInfo) -> Result<(), String> {
    for (k, b) in bodies.iter().enumerate() {
        info.check_body(&format!("materials[{k}].body"), b)?;
        if bodies[..k].contains(b) {
            return Err(format!("materials[{k}].body: `{b}` is given twice"));
        }
    }
    Ok(())
}

/// The coefficients of every body by [`BodyId`]: a body's own from `materials`, `default`
/// for the others; empty when no body has its own (every particle then has `default`).
fn by_body<'m, V: Vector, C: Copy + PartialEq>(
    sim: &Sim<V>,
    default: C,
    materials: impl Iterator<Item = (&'m str, C)> + Clone,
) -> Vec<C> {
    let names = sim.world.resource::<dualsph_core::bodies::Bodies>().names();
    let all: Vec<C> = names
        .iter()
        .map(|n| {
            materials
                .clone()
                .find(|(b, _)| b == n)
                .map_or(default, |m| m.1)
        })
        .collect();
    if all.iter().all(|&c| c == default) {
        Vec::new()
    } else {
        all
    }
}

fn raise_viscosity<V: Vector>(sim: &mut Sim<V>, mu: Real) {
    let mut m = sim.world.resource_mut::<MaxViscosity>();
    m.0 = m.0.max(mu);
}

#[cfg(test)]
mod tests;
