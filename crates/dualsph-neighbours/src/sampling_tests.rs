//! Tests of field sampling against analytic fields in 1, 2 and 3 D.

use super::*;
use dualsph_math::Vec1;
use dualsph_math::kernels::KernelKind;
use glam::{DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A jittered lattice on [0, 1]^d with spacing `dx` (jitter ±0.2 dx), volumes dx^d and
/// support radii varying between 2.0 and 2.6 dx (so point supports are genuinely
/// dual-support: particles reach x with different radii).
fn cloud<V: Vector>(dx: Real, seed: u64) -> SamplingCloud<V> {
    let n = (1.0 / dx).round() as usize + 1;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let total = n.pow(V::DIM as u32);
    let mut pos = Vec::with_capacity(total);
    let mut h = Vec::with_capacity(total);
    for idx in 0..total {
        let mut p = V::zero();
        let mut rest = idx;
        for k in 0..V::DIM {
            let c = rest % n;
            rest /= n;
            p.set(k, (c as Real + rng.random_range(-0.2..0.2)) * dx);
        }
        pos.push(p);
        h.push(dx * rng.random_range(2.0..2.6));
    }
    let vol = vec![dx.powi(V::DIM as i32); total];
    SamplingCloud::new(Kernel::new(KernelKind::CubicSpline, V::DIM), pos, vol, h)
}

/// Fixed interior query points in [0.3, 0.7]^d (full support at every resolution tested).
fn points<V: Vector>(count: usize) -> Vec<V> {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    (0..count)
        .map(|_| {
            let mut p = V::zero();
            for k in 0..V::DIM {
                p.set(k, rng.random_range(0.3..0.7));
            }
            p
        })
        .collect()
}

fn field<V: Vector>(c: &SamplingCloud<V>, f: impl Fn(V) -> Real) -> Vec<Real> {
    c.pos.iter().map(|&p| f(p)).collect()
}

fn linear<V: Vector>(x: V) -> Real {
    (0..V::DIM)
        .map(|k| (k as Real + 1.5) * x.get(k))
        .sum::<Real>()
        - 0.7
}

fn linear_grad<V: Vector>() -> V {
    let mut g = V::zero();
    for k in 0..V::DIM {
        g.set(k, k as Real + 1.5);
    }
    g
}

/// `A = 1 + Σ_k (k+1) x_k² + x_0 x_{d−1}` and its gradient.
fn quadratic<V: Vector>(x: V) -> Real {
    let d = V::DIM;
    1.0 + (0..d)
        .map(|k| (k as Real + 1.0) * x.get(k) * x.get(k))
        .sum::<Real>()
        + x.get(0) * x.get(d - 1)
}

fn quadratic_grad<V: Vector>(x: V) -> V {
    let d = V::DIM;
    let mut g = V::zero();
    for k in 0..d {
        g.set(k, 2.0 * (k as Real + 1.0) * x.get(k));
    }
    g.set(0, g.get(0) + x.get(d - 1));
    g.set(d - 1, g.get(d - 1) + x.get(0));
    g
}

fn support_is_the_dual_support_of_the_point<V: Vector>() {
    let c = cloud::<V>(0.1, 1);
    for x in points::<V>(20) {
        let brute: Vec<u32> = (0..c.len())
            .filter(|&j| (x - c.pos[j]).length() < c.h[j])
            .map(|j| j as u32)
            .collect();
        assert_eq!(c.support(x), brute, "{}-D support of {x:?}", V::DIM);
        assert!(!brute.is_empty());
    }
}

#[test]
fn point_support_matches_brute_force_1d_2d_3d() {
    support_is_the_dual_support_of_the_point::<Vec1>();
    support_is_the_dual_support_of_the_point::<DVec2>();
    support_is_the_dual_support_of_the_point::<DVec3>();
}

fn exactness<V: Vector>(dx: Real) {
    let c = cloud::<V>(dx, 2);
    let constant = vec![3.7; c.len()];
    let lin = field(&c, linear::<V>);
    for x in points::<V>(40) {
        let s = c.sample(x, &constant);
        let shep = s.shepard.expect("interior point has a support");
        assert!(
            (shep - 3.7).abs() < 1e-13 * 3.7,
            "{}-D Shepard of a constant: {shep}",
            V::DIM
        );
        // the plain interpolant is not exact on an irregular cloud: σ ≠ 1 (but close)
        assert!((s.shepard_sum - 1.0).abs() < 0.2, "σ = {}", s.shepard_sum);
        let s = c.sample(x, &lin);
        let exact = linear(x);
        let a1 = s.linear.expect("linear fit exists");
        assert!(
            (a1 - exact).abs() < 1e-11,
            "{}-D linear value {a1} vs {exact}",
            V::DIM
        );
        let g = s.gradient_corrected.expect("corrected gradient exists");
        let err = (g - linear_grad::<V>()).length();
        assert!(err < 1e-10, "{}-D corrected gradient error {err}", V::DIM);
        // the uncorrected Thm 3.3 gradient is not exact on this cloud
        let plain_err = (s.gradient - linear_grad::<V>()).length();
        assert!(plain_err > 1e-6, "plain gradient unexpectedly exact");
    }
}

#[test]
fn shepard_exact_for_constants_and_corrected_exact_for_linear_1d_2d_3d() {
    exactness::<Vec1>(0.01);
    exactness::<DVec2>(0.04);
    exactness::<DVec3>(0.1);
}

/// RMS errors of the consistent value and corrected gradient on the quadratic field.
fn quadratic_errors<V: Vector>(dx: Real) -> (Real, Real) {
    let c = cloud::<V>(dx, 3);
    let a = field(&c, quadratic::<V>);
    let pts = points::<V>(200);
    let mut e = (0.0, 0.0);
    for &x in &pts {
        let s = c.sample(x, &a);
        e.0 += (s.linear.unwrap() - quadratic(x)).powi(2);
        e.1 += (s.gradient_corrected.unwrap() - quadratic_grad(x)).length_squared();
    }
    let n = pts.len() as Real;
    ((e.0 / n).sqrt(), (e.1 / n).sqrt())
}

/// Orders measured from three resolutions dx, dx/2, dx/4 (least-squares slope of log error
/// against log dx): value ≈ 2, gradient ≈ 1 (the jittered cloud is irregular, so the
/// corrected gradient is only first order).
fn convergence<V: Vector>(dx: Real) {
    let e: Vec<(Real, Real)> = [dx, dx / 2.0, dx / 4.0]
        .iter()
        .map(|&d| quadratic_errors::<V>(d))
        .collect();
    // slope over log2 spacings 0, −1, −2: (log e0 − log e2)/2 is the least-squares slope
    let order = |a: Real, b: Real| libm::log2(a / b) / 2.0;
    let (ov, og) = (order(e[0].0, e[2].0), order(e[0].1, e[2].1));
    eprintln!(
        "{}-D quadratic field: value order {ov:.2}, gradient order {og:.2} ({e:?})",
        V::DIM
    );
    assert!(
        (1.7..2.5).contains(&ov),
        "{}-D value order {ov:.2} (errors {e:?})",
        V::DIM
    );
    assert!(
        (0.75..1.6).contains(&og),
        "{}-D gradient order {og:.2} (errors {e:?})",
        V::DIM
    );
    // and the error decreases at each refinement
    assert!(e[1].0 < e[0].0 && e[2].0 < e[1].0 && e[1].1 < e[0].1 && e[2].1 < e[1].1);
}

#[test]
fn quadratic_field_converges_at_second_and_first_order_1d() {
    convergence::<Vec1>(0.02);
}

#[test]
fn quadratic_field_converges_at_second_and_first_order_2d() {
    convergence::<DVec2>(0.05);
}

#[test]
fn quadratic_field_converges_at_second_and_first_order_3d() {
    convergence::<DVec3>(0.1);
}

#[test]
fn density_of_a_regular_lattice_is_recovered() {
    // Thm. 3.2 on a regular 2-D lattice of density 1000: ρ(x) = Σ m_j W_j ≈ 1000 inside,
    // and the Shepard sum falls to ½ at the free edge of a half-space.
    let dx = 0.02;
    let mut pos = Vec::new();
    for a in 0..50 {
        for b in 0..50 {
            pos.push(DVec2::new((a as Real + 0.5) * dx, (b as Real + 0.5) * dx));
        }
    }
    let n = pos.len();
    let m = vec![1000.0 * dx * dx; n];
    let rho = vec![1000.0; n];
    let c = SamplingCloud::from_particles(
        Kernel::new(KernelKind::CubicSpline, 2),
        pos,
        &m,
        &rho,
        vec![2.0 * dx; n],
    );
    let s = c.sample(DVec2::new(0.503, 0.517), &rho);
    assert!((s.value - 1000.0).abs() < 5.0, "ρ = {}", s.value);
    let edge = c.shepard_sum(DVec2::new(0.5, 1.0));
    assert!((edge - 0.5).abs() < 0.03, "σ at the surface = {edge}");
    assert_eq!(c.shepard_sum(DVec2::new(0.5, 1.2)), 0.0);
}

#[test]
fn sampling_is_identical_on_one_and_two_threads() {
    let c = cloud::<DVec2>(0.02, 5);
    let a = field(&c, quadratic::<DVec2>);
    let pts = points::<DVec2>(500);
    let run = |t: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
            .install(|| c.sample_many(&pts, &a))
    };
    let (one, two) = (run(1), run(2));
    for (p, q) in one.iter().zip(&two) {
        assert_eq!(p.value.to_bits(), q.value.to_bits());
        assert_eq!(p.linear.map(Real::to_bits), q.linear.map(Real::to_bits));
    }
}

#[test]
fn solver_rejects_singular_systems() {
    let mut m = [[0.0; 4]; 4];
    m[0][0] = 1.0;
    m[1][1] = 1e-20;
    assert!(solve(m, [1.0; 4], 2).is_none());
    m[1][1] = 2.0;
    m[0][1] = 1.0;
    let x = solve(m, [3.0, 4.0, 0.0, 0.0], 2).unwrap();
    assert!((x[1] - 2.0).abs() < 1e-15 && (x[0] - 1.0).abs() < 1e-15);
}
