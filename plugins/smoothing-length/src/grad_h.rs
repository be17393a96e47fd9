//! The grad-h formulation's smoothing length: at every step `h_i` and the summation density
//! `ρ_i` are solved together,
//!
//! `ρ_i = Σ_j m_j W(r_ij, h_i)` (j = i included) and `ρ_i = m_i (η/h_i)^d`,
//!
//! i.e. Eq. 6.1 (`h_i = η (m_i/ρ_i)^{1/d}`, η the scene's `n`) holding exactly with the density
//! summed at the same h (Springel & Hernquist, *Cosmological smoothed particle hydrodynamics
//! simulations: the entropy equation*, MNRAS 333 (2002) 649–664; Price, *Smoothed particle
//! hydrodynamics and magnetohydrodynamics*, J. Comput. Phys. 231 (2012) 759–794;
//! SpringelHernquist2002 and Price2012 in `docs/references.md`), here with h the support
//! radius. Then
//!
//! `Ω_i = 1 − (∂h_i/∂ρ_i) Σ_j m_j ∂W(r_ij, h_i)/∂h_i = 1 + h_i/(d ρ_i) Σ_j m_j ∂W(r_ij, h_i)/∂h_i`
//!
//! (with `∂h/∂ρ = −h/(dρ)`), which the pressure and viscous forces divide
//! the owner's factor by ([`GradHFactor`]).
//!
//! Per particle, `f(h) = Σ_j m_j W(r_ij, h) − m_i (η/h)^d` is solved by Newton–Raphson
//! (`f'(h) = Σ_j m_j ∂W/∂h + d m_i η^d / h^{d+1}`) inside a bracket kept by the sign of f,
//! with a bisection step whenever Newton would leave it, until `|f| ≤ tol · m_i (η/h)^d`.
//! The candidates are the neighbour lists of this step, built at the current positions with
//! radius `h_i (1 + skin)`: h can grow by at most the skin in one step (a solution beyond is
//! clamped there and counted in [`GradHStats`]), and the lists are marked for rebuild after
//! every solve. Each particle is solved from its own candidates, so the result does not
//! depend on the number of threads.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::kernels::Kernel;
use dualsph_core::neighbours::Neighbours;
use dualsph_fluid::prelude::*;
use rayon::prelude::*;

/// The solve's settings (a resource).
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct GradHSettings {
    /// η: `h = η (m/ρ)^{1/d}`.
    pub eta: Real,
    /// Relative density residual at which the iteration stops.
    pub tolerance: Real,
    /// Iterations before the solve gives up (the last iterate is kept and counted).
    pub max_iterations: u32,
}

/// What the last solve did, over all particles.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct GradHStats {
    /// The most iterations one particle took.
    pub max_iterations: u32,
    /// Particles whose solution lay beyond the reach of their lists (h kept at the reach).
    pub clamped: u64,
    /// Particles not converged within the iteration limit.
    pub unconverged: u64,
}

/// One particle's solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solution {
    /// `h_i`.
    pub h: Real,
    /// `ρ_i = Σ_j m_j W(r_ij, h_i)`.
    pub rho: Real,
    /// `Ω_i`.
    pub omega: Real,
    /// Iterations taken.
    pub iterations: u32,
    /// True when h was kept at the reach of the lists.
    pub clamped: bool,
    /// True when the residual met the tolerance.
    pub converged: bool,
}

/// `(Σ m_j W, Σ m_j ∂W/∂h)` at `h` over `(r_ij, m_j)` (the particle itself at r = 0 included).
fn sums(kernel: &Kernel, pairs: &[(Real, Real)], h: Real) -> (Real, Real) {
    pairs.iter().fold((0.0, 0.0), |(w, dw), &(r, m)| {
        (w + m * kernel.w(r, h), dw + m * kernel.dw_dh(r, h))
    })
}

/// Solves one particle of mass `m` from `h0` with its `(r_ij, m_j)` (itself included), h at
/// most `reach` (see the module docs).
pub fn solve(
    kernel: &Kernel,
    pairs: &[(Real, Real)],
    (m, h0, reach): (Real, Real, Real),
    settings: &GradHSettings,
) -> Solution {
    let d = kernel.dim as i32;
    let eta_d = settings.eta.powi(d);
    let target = |h: Real| m * eta_d / h.powi(d);
    let f = |h: Real| {
        let (w, dw) = sums(kernel, pairs, h);
        (w - target(h), dw + d as Real * target(h) / h, w, dw)
    };
    // bracket: f < 0 where the support holds the particle alone, f > 0 at the reach (else
    // the solution lies beyond it)
    let (mut lo, mut hi) = (reach * 1e-3, reach);
    let (f_hi, ..) = f(hi);
    let finish = |h: Real, iterations, clamped, converged| {
        let (_, _, rho, dw) = f(h);
        let omega = 1.0 + h / (d as Real * rho) * dw;
        Solution {
            h,
            rho,
            omega,
            iterations,
            clamped,
            converged,
        }
    };
    if f_hi < 0.0 {
        return finish(reach, 0, true, false);
    }
    let mut h = h0.clamp(lo, hi);
    for it in 1..=settings.max_iterations {
        let (fh, dfh, ..) = f(h);
        if fh.abs() <= settings.tolerance * target(h) {
            return finish(h, it, false, true);
        }
        if fh < 0.0 {
            lo = h;
        } else {
            hi = h;
        }
        let newton = h - fh / dfh;
        h = if dfh > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    finish(h, settings.max_iterations, false, false)
}

/// The grad-h step (in `Density`): every particle's h, ρ and Ω solved (module docs).
#[inline(never)] // a frame of its own in profiles
pub fn grad_h<V: Vector>(
    settings: Res<GradHSettings>,
    kernel: Res<KernelRes>,
    mut stats: ResMut<GradHStats>,
    mut nb: ResMut<Neighbours<V>>,
    mut q: Query<(
        &Position<V>,
        &Mass,
        &mut SmoothingLength,
        &mut Density,
        &mut GradHFactor,
    )>,
) {
    let rows: Vec<_> = q.iter().map(|(r, m, h, ..)| (r.0, m.0, h.0)).collect();
    let (k, s, skin) = (&kernel.0, &*settings, nb.skin);
    let nb_ref = &*nb;
    let solved: Vec<Solution> = (0..rows.len())
        .into_par_iter()
        .with_min_len(256)
        .map_init(Vec::new, |pairs, i| {
            let (xi, mi, hi) = rows[i];
            pairs.clear();
            pairs.push((0.0, mi));
            for &j in nb_ref.support.row(i) {
                let (xj, mj, _) = rows[j as usize];
                pairs.push((nb_ref.separation(xi, xj).length(), mj));
            }
            solve(k, pairs, (mi, hi, hi * (1.0 + skin)), s)
        })
        .collect();
    let mut st = GradHStats::default();
    for ((_, _, mut h, mut rho, mut omega), x) in q.iter_mut().zip(&solved) {
        (h.0, rho.0, omega.0) = (x.h, x.rho, x.omega);
        st.max_iterations = st.max_iterations.max(x.iterations);
        st.clamped += x.clamped as u64;
        st.unconverged += !(x.converged || x.clamped) as u64;
    }
    *stats = st;
    nb.dirty = true;
}

#[cfg(test)]
mod tests {
    use super::*;

    const SETTINGS: GradHSettings = GradHSettings {
        eta: 2.0,
        tolerance: 1e-12,
        max_iterations: 50,
    };

    /// A uniform 1-D lattice of spacing `dx` and unit density: the neighbours of the particle
    /// at 0 within 3 spacings of η.
    fn lattice_1d(dx: Real) -> Vec<(Real, Real)> {
        let mut pairs = vec![(0.0, dx)];
        for k in 1..=8 {
            let r = k as Real * dx;
            pairs.extend([(r, dx), (r, dx)]);
        }
        pairs
    }

    #[test]
    fn a_uniform_lattice_gives_its_density_and_h_equal_to_eta_spacings() {
        let kernel = Kernel::new(KernelKind::CubicSpline, 1);
        let dx = 0.01;
        let pairs = lattice_1d(dx);
        // start 20 % off; the answer is near h = η Δx with ρ near 1
        let s = solve(&kernel, &pairs, (dx, 0.8 * 2.0 * dx, 4.0 * dx), &SETTINGS);
        assert!(s.converged && !s.clamped, "{s:?}");
        // ρ = m (η/h)^d holds to the tolerance
        let residual = s.rho / (dx * SETTINGS.eta / s.h) - 1.0;
        assert!(residual.abs() < 1e-11, "{s:?}: residual {residual:e}");
        // the lattice sum of the cubic spline at h = 2Δx is exactly 1 (the spline's partition
        // of unity on a lattice of spacing h/2), so the solution is h = 2Δx, ρ = 1
        assert!((s.h / (2.0 * dx) - 1.0).abs() < 1e-9, "h = {}", s.h);
        assert!((s.rho - 1.0).abs() < 1e-9, "ρ = {}", s.rho);
        assert!(s.iterations <= 8, "{} iterations", s.iterations);
    }

    #[test]
    fn omega_is_one_plus_h_over_d_rho_times_the_h_derivative_of_the_sum() {
        let kernel = Kernel::new(KernelKind::CubicSpline, 1);
        let dx = 0.013;
        let mut pairs = lattice_1d(dx);
        pairs[3].0 *= 1.1; // an irregular neighbourhood
        let s = solve(&kernel, &pairs, (dx, 2.0 * dx, 4.0 * dx), &SETTINGS);
        // ∂ρ_sum/∂h by central differences, independently of dw_dh
        let e = 1e-6 * s.h;
        let rho_at = |h: Real| pairs.iter().map(|&(r, m)| m * kernel.w(r, h)).sum::<Real>();
        let drho_dh = (rho_at(s.h + e) - rho_at(s.h - e)) / (2.0 * e);
        let omega = 1.0 + s.h / s.rho * drho_dh;
        assert!((s.omega - omega).abs() < 1e-7, "Ω {} vs {omega}", s.omega);
    }

    #[test]
    fn a_solution_beyond_the_reach_is_clamped_and_said() {
        let kernel = Kernel::new(KernelKind::CubicSpline, 2);
        // a lone particle: no h makes its own kernel reach m (η/h)²
        let s = solve(&kernel, &[(0.0, 1.0)], (1.0, 1.0, 1.15), &SETTINGS);
        assert!(s.clamped && !s.converged && s.h == 1.15, "{s:?}");
    }
}
