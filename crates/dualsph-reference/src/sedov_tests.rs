//! Tests of [`super::Sedov`]: published constants, the shock jump, conservation of energy and
//! mass by an independent quadrature in `r`, the Euler equations by finite differences, the
//! centre, and bad input.

use super::*;

const GEOMETRIES: [Geometry; 3] = [Geometry::Planar, Geometry::Cylindrical, Geometry::Spherical];
const GAMMAS: [f64; 2] = [1.4, 5.0 / 3.0];

/// `∫₀^R field(sample(r)) σ_j r^{j−1} dr` by composite 5-point Gauss–Legendre on `panels`
/// equal panels in `r`, through the public `sample` (the root-finding path), independent of
/// the quadrature over `η` that produced `α`.
fn radial_integral(
    s: &Sedov,
    (e, rho0, t): (f64, f64, f64),
    field: &dyn Fn(&SedovSample) -> f64,
    panels: usize,
) -> f64 {
    let big_r = s.shock_radius(e, rho0, t);
    let jm1 = f64::from(s.geometry().j()) - 1.0;
    let integrand = |r: f64| field(&s.sample(e, rho0, t, r)) * libm::pow(r, jm1);
    let h = big_r / panels as f64;
    let sum: f64 = (0..panels)
        .map(|k| gauss5(&integrand, k as f64 * h, (k + 1) as f64 * h))
        .sum();
    s.geometry().measure() * sum
}

#[test]
fn alpha_matches_published_values() {
    // Kamm & Timmes 2007, Table 4 (γ = 1.4, ω = 0), six digits; transcribed from the tests of
    // LANL's ExactPack (exactpack/tests/test_sedov_doebling.py), the report itself not being
    // at hand. For the spherical case, 0.851072 is the energy Kamm & Timmes and ExactPack
    // (exactpack/solvers/sedov/__init__.py) use to put the shock at R(1) = 1 (Table 4 itself
    // lists 0.851060, i.e. 2π(J₁ + 2J₂/(γ−1)) from its rounded J's). Measured here: planar
    // 0.5387428, cylindrical 0.9840740, spherical 0.8510719. The spherical value agrees to
    // all six digits; the planar and cylindrical ones sit 3.6e-4 and 3.4e-5 (relative) above
    // the table. That pattern follows the strength of the integrable endpoint singularity
    // of the energy integrand over V (∝ (V − V₀)^{−jα₂−1}, strongest for j = 1), which the
    // report's quadrature in V must resolve; the profiles here satisfy the Euler equations
    // and conserve mass (tests below), and α is their energy integral to 1e-13, so the
    // tolerances are the measured gaps, not a sign of an error on this side.
    let cases = [
        (Geometry::Planar, 0.538548, 4e-4),
        (Geometry::Cylindrical, 0.984041, 4e-5),
        (Geometry::Spherical, 0.851072, 2e-6),
    ];
    for (geometry, published, rel_tol) in cases {
        let a = Sedov::new(1.4, geometry).unwrap().alpha();
        eprintln!("{geometry:?} γ=1.4: α = {a:.10} (published {published})");
        let rel = a / published - 1.0;
        assert!(rel.abs() < rel_tol, "{geometry:?}: {a} vs {published}");
    }
    // γ = 5/3, spherical: ξ₀ = 1.15167, the value commonly quoted for a monatomic gas and
    // attributed to Ostriker & McKee 1988 (OstrikerMcKee1988 in docs/references.md); the
    // paper itself was not consulted here. Measured: α = 0.4935901, ξ₀ = 1.1516664.
    let s = Sedov::new(5.0 / 3.0, Geometry::Spherical).unwrap();
    eprintln!(
        "Spherical γ=5/3: α = {:.10}, ξ0 = {:.10}",
        s.alpha(),
        s.xi0()
    );
    assert!((s.xi0() - 1.15167).abs() < 6e-6, "ξ0 = {}", s.xi0());
    // ξ₀ for γ = 1.4, spherical: 0.851072^(−1/5) = 1.032777 (the brief's 1.033).
    let s = Sedov::new(1.4, Geometry::Spherical).unwrap();
    assert!((s.xi0() - 1.032777).abs() < 1e-6, "ξ0 = {}", s.xi0());
}

#[test]
fn profile_matches_sedov_table() {
    // Kamm & Timmes 2007, Table 3 (γ = 1.4, spherical): V, λ, f, g, h to four decimals, as
    // transcribed in ExactPack's tests. Evaluated at the tabulated λ: the V column, rounded to
    // 4 decimals where dλ/dV ≈ 4, does not pin λ down to the table's precision.
    let table = [
        (0.3300, 0.9913, 0.9814, 0.8388, 0.9116),
        (0.3250, 0.9773, 0.9529, 0.6454, 0.7992),
        (0.3200, 0.9622, 0.9238, 0.4984, 0.7082),
        (0.3120, 0.9342, 0.8745, 0.3248, 0.5929),
        (0.3060, 0.9080, 0.8335, 0.2275, 0.5238),
        (0.3000, 0.8747, 0.7872, 0.1508, 0.4674),
        (0.2950, 0.8359, 0.7398, 0.0968, 0.4273),
        (0.2915, 0.7950, 0.6952, 0.0620, 0.4021),
        (0.2890, 0.7493, 0.6497, 0.0379, 0.3857),
        (0.2870, 0.6788, 0.5844, 0.0174, 0.3732),
        (0.2860, 0.5794, 0.4971, 0.0052, 0.3672),
    ];
    let s = Sedov::new(1.4, Geometry::Spherical).unwrap();
    for (_v, lam, f, g, h) in table {
        // At the tabulated λ, f, g, h to the table's four decimals, widened by the change of
        // each over the ±5e-5 rounding of λ (g is steep near the shock).
        let (got, dl) = (s.shape(lam), 5e-5);
        let (up, down) = (s.shape(lam + dl), s.shape(lam - dl));
        let pairs = [
            (got.0, f, up.0 - down.0),
            (got.1, g, up.1 - down.1),
            (got.2, h, up.2 - down.2),
        ];
        for (x, want, spread) in pairs {
            let tol = 5.5e-5 + 0.5 * spread.abs();
            assert!((x - want).abs() < tol, "λ = {lam}: {got:?} vs {f} {g} {h}");
        }
    }
}

#[test]
fn rankine_hugoniot_at_the_shock() {
    let (e, rho0, t) = (2.5, 1.3, 0.7);
    for geometry in GEOMETRIES {
        for g in GAMMAS {
            let s = Sedov::new(g, geometry).unwrap();
            let big_r = s.shock_radius(e, rho0, t);
            let rdot = s.shock_speed(e, rho0, t);
            let x = s.sample(e, rho0, t, big_r);
            let rho = rho0 * (g + 1.0) / (g - 1.0);
            let u = 2.0 / (g + 1.0) * rdot;
            let p = 2.0 / (g + 1.0) * rho0 * rdot * rdot;
            for (got, want) in [(x.rho, rho), (x.u, u), (x.p, p)] {
                assert!(
                    (got / want - 1.0).abs() < 1e-12,
                    "{geometry:?} γ={g}: {x:?}"
                );
            }
            // Ṙ is the time derivative of R: a wrong exponent shows here.
            let dt = 1e-6 * t;
            let fd =
                (s.shock_radius(e, rho0, t + dt) - s.shock_radius(e, rho0, t - dt)) / (2.0 * dt);
            assert!((fd / rdot - 1.0).abs() < 1e-9);
            let beyond = s.sample(e, rho0, t, big_r * (1.0 + 1e-12));
            assert_eq!((beyond.rho, beyond.u, beyond.p), (rho0, 0.0, 0.0));
        }
    }
}

#[test]
fn energy_of_the_profiles_is_e() {
    let (e, rho0, t) = (3.0, 0.8, 1.9);
    for geometry in GEOMETRIES {
        for g in GAMMAS {
            let s = Sedov::new(g, geometry).unwrap();
            let energy = |x: &SedovSample| 0.5 * x.rho * x.u * x.u + x.p / (g - 1.0);
            let got = radial_integral(&s, (e, rho0, t), &energy, 400);
            eprintln!(
                "energy {geometry:?} γ={g:.4}: rel err {:.2e}",
                got / e - 1.0
            );
            assert!(
                (got / e - 1.0).abs() < 1e-9,
                "{geometry:?} γ={g}: {got} vs {e}"
            );
        }
    }
}

#[test]
fn mass_of_the_profiles_is_the_swept_up_mass() {
    let (e, rho0, t) = (0.6, 2.2, 0.4);
    for geometry in GEOMETRIES {
        for g in GAMMAS {
            let s = Sedov::new(g, geometry).unwrap();
            let big_r = s.shock_radius(e, rho0, t);
            let j = f64::from(geometry.j());
            let swept = rho0 * geometry.measure() * libm::pow(big_r, j) / j;
            let got = radial_integral(&s, (e, rho0, t), &|x| x.rho, 400);
            eprintln!(
                "mass {geometry:?} γ={g:.4}: rel err {:.2e}",
                got / swept - 1.0
            );
            assert!(
                (got / swept - 1.0).abs() < 1e-9,
                "{geometry:?} γ={g}: {got} vs {swept}"
            );
        }
    }
}

#[test]
fn profiles_solve_the_euler_equations() {
    // Central differences of ρ_t + (ρu)_r + (j−1)ρu/r, u_t + u u_r + p_r/ρ and the advection
    // of ln(p ρ^−γ), each scaled by its own natural size, at interior points.
    let (e, rho0, t) = (1.0, 1.0, 1.0);
    for geometry in GEOMETRIES {
        for g in GAMMAS {
            let s = Sedov::new(g, geometry).unwrap();
            let big_r = s.shock_radius(e, rho0, t);
            let rdot = s.shock_speed(e, rho0, t);
            let jm1 = f64::from(geometry.j()) - 1.0;
            for lam in [0.45, 0.7, 0.9, 0.98] {
                let r = lam * big_r;
                let (dr, dt) = (1e-5 * big_r, 1e-5 * t);
                let at = |r: f64, t: f64| s.sample(e, rho0, t, r);
                let (c, rp, rm, tp, tm) = (
                    at(r, t),
                    at(r + dr, t),
                    at(r - dr, t),
                    at(r, t + dt),
                    at(r, t - dt),
                );
                let ddr = |f: &dyn Fn(&SedovSample) -> f64| (f(&rp) - f(&rm)) / (2.0 * dr);
                let ddt = |f: &dyn Fn(&SedovSample) -> f64| (f(&tp) - f(&tm)) / (2.0 * dt);
                let ent = |x: &SedovSample| libm::log(x.p) - g * libm::log(x.rho);
                let mass = ddt(&|x| x.rho) + ddr(&|x| x.rho * x.u) + jm1 * c.rho * c.u / r;
                let mom = ddt(&|x| x.u) + c.u * ddr(&|x| x.u) + ddr(&|x| x.p) / c.rho;
                let adv = ddt(&ent) + c.u * ddr(&ent);
                let scaled = [
                    mass / (c.rho * rdot / big_r),
                    mom / (rdot * rdot / big_r),
                    adv / (rdot / big_r),
                ];
                for x in scaled {
                    assert!(x.abs() < 1e-6, "{geometry:?} γ={g} λ={lam}: {scaled:?}");
                }
            }
        }
    }
}

#[test]
fn centre_is_finite_with_vanishing_density() {
    let (e, rho0, t) = (1.0, 1.0, 1.0);
    for geometry in GEOMETRIES {
        for g in [1.1, 1.4, 5.0 / 3.0, 3.0] {
            let s = Sedov::new(g, geometry).unwrap();
            let big_r = s.shock_radius(e, rho0, t);
            let centre = s.sample(e, rho0, t, 0.0);
            assert_eq!((centre.rho, centre.u), (0.0, 0.0));
            assert!(centre.p.is_finite() && centre.p > 0.0 && centre.e_specific == f64::INFINITY);
            let mut last = s.sample(e, rho0, t, big_r);
            for k in 1..=300 {
                let x = s.sample(e, rho0, t, big_r * 0.9f64.powi(k));
                // Once ρ underflows (γ near 1: ρ ∝ λ^{j/(γ−1)}), e = p/((γ−1)ρ) overflows to +∞.
                let e_ok = x.e_specific.is_finite() || (x.rho < 1e-300 && x.e_specific > 0.0);
                let ok = x.rho.is_finite() && x.u.is_finite() && x.p.is_finite() && e_ok;
                assert!(
                    ok && x.rho <= last.rho && x.u <= last.u,
                    "{geometry:?} γ={g} k={k}"
                );
                last = x;
            }
            // λ = 0.9³⁰⁰ ≈ 2e-14: the pressure has reached its central value.
            assert!(
                (last.p / centre.p - 1.0).abs() < 1e-12,
                "{} vs {}",
                last.p,
                centre.p
            );
            // At λ = 1e-6 the density falls off like λ^{j/(γ−1)} and the velocity like λ.
            let power = f64::from(geometry.j()) / (g - 1.0);
            let (outer, inner) = (
                s.sample(e, rho0, t, 1e-6 * big_r),
                s.sample(e, rho0, t, 0.9e-6 * big_r),
            );
            let slope = libm::log(outer.rho / inner.rho) / libm::log(1.0f64 / 0.9);
            assert!(
                (slope / power - 1.0).abs() < 1e-9,
                "{geometry:?} γ={g}: {slope}"
            );
            assert!((outer.u / inner.u * 0.9 - 1.0).abs() < 1e-9);
        }
    }
}

#[test]
fn shock_time_inverts_shock_radius() {
    for geometry in GEOMETRIES {
        let s = Sedov::new(1.4, geometry).unwrap();
        let (e, rho0) = (7.0, 0.3);
        for t in [1e-3, 0.5, 2.0, 40.0] {
            let r = s.shock_radius(e, rho0, t);
            assert!((s.shock_time(e, rho0, r) / t - 1.0).abs() < 1e-13);
        }
        // E = α ρ₀ R^{j+2}/t²: the definition of α.
        let r = s.shock_radius(e, rho0, 1.3);
        let j2 = f64::from(geometry.j()) + 2.0;
        assert!((s.alpha() * rho0 * libm::pow(r, j2) / (1.3 * 1.3) / e - 1.0).abs() < 1e-13);
    }
}

#[test]
fn alpha_is_continuous_across_the_refused_gamma_2() {
    // The limit γ → 2 exists; both sides close to it agree and Sedov::new refuses 2 itself.
    for geometry in GEOMETRIES {
        let lo = Sedov::new(2.0 - 1e-4, geometry).unwrap().alpha();
        let hi = Sedov::new(2.0 + 1e-4, geometry).unwrap().alpha();
        assert!((lo / hi - 1.0).abs() < 1e-3, "{geometry:?}: {lo} vs {hi}");
        assert!(Sedov::new(2.0, geometry).is_err());
    }
}

#[test]
fn bad_input_is_refused_or_documented() {
    for g in [1.0, 0.5, -2.0, f64::NAN, f64::INFINITY] {
        assert!(Sedov::new(g, Geometry::Spherical).is_err(), "γ = {g}");
    }
    assert!(Sedov::new(7.0, Geometry::Spherical).is_err());
    assert!(Sedov::new(8.0, Geometry::Spherical).is_err());
    assert!(Sedov::new(8.0, Geometry::Planar).is_ok());
    let s = Sedov::new(1.4, Geometry::Cylindrical).unwrap();
    let ambient = SedovSample {
        rho: 2.0,
        u: 0.0,
        p: 0.0,
        e_specific: 0.0,
    };
    assert_eq!(s.sample(1.0, 2.0, 0.0, 0.1), ambient);
    assert_eq!(s.sample(1.0, 2.0, -1.0, 0.1), ambient);
    for (e, rho0, t, r) in [
        (f64::NAN, 1.0, 1.0, 0.1),
        (1.0, 1.0, f64::NAN, 0.1),
        (1.0, 1.0, 1.0, f64::NAN),
        (1.0, 1.0, 1.0, -0.1),
        (0.0, 1.0, 1.0, 0.1),
        (1.0, -1.0, 1.0, 0.1),
        (1.0, 1.0, f64::INFINITY, 0.1),
    ] {
        let x = s.sample(e, rho0, t, r);
        assert!(x.rho.is_nan() && x.u.is_nan() && x.p.is_nan() && x.e_specific.is_nan());
    }
    assert_eq!(s.shock_radius(1.0, 1.0, 0.0), 0.0);
    assert!(s.shock_radius(1.0, 1.0, -1.0).is_nan());
    assert!(s.shock_time(1.0, 1.0, -1.0).is_nan());
}
