use super::*;

#[test]
fn two_lanes_equal_one_lane_bitwise() {
    use dualsph_fluid::checks::check_lanes_2d;
    let av = ArtificialViscosityTerm {
        alpha: 1.0,
        beta: 2.0,
        eta_factor: 0.1,
        by_body: Vec::new(),
        dissipation: true,
    };
    check_lanes_2d(&av).unwrap();
    let physical = PhysicalViscosityTerm {
        mu: 1e-3,
        eta_factor: 0.1,
        by_body: Vec::new(),
    };
    check_lanes_2d(&physical).unwrap();
    check_lanes_2d(&ViscousStressTerm {
        mu: 1e-3,
        lambda: 2e-4,
    })
    .unwrap();
}

/// The artificial viscosity as a sweep's only term, with and without a dissipation channel:
/// its block loop gives bitwise the sums of its dynamic calls.
#[test]
fn the_viscosity_block_loop_gives_the_same_sums() {
    use dualsph_fluid::checks::check_block_loop_2d;
    for dissipation in [false, true] {
        let av = ArtificialViscosityTerm {
            alpha: 1.0,
            beta: 2.0,
            eta_factor: 0.1,
            by_body: Vec::new(),
            dissipation,
        };
        check_block_loop_2d(std::sync::Arc::new(av)).unwrap();
    }
}

/// Eq. 4.23's Laplacian of `u = y²/2` (exactly 1) at a particle of a square lattice of
/// spacing 1, Wendland C2 with support 3: `2 Σ_j V_j (u_i − u_j) r_ij W'(r)/(r² + η²)`,
/// `η = eta_factor · 3`. The regularisation lowers it by 5 % at the default 0.1, by 0.3 %
/// at 0.01 (the figures `eta_factor`'s docs quote).
#[test]
fn regularisation_lowers_the_laplacian() {
    use dualsph_core::kernels::{Kernel, KernelKind};
    let k = Kernel::new(KernelKind::WendlandC2, 2);
    let laplacian = |eta_factor: Real| {
        let (h, eta) = (3.0, eta_factor * 3.0);
        let mut sum = 0.0;
        for a in -3i32..=3 {
            for b in -3i32..=3 {
                let r = Real::from(a * a + b * b).sqrt();
                if r > 0.0 && r < h {
                    let du = -0.5 * Real::from(b * b);
                    sum += 2.0 * du * r * k.dw_dr(r, h) / (r * r + eta * eta);
                }
            }
        }
        sum
    };
    let (coarse, fine) = (laplacian(0.1), laplacian(0.01));
    assert!((coarse - 0.950).abs() < 5e-4, "eta 0.1 h: {coarse}");
    assert!((fine - 0.997).abs() < 5e-4, "eta 0.01 h: {fine}");
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
