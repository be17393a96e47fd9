//! What every pass over supports needs ([`SweepCtx`], [`Support`]): the particles' core
//! columns, the lists, the kernel and the formulation, and the walk over a support.

use crate::pair::OwnerKernel;
use bevy_ecs::prelude::Component;
use dualsph_core::components::{Position, SmoothingLength};
use dualsph_core::kernels::Kernel;
use dualsph_core::math::{Matrix, Real, Vector};
use dualsph_core::neighbours::Neighbours;
use dualsph_core::sim::Formulation;
use dualsph_core::store::ParticleData;

/// Kernel-gradient correction matrix `L_i` (Eq. 2.10): when the particles have it, every
/// pass over supports corrects the owner's kernel gradients with it (`L_i ∇_iW_ij`). The
/// correction plugin adds and computes it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct GradientCorrection<V: Vector>(pub V::Mat);

dualsph_core::matrix_column!(GradientCorrection);

/// Everything a pass over neighbours needs.
#[derive(Clone, Copy)]
pub struct SweepCtx<'a, V: Vector> {
    /// The particles' core columns.
    pub data: ParticleData<'a, V>,
    /// The kernel-gradient corrections `L_i` (Eq. 2.10), when the scene computes them.
    pub correction: Option<&'a [GradientCorrection<V>]>,
    /// Lists.
    pub neighbours: &'a Neighbours<V>,
    /// Kernel.
    pub kernel: &'a Kernel,
    /// Formulation.
    pub formulation: Formulation,
}

/// Visits the union of two ascending lists in ascending order.
fn for_each_union(a: &[u32], b: &[u32], mut f: impl FnMut(usize)) {
    let (mut x, mut y) = (0, 0);
    while x < a.len() || y < b.len() {
        let j = match (a.get(x), b.get(y)) {
            (Some(&p), Some(&q)) if p == q => {
                x += 1;
                y += 1;
                p
            }
            (Some(&p), Some(&q)) if p < q => {
                x += 1;
                p
            }
            (Some(_), Some(&q)) => {
                y += 1;
                q
            }
            (Some(&p), None) => {
                x += 1;
                p
            }
            (None, Some(&q)) => {
                y += 1;
                q
            }
            (None, None) => unreachable!(),
        };
        f(j as usize);
    }
}

impl<'a, V: Vector> SweepCtx<'a, V> {
    /// The context of `data`'s particles, with the correction matrices when they have them.
    pub fn new(
        data: ParticleData<'a, V>,
        neighbours: &'a Neighbours<V>,
        kernel: &'a Kernel,
        formulation: Formulation,
    ) -> Self {
        SweepCtx {
            data,
            correction: data.column(),
            neighbours,
            kernel,
            formulation,
        }
    }

    /// Number of particles.
    #[inline]
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// True without particles.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Applies `L_owner` (Eq. 2.10) to a kernel gradient if the correction is active.
    #[inline]
    pub fn corrected(&self, owner: usize, g: V) -> V {
        match self.correction {
            Some(l) => l[owner].0.mul_vec(g),
            None => g,
        }
    }

    /// The support lists and geometry of the particles.
    #[inline]
    pub fn support(&self) -> Support<'a, V> {
        Support {
            pos: self.data.pos,
            h: self.data.h,
            neighbours: self.neighbours,
            kernel: self.kernel,
            formulation: self.formulation,
        }
    }

    /// See [`Support::for_each_neighbour`].
    #[inline]
    pub fn for_each_neighbour(&self, i: usize, f: impl FnMut(usize, V, Real, Real, V)) {
        self.support().for_each_neighbour(i, f)
    }
}

/// What a loop over supports needs: positions, support radii, lists, kernel, formulation
/// (the own-support passes, which write other columns, borrow only these).
#[derive(Clone, Copy)]
pub struct Support<'a, V: Vector> {
    /// Positions.
    pub pos: &'a [Position<V>],
    /// Support radii.
    pub h: &'a [SmoothingLength],
    /// Lists.
    pub neighbours: &'a Neighbours<V>,
    /// Kernel.
    pub kernel: &'a Kernel,
    /// Formulation.
    pub formulation: Formulation,
}

impl<V: Vector> Support<'_, V> {
    /// Visits i's interpolation neighbourhood: `j ∈ H_i` with `W(r, h_i)` and its raw gradient,
    /// or for `AveragedKernel` the union `H_i ∪ H'_i` with the averaged kernel (Eq. 2.13).
    /// Callback: `(j, r_ij, r, W, ∇_iW)`. Used by own-support passes (density, correction,
    /// velocity gradient), which need no reaction.
    #[inline]
    pub fn for_each_neighbour(&self, i: usize, mut f: impl FnMut(usize, V, Real, Real, V)) {
        let (pos, h) = (self.pos, self.h);
        let (xi, hi) = (pos[i].0, h[i].0);
        match self.formulation {
            Formulation::AveragedKernel => for_each_union(
                self.neighbours.support.row(i),
                self.neighbours.dual.row(i),
                |j| {
                    let rij = self.neighbours.separation(xi, pos[j].0);
                    let r = rij.length();
                    let hj = h[j].0;
                    if r < hi.max(hj) {
                        let w = 0.5 * (self.kernel.w(r, hi) + self.kernel.w(r, hj));
                        let g = (self.kernel.grad(rij, r, hi) + self.kernel.grad(rij, r, hj)) * 0.5;
                        f(j, rij, r, w, g);
                    }
                },
            ),
            _ => {
                let row = self.neighbours.support.row(i);
                let k = OwnerKernel::new(self.kernel, hi);
                match &self.neighbours.period {
                    None => own_support(row, |j| xi - pos[j].0, &k, f),
                    Some(p) => own_support(row, |j| p.image(xi - pos[j].0), &k, f),
                }
            }
        }
    }

    /// Visits every j that `keep` accepts within the larger of the two supports,
    /// `|r_ij| < max(h_i, h_j)` (the union of i's support `H_i` and its dual-support), with
    /// `W(r, max(h_i, h_j))`. Callback: `(j, r_ij, W)`. For values extrapolated to a particle
    /// from the particles around it whatever their h (wall particles): a neighbour whose
    /// support is larger than i's own is not missed. `keep` is asked before anything is
    /// computed for j, so the neighbours it refuses cost an index test. The kernel of `h_i` is
    /// built once for the row (and one of `h_j` for a neighbour with a larger support); where
    /// `h_j = h_i` this is i's own support with its own kernel, in the same order and
    /// arithmetic as [`Support::for_each_neighbour`].
    #[inline]
    pub fn for_each_within_either(
        &self,
        i: usize,
        keep: impl Fn(usize) -> bool,
        mut f: impl FnMut(usize, V, Real),
    ) {
        let (xi, hi) = (self.pos[i].0, self.h[i].0);
        let nb = self.neighbours;
        let own = OwnerKernel::new(self.kernel, hi);
        for_each_union(nb.support.row(i), nb.dual.row(i), |j| {
            if !keep(j) {
                return;
            }
            let rij = nb.separation(xi, self.pos[j].0);
            let hj = self.h[j].0;
            let r2 = rij.length_squared();
            if hj <= hi {
                if r2 < own.h2 {
                    f(j, rij, own.w(r2.sqrt()));
                }
            } else if r2 < hj * hj {
                f(j, rij, OwnerKernel::new(self.kernel, hj).w(r2.sqrt()));
            }
        });
    }
}

/// The pairs of a support row with `|r_ij| < h_i`, `rij(j)` their separation, to `f` with
/// the owner kernel's `W` and `∇W` (see [`Support::for_each_neighbour`]).
#[inline(always)]
fn own_support<V: Vector>(
    row: &[u32],
    rij: impl Fn(usize) -> V,
    k: &OwnerKernel,
    mut f: impl FnMut(usize, V, Real, Real, V),
) {
    for &j in row {
        let j = j as usize;
        let rij = rij(j);
        let r2 = rij.length_squared();
        if r2 < k.h2 {
            let r = r2.sqrt();
            let (w, g) = k.eval(rij, r);
            f(j, rij, r, w, g);
        }
    }
}
