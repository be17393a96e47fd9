//! The free elliptical drop (§7.3 and Eq. 7.6 of Ren, Dai, Zhuang & Rabczuk, *Dual-support
//! Smoothed Particle Hydrodynamics*, preprint; RenDSSPH in docs/references.md), Monaghan's
//! "water bubble".
//!
//! A circle of radius R with the velocity field `v = A(t)·(−x, y)` stays an ellipse with
//! semi-axes `a` (along x) and `b = R²/a` (along y, area conserved). With `a` in units of R:
//!
//! `da/dt = −a A`, `dA/dt = A² (a⁴ − 1)/(a⁴ + 1)`, `a(0) = 1`, `A(0) = A₀`.
//!
//! Integrated with classical fourth-order Runge–Kutta.

/// Semi-axes of the drop at time `t`: `(a, b)` with `a` along x (shrinking) and `b` along y
/// (growing), in units of the initial radius, for an initial strain rate `a0_rate` (1/s).
pub fn semi_axes(a0_rate: f64, t: f64) -> (f64, f64) {
    let n = ((t.abs() * a0_rate * 2.0e4).ceil() as usize).max(1000);
    let dt = t / n as f64;
    let rhs = |s: [f64; 2]| -> [f64; 2] {
        let (a, big_a) = (s[0], s[1]);
        let a4 = a.powi(4);
        [-a * big_a, big_a * big_a * (a4 - 1.0) / (a4 + 1.0)]
    };
    let mut s = [1.0, a0_rate];
    for _ in 0..n {
        let k1 = rhs(s);
        let k2 = rhs([s[0] + 0.5 * dt * k1[0], s[1] + 0.5 * dt * k1[1]]);
        let k3 = rhs([s[0] + 0.5 * dt * k2[0], s[1] + 0.5 * dt * k2[1]]);
        let k4 = rhs([s[0] + dt * k3[0], s[1] + dt * k3[1]]);
        for k in 0..2 {
            s[k] += dt / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]);
        }
    }
    (s[0], 1.0 / s[0])
}

/// Stretch factors `F_k(t)` (semi-axes `a_k = R F_k`) of a free, incompressible, inviscid
/// ellipse (2 entries) or ellipsoid (3) whose initial velocity is `v_k = rates[k]·x_k`
/// (`Σ rates = 0`), e.g. `[−A₀, A₀, 0]` for the 3-D analogue of the drop.
///
/// With `x_k = F_k X_k` the pressure `p = P(t)(1 − Σ x_k²/a_k²)` accelerates every axis alike,
/// `F_k F_k'' = λ(t) = 2P/(ρR²)`; incompressibility `Π F_k = 1` (so `Σ F_k'/F_k = 0`, and its
/// derivative) fixes `λ = Σ (F_k'/F_k)² / Σ F_k⁻²`. In 2-D this is Eq. 7.6 ([`semi_axes`]).
/// Integrated with classical fourth-order Runge–Kutta.
pub fn linear_drop_axes(rates: &[f64], t: f64) -> Vec<f64> {
    let d = rates.len();
    let scale = rates.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    let n = ((t.abs() * scale * 2.0e4).ceil() as usize).max(1000);
    let dt = t / n as f64;
    // state: F_0..F_{d-1}, F'_0..F'_{d-1}
    let rhs = |s: &[f64]| -> Vec<f64> {
        let (f, fd) = s.split_at(d);
        let num: f64 = (0..d).map(|k| (fd[k] / f[k]).powi(2)).sum();
        let den: f64 = f.iter().map(|x| x.powi(-2)).sum();
        let lambda = num / den;
        fd.iter()
            .copied()
            .chain(f.iter().map(|x| lambda / x))
            .collect()
    };
    let mut s: Vec<f64> = std::iter::repeat_n(1.0, d)
        .chain(rates.iter().copied())
        .collect();
    let axpy = |s: &[f64], k: &[f64], h: f64| -> Vec<f64> {
        s.iter().zip(k).map(|(a, b)| a + h * b).collect()
    };
    for _ in 0..n {
        let k1 = rhs(&s);
        let k2 = rhs(&axpy(&s, &k1, 0.5 * dt));
        let k3 = rhs(&axpy(&s, &k2, 0.5 * dt));
        let k4 = rhs(&axpy(&s, &k3, dt));
        for k in 0..2 * d {
            s[k] += dt / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]);
        }
    }
    s.truncate(d);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_published_semi_major_axis() {
        // DESIGN.md reference figures: b = 1.944517 at t = 0.0076 s and 1.99930 at 0.008 s.
        let (_, b) = semi_axes(100.0, 0.0076);
        assert!((b - 1.944517).abs() < 5e-6, "{b}");
        let (_, b) = semi_axes(100.0, 0.008);
        assert!((b - 1.99930).abs() < 5e-5, "{b}");
    }

    #[test]
    fn early_times_follow_the_initial_rate() {
        // For small t, b ≈ e^{A0 t}: the strain rate is nearly constant at first.
        let (a, b) = semi_axes(100.0, 1e-4);
        assert!((b - libm::exp(0.01f64)).abs() < 1e-6);
        assert!((a * b - 1.0).abs() < 1e-15);
    }

    #[test]
    fn general_form_reduces_to_eq_7_6_in_2d_and_keeps_volume_in_3d() {
        for t in [0.002, 0.005, 0.008] {
            let (a, b) = semi_axes(100.0, t);
            let f = linear_drop_axes(&[-100.0, 100.0], t);
            assert!(
                (f[0] - a).abs() < 1e-9 && (f[1] - b).abs() < 1e-9,
                "{t}: {f:?}"
            );
            let g = linear_drop_axes(&[-100.0, 100.0, 0.0], t);
            assert!((g[0] * g[1] * g[2] - 1.0).abs() < 1e-9, "{g:?}");
            // The pressure that slows the strain (F_k'' = λ/F_k > 0) also pushes z outward.
            assert!(g[2] > 1.0 && g[1] > 1.0 && g[0] < 1.0, "{g:?}");
        }
    }
}
