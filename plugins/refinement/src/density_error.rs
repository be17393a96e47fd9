//! How far a split moves the density, two ways.
//!
//! **As DS-SPH sums it** ([`split_gather_error`]): the summation density of RenDSSPH Eq. 4.8
//! gathers over each particle's own support, `ρ_i = Σ_j m_j W(r_ij, h_i)`. On a square
//! lattice of particles of size Δx and radius `h = h_factor Δx` (every particle within
//! `h_factor + 2` sizes of the centre), one particle splits; the error is the largest
//! relative change of any particle's summed density (a child's against its parent's before
//! the split). A neighbour's sum uses its own radius, so it depends on the offset ε alone
//! and is second order in it; a child's sum uses `αh`.
//!
//! **As Feldman & Bonet (2007) measure it** ([`split_density_error`]): the error they minimise
//! to choose a pattern (Int. J. Numer. Meth. Engng 72, 295, Eq. 20), the integral over space
//! of the squared difference between the parent's and the children's contributions to a
//! density field in which each particle spreads with its own radius (the scatter form),
//! here relative to the parent's own:
//!
//! `e(ε, α) = ( ∫ (m W(|x − x_p|, h) − Σ_c m_c W(|x − x_c|, α h))² dx / ∫ (m W(|x − x_p|, h))² dx )^{1/2}`
//!
//! with the children of [`crate::split::children`]. Both depend on the kernel, the dimension,
//! the support in units of the particle size (`h/Δx`, the scene's `h_factor`), the offset ε
//! and the children's radius ratio α. The integral is a midpoint sum on a grid of `cells`
//! per support radius and axis over the cube that holds every support.
//!
//! With α = 1/2 (the radius Eq. 6.1 gives the children) the scatter error is large, as the
//! children's narrow kernels concentrate the density at four points, while the gathered
//! densities, which DS-SPH's equations use, change by a few per cent (`docs/refinement.md`
//! lists both, and why the default offset is the lattice's rather than the one of least
//! gather error).

use crate::split::children;
use dualsph_core::kernels::{Kernel, KernelKind};
use dualsph_core::math::{Real, Vector};
use dualsph_core::population::CoreState;

/// `e(ε, α)` (module docs) for a parent of support `h_factor` sizes, in dimension `V::DIM`.
pub fn split_density_error<V: Vector>(
    kind: KernelKind,
    h_factor: Real,
    epsilon: Real,
    alpha: Real,
    cells: usize,
) -> Real {
    let kernel = Kernel::new(kind, V::DIM);
    let parent = CoreState {
        pos: V::zero(),
        vel: V::zero(),
        mass: 1.0,
        density: 1.0,
        h: h_factor,
    };
    let kids = children(&parent, V::DIM, epsilon, alpha);
    // every support lies within the parent's, or the farthest child's
    let reach = (epsilon * (V::DIM as Real).sqrt() + alpha * h_factor).max(h_factor);
    let n = (cells as Real * reach / h_factor).ceil() as usize;
    let step = 2.0 * reach / n as Real;
    let (mut diff, mut own) = (0.0, 0.0);
    let points = n.pow(V::DIM as u32);
    for flat in 0..points {
        let mut x = V::zero();
        let mut rest = flat;
        for k in 0..V::DIM {
            x.set(k, -reach + step * ((rest % n) as Real + 0.5));
            rest /= n;
        }
        let p = kernel.w(x.length(), parent.h);
        let c: Real = kids
            .iter()
            .map(|k| k.mass * kernel.w((x - k.pos).length(), k.h))
            .sum();
        diff += (p - c) * (p - c);
        own += p * p;
    }
    (diff / own).sqrt()
}

/// The summation density of every particle of `pts` (mass, radius) at its own radius.
fn gathered<V: Vector>(kernel: &Kernel, pts: &[(V, Real, Real)]) -> Vec<Real> {
    pts.iter()
        .map(|&(xi, _, hi)| {
            pts.iter()
                .map(|&(xj, mj, _)| mj * kernel.w((xi - xj).length(), hi))
                .sum()
        })
        .collect()
}

/// The gather error of a split (module docs): the largest `|ρ_after/ρ_before − 1|` over the
/// lattice, a child compared with its parent, when the one particle at the centre splits.
pub fn split_gather_error<V: Vector>(
    kind: KernelKind,
    h_factor: Real,
    epsilon: Real,
    alpha: Real,
) -> Real {
    gather_error::<V>(kind, h_factor, (epsilon, alpha), |x| x.length() == 0.0)
}

/// The gather error at a refinement front: every particle of the lattice with `x < 0` (the
/// first axis) splits, those at `x ≥ 0` stay.
pub fn front_gather_error<V: Vector>(
    kind: KernelKind,
    h_factor: Real,
    epsilon: Real,
    alpha: Real,
) -> Real {
    gather_error::<V>(kind, h_factor, (epsilon, alpha), |x| x.get(0) < 0.0)
}

/// The largest `|ρ_after/ρ_before − 1|` over the particles of a unit lattice whose support
/// lies in it, when the particles at the sites where `splits` holds split with `(ε, α)`.
fn gather_error<V: Vector>(
    kind: KernelKind,
    h_factor: Real,
    (epsilon, alpha): (Real, Real),
    splits: impl Fn(V) -> bool,
) -> Real {
    let kernel = Kernel::new(kind, V::DIM);
    let k = h_factor.ceil() as i64 + 2;
    let side = (2 * k + 1) as usize;
    let lattice: Vec<(V, Real, Real)> = (0..side.pow(V::DIM as u32))
        .map(|flat| {
            let mut x = V::zero();
            let mut rest = flat;
            for a in 0..V::DIM {
                x.set(a, (rest % side) as Real - k as Real);
                rest /= side;
            }
            (x, 1.0, h_factor)
        })
        .collect();
    let before = gathered(&kernel, &lattice);
    let (mut after_pts, mut reference) = (Vec::new(), Vec::new());
    for (&(x, m, h), &rho) in lattice.iter().zip(&before) {
        if splits(x) {
            let parent = CoreState {
                pos: x,
                vel: V::zero(),
                mass: m,
                density: 1.0,
                h,
            };
            for c in children(&parent, V::DIM, epsilon, alpha) {
                after_pts.push((c.pos, c.mass, c.h));
                reference.push(rho);
            }
        } else {
            after_pts.push((x, m, h));
            reference.push(rho);
        }
    }
    let after = gathered(&kernel, &after_pts);
    // the lattice's outer rows see a truncated support: compare only the particles whose
    // support lies inside it
    after
        .iter()
        .zip(&reference)
        .zip(&after_pts)
        .filter(|(_, (x, _, h))| (0..V::DIM).all(|a| x.get(a).abs() + h <= k as Real + 0.5))
        .map(|((a, b), _)| (a / b - 1.0).abs())
        .fold(0.0, Real::max)
}
