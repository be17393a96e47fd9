//! Field sampling at arbitrary points: the SPH interpolant of R. E. Fry, *FLUISIM:
//! Smoothed Particle Hydrodynamics*, notes, 2025 ("FLUISIM" below), evaluated
//! with each particle's **own** kernel and support radius.
//!
//! For a point x, its support is the set of particles whose support reaches it,
//! `S(x) = { j : |x − x_j| < h_j }` — the dual-support view of a point (Ren, Dai, Zhuang & Rabczuk, *Dual-support SPH*, Eq. 3.2):
//! x is "in the support" of j. It is found with a kiddo k-d tree queried with the largest
//! radius `h_max`, then filtered by each particle's own `h_j`, and summed in ascending j, so a
//! result never depends on the thread count. With `V_j = m_j/ρ_j` and
//! `W_j = W(x − x_j, h_j)` (Def. 2.3, normalised over the shell, see [`dualsph_math::kernels`]):
//!
//! * plain interpolant (FLUISIM Def. 3.1, Eq. 3): `A(x) = Σ_j A_j V_j W_j`;
//!   with `A_j = ρ_j` this is the density of Thm. 3.2, `ρ(x) = Σ_j m_j W_j`;
//! * Shepard sum `σ(x) = Σ_j V_j W_j` (≈ 1 inside the fluid, → 0 outside: a free-surface
//!   indicator) and the Shepard-normalised interpolant `A_S(x) = Σ_j A_j V_j W_j / σ(x)`,
//!   exact for constant fields;
//! * plain gradient (FLUISIM Thm. 3.3, Eq. 5): `∇A(x) = Σ_j A_j V_j ∇W_j`, with
//!   `∇W_j = ∂W/∂r (x − x_j)/|x − x_j|` (Thm. 2.4);
//! * first-order consistent value `A_1(x)`: the weighted least-squares fit
//!   `min_{a,g} Σ_j V_j W_j (A_j − a − g·(x_j − x))²`, `A_1 = a` (a moving-least-squares
//!   interpolant with the SPH weights), exact for linear fields;
//! * corrected gradient, the difference form with the kernel-gradient correction of Ren, Dai, Zhuang & Rabczuk
//!   Eq. 2.10 evaluated at x: `∇̃A(x) = L(x) Σ_j (A_j − A_1(x)) V_j ∇W_j`,
//!   `L(x) = [Σ_j V_j ∇W_j ⊗ (x_j − x)]^{-1}`, exact for linear fields.
//!
//! For a smooth field the consistent forms converge as `O(h²)` (value) and `O(h)` (gradient)
//! on irregular particle clouds with `h/Δx` fixed; the tests measure these orders.

use crate::KdTree;
use dualsph_math::kernels::Kernel;
use dualsph_math::{Matrix, Real, Vector};
use rayon::prelude::*;

/// Everything sampled for one quantity at one point (see the module docs for the formulas).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample<V: Vector> {
    /// Plain interpolant `Σ A_j V_j W_j` (FLUISIM Def. 3.1).
    pub value: Real,
    /// Shepard sum `σ = Σ V_j W_j`.
    pub shepard_sum: Real,
    /// Shepard-normalised value `Σ A_j V_j W_j / σ`; `None` where no particle reaches x.
    pub shepard: Option<Real>,
    /// Plain gradient `Σ A_j V_j ∇W_j` (FLUISIM Thm. 3.3).
    pub gradient: V,
    /// First-order consistent value (weighted least squares); `None` where the support is
    /// too small or degenerate to fit a linear function.
    pub linear: Option<Real>,
    /// Corrected gradient `L(x) Σ (A_j − A_1(x)) V_j ∇W_j`; `None` as for `linear` or where
    /// `L(x)` is singular.
    pub gradient_corrected: Option<V>,
}

/// A frozen particle configuration that can be sampled at any point.
pub struct SamplingCloud<V: Vector> {
    kernel: Kernel,
    pos: Vec<V>,
    volume: Vec<Real>,
    h: Vec<Real>,
    h_max: Real,
    tree: KdTree,
}

impl<V: Vector> std::fmt::Debug for SamplingCloud<V> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SamplingCloud")
            .field("kernel", &self.kernel)
            .field("particles", &self.pos.len())
            .field("h_max", &self.h_max)
            .finish()
    }
}

impl<V: Vector> SamplingCloud<V> {
    /// A cloud from positions, volumes `V_j = m_j/ρ_j` and support radii `h_j` (same length).
    ///
    /// # Panics
    /// If the three slices differ in length (a programming error).
    pub fn new(kernel: Kernel, pos: Vec<V>, volume: Vec<Real>, h: Vec<Real>) -> Self {
        assert!(
            pos.len() == volume.len() && pos.len() == h.len(),
            "SamplingCloud::new: {} positions, {} volumes, {} radii",
            pos.len(),
            volume.len(),
            h.len()
        );
        let h_max = h
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(0.0, Real::max);
        let tree = KdTree::new(&pos);
        SamplingCloud {
            kernel,
            pos,
            volume,
            h,
            h_max,
            tree,
        }
    }

    /// A cloud from positions, masses, densities and support radii (`V_j = m_j/ρ_j`).
    pub fn from_particles(
        kernel: Kernel,
        pos: Vec<V>,
        mass: &[Real],
        rho: &[Real],
        h: Vec<Real>,
    ) -> Self {
        let volume = mass.iter().zip(rho).map(|(m, r)| m / r).collect();
        Self::new(kernel, pos, volume, h)
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True if there are no particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// The largest support radius (the tree's query radius).
    pub fn h_max(&self) -> Real {
        self.h_max
    }

    /// The support of the point x, `{ j : |x − x_j| < h_j }`, ascending.
    pub fn support(&self, x: V) -> Vec<u32> {
        if self.pos.is_empty() {
            return Vec::new();
        }
        let mut s = Vec::new();
        self.tree.for_each_within(x, self.h_max, |j| {
            let k = j as usize;
            if (x - self.pos[k]).length_squared() < self.h[k] * self.h[k] {
                s.push(j);
            }
        });
        s.sort_unstable();
        s
    }

    /// The Shepard sum `σ(x) = Σ_j V_j W(x − x_j, h_j)`.
    pub fn shepard_sum(&self, x: V) -> Real {
        self.support(x)
            .into_iter()
            .map(|j| {
                let j = j as usize;
                self.volume[j] * self.kernel.w((x - self.pos[j]).length(), self.h[j])
            })
            .sum()
    }

    /// Samples quantity `a` (one value per particle) at x.
    ///
    /// # Panics
    /// If `a` has fewer entries than the cloud has particles.
    pub fn sample(&self, x: V, a: &[Real]) -> Sample<V> {
        assert!(a.len() >= self.pos.len(), "one value per particle needed");
        let support = self.support(x);
        let d = V::DIM;
        let scale = self.h_max.max(Real::MIN_POSITIVE);
        let (mut value, mut sigma, mut gradient) = (0.0, 0.0, V::zero());
        // weighted least squares in scaled offsets s_j = (x_j − x)/h_max: M c = b
        let mut m = [[0.0; 4]; 4];
        let mut b = [0.0; 4];
        let mut l = V::Mat::zero();
        for &j in &support {
            let j = j as usize;
            let rel = x - self.pos[j];
            let r = rel.length();
            let vw = self.volume[j] * self.kernel.w(r, self.h[j]);
            let vg = self.kernel.grad(rel, r, self.h[j]) * self.volume[j];
            value += a[j] * vw;
            sigma += vw;
            gradient += vg * a[j];
            l += V::outer(vg, -rel);
            let mut p = [1.0, 0.0, 0.0, 0.0];
            for k in 0..d {
                p[k + 1] = -rel.get(k) / scale;
            }
            for r_ in 0..=d {
                b[r_] += vw * p[r_] * a[j];
                for c in 0..=d {
                    m[r_][c] += vw * p[r_] * p[c];
                }
            }
        }
        let shepard = (sigma > 0.0).then(|| value / sigma);
        let linear = solve(m, b, d + 1).map(|c| c[0]);
        let gradient_corrected = match (linear, l.try_inverse(1e-6)) {
            (Some(a1), Some(l_inv)) => {
                let mut s = V::zero();
                for &j in &support {
                    let j = j as usize;
                    let rel = x - self.pos[j];
                    let g = self.kernel.grad(rel, rel.length(), self.h[j]);
                    s += g * ((a[j] - a1) * self.volume[j]);
                }
                Some(l_inv.mul_vec(s))
            }
            _ => None,
        };
        Sample {
            value,
            shepard_sum: sigma,
            shepard,
            gradient,
            linear,
            gradient_corrected,
        }
    }

    /// Samples `a` at every point, in parallel; the result is independent of the thread count
    /// (each point is summed on its own, in ascending particle order).
    pub fn sample_many(&self, points: &[V], a: &[Real]) -> Vec<Sample<V>> {
        points.par_iter().map(|&x| self.sample(x, a)).collect()
    }

    /// Shepard sums at every point, in parallel (deterministic as [`Self::sample_many`]).
    pub fn shepard_sums(&self, points: &[V]) -> Vec<Real> {
        points.par_iter().map(|&x| self.shepard_sum(x)).collect()
    }
}

/// Solves the n × n system (n ≤ 4) by Gaussian elimination with partial pivoting; `None` when
/// a pivot is below 1e-10 of the largest diagonal entry (singular or too few neighbours).
fn solve(mut m: [[Real; 4]; 4], mut b: [Real; 4], n: usize) -> Option<[Real; 4]> {
    let big = (0..n).map(|k| m[k][k].abs()).fold(0.0, Real::max);
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    for col in 0..n {
        let piv = (col..n).max_by(|&p, &q| m[p][col].abs().total_cmp(&m[q][col].abs()))?;
        if m[piv][col].abs() < 1e-10 * big {
            return None;
        }
        m.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..n {
            let f = m[row][col] / m[col][col];
            for c in col..n {
                m[row][c] -= f * m[col][c];
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 4];
    for row in (0..n).rev() {
        let s: Real = (row + 1..n).map(|c| m[row][c] * x[c]).sum();
        x[row] = (b[row] - s) / m[row][row];
    }
    Some(x)
}

#[cfg(test)]
#[path = "sampling_tests.rs"]
mod tests;
