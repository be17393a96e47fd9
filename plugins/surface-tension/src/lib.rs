//! `SurfaceTension(sigma: σ)`: surface tension from a pairwise cohesion force, the worked
//! example of a physics plugin written only against the public API (`dualsph_core::prelude`).
//!
//! # The model
//! Akinci, Akinci & Teschner, *Versatile surface tension and adhesion for SPH fluids*
//! (ACM TOG 32(6), 2013), Eq. 1–2: a central pair force along `r̂_ij = r_ij/|r_ij|` with the
//! cohesion spline, here in the support variable `q = r/h` (h is the support radius):
//!
//! ```text
//! c(q) = (1 − q)³ q³               for ½ < q ≤ 1,
//!        2 (1 − q)³ q³ − 1/64      for 0 < q ≤ ½,        c = 0 for q > 1,
//! ```
//!
//! attractive (c > 0) for `q > 0.27`, mildly repulsive closer in. In the dual-support sweep
//! the owner i evaluates the pair once with its own `h_i` and j receives the reaction:
//!
//! ```text
//! f_i ← j = −½ k_d σ V_i V_j c(r/h_i) / (M_d h_i^{d+2}) r̂_ij,     f_j ← i = −f_i ← j,
//! V = m/ρ,   M_d = ∫₀¹ q^{d+1} c(q) dq  (M_2 = 33/28672, M_3 = 21/28160),
//! k_2 = 3,   k_3 = 8/π.
//! ```
//!
//! With equal h the pair is met from both supports and the halves add up to Akinci's force.
//!
//! # Calibration (what σ means)
//! For a pairwise-additive force `F(r)` (attractive > 0) in a fluid of uniform number density
//! n, the work to cleave it along a plane gives the Kirkwood–Buff mean-field surface tension
//! (pair correlation g = 1): `σ = (n²/3) ∫ r³ F dr` in 2-D and `σ = (π n²/8) ∫ r⁴ F dr` in
//! 3-D. With `F = k_d σ V² c(r/h)/(M_d h^{d+2})` and `nV = 1` both give back σ for every h:
//! the coefficient is a surface tension in N/m (3-D) or N (2-D), not a tuning knob. It is a
//! mean-field value: the particles' discreteness and the truncated support at the surface
//! change the effective σ by a factor of order one (measured in `tests/e2e/surface_tension.rs`).
//! The same force also carries a bulk cohesive pressure
//! `p_c = −(n²/2d) ∫ r F dS_d(r) ∝ −σ/h`, balanced by the equation of state, so a drop at rest
//! sits slightly compressed; use a `TaitEos` with `c0² ≫ σ/(ρ h)`.
//!
//! # Conservation
//! Momentum: the sweep applies `−f` to j (exact to round-off for any h field). Angular
//! momentum: f is parallel to `r_ij`, so `r_i × f + r_j × (−f) = r_ij × f = 0`. Energy: the
//! force is conservative; the cohesive binding energy is booked as internal energy, the pair
//! power `−f·v_ij` split ½/½ (as for the dissipative terms, Eqs. 4.20, 4.24), so
//! `e_kin + e_int` is conserved when the scene integrates internal energy (any plugin that
//! enables the energy equation, e.g. `PressureForce`); with `IdealGas` this energy would feed
//! back into the pressure, so use it with `TaitEos`.

#![warn(missing_docs)]

use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// Pairwise cohesion surface tension (Akinci et al. 2013), calibrated to a surface tension σ.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfaceTension {
    /// Surface tension σ (N/m; N in 2-D), ≥ 0.
    pub sigma: Real,
}

/// `M_2 = ∫₀¹ q³ c(q) dq = 33/28672` (exact, polynomial integration).
pub const MOMENT_2D: Real = 33.0 / 28672.0;
/// `M_3 = ∫₀¹ q⁴ c(q) dq = 21/28160` (exact, polynomial integration).
pub const MOMENT_3D: Real = 21.0 / 28160.0;

/// Akinci's cohesion spline `c(q)` on the support variable `q = r/h` (Eq. 2 of Akinci et al.
/// 2013 with `r/h → q` and without the `32/(π h⁹)` factor): `(1 − q)³q³` for `½ < q ≤ 1`,
/// `2(1 − q)³q³ − 1/64` for `0 < q ≤ ½`, 0 otherwise.
#[inline]
pub fn cohesion_spline(q: Real) -> Real {
    if !(q > 0.0 && q <= 1.0) {
        return 0.0;
    }
    let s = (1.0 - q) * q;
    let s3 = s * s * s;
    if q > 0.5 { s3 } else { 2.0 * s3 - 1.0 / 64.0 }
}

/// The pair term: owner i pulls j (and is pulled) with
/// `f_i = −½ k_d σ V_i V_j c(r/h_i)/(M_d h_i^{d+2}) r̂_ij`.
#[derive(Debug, Clone, Copy)]
pub struct CohesionTerm {
    /// `½ k_d σ / M_d`: the prefactor without the h- and volume-dependence.
    pub coef: Real,
    /// Exponent `d + 2` of `h_i`.
    pub h_power: i32,
}

impl CohesionTerm {
    /// The term for surface tension `sigma` in `dimension` 2 or 3 (`None` otherwise).
    pub fn new(sigma: Real, dimension: usize) -> Option<Self> {
        let (k, m) = match dimension {
            2 => (3.0, MOMENT_2D),
            3 => (8.0 / std::f64::consts::PI, MOMENT_3D),
            _ => return None,
        };
        Some(CohesionTerm {
            coef: 0.5 * k * sigma / m,
            h_power: dimension as i32 + 2,
        })
    }

    /// The force on the owner i from j (its reaction on j is the negative).
    #[inline]
    pub fn force<V: Vector>(
        &self,
        f: &ParticleData<'_, V>,
        i: usize,
        j: usize,
        rij: V,
        r: Real,
    ) -> V {
        let h = f.h[i].0;
        let c = cohesion_spline(r / h);
        if c == 0.0 || r == 0.0 {
            return V::zero();
        }
        let mag = self.coef * f.volume(i) * f.volume(j) * c / h.powi(self.h_power);
        rij * (-mag / r)
    }
}

/// [`CohesionTerm`] bound to its sums.
#[derive(Clone, Copy, Debug)]
pub struct BoundCohesion {
    term: CohesionTerm,
}

impl<V: Vector> PairTerm<V> for CohesionTerm {
    type Bound<'w> = BoundCohesion;

    fn name(&self) -> &str {
        "surface tension: pairwise cohesion (Akinci et al. 2013)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundCohesion, String> {
        b.force()?;
        b.power()?;
        Ok(BoundCohesion { term: *self })
    }
}

impl<V: Vector> BoundTerm<V> for BoundCohesion {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    #[inline]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i, rij, r) = (p.data(), p.i(), p.rij(), p.r());
        let force =
            LaneVec::<T>::from_fn(|l| self.term.force(d, i, p.j(l), rij.lane::<V>(l), r.lane(l)));
        out.add_force::<V>(force);
        // Conservative force: the kinetic energy it gives, f·v_ij, is taken from the
        // internal (cohesive binding) energy, half from each particle.
        let heat = T::splat(-0.5) * force.dot::<V>(p.vij());
        out.add_power(heat);
        out.react_power(heat);
    }
}

impl SimPlugin for SurfaceTension {
    const NAME: &'static str = "SurfaceTension";
    const SUMMARY: &'static str =
        "surface tension from a pairwise cohesion force (Akinci et al. 2013), calibrated to σ";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        if !(self.sigma.is_finite() && self.sigma >= 0.0) {
            return Err(format!(
                "sigma: must be a finite surface tension >= 0, got {}",
                self.sigma
            ));
        }
        if !matches!(info.dimension, 2 | 3) {
            return Err(format!(
                "sigma: surface tension needs a 2-D or 3-D scene, this one is {}-D",
                info.dimension
            ));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        SimPlugin::validate(self, &SceneInfo::of_dimension(V::DIM))
            .map_err(|e| SimError::Build(format!("SurfaceTension.{e}")))?;
        let term = CohesionTerm::new(self.sigma, V::DIM).ok_or_else(|| {
            SimError::Build(format!("SurfaceTension: unsupported dimension {}", V::DIM))
        })?;
        sim.add_pair_term(term);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Composite Simpson on [a, b] with n (even) intervals.
    fn simpson(f: impl Fn(Real) -> Real, a: Real, b: Real, n: usize) -> Real {
        let h = (b - a) / n as Real;
        let mut s = f(a) + f(b);
        for k in 1..n {
            s += f(a + k as Real * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        let term = CohesionTerm::new(1.0, 2).unwrap();
        dualsph_fluid::checks::check_lanes_2d(&term).unwrap();
    }

    #[test]
    fn moments_match_quadrature() {
        // Each piece is a polynomial of degree ≤ 10: Simpson on the two pieces separately.
        for (d, m) in [(2, MOMENT_2D), (3, MOMENT_3D)] {
            let g = |q: Real| q.powi(d + 1) * cohesion_spline(q);
            let num = simpson(g, 1e-300, 0.5, 2000) + simpson(g, 0.5, 1.0, 2000);
            assert!((num - m).abs() <= 1e-12 * m, "{d}-D: {num} vs {m}");
        }
    }

    #[test]
    fn spline_is_continuous_and_changes_sign_once() {
        assert_eq!(cohesion_spline(0.0), 0.0);
        assert_eq!(cohesion_spline(1.0), 0.0);
        assert_eq!(cohesion_spline(1.5), 0.0);
        let below = 2.0 * (0.5f64 * 0.5).powi(3) - 1.0 / 64.0;
        assert!((cohesion_spline(0.5) - below).abs() < 1e-18);
        assert!((cohesion_spline(0.5 + 1e-12) - 1.0 / 64.0).abs() < 1e-12);
        let signs: Vec<bool> = (1..1000)
            .map(|k| cohesion_spline(k as Real / 1000.0) > 0.0)
            .collect();
        let changes = signs.windows(2).filter(|w| w[0] != w[1]).count();
        assert_eq!(changes, 1);
    }

    #[test]
    fn negative_or_nan_sigma_and_1d_are_rejected_naming_the_field() {
        let two = SceneInfo::of_dimension(2);
        for bad in [-1.0, Real::NAN, Real::INFINITY] {
            let e = SimPlugin::validate(&SurfaceTension { sigma: bad }, &two).unwrap_err();
            assert!(e.starts_with("sigma:"), "{e}");
        }
        let e = SimPlugin::validate(&SurfaceTension { sigma: 1.0 }, &SceneInfo::of_dimension(1))
            .unwrap_err();
        assert!(e.contains("2-D or 3-D"), "{e}");
        let three = SceneInfo::of_dimension(3);
        assert!(SimPlugin::validate(&SurfaceTension { sigma: 0.5 }, &three).is_ok());
    }
}
