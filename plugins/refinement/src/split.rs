//! The arithmetic of a split and of a merge: pure functions of the particles' core state.
//!
//! **Split** (Feldman & Bonet 2007, *Dynamic refinement and boundary contact forces in SPH
//! with applications in fluid flow problems*, Int. J. Numer. Meth. Engng 72, 295, §3; the
//! square pattern of their Fig. 2, a cube in 3-D): a parent of mass `m`, density `ρ`,
//! support radius `h` and size `Δx = (m/ρ)^{1/d}` becomes `N = 2^d` children at the corners
//! of a cube of side `2εΔx` centred on it,
//!
//! `x_c = x + εΔx s_c` (`s_c ∈ {−1, 1}^d`), `m_c = m/N`, `v_c = v`, `ρ_c = ρ`, `h_c = α h`.
//!
//! A split along the first `j < d` axes only (`N = 2^j` children, `s_c ∈ {−1, 1}^j × {0}`)
//! takes a particle that a merge left between two sizes of the `2^{-k}` ladder to the next
//! size down: the children's size is `Δx_c = 2^{-j/d} Δx`, their offset `2εΔx_c` along each
//! split axis (the full split's `εΔx`), their radius `α^{j/d} h`.
//!
//! What it conserves: `Σ m_c = m`; `Σ m_c v_c = m v`; `Σ m_c x_c = m x` (the pattern is
//! symmetric), so the angular momentum `Σ m_c x_c × v_c = (Σ m_c x_c) × v = m x × v`; the
//! kinetic energy `Σ ½ m_c v² = ½ m v²`; a uniform body force's potential `Σ m_c g·x_c`;
//! and, with the specific internal energy copied, `Σ m_c ε = m ε` — all exactly in
//! arithmetic, to round-off in floating point (`m/N` is exact: N is a power of two).
//! The children's size is `Δx/2` in every dimension, so `α = 1/2` is the smoothing length
//! Eq. 6.1 of RenDSSPH (`h = n (m/ρ)^{1/d}`) gives them: the h-update finds nothing to
//! change. `ε` and `α` set how far the children's summed density departs from the parent's
//! ([`crate::density_error`]).
//!
//! **Merge** (Vacondio, Rogers, Stansby, Mignosa & Feldman 2013, *Variable resolution for
//! SPH: a dynamic particle coalescing and splitting scheme*, Comput. Methods Appl. Mech.
//! Engrg. 256, 132, §3.2): particles a and b become one of mass `M = m_a + m_b` at their
//! centre of mass with their mean momentum,
//!
//! `x = (m_a x_a + m_b x_b)/M`, `v = (m_a v_a + m_b v_b)/M`,
//! `ρ = M/(m_a/ρ_a + m_b/ρ_b)` (the volume is kept), `h = (h_a^d + h_b^d)^{1/d}`,
//!
//! which keeps the mass, the momentum and the centre of mass (so the potential of a uniform
//! body force) exactly; it removes the kinetic energy of the relative motion and the
//! angular momentum about the pair's centre of mass ([`Merge::removed_kinetic_energy`],
//! [`Merge::removed_angular_momentum`]), which the plugin reports and, where the particles
//! carry an internal energy, turns into heat.

use dualsph_core::math::{Real, Vector};
use dualsph_core::population::CoreState;
use glam::DVec3;

/// The `2^j` sign vectors `s_c ∈ {−1, 1}^j × {0}^{d−j}` of the children of a split along
/// the first `j` axes, the first axis fastest.
pub fn signs<V: Vector>(j: usize) -> Vec<V> {
    (0..1usize << j)
        .map(|c| {
            let mut s = V::zero();
            for k in 0..j {
                s.set(k, if c >> k & 1 == 1 { 1.0 } else { -1.0 });
            }
            s
        })
        .collect()
}

/// A particle's size `Δx = (m/ρ)^{1/d}` ([`dualsph_core::math::particle_size`]).
pub fn size(dim: usize, mass: Real, density: Real) -> Real {
    dualsph_core::math::particle_size(dim, mass, density)
}

/// The children of a split of `parent` along its first `axes` axes (module docs): offset
/// `epsilon` (in units of the parent's size, for a split along every axis), support radii
/// `alpha^{axes/d} h`.
pub fn children<V: Vector>(
    parent: &CoreState<V>,
    axes: usize,
    epsilon: Real,
    alpha: Real,
) -> Vec<CoreState<V>> {
    let j = axes.clamp(1, V::DIM);
    let signs = signs::<V>(j);
    let n = signs.len() as Real;
    let shrink = (j as Real) / V::DIM as Real;
    let child_size = size(V::DIM, parent.mass, parent.density) * libm::pow(0.5 as Real, shrink);
    let step = 2.0 * epsilon * child_size;
    let h = libm::pow(alpha, shrink) * parent.h;
    signs
        .into_iter()
        .map(|s| CoreState {
            pos: parent.pos + s * step,
            vel: parent.vel,
            mass: parent.mass / n,
            density: parent.density,
            h,
        })
        .collect()
}

/// A merge of two particles (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Merge<V: Vector> {
    /// The merged particle.
    pub state: CoreState<V>,
    /// The kinetic energy of the pair's relative motion, `½ (m_a m_b / M) |v_a − v_b|²`.
    pub removed_kinetic_energy: Real,
    /// The angular momentum about the pair's centre of mass,
    /// `(m_a m_b / M) (x_a − x_b) × (v_a − v_b)` (3-D embedding).
    pub removed_angular_momentum: DVec3,
}

/// Merges `a` and `b` (module docs).
pub fn merge<V: Vector>(a: &CoreState<V>, b: &CoreState<V>) -> Merge<V> {
    let m = a.mass + b.mass;
    let (wa, wb) = (a.mass / m, b.mass / m);
    let d = V::DIM as i32;
    let reduced = a.mass * b.mass / m;
    let dv = a.vel - b.vel;
    let dx = DVec3::from_array((a.pos - b.pos).to_xyz());
    Merge {
        state: CoreState {
            pos: a.pos * wa + b.pos * wb,
            vel: a.vel * wa + b.vel * wb,
            mass: m,
            density: m / (a.mass / a.density + b.mass / b.density),
            h: libm::pow(a.h.powi(d) + b.h.powi(d), 1.0 / d as Real),
        },
        removed_kinetic_energy: 0.5 * reduced * dv.length_squared(),
        removed_angular_momentum: dx.cross(DVec3::from_array(dv.to_xyz())) * reduced,
    }
}
