//! Smoothing kernels, each written once as a 1-D radial profile and normalised in 1, 2 and 3 D.
//!
//! Notation (Ren, Dai, Zhuang & Rabczuk, *Dual-support Smoothed Particle Hydrodynamics*, preprint, Bauhaus-Universität Weimar; Eq. 2.1): **h is the support radius**, `W_ij = w(r_ij / h_i)` and the
//! kernel vanishes for `r >= h`. (Many codes call this radius 2h or 3h.)
//!
//! A profile `f(q)`, `q = r/h ∈ [0, 1]`, becomes a d-dimensional kernel through the construction
//! of R. E. Fry, *FLUISIM: Smoothed Particle Hydrodynamics*, notes, 2025 (Defs. 2.1–2.3): `W(r, h) = C_d / h^d · f(r/h)` with
//! `1/C_d = ∫_0^1 f(q) dB(d, q)/dq dq = S_d ∫_0^1 f(q) q^{d-1} dq`, where
//! `B(d, r) = π^{d/2} r^d / Γ(1 + d/2)` is the volume of the d-ball and `S_d = dB/dr|_{r=1}`
//! its surface. FLUISIM's Def. 2.2 as printed weights the profile by the ball *volume*
//! `B(d, r)`; that does not give a unit integral, and the numerical tests below (which
//! integrate `W` over space independently) confirm that the shell `dB/dr` is the right weight.
//! The integral is evaluated once per kernel by Gauss–Legendre quadrature on the profile's
//! polynomial pieces (exact for the piecewise polynomials used here).
//!
//! The gradient (FLUISIM Thm. 2.4, paper Eq. 2.2): `∇_i W_ij = C_d / h^{d+1} f'(q) r_ij / r_ij`.
//!
//! ## The FLUISIM / Müller et al. (2003) kernels
//! [`KernelKind::Poly6`] (FLUISIM Example 1.3, `(h² − r²)³` → `f = (1 − q²)³`),
//! [`KernelKind::Spiky`] (`f = (1 − q)³`) and [`KernelKind::MullerViscosity`]
//! (`f = −q³/2 + q² + 1/(2q) − 1`) are normalised by the same shell integral as the splines;
//! the tests check the 3-D constants against Müller's `315/(64π h⁹)`, `15/(π h⁶)` and
//! `15/(2π h³)`. The viscosity kernel is singular at `q = 0` (`W(0) = ∞`): Müller et al. use
//! only its **Laplacian** `∇²W = 45/(π h⁶) (h − r)` (3-D), which is positive everywhere, for
//! the viscous force; its value and gradient are still tested like the others. In 1-D its
//! radial moment `∫ f dq` diverges (the `1/(2q)` term), so it is normalisable only in 2-D and
//! 3-D ([`KernelKind::supports_dimension`]; a 1-D scene asking for it is rejected), and with
//! `W(0) = ∞` it must not be used with summation density.

use crate::lanes::Lanes;
use crate::{Real, Vector};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The kernels a scene can choose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
pub enum KernelKind {
    /// Cubic B-spline M4 (Monaghan & Lattanzio 1985); `s = 2q`.
    CubicSpline,
    /// Wendland C2, `(1 − q)^4 (1 + 4q)` (used in every dimension).
    WendlandC2,
    /// Quintic B-spline M6; `s = 3q`.
    QuinticSpline,
    /// FLUISIM's reference kernel (Example 1.3; Müller et al. 2003): `f = (1 − q²)³`.
    Poly6,
    /// Müller et al. (2003) spiky kernel, `f = (1 − q)³` (non-vanishing gradient at q → 0).
    Spiky,
    /// Müller et al. (2003) viscosity kernel, `f = −q³/2 + q² + 1/(2q) − 1`; singular at
    /// q = 0, meant for its Laplacian; 2-D and 3-D only (see the module docs).
    MullerViscosity,
}

impl KernelKind {
    /// Every kernel, for listings and tests, in declaration order (`ALL[kind as usize] ==
    /// kind`).
    pub const ALL: [KernelKind; 6] = [
        KernelKind::CubicSpline,
        KernelKind::WendlandC2,
        KernelKind::QuinticSpline,
        KernelKind::Poly6,
        KernelKind::Spiky,
        KernelKind::MullerViscosity,
    ];

    /// False where the profile cannot be normalised: the viscosity kernel in 1-D
    /// (`∫_0^1 f(q) dq` diverges logarithmically at q = 0).
    pub fn supports_dimension(self, dim: usize) -> bool {
        (1..=3).contains(&dim) && !(self == KernelKind::MullerViscosity && dim == 1)
    }

    /// Radial profile `f(q)` for `0 <= q <= 1` (0 beyond).
    #[inline]
    pub fn profile(self, q: Real) -> Real {
        if !(0.0..1.0).contains(&q) {
            return 0.0;
        }
        match self {
            KernelKind::CubicSpline => {
                let s = 2.0 * q;
                if s < 1.0 {
                    1.0 - 1.5 * s * s + 0.75 * s * s * s
                } else {
                    let t = 2.0 - s;
                    0.25 * t * t * t
                }
            }
            KernelKind::WendlandC2 => {
                let t = 1.0 - q;
                let t2 = t * t;
                t2 * t2 * (1.0 + 4.0 * q)
            }
            KernelKind::QuinticSpline => {
                let s = 3.0 * q;
                let p5 = |x: Real| if x > 0.0 { x.powi(5) } else { 0.0 };
                p5(3.0 - s) - 6.0 * p5(2.0 - s) + 15.0 * p5(1.0 - s)
            }
            KernelKind::Poly6 => {
                let t = 1.0 - q * q;
                t * t * t
            }
            KernelKind::Spiky => {
                let t = 1.0 - q;
                t * t * t
            }
            KernelKind::MullerViscosity => -0.5 * q * q * q + q * q + 0.5 / q - 1.0,
        }
    }

    /// Derivative `f'(q)` of the profile.
    #[inline(always)]
    pub fn profile_derivative(self, q: Real) -> Real {
        self.profile_derivative_lanes(q)
    }

    /// [`Self::profile_derivative`] for one pair or several side by side ([`Lanes`]), written
    /// once for both.
    #[inline(always)]
    pub fn profile_derivative_lanes<T: Lanes>(self, q: T) -> T {
        let c = T::splat;
        // Every piece is evaluated and the right one selected (no branch on q), so a loop over
        // a row of pairs compiles to vector instructions; the values are those of the
        // piecewise formulas.
        let d = match self {
            KernelKind::CubicSpline => {
                let s = c(2.0) * q;
                let inner = c(-3.0) * s + c(2.25) * s * s;
                let t = c(2.0) - s;
                let outer = c(-0.75) * t * t;
                c(2.0) * T::if_lt(s, c(1.0), inner, outer)
            }
            KernelKind::WendlandC2 => {
                let t = c(1.0) - q;
                c(-20.0) * q * t * t * t
            }
            KernelKind::QuinticSpline => {
                let s = c(3.0) * q;
                // x⁴ as (x²)², the products `powi(4)` forms
                let p4 = |x: T| {
                    let x2 = x * x;
                    T::if_gt(x, c(0.0), x2 * x2, c(0.0))
                };
                c(3.0)
                    * (c(-5.0) * p4(c(3.0) - s) + c(30.0) * p4(c(2.0) - s)
                        - c(75.0) * p4(c(1.0) - s))
            }
            KernelKind::Poly6 => {
                let t = c(1.0) - q * q;
                c(-6.0) * q * t * t
            }
            KernelKind::Spiky => {
                let t = c(1.0) - q;
                c(-3.0) * t * t
            }
            KernelKind::MullerViscosity => c(-1.5) * q * q + c(2.0) * q - c(0.5) / (q * q),
        };
        T::in_unit(q, d)
    }

    /// The points in `[0, 1]` where the piecewise polynomial profile changes formula.
    pub fn breakpoints(self) -> &'static [Real] {
        match self {
            KernelKind::CubicSpline => &[0.0, 0.5, 1.0],
            KernelKind::WendlandC2
            | KernelKind::Poly6
            | KernelKind::Spiky
            | KernelKind::MullerViscosity => &[0.0, 1.0],
            KernelKind::QuinticSpline => &[0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0],
        }
    }
}

/// Surface of the unit d-sphere, `S_d = dB(d, r)/dr |_{r=1} = d π^{d/2} / Γ(1 + d/2)`.
pub fn unit_sphere_surface(dim: usize) -> Real {
    // Γ(1 + d/2) for d = 1, 2, 3: √π/2, 1, 3√π/4.
    let gamma = match dim {
        1 => PI.sqrt() / 2.0,
        2 => 1.0,
        3 => 3.0 * PI.sqrt() / 4.0,
        _ => panic!("unit_sphere_surface: dimension {dim} is not 1, 2 or 3"),
    };
    dim as Real * libm::pow(PI, dim as Real / 2.0) / gamma
}

/// Gauss–Legendre nodes and weights on `[-1, 1]` (Newton iteration on `P_n`).
pub fn gauss_legendre(n: usize) -> Vec<(Real, Real)> {
    (0..n)
        .map(|k| {
            let mut x = libm::cos(PI * (k as Real + 0.75) / (n as Real + 0.5));
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for m in 2..=n {
                    let p2 = ((2 * m - 1) as Real * x * p1 - (m - 1) as Real * p0) / m as Real;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as Real * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// `∫_0^1 f(q) q^{d-1} dq`, piece by piece with 12-point Gauss–Legendre (exact to degree 23;
/// the viscosity kernel's `f q^{d-1}` is a polynomial for d = 2, 3, so exact there too).
pub fn radial_moment(kind: KernelKind, dim: usize) -> Real {
    let gl = gauss_legendre(12);
    kind.breakpoints()
        .windows(2)
        .map(|ab| {
            let (a, b) = (ab[0], ab[1]);
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            gl.iter()
                .map(|(x, w)| {
                    let q = mid + half * x;
                    w * half * kind.profile(q) * q.powi(dim as i32 - 1)
                })
                .sum::<Real>()
        })
        .sum()
}

/// A kernel normalised for one dimension: `W(r, h) = C_d h^{-d} f(r/h)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kernel {
    /// Which profile.
    pub kind: KernelKind,
    /// Spatial dimension d.
    pub dim: usize,
    /// The normalisation `C_d`.
    pub norm: Real,
}

impl Kernel {
    /// Normalises `kind` in `dim` dimensions (FLUISIM Def. 2.3 with the shell weight
    /// `dB(d, r)/dr`, not the printed ball volume `B(d, r)` of Def. 2.2: see the module docs).
    /// For a kind that does not [support](KernelKind::supports_dimension) `dim` the constant is
    /// meaningless; scenes reject that combination before building.
    pub fn new(kind: KernelKind, dim: usize) -> Self {
        let norm = 1.0 / (unit_sphere_surface(dim) * radial_moment(kind, dim));
        Kernel { kind, dim, norm }
    }

    #[inline]
    fn h_pow(&self, h: Real) -> Real {
        match self.dim {
            1 => h,
            2 => h * h,
            _ => h * h * h,
        }
    }

    /// `W(r, h)` (Eq. 2.1), zero for `r >= h`.
    #[inline]
    pub fn w(&self, r: Real, h: Real) -> Real {
        self.norm / self.h_pow(h) * self.kind.profile(r / h)
    }

    /// `∂W/∂r (r, h)`.
    #[inline]
    pub fn dw_dr(&self, r: Real, h: Real) -> Real {
        self.norm / (self.h_pow(h) * h) * self.kind.profile_derivative(r / h)
    }

    /// `∂W/∂h (r, h) = −(d W + r ∂W/∂r)/h` (from `W = C_d h^{-d} f(r/h)`), zero for `r >= h`:
    /// what the grad-h factor Ω sums.
    #[inline]
    pub fn dw_dh(&self, r: Real, h: Real) -> Real {
        -(self.dim as Real * self.w(r, h) + r * self.dw_dr(r, h)) / h
    }

    /// `∇_i W_ij = ∂W/∂r · r_ij / r_ij` (Eq. 2.2) for `r_ij = r_i − r_j`, `r = |r_ij|`.
    /// Zero at `r = 0` and for `r >= h`.
    #[inline]
    pub fn grad<V: Vector>(&self, rij: V, r: Real, h: Real) -> V {
        if r <= 0.0 || r >= h {
            return V::zero();
        }
        rij * (self.dw_dr(r, h) / r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    /// Independent check of the normalisation: integrate W over space with a fine
    /// composite Simpson rule in r (1-D: over [-h, h]; 2-D/3-D: shells 2πr, 4πr²).
    fn simpson_volume_integral(k: &Kernel, h: Real) -> Real {
        let n = 200_000;
        let dr = h / n as Real;
        let shell = |r: Real| match k.dim {
            1 => 2.0,
            2 => 2.0 * PI * r,
            _ => 4.0 * PI * r * r,
        };
        // The viscosity kernel has W(0) = ∞ but a finite integrand W·shell at r → 0 in
        // 2-D/3-D: take that limit (r = 1e-12 dr) instead of evaluating at 0.
        let f = |i: usize| {
            let mut r = i as Real * dr;
            if i == 0 && !k.w(0.0, h).is_finite() {
                r = 1e-12 * dr;
            }
            k.w(r, h) * shell(r)
        };
        let mut s = f(0) + f(n);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i);
        }
        s * dr / 3.0
    }

    /// A second, Cartesian check in 2-D: midpoint sum over a fine grid.
    fn grid_integral_2d(k: &Kernel, h: Real) -> Real {
        let n = 1200;
        let d = 2.0 * h / n as Real;
        let mut s = 0.0;
        for a in 0..n {
            for b in 0..n {
                let x = -h + (a as Real + 0.5) * d;
                let y = -h + (b as Real + 0.5) * d;
                s += k.w((x * x + y * y).sqrt(), h);
            }
        }
        s * d * d
    }

    #[test]
    fn all_is_in_declaration_order() {
        for (k, kind) in KernelKind::ALL.into_iter().enumerate() {
            assert_eq!(kind as usize, k);
        }
    }

    #[test]
    fn normalised_in_every_dimension() {
        for kind in KernelKind::ALL {
            for dim in (1..=3).filter(|&d| kind.supports_dimension(d)) {
                let k = Kernel::new(kind, dim);
                for h in [0.37, 1.0, 2.5] {
                    let integral = simpson_volume_integral(&k, h);
                    assert!(
                        (integral - 1.0).abs() < 1e-6,
                        "{kind:?} in {dim}D, h = {h}: ∫W = {integral}"
                    );
                }
            }
            let k2 = Kernel::new(kind, 2);
            let g = grid_integral_2d(&k2, 0.8);
            // the viscosity kernel's 1/r singularity limits the midpoint rule to ~1e-3
            let tol = if kind == KernelKind::MullerViscosity {
                3e-3
            } else {
                1e-5
            };
            assert!((g - 1.0).abs() < tol, "{kind:?} 2-D grid ∫W = {g}");
        }
    }

    #[test]
    fn volume_weighted_normalisation_as_printed_is_wrong() {
        // FLUISIM Def. 2.2 literally: V = ∫ B(d, r) ω dr. Show it does not normalise.
        let k = Kernel::new(KernelKind::CubicSpline, 2);
        let gl = gauss_legendre(12);
        let printed: Real = gl
            .iter()
            .map(|(x, w)| {
                let q = 0.5 + 0.5 * x;
                0.5 * w * PI * q * q * k.kind.profile(q)
            })
            .sum();
        let w_printed = |r: Real| k.kind.profile(r) / printed;
        let n = 20_000;
        let dr = 1.0 / n as Real;
        let integral: Real = (0..n)
            .map(|i| {
                let r = (i as Real + 0.5) * dr;
                w_printed(r) * 2.0 * PI * r * dr
            })
            .sum();
        assert!(
            (integral - 1.0).abs() > 0.1,
            "printed form integrates to {integral}"
        );
    }

    #[test]
    fn gradient_matches_central_difference() {
        // FLUISIM Thm. 4.1 with n = 1: f'(x) ≈ (f(x+δ) − f(x−δ)) / 2δ.
        for kind in KernelKind::ALL {
            for dim in (1..=3).filter(|&d| kind.supports_dimension(d)) {
                let k = Kernel::new(kind, dim);
                let h = 1.3;
                for i in 1..200 {
                    let r = h * i as Real / 200.0;
                    let d = 1e-6;
                    let numeric = (k.w(r + d, h) - k.w(r - d, h)) / (2.0 * d);
                    let analytic = k.dw_dr(r, h);
                    let scale = k.norm / h.powi(dim as i32 + 1);
                    // relative to |∂W/∂r| where that is large (the viscosity kernel's
                    // gradient grows like 1/r² near 0)
                    let tol = 1e-6 * scale.max(1.0).max(analytic.abs());
                    assert!(
                        (numeric - analytic).abs() < tol,
                        "{kind:?} {dim}D r = {r}: {numeric} vs {analytic}"
                    );
                }
                // vector gradient = ∂W/∂r · r̂, checked component-wise in 3-D
                let k3 = Kernel::new(kind, 3);
                let x = DVec3::new(0.3, -0.2, 0.25);
                let g = k3.grad(x, x.length(), h);
                for c in 0..3 {
                    let mut e = DVec3::ZERO;
                    e[c] = 1e-6;
                    let num = (k3.w((x + e).length(), h) - k3.w((x - e).length(), h)) / 2e-6;
                    assert!(
                        (num - g[c]).abs() < 1e-6 * g[c].abs().max(1.0),
                        "{kind:?} ∂W/∂x{c}"
                    );
                }
            }
        }
    }

    #[test]
    fn fluisim_kernels_match_mueller_constants_in_3d() {
        // Müller, Charypar & Gross (2003), with h the support radius:
        // poly6 315/(64π h⁹)(h² − r²)³, spiky 15/(π h⁶)(h − r)³,
        // viscosity 15/(2π h³)(−r³/2h³ + r²/h² + h/2r − 1).
        let h: Real = 0.9;
        for (kind, c) in [
            (KernelKind::Poly6, 315.0 / (64.0 * PI)),
            (KernelKind::Spiky, 15.0 / PI),
            (KernelKind::MullerViscosity, 15.0 / (2.0 * PI)),
        ] {
            let k = Kernel::new(kind, 3);
            for r in [0.1, 0.35, 0.6, 0.85] {
                let expect = match kind {
                    KernelKind::Poly6 => c / h.powi(9) * (h * h - r * r).powi(3),
                    KernelKind::Spiky => c / h.powi(6) * (h - r).powi(3),
                    _ => {
                        c / h.powi(3)
                            * (-r.powi(3) / (2.0 * h.powi(3)) + r * r / (h * h) + h / (2.0 * r)
                                - 1.0)
                    }
                };
                let got = k.w(r, h);
                assert!(
                    (got - expect).abs() < 1e-12 * expect.abs(),
                    "{kind:?} r = {r}: {got} vs {expect}"
                );
            }
        }
        // 2-D poly6: 4/(π h⁸)(h² − r²)³ (the usual 2-D constant)
        let k = Kernel::new(KernelKind::Poly6, 2);
        let expect = 4.0 / (PI * h.powi(8)) * (h * h - 0.25_f64).powi(3);
        assert!((k.w(0.5, h) - expect).abs() < 1e-12 * expect);
    }

    #[test]
    fn viscosity_kernel_is_not_normalisable_in_1d() {
        assert!(!KernelKind::MullerViscosity.supports_dimension(1));
        // ∫_ε^1 f dq grows like ½ ln(1/ε): no finite normalisation exists
        // midpoint rule in u = ln q (dq = q du), smooth in u
        let tail = |eps: Real| {
            let n = 100_000;
            let d = -libm::log(eps) / n as Real;
            (0..n)
                .map(|i| {
                    let q = libm::exp(libm::log(eps) + (i as Real + 0.5) * d);
                    KernelKind::MullerViscosity.profile(q) * q * d
                })
                .sum::<Real>()
        };
        let growth = tail(1e-6) - tail(1e-3);
        assert!(
            (growth - 0.5 * libm::log(1e3 as Real)).abs() < 0.01,
            "growth {growth}"
        );
    }

    #[test]
    fn compact_support_at_h() {
        for kind in KernelKind::ALL {
            for dim in (1..=3).filter(|&d| kind.supports_dimension(d)) {
                let k = Kernel::new(kind, dim);
                let h = 0.7;
                assert_eq!(k.w(h, h), 0.0);
                assert_eq!(k.w(1.5 * h, h), 0.0);
                assert_eq!(k.dw_dr(h, h), 0.0);
                assert!(k.w(0.999 * h, h) >= 0.0 && k.w(0.999 * h, h) < 1e-6);
                assert_eq!(k.grad(DVec2::new(h, 0.0), h, h), DVec2::ZERO);
                assert!(k.w(0.0, h) > 0.0);
            }
        }
    }
}
