//! The Sedov–Taylor point explosion: the exact self-similar solution for an energy `E`
//! released at `r = 0`, `t = 0` in a cold (`p₀ = 0`), resting ideal gas (`p = (γ − 1) ρ e`) of
//! uniform density `ρ₀`, in planar (`j = 1`), cylindrical (`j = 2`) and spherical (`j = 3`)
//! geometry (Sedov, *Similarity and Dimensional Methods in Mechanics*, 1959, ch. IV; Sedov1959
//! in docs/references.md). The closed-form parametric solution is the one written out by Kamm &
//! Timmes, *On Efficient Generation of Numerically Robust Sedov Solutions*, LA-UR-07-2849, 2007
//! (KammTimmes2007), for the standard case with uniform ambient density (`ω = 0`).
//!
//! The shock radius is `R(t) = ξ₀ (E t²/ρ₀)^{1/(j+2)}`, `ξ₀ = α^{−1/(j+2)}`, with `α` the
//! dimensionless energy integral. Behind the shock, with `λ = r/R` and `Ṙ = 2R/((j+2) t)`,
//!
//! `ρ = ρ₀ (γ+1)/(γ−1) · g(λ)`, `u = 2Ṙ/(γ+1) · f(λ)`, `p = 2ρ₀Ṙ²/(γ+1) · h(λ)`,
//!
//! so that `f = g = h = 1` is the strong-shock Rankine–Hugoniot state. `f`, `g`, `h` and `λ`
//! are given in terms of a parameter `V ∈ [V₀, V₂]`, `V₀ = 2/((j+2)γ)` at the centre and
//! `V₂ = 4/((j+2)(γ+1))` at the shock (KammTimmes2007's standard case with `ω = 0`; the
//! equation numbers of the report could not be checked here, so none are given):
//!
//! ```text
//! x₁ = a V,  x₂ = b (c V − 1),  x₃ = d (1 − e V),  x₄ = b (1 − c V/γ)
//! a = (j+2)(γ+1)/4,  b = (γ+1)/(γ−1),  c = (j+2)γ/2,
//! d = (j+2)(γ+1) / ((j+2)(γ+1) − 2(2 + j(γ−1))),  e = (2 + j(γ−1))/2
//! α₀ = 2/(j+2),  α₂ = −(γ−1)/(2(γ−1) + j),  α₃ = j/(2(γ−1) + j)
//! α₁ = (j+2)γ/(2 + j(γ−1)) · [2j(2−γ)/(γ(j+2)²) − α₂]
//! α₄ = (j+2) α₁/(2−γ),  α₅ = −2/(2−γ)
//! λ = x₁^{−α₀} x₂^{−α₂} x₃^{−α₁},  f = x₁ λ,
//! g = x₂^{α₃} x₃^{α₄} x₄^{α₅},  h = x₁^{jα₀} x₃^{α₄−2α₁} x₄^{1+α₅}.
//! ```
//!
//! The energy integral (KammTimmes2007's `α` from its integrals `J₁`, `J₂`, rewritten over `λ`)
//! is
//!
//! `α = 8 σ_j / ((j+2)² (γ²−1)) · ∫₀¹ (g f² + h) λ^{j−1} dλ`,
//!
//! with `σ_j` the measure of the geometry: `dV = σ_j r^{j−1} dr`, `σ₁ = 1`, `σ₂ = 2π`,
//! `σ₃ = 4π`. `E` is therefore the energy per unit area of the half-space `x ≥ 0` in the planar
//! case (the whole slab `−R ≤ x ≤ R` holds `2E`; this is Kamm & Timmes' convention: their
//! Table 4 gives `α ≈ 0.5385` for `γ = 1.4`, not twice that), the energy per unit length in
//! the cylindrical case and the total energy in the spherical case.
//!
//! The formulas are singular at `γ = 2` (`α₄`, `α₅`) in every geometry and, in the spherical
//! case, at `γ = 7` (`d`); for `γ > 7` the spherical `x₃` vanishes between `V₀` and `V₂`, so
//! the parametrisation over `[V₀, V₂]` used here does not apply. [`Sedov::new`] refuses those.
//! Close to `γ = 2` the large exponents cancel in `g` and `h`, costing a relative precision of
//! about `ε/|γ − 2|` (`ε` the machine epsilon); `γ` within 1e-6 of 2 is refused.
//!
//! Toward the centre `x₂ → 0` as `λ^{1/|α₂|}`: the density vanishes like `λ^{j/(γ−1)}`, the
//! velocity like `λ`, and the pressure tends to the finite `h(V₀)`. The profiles are evaluated
//! with `η = ln(V − V₀)` as the independent variable, so that this limit costs no precision.

use std::f64::consts::PI;

/// The symmetry of the explosion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// Plane symmetry, `j = 1`: `r` is the distance `|x|` from the plane of the explosion.
    Planar,
    /// Cylindrical symmetry, `j = 2`: `r` is the distance from the axis.
    Cylindrical,
    /// Spherical symmetry, `j = 3`: `r` is the distance from the centre.
    Spherical,
}

impl Geometry {
    /// The index `j` of KammTimmes2007: 1, 2 or 3.
    pub fn j(self) -> u32 {
        match self {
            Geometry::Planar => 1,
            Geometry::Cylindrical => 2,
            Geometry::Spherical => 3,
        }
    }

    /// `σ_j` of `dV = σ_j r^{j−1} dr`: 1 (per unit area of one side), 2π, 4π.
    pub fn measure(self) -> f64 {
        match self {
            Geometry::Planar => 1.0,
            Geometry::Cylindrical => 2.0 * PI,
            Geometry::Spherical => 4.0 * PI,
        }
    }
}

/// The state of the gas at one point, with the specific internal energy `e = p/((γ−1)ρ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SedovSample {
    /// Density.
    pub rho: f64,
    /// Radial velocity (away from the centre).
    pub u: f64,
    /// Pressure.
    pub p: f64,
    /// Specific internal energy: 0 in the cold ambient gas and `+∞` at `r = 0`, where the
    /// density vanishes while the pressure stays finite (also so close to the centre that the
    /// density, `∝ λ^{j/(γ−1)}`, underflows).
    pub e_specific: f64,
}

/// The dimensionless profile at one value of the parameter `V = V₀ + e^η`.
#[derive(Clone, Copy, Debug)]
struct Profile {
    /// `ln λ`.
    ln_lambda: f64,
    /// `d ln λ / dη`, positive.
    dln_lambda: f64,
    /// Velocity over its post-shock value.
    f: f64,
    /// Density over its post-shock value.
    g: f64,
    /// Pressure over its post-shock value.
    h: f64,
}

/// The Sedov–Taylor solution for one `γ` and geometry, with its energy integral `α`.
#[derive(Clone, Debug)]
pub struct Sedov {
    gamma: f64,
    geometry: Geometry,
    /// The coefficients `a, b, c, d, e` of `x₁…x₄`.
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    e: f64,
    /// The exponents `α₀ … α₅`.
    a0: f64,
    a1: f64,
    a2: f64,
    a3: f64,
    a4: f64,
    a5: f64,
    v0: f64,
    /// `ln(V₂ − V₀)`: the value of `η` at the shock.
    eta_shock: f64,
    alpha: f64,
}

/// `|γ − 2|` below which `γ` is refused as the singular value 2.
const GAMMA_2_GAP: f64 = 1e-6;

impl Sedov {
    /// The solution for adiabatic index `gamma` in `geometry`, with `α` computed once.
    ///
    /// Refuses non-finite `γ`, `γ ≤ 1`, `γ` within 1e-6 of the singular value 2, and in the
    /// spherical case `γ ≥ 7` (see the module documentation).
    pub fn new(gamma: f64, geometry: Geometry) -> Result<Sedov, String> {
        if !gamma.is_finite() || gamma <= 1.0 {
            return Err(format!("Sedov: γ must be finite and > 1, got {gamma}"));
        }
        if (gamma - 2.0).abs() < GAMMA_2_GAP {
            return Err(format!(
                "Sedov: γ = {gamma} is the singular value 2 of the ω = 0 solution \
                 (its exponents α₄, α₅ diverge); use a γ at least {GAMMA_2_GAP} away"
            ));
        }
        if geometry == Geometry::Spherical && gamma >= 7.0 {
            return Err(format!(
                "Sedov: γ = {gamma} ≥ 7 in spherical geometry is outside the standard \
                 ω = 0 solution used here (γ = 7 is singular; for γ > 7 its x₃ vanishes \
                 inside the shocked region)"
            ));
        }
        let j = f64::from(geometry.j());
        let g = gamma;
        let denom = 2.0 * (g - 1.0) + j;
        let a2 = -(g - 1.0) / denom;
        let a1 = (j + 2.0) * g / (2.0 + j * (g - 1.0))
            * (2.0 * j * (2.0 - g) / (g * (j + 2.0) * (j + 2.0)) - a2);
        let mut s = Sedov {
            gamma,
            geometry,
            a: (j + 2.0) * (g + 1.0) / 4.0,
            b: (g + 1.0) / (g - 1.0),
            c: (j + 2.0) * g / 2.0,
            d: (j + 2.0) * (g + 1.0) / ((j + 2.0) * (g + 1.0) - 2.0 * (2.0 + j * (g - 1.0))),
            e: (2.0 + j * (g - 1.0)) / 2.0,
            a0: 2.0 / (j + 2.0),
            a1,
            a2,
            a3: j / denom,
            a4: (j + 2.0) * a1 / (2.0 - g),
            a5: -2.0 / (2.0 - g),
            v0: 2.0 / ((j + 2.0) * g),
            eta_shock: libm::log(4.0 / ((j + 2.0) * (g + 1.0)) - 2.0 / ((j + 2.0) * g)),
            alpha: f64::NAN,
        };
        s.alpha = s.energy_integral();
        if !(s.alpha.is_finite() && s.alpha > 0.0) {
            return Err(format!("Sedov: the energy integral failed for γ = {gamma}"));
        }
        Ok(s)
    }

    /// The adiabatic index `γ`.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// The geometry.
    pub fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// The energy integral `α`: `E = α ρ₀ R^{j+2} / t²`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// `ξ₀ = α^{−1/(j+2)}`, the coefficient of `R = ξ₀ (E t²/ρ₀)^{1/(j+2)}`.
    pub fn xi0(&self) -> f64 {
        libm::pow(self.alpha, -1.0 / self.jp2())
    }

    fn jp2(&self) -> f64 {
        f64::from(self.geometry.j()) + 2.0
    }

    /// The shock radius `R(t) = (E t²/(α ρ₀))^{1/(j+2)}`; 0 at `t = 0`, NaN for `t < 0`.
    pub fn shock_radius(&self, e: f64, rho0: f64, t: f64) -> f64 {
        if t < 0.0 {
            return f64::NAN;
        }
        libm::pow(e * t * t / (self.alpha * rho0), 1.0 / self.jp2())
    }

    /// The time at which the shock reaches `r`: `t = (α ρ₀ r^{j+2} / E)^{1/2}`, the inverse of
    /// [`Sedov::shock_radius`]; NaN for `r < 0`.
    pub fn shock_time(&self, e: f64, rho0: f64, r: f64) -> f64 {
        if r < 0.0 {
            return f64::NAN;
        }
        (self.alpha * rho0 * libm::pow(r, self.jp2()) / e).sqrt()
    }

    /// The shock speed `Ṙ = 2R/((j+2) t)`, for `t > 0` (NaN at `t = 0`, where it is infinite).
    pub fn shock_speed(&self, e: f64, rho0: f64, t: f64) -> f64 {
        2.0 * self.shock_radius(e, rho0, t) / (self.jp2() * t)
    }

    /// The gas at distance `r ≥ 0` from the centre at time `t` after the release of `E` in gas
    /// of density `ρ₀`. Points with `r ≤ R(t)` are shocked (at `r = R` the post-shock state);
    /// beyond, the ambient state `(ρ₀, 0, 0, 0)`. At `r = 0` exactly the limits `ρ = 0`,
    /// `u = 0`, `p = p_c` (finite) and `e = +∞`.
    ///
    /// Documented values for inputs outside the problem: for `t ≤ 0` the ambient state (before
    /// the release, and at `t = 0` the energy occupies the single point `r = 0`); all fields
    /// NaN if `E ≤ 0`, `ρ₀ ≤ 0`, `r < 0` or any argument is NaN or infinite.
    pub fn sample(&self, e: f64, rho0: f64, t: f64, r: f64) -> SedovSample {
        let bad = [e, rho0, t, r].iter().any(|x| !x.is_finite()) || e <= 0.0 || rho0 <= 0.0;
        if bad || r < 0.0 {
            let nan = f64::NAN;
            return SedovSample {
                rho: nan,
                u: nan,
                p: nan,
                e_specific: nan,
            };
        }
        let ambient = SedovSample {
            rho: rho0,
            u: 0.0,
            p: 0.0,
            e_specific: 0.0,
        };
        let big_r = self.shock_radius(e, rho0, t);
        if t <= 0.0 || r > big_r {
            return ambient;
        }
        let g = self.gamma;
        let speed = self.shock_speed(e, rho0, t);
        let (f, gg, h) = self.shape(r / big_r);
        let rho = rho0 * (g + 1.0) / (g - 1.0) * gg;
        let p = 2.0 * rho0 * speed * speed / (g + 1.0) * h;
        SedovSample {
            rho,
            u: 2.0 * speed / (g + 1.0) * f,
            p,
            e_specific: if rho > 0.0 {
                p / ((g - 1.0) * rho)
            } else {
                f64::INFINITY
            },
        }
    }

    /// `(f, g, h)` at `λ ∈ [0, 1]`: velocity, density and pressure over their post-shock values.
    pub fn shape(&self, lambda: f64) -> (f64, f64, f64) {
        if lambda <= 0.0 {
            return (0.0, 0.0, self.centre_h());
        }
        let pr = self.profile(self.eta_of(libm::log(lambda.min(1.0))));
        (pr.f, pr.g, pr.h)
    }

    /// `h` at the centre (`V = V₀`, `x₂ = 0`), which does not involve `x₂`.
    fn centre_h(&self) -> f64 {
        let j = f64::from(self.geometry.j());
        let v = self.v0;
        let (x1, x3, x4) = (
            self.a * v,
            self.d * (1.0 - self.e * v),
            self.b * (1.0 - self.c * v / self.gamma),
        );
        libm::exp(
            j * self.a0 * libm::log(x1)
                + (self.a4 - 2.0 * self.a1) * libm::log(x3)
                + (1.0 + self.a5) * libm::log(x4),
        )
    }

    /// The profile at `V = V₀ + e^η`, in logarithms so that `V → V₀` (`η → −∞`) is exact.
    fn profile(&self, eta: f64) -> Profile {
        let j = f64::from(self.geometry.j());
        let dv = libm::exp(eta);
        let v = self.v0 + dv;
        let x1 = self.a * v;
        let x3 = self.d * (1.0 - self.e * v);
        let x4 = self.b * (1.0 - self.c * v / self.gamma);
        // x₂ = b(cV − 1) = b c (V − V₀), since c V₀ = 1.
        let ln_x2 = libm::log(self.b * self.c) + eta;
        let (ln_x1, ln_x3, ln_x4) = (libm::log(x1), libm::log(x3), libm::log(x4));
        let ln_lambda = -self.a0 * ln_x1 - self.a2 * ln_x2 - self.a1 * ln_x3;
        // d ln λ/dη = (V − V₀) d ln λ/dV, with d ln x₂/dV = 1/(V − V₀).
        let dln_lambda = -self.a2 + dv * (-self.a0 * self.a / x1 + self.a1 * self.d * self.e / x3);
        let lambda = libm::exp(ln_lambda);
        Profile {
            ln_lambda,
            dln_lambda,
            f: x1 * lambda,
            g: libm::exp(self.a3 * ln_x2 + self.a4 * ln_x3 + self.a5 * ln_x4),
            h: libm::exp(
                j * self.a0 * ln_x1 + (self.a4 - 2.0 * self.a1) * ln_x3 + (1.0 + self.a5) * ln_x4,
            ),
        }
    }

    /// The `η` at which `ln λ(η) = target ≤ 0`: safeguarded Newton inside a bracket, `ln λ`
    /// being increasing in `η` (its slope tends to `−α₂ > 0` at the centre).
    fn eta_of(&self, target: f64) -> f64 {
        let mut hi = self.eta_shock;
        if target >= 0.0 {
            return hi;
        }
        // Near the centre ln λ ≈ −α₂ η + const: start one step past that estimate.
        let mut step = 1.0 + target / self.a2;
        let mut lo = hi - step;
        while self.profile(lo).ln_lambda > target {
            hi = lo;
            step *= 2.0;
            lo -= step;
        }
        let mut eta = 0.5 * (lo + hi);
        for _ in 0..200 {
            let pr = self.profile(eta);
            let res = pr.ln_lambda - target;
            if res > 0.0 {
                hi = eta;
            } else {
                lo = eta;
            }
            let newton = eta - res / pr.dln_lambda;
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (next - eta).abs() <= 4.0 * f64::EPSILON * eta.abs().max(1.0) {
                return next;
            }
            eta = next;
        }
        eta
    }

    /// `α` of the module documentation, integrated over `η` rather than `λ`:
    /// `λ^{j−1} dλ = λ^j (d ln λ/dη) dη`, smooth in `η` and decaying like `λ^j` as `η → −∞`;
    /// the tail below `λ^j = 1e-20` is dropped.
    fn energy_integral(&self) -> f64 {
        let j = f64::from(self.geometry.j());
        let g = self.gamma;
        let lo = self.eta_of(-20.0 * std::f64::consts::LN_10 / j);
        let integrand = |eta: f64| {
            let pr = self.profile(eta);
            (pr.g * pr.f * pr.f + pr.h) * libm::exp(j * pr.ln_lambda) * pr.dln_lambda
        };
        let integral = adaptive_gauss(&integrand, lo, self.eta_shock, 1e-13, 12);
        8.0 * self.geometry.measure() / ((j + 2.0) * (j + 2.0) * (g * g - 1.0)) * integral
    }
}

/// 5-point Gauss–Legendre on `[a, b]`: nodes `0`, `±⅓√(5 ∓ 2√(10/7))`, exact to degree 9.
pub(crate) fn gauss5(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let s = (10.0f64 / 7.0).sqrt();
    let (x1, x2) = ((5.0 - 2.0 * s).sqrt() / 3.0, (5.0 + 2.0 * s).sqrt() / 3.0);
    let r70 = 70.0f64.sqrt();
    let (w0, w1, w2) = (
        128.0 / 225.0,
        (322.0 + 13.0 * r70) / 900.0,
        (322.0 - 13.0 * r70) / 900.0,
    );
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    h * (w0 * f(m) + w1 * (f(m - h * x1) + f(m + h * x1)) + w2 * (f(m - h * x2) + f(m + h * x2)))
}

/// Adaptive bisection on 5-point Gauss–Legendre: the integral is first estimated on 64 equal
/// panels, then each panel is halved until it agrees with the sum over its two halves to its
/// share of `tol` relative to that estimate. Written here rather than taken from a crate: the
/// crate depends on `libm` only, and twenty lines of a textbook rule are easier to audit than
/// a dependency whose tolerance semantics would need checking.
pub(crate) fn adaptive_gauss(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, depth: u32) -> f64 {
    const PANELS: usize = 64;
    let h = (b - a) / PANELS as f64;
    let ends = |k: usize| {
        (
            a + k as f64 * h,
            if k + 1 == PANELS {
                b
            } else {
                a + (k + 1) as f64 * h
            },
        )
    };
    let coarse: Vec<f64> = (0..PANELS)
        .map(|k| gauss5(f, ends(k).0, ends(k).1))
        .collect();
    let scale = coarse
        .iter()
        .map(|x| x.abs())
        .sum::<f64>()
        .max(f64::MIN_POSITIVE);
    let abs_tol = tol * scale / PANELS as f64;
    (0..PANELS)
        .map(|k| refine(f, ends(k).0, ends(k).1, coarse[k], abs_tol, depth))
        .sum()
}

fn refine(f: &dyn Fn(f64) -> f64, a: f64, b: f64, whole: f64, abs_tol: f64, depth: u32) -> f64 {
    let m = 0.5 * (a + b);
    let (left, right) = (gauss5(f, a, m), gauss5(f, m, b));
    let diff = (left + right - whole).abs();
    // A NaN stops the refinement and propagates to the result.
    if depth == 0 || diff.is_nan() || diff <= abs_tol {
        return left + right;
    }
    refine(f, a, m, left, 0.5 * abs_tol, depth - 1)
        + refine(f, m, b, right, 0.5 * abs_tol, depth - 1)
}

#[cfg(test)]
#[path = "sedov_tests.rs"]
mod tests;
