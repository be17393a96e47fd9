//! Equations of state: `TaitEos(rho0, gamma, c0 | p0)` (Eq. 7.5) and `IdealGas(gamma)`
//! (Eq. 7.3). Each adds `Pressure` and `SoundSpeed` to the particles and fills the dense
//! arrays used by the pair sweep.
#![warn(missing_docs)]

pub mod cavitation;
pub mod hydrostatic;
pub mod initial;
pub mod mach;
pub mod sound_speed;
pub use hydrostatic::HydrostaticStart;
pub use initial::InitialPressure;
pub use sound_speed::SoundSpeedSetting;

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::Bodies;
use dualsph_core::chunks::DENSE;
use dualsph_core::plugin::positive;
use dualsph_fluid::ensure_energy_equation;
use dualsph_fluid::prelude::*;
use dualsph_fluid::{BodyEos, EosLaw, EquationOfState, Liquid};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Weakly compressible Tait equation (Eq. 7.5): `p = p0((ρ/ρ0)^γ − 1)`, `p0 = c0²ρ0/γ`,
/// `c = c0 (ρ/ρ0)^{(γ−1)/2}`. Give either `c0` (a value, or `Auto(factor: 10.0)` to derive
/// it from the speeds the scene implies: [`sound_speed`]) or `p0`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TaitEos {
    /// Reference density ρ0 (kg/m³).
    pub rho0: Real,
    /// Exponent γ (dimensionless; 7 for water).
    pub gamma: Real,
    /// Reference sound speed c0 (m/s), or `Auto(factor: 10.0)`: factor × the largest speed
    /// the scene implies.
    #[serde(default)]
    pub c0: Option<SoundSpeedSetting>,
    /// Bulk modulus p0 (Pa; alternative to c0).
    #[serde(default)]
    pub p0: Option<Real>,
    /// Pressure floor `p_min` (Pa): `p = max(p0((ρ/ρ0)^γ − 1), p_min)`. None (the default) keeps
    /// the tension Eq. 7.5 gives. `Some(0.0)` is the usual choice for free-surface flows with
    /// walls that truncate the kernel (specular walls, Eq. 7.7): there the truncated support
    /// reads as tension, which clumps particles (the tensile instability). The floor acts
    /// on `p` only, inside every pair term, so the pair forces stay antisymmetric and the
    /// energy equation uses the same `p`: conservation is unchanged. With `cavitation: true`
    /// it is the cavitation pressure (below).
    #[serde(default)]
    pub min_pressure: Option<Real>,
    /// The liquid separates instead of stretching (default false): the pressure is floored
    /// at the cavitation pressure `p_c` (`min_pressure`, 0 when it is left out) and the
    /// density at `ρ_c`, where Eq. 7.5 gives `p_c` (ρ0 for `p_c` = 0 without a background
    /// pressure). A splash or a jet's tip then pulls on its neighbours and on a wall with at
    /// most `|p_c|` (not the unbounded tension that throws a lone particle into a wall), and
    /// a particle leaving the water keeps a density near water's instead of the vanishing
    /// one the continuity equation gives it there, so it re-enters with a sane support.
    /// The raise changes no velocity and no internal energy, so the energy account stays
    /// exact (with `p_c` = 0 it also does no work: the pressure there is 0). Water at
    /// 20 °C under the atmosphere cavitates at `p_c` = p_v − p_atm ≈ 2.3 − 101.3 = −99 kPa
    /// (gauge pressure, the free surface at 0). (SPHinXsys, for the same reason, keeps the
    /// summation density of its free-surface particles from falling below ρ0.)
    #[serde(default)]
    pub cavitation: bool,
    /// Background pressure `p_b` (Pa), added to Eq. 7.5: `p = p0((ρ/ρ0)^γ − 1) + p_b` (0 by
    /// default). A positive `p_b` keeps an enclosed or periodic flow without a free surface
    /// out of tension, where the tensile instability clumps particles (Morris, Fox & Zhu
    /// 1997, *J. Comput. Phys.* 136, 214, §2.2, take `p = c²ρ`, i.e. `p_b = c²ρ0` for γ = 1).
    /// A uniform `p_b` exerts no net force on a uniform lattice; the pair forces stay
    /// antisymmetric, so conservation is unchanged. Shared by all materials.
    #[serde(default)]
    pub background: Real,
    /// Other materials, by body: `materials: [(body: "oil", rho0: 800.0, c0: 40.0)]`. The
    /// bodies not named here take `rho0` and `c0`/`p0` above; `gamma` and `min_pressure` are
    /// shared.
    #[serde(default)]
    pub materials: Vec<TaitMaterial>,
}

/// A body's Tait parameters (see [`TaitEos::materials`]).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TaitMaterial {
    /// The body's name.
    pub body: String,
    /// Reference density ρ0 (kg/m³).
    pub rho0: Real,
    /// Reference sound speed c0 (m/s), or `Auto(factor: 10.0)`: factor × the largest speed
    /// the scene implies.
    #[serde(default)]
    pub c0: Option<SoundSpeedSetting>,
    /// Bulk modulus p0 (Pa; alternative to c0).
    #[serde(default)]
    pub p0: Option<Real>,
}

/// The laws of this plugin's bodies, read back from the fluid's [`BodyEos`] (where this
/// plugin publishes them): one per body, indexed by [`BodyId`].
pub fn materials(laws: &BodyEos) -> Vec<Eos> {
    (0..laws.0.len())
        .map(|b| {
            *laws
                .law_as::<Eos>(b)
                .expect("every body's law is this plugin's")
        })
        .collect()
}

/// Ideal gas (Eq. 7.3): `p = (γ − 1) ρ ε`, `c = sqrt(γ p / ρ)`.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IdealGas {
    /// Adiabatic index γ (dimensionless).
    pub gamma: Real,
}

/// The EOS as a resource.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub enum Eos {
    /// Tait with ρ0, γ, p0, c0.
    Tait {
        /// ρ0.
        rho0: Real,
        /// γ.
        gamma: Real,
        /// p0.
        p0: Real,
        /// c0.
        c0: Real,
        /// Pressure floor (−∞ for none).
        p_min: Real,
        /// Background pressure `p_b` added to Eq. 7.5.
        p_b: Real,
        /// Density floor (−∞ for none; [`TaitEos::cavitation`]).
        rho_min: Real,
    },
    /// Ideal gas with γ.
    Ideal {
        /// γ.
        gamma: Real,
    },
}

impl Eos {
    /// `(p, c)` at density ρ and specific internal energy ε.
    #[inline]
    pub fn eval(&self, rho: Real, eps: Real) -> (Real, Real) {
        match *self {
            Eos::Tait {
                rho0,
                gamma,
                p0,
                c0,
                p_min,
                p_b,
                ..
            } => {
                let x = rho / rho0;
                let (x_gamma, x_c) = if gamma == 7.0 {
                    water_powers(x)
                } else {
                    (pow(x, gamma), pow(x, 0.5 * (gamma - 1.0)))
                };
                let p = p0 * (x_gamma - 1.0) + p_b;
                (p.max(p_min), c0 * x_c)
            }
            Eos::Ideal { gamma } => {
                let p = (gamma - 1.0) * rho * eps;
                (p, (gamma * p.max(0.0) / rho).sqrt())
            }
        }
    }
}

impl Eos {
    /// The density `rho` raised to the law's floor ([`TaitEos::cavitation`]; unchanged
    /// without one).
    #[inline]
    pub fn floored(&self, rho: Real) -> Real {
        match *self {
            // a comparison, not `f64::max`: a NaN density stays NaN for the health check
            Eos::Tait { rho_min, .. } if rho < rho_min => rho_min,
            Eos::Tait { .. } => rho,
            Eos::Ideal { .. } => rho,
        }
    }
}

impl EosLaw for Eos {
    #[inline]
    fn eval(&self, rho: Real, eps: Real) -> (Real, Real) {
        Eos::eval(self, rho, eps)
    }

    /// The inverse of Eq. 7.5 with the background pressure, `ρ = ρ0 ((p − p_b)/p0 + 1)^{1/γ}`,
    /// for a liquid; `None` for a gas, whose pressure depends on its internal energy too, or
    /// for a tension beyond `−p0` that no density gives.
    fn density_at(&self, p: Real) -> Option<Real> {
        Eos::density_at(self, p)
    }

    fn reference_density(&self) -> Option<Real> {
        match *self {
            Eos::Tait { rho0, .. } => Some(rho0),
            Eos::Ideal { .. } => None,
        }
    }

    fn hydrostatic_pressure(&self, g: Real, s: Real) -> Option<Real> {
        Eos::hydrostatic_pressure(self, g, s)
    }
}

impl Eos {
    /// The density at which the equation gives pressure `p` (the inverse of Eq. 7.5 with the
    /// background pressure, `ρ = ρ0 ((p − p_b)/p0 + 1)^{1/γ}`), for a liquid; `None` for a
    /// gas, whose pressure depends on its internal energy too, or for a tension beyond
    /// `−p0` that no density gives.
    pub fn density_at(&self, p: Real) -> Option<Real> {
        match *self {
            Eos::Tait {
                rho0,
                gamma,
                p0,
                p_b,
                ..
            } => {
                let x = (p - p_b) / p0 + 1.0;
                (x > 0.0).then(|| rho0 * libm::pow(x, 1.0 / gamma))
            }
            Eos::Ideal { .. } => None,
        }
    }
}

/// `x^e`, by repeated multiplication when e is a small whole number (γ = 7 gives x⁷ and x³).
/// The whole-number test is a round trip through `i32` (no `trunc` call: the baseline x86-64
/// target has no rounding instruction and `f64::trunc` becomes a library call per particle).
#[inline]
fn pow(x: Real, e: Real) -> Real {
    let k = e as i32;
    if k as Real == e && k.abs() <= 16 {
        powi(x, k)
    } else {
        libm::pow(x, e)
    }
}

/// `(x⁷, x³)` for water's γ = 7 with four multiplications, `x³ = x·x²` and
/// `x⁷ = x³·(x²·x²)`: the products [`powi`] forms for 7 and 3, in its order, so the values are
/// bitwise those of `pow(x, 7.0)` and `pow(x, 3.0)` (tested) without the exponent loop.
#[inline(always)]
fn water_powers(x: Real) -> (Real, Real) {
    let x2 = x * x;
    let x3 = x * x2;
    (x3 * (x2 * x2), x3)
}

/// `x^n` by binary exponentiation, inlined: the same multiplications in the same order as
/// the runtime's `__powidf2` that `f64::powi` calls for an exponent unknown at compile time,
/// so the result is bitwise that of `x.powi(n)` (tested), without the call.
#[inline(always)]
fn powi(mut x: Real, n: i32) -> Real {
    let mut b = n.unsigned_abs();
    let mut r = 1.0;
    loop {
        if b & 1 != 0 {
            r *= x;
        }
        b /= 2;
        if b == 0 {
            break;
        }
        x *= x;
    }
    if n < 0 { 1.0 / r } else { r }
}

/// Evaluates the EOS for every particle, writing its pressure and sound speed in place.
#[inline(never)] // a frame of its own in profiles
pub fn apply_eos(
    eos: Res<Eos>,
    mut q: Query<(
        &mut Density,
        Option<&InternalEnergy>,
        &mut Pressure,
        &mut SoundSpeed,
    )>,
) {
    let eos = *eos;
    for (mut rho, eps, mut p, mut c) in q.contiguous_iter_mut().expect(DENSE) {
        let rho = rho.bypass_change_detection();
        let (p, c) = (p.bypass_change_detection(), c.bypass_change_detection());
        match eps {
            Some(eps) => (rho, eps, p, c)
                .into_par_iter()
                .with_min_len(1024)
                .for_each(|(rho, eps, p, c)| {
                    rho.0 = eos.floored(rho.0);
                    (p.0, c.0) = eos.eval(rho.0, eps.0);
                }),
            None => (rho, p, c)
                .into_par_iter()
                .with_min_len(1024)
                .for_each(|(rho, p, c)| {
                    rho.0 = eos.floored(rho.0);
                    (p.0, c.0) = eos.eval(rho.0, 0.0);
                }),
        }
    }
}

/// [`apply_eos`] with each particle's body's equation of state (scenes whose bodies differ).
#[inline(never)] // a frame of its own in profiles
pub fn apply_eos_by_body(
    laws: Res<BodyEos>,
    mut q: Query<(
        &BodyId,
        &mut Density,
        Option<&InternalEnergy>,
        &mut Pressure,
        &mut SoundSpeed,
    )>,
) {
    let eos = &materials(&laws);
    for (body, mut rho, eps, mut p, mut c) in q.contiguous_iter_mut().expect(DENSE) {
        let rho = rho.bypass_change_detection();
        let (p, c) = (p.bypass_change_detection(), c.bypass_change_detection());
        (body, rho, p, c)
            .into_par_iter()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(k, (b, rho, p, c))| {
                let e = eps.map_or(0.0, |e| e[k].0);
                let law = &eos[b.0 as usize];
                rho.0 = law.floored(rho.0);
                (p.0, c.0) = law.eval(rho.0, e);
            });
    }
}

/// Adds the EOS: `materials` holds one per body (all equal to `eos` for a single material).
fn install<V: Vector>(
    sim: &mut Sim<V>,
    eos: Eos,
    materials: Vec<Eos>,
    label: &str,
) -> Result<(), SimError> {
    if !sim.enable::<EquationOfState>() {
        return Err(SimError::Build(
            "only one equation of state may be used".into(),
        ));
    }
    sim.world.insert_resource(eos);
    sim.add_column(ColumnSpec::state("pressure", "p"), |_| Pressure(0.0))?;
    sim.add_column(ColumnSpec::restart_only("sound_speed"), |_| SoundSpeed(0.0))?;
    if materials.iter().all(|m| *m == eos) {
        sim.add_system(StepSet::Eos, label.to_string(), apply_eos)
            .in_group::<EquationOfState>();
    } else {
        sim.add_system(
            StepSet::Eos,
            format!("{label}, per body"),
            apply_eos_by_body,
        )
        .in_group::<EquationOfState>();
    }
    if cavitation::any_floor(&materials) {
        sim.add_system(
            StepSet::Boundary,
            cavitation::FLOOR_LABEL,
            cavitation::floor_density,
        );
    }
    let laws = materials
        .into_iter()
        .map(|m| Arc::new(m) as Arc<dyn EosLaw>);
    sim.world.insert_resource(BodyEos(laws.collect()));
    Ok(())
}

impl SimPlugin for TaitEos {
    const NAME: &'static str = "TaitEos";
    const SUMMARY: &'static str = "Tait equation of state p = p0((rho/rho0)^gamma - 1) (Eq. 7.5)";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        positive("rho0", self.rho0)?;
        for (k, m) in self.materials.iter().enumerate() {
            let at = format!("materials[{k}]");
            info.check_body(&format!("{at}.body"), &m.body)?;
            if self.materials[..k].iter().any(|o| o.body == m.body) {
                return Err(format!("{at}.body: `{}` is given twice", m.body));
            }
            positive(&format!("{at}.rho0"), m.rho0)?;
            reference_scale(&at, m.c0, m.p0)?;
        }
        positive("gamma", self.gamma)?;
        if let Some(p) = self.min_pressure
            && !(p.is_finite() && p <= 0.0)
        {
            return Err(format!(
                "min_pressure: must be finite and ≤ 0 (a floor on tension), got {p}"
            ));
        }
        if !(self.background.is_finite() && self.background >= 0.0) {
            return Err(format!(
                "background: must be finite and ≥ 0, got {}",
                self.background
            ));
        }
        reference_scale("", self.c0, self.p0)
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let c0 = sound_speed::resolve(sim, self.c0, "c0")?;
        let eos = self.tait(self.rho0, c0, self.p0)?;
        let bodies = sim.world.resource::<Bodies>().names();
        let mut materials = Vec::with_capacity(bodies.len());
        for name in &bodies {
            materials.push(match self.materials.iter().find(|m| &m.body == name) {
                Some(m) => {
                    let field = format!("materials[{name}].c0");
                    self.tait(m.rho0, sound_speed::resolve(sim, m.c0, &field)?, m.p0)?
                }
                None => eos,
            });
        }
        sim.enable::<Liquid>();
        sim.advise(mach::sound_speed_advice::<V>);
        install(sim, eos, materials, "tait_eos (Eq. 7.5)")
    }
}

impl TaitEos {
    /// The Tait EOS of reference density `rho0` and sound speed `c0` or bulk modulus `p0`
    /// (`p0 = c0² ρ0/γ`), with this plugin's γ and pressure floor.
    fn tait(&self, rho0: Real, c0: Option<Real>, p0: Option<Real>) -> Result<Eos, SimError> {
        let (p0, c0) = match (c0, p0) {
            (Some(c0), _) => (c0 * c0 * rho0 / self.gamma, c0),
            (None, Some(p0)) => (p0, (self.gamma * p0 / rho0).sqrt()),
            (None, None) => return Err(SimError::Build("TaitEos needs c0 or p0".into())),
        };
        let free = Eos::Tait {
            rho0,
            gamma: self.gamma,
            p0,
            c0,
            p_min: self.min_pressure.unwrap_or(Real::NEG_INFINITY),
            p_b: self.background,
            rho_min: Real::NEG_INFINITY,
        };
        if !self.cavitation {
            return Ok(free);
        }
        // the density where Eq. 7.5 with the background pressure gives the cavitation pressure
        let p_c = self.min_pressure.unwrap_or(0.0);
        let rho_c = free.density_at(p_c).ok_or_else(|| {
            SimError::Build(format!(
                "TaitEos: min_pressure {p_c} Pa is below the largest tension the law gives \
                 (−p0 + background = {} Pa): no density cavitates there",
                self.background - p0
            ))
        })?;
        Ok(Eos::Tait {
            rho0,
            gamma: self.gamma,
            p0,
            c0,
            p_min: p_c,
            p_b: self.background,
            rho_min: rho_c,
        })
    }
}

/// Exactly one of `c0` and `p0`, positive; `at` prefixes the field names.
fn reference_scale(
    at: &str,
    c0: Option<SoundSpeedSetting>,
    p0: Option<Real>,
) -> Result<(), String> {
    let dot = if at.is_empty() { "" } else { "." };
    match (c0, p0) {
        (Some(c), None) => c.validate(&format!("{at}{dot}c0")),
        (None, Some(p)) => positive(&format!("{at}{dot}p0"), p),
        _ => Err(format!(
            "{at}{dot}c0, {at}{dot}p0: give exactly one of them"
        )),
    }
}

impl SimPlugin for IdealGas {
    const NAME: &'static str = "IdealGas";
    const SUMMARY: &'static str = "ideal gas p = (gamma - 1) rho e (Eq. 7.3)";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.gamma.is_finite() && self.gamma > 1.0) {
            return Err(format!("gamma: must be > 1, got {}", self.gamma));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        ensure_energy_equation(sim)?;
        let eos = Eos::Ideal { gamma: self.gamma };
        let n = sim.world.resource::<Bodies>().0.len();
        install(sim, eos, vec![eos; n], "ideal_gas_eos (Eq. 7.3)")
    }
}

/// Sets each fluid particle's density to what its body's law gives at the pressure
/// `pressure(x, law)` (`None`: the particle is left as generated), and scales its mass with it
/// (`m ← m ρ/ρ_gen`) so that its volume stays the lattice cell it was generated in: the start
/// of `HydrostaticStart` and of `InitialPressure`. Particles of bodies that are not fluid are
/// left as generated.
pub fn start_from_pressure<V: Vector>(
    bodies: &Bodies,
    laws: &BodyEos,
    q: &mut Query<(&Position<V>, &BodyId, &mut Density, &mut Mass)>,
    pressure: impl Fn(V, &dyn EosLaw) -> Option<Real>,
) {
    for (r, b, mut rho, mut m) in q.contiguous_iter_mut().expect(DENSE) {
        for (((r, b), rho), m) in r.iter().zip(b).zip(rho.iter_mut()).zip(m.iter_mut()) {
            let body = b.0 as usize;
            if !bodies.0[body].is_fluid() {
                continue;
            }
            let eos = laws.0[body].as_ref();
            if let Some(rho_p) = pressure(r.0, eos).and_then(|p| eos.density_at(p)) {
                m.0 *= rho_p / rho.0;
                rho.0 = rho_p;
            }
        }
    }
}

#[cfg(test)]
mod tests;
