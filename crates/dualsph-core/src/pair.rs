//! The pair-term contract: what a term sees — the particles' core columns
//! ([`ParticleData`]), one pair ([`Pair`]) or one owner's whole support ([`Row`]) — what it
//! returns ([`PairOut`]), the [`PairTerm`] trait with its per-sweep binding to the columns it
//! reads ([`BoundTerm`]), and the owner's precomputed kernel ([`OwnerKernel`]). The sweep
//! itself is in [`crate::sweep`], which re-exports everything here.

use crate::kernels::{Kernel, KernelKind};
use crate::lanes::Lanes;
use crate::math::{Real, Vector};
pub use crate::store::ParticleData;
use bevy_ecs::prelude::*;
use std::sync::Arc;

/// One evaluation of a pair: `owner` is the particle whose kernel and support are used.
#[derive(Clone, Copy, Debug)]
pub struct Pair<'a, V: Vector> {
    /// The owner i (kernel `W(·, h_i)`).
    pub i: usize,
    /// The neighbour j ∈ H_i.
    pub j: usize,
    /// `r_ij = r_i − r_j`.
    pub rij: V,
    /// `|r_ij|`.
    pub r: Real,
    /// `W_ij`.
    pub w: Real,
    /// `∇_i W_ij` as is.
    pub grad_raw: V,
    /// `∇_i W_ij`, with the kernel-gradient correction `L_i` applied when it is active.
    pub grad: V,
    /// The particles' core columns.
    pub data: &'a ParticleData<'a, V>,
}

impl<V: Vector> Pair<'_, V> {
    /// `v_ij = v_i − v_j`.
    #[inline]
    pub fn vij(&self) -> V {
        self.data.vij(self.i, self.j)
    }
}

/// What one term gives for one pair: the force on the owner i (j receives `−force`) and the
/// rates of internal energy `m ε̇` credited to i and to j. A term conserves energy when
/// `power_i + power_j = −force · v_ij` (the pair's work goes into heat, nothing is lost).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairOut<V: Vector> {
    /// Force on i; the reaction `−force` acts on j.
    pub force: V,
    /// `m_i dε_i/dt` contribution.
    pub power_i: Real,
    /// `m_j dε_j/dt` contribution.
    pub power_j: Real,
}

impl<V: Vector> Default for PairOut<V> {
    fn default() -> Self {
        PairOut {
            force: V::zero(),
            power_i: 0.0,
            power_j: 0.0,
        }
    }
}

/// One owner's support `H_i` as the sweep hands it to [`BoundTerm::interact_row`]: the
/// neighbours `j` strictly inside `h_i`, ascending, with the pair geometry as parallel slices
/// (`rij[k]`, `r[k]`, `grad_raw[k]`, `grad[k]` belong to `j[k]`).
#[derive(Clone, Copy, Debug)]
pub struct Row<'a, V: Vector> {
    /// The owner i.
    pub i: usize,
    /// `j ∈ H_i`, ascending.
    pub j: &'a [u32],
    /// `r_ij = r_i − r_j`.
    pub rij: &'a [V],
    /// `|r_ij|`.
    pub r: &'a [Real],
    /// `v_ij = v_i − v_j` (formed once per row for every term).
    pub vij: &'a [V],
    /// `∇_i W_ij` as is (Eq. 2.2).
    pub grad_raw: &'a [V],
    /// `∇_i W_ij` with `L_i` applied when the correction is active (Eq. 2.10); the same slice
    /// as `grad_raw` otherwise.
    pub grad: &'a [V],
    /// The owner's kernel (for `W_ij`, computed on demand by [`Row::w`]).
    pub kernel: OwnerKernel,
    /// The particles' core columns.
    pub data: &'a ParticleData<'a, V>,
}

impl<'a, V: Vector> Row<'a, V> {
    /// Number of pairs.
    #[inline]
    pub fn len(&self) -> usize {
        self.j.len()
    }

    /// True when `H_i` is empty.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.j.is_empty()
    }

    /// `W_ij = W(r_ij, h_i)` of the k-th pair (Eq. 2.1).
    #[inline]
    pub fn w(&self, k: usize) -> Real {
        self.kernel.w(self.r[k])
    }

    /// The k-th pair of the row.
    #[inline]
    pub fn pair(&self, k: usize) -> Pair<'a, V> {
        Pair {
            i: self.i,
            j: self.j[k] as usize,
            rij: self.rij[k],
            r: self.r[k],
            w: self.w(k),
            grad_raw: self.grad_raw[k],
            grad: self.grad[k],
            data: self.data,
        }
    }
}

/// A physics term that joins the pair sweep: for the pair (i owner, j ∈ H_i) it adds the
/// force on i and the energy rates of i and j to a [`PairOut`], and inherits the sweep's
/// conservation (j receives the reaction through its dual-support) and determinism.
///
/// Once per sweep the term is **bound** ([`PairTerm::bind`]) to the columns it reads beyond
/// the core ones of [`ParticleData`] — that is where it declares them, by type
/// (`data.require::<Pressure>(name)`); a column no plugin adds is a build error naming the
/// term. The bound term ([`BoundTerm`]) evaluates pairs. A term that reads no other column
/// can be its own bound term (`type Bound<'w> = Self`, `bind` returns a copy).
pub trait PairTerm<V: Vector>: Send + Sync + 'static {
    /// The term bound to its columns for one sweep.
    type Bound<'w>: BoundTerm<V> + 'w;
    /// Name shown by `plan`.
    fn name(&self) -> &str;
    /// Binds the columns the term reads (once per sweep); the error names what is missing.
    fn bind<'w>(&'w self, data: &ParticleData<'w, V>) -> Result<Self::Bound<'w>, String>;
    /// The built-in term this is, if any: the sweep then may evaluate it in its fused loop
    /// ([`crate::sweep::BuiltinTerm`]), which must give bitwise what `interact` gives.
    fn builtin(&self) -> Option<crate::sweep::BuiltinTerm> {
        None
    }
}

/// A [`PairTerm`] bound to its columns for one sweep.
///
/// Only [`BoundTerm::interact`] must be written. The sweep calls [`BoundTerm::interact_row`]
/// once per owner and term; its default loops over the row calling `interact`, statically
/// dispatched and inlined, so a term costs one dynamic call per particle, not per pair.
/// Override it only to vectorise a term by hand; it must give the same `out` as the default.
pub trait BoundTerm<V: Vector>: Sync {
    /// Adds this term's force and energy rates for the pair.
    fn interact(&self, pair: &Pair<'_, V>, out: &mut PairOut<V>);
    /// Adds this term to `out[k]` for every pair `k` of the row (`out.len() == row.len()`).
    #[inline]
    fn interact_row(&self, row: &Row<'_, V>, out: &mut [PairOut<V>]) {
        for (k, o) in out.iter_mut().enumerate() {
            self.interact(&row.pair(k), o);
        }
    }
}

/// A [`PairTerm`] with its type erased, as the sweep holds it.
pub trait DynPairTerm<V: Vector>: Send + Sync {
    /// See [`PairTerm::name`].
    fn name(&self) -> &str;
    /// See [`PairTerm::builtin`].
    fn builtin(&self) -> Option<crate::sweep::BuiltinTerm>;
    /// See [`PairTerm::bind`].
    fn bind_dyn<'w>(
        &'w self,
        data: &ParticleData<'w, V>,
    ) -> Result<Box<dyn BoundTerm<V> + 'w>, String>;
}

impl<V: Vector, T: PairTerm<V>> DynPairTerm<V> for T {
    fn name(&self) -> &str {
        PairTerm::name(self)
    }
    fn builtin(&self) -> Option<crate::sweep::BuiltinTerm> {
        PairTerm::builtin(self)
    }
    fn bind_dyn<'w>(
        &'w self,
        data: &ParticleData<'w, V>,
    ) -> Result<Box<dyn BoundTerm<V> + 'w>, String> {
        Ok(Box::new(self.bind(data)?))
    }
}

/// The terms fused into the sweep, in order.
#[derive(Resource)]
pub struct PairTerms<V: Vector> {
    /// Terms.
    pub terms: Vec<Arc<dyn DynPairTerm<V>>>,
}

impl<V: Vector> Default for PairTerms<V> {
    fn default() -> Self {
        PairTerms { terms: Vec::new() }
    }
}

impl<V: Vector> PairTerms<V> {
    /// Every term bound to `data`'s columns, in order; the error names the term and the
    /// column it misses.
    pub fn bind<'w>(
        &'w self,
        data: &ParticleData<'w, V>,
    ) -> Result<Vec<Box<dyn BoundTerm<V> + 'w>>, String> {
        self.terms.iter().map(|t| t.bind_dyn(data)).collect()
    }
}

/// The kernel of one owner i with its normalisations computed once:
/// `W(r, h_i) = C_d h_i^{-d} f(r/h_i)` (Eq. 2.1) and `∇_iW = C_d h_i^{-d-1} f'(r/h_i) r_ij/r`
/// (Eq. 2.2) — what [`Kernel::w`] and [`Kernel::grad`] give inside the support (to round-off:
/// `q = r · (1/h_i)`), without their per-call divisions by powers of h.
#[derive(Clone, Copy, Debug)]
pub struct OwnerKernel {
    kind: KernelKind,
    inv_h: Real,
    /// `h_i²`: a candidate is in `H_i` when `r² < h_i²`.
    pub h2: Real,
    w_norm: Real,
    g_norm: Real,
}

impl OwnerKernel {
    /// The kernel of an owner with support radius `h`.
    #[inline]
    pub fn new(kernel: &Kernel, h: Real) -> Self {
        let hd = match kernel.dim {
            1 => h,
            2 => h * h,
            _ => h * h * h,
        };
        OwnerKernel {
            kind: kernel.kind,
            inv_h: 1.0 / h,
            h2: h * h,
            w_norm: kernel.norm / hd,
            g_norm: kernel.norm / (hd * h),
        }
    }

    /// `W(r, h_i)` (Eq. 2.1) for `r < h_i`.
    #[inline(always)]
    pub fn w(&self, r: Real) -> Real {
        self.w_norm * self.kind.profile(r * self.inv_h)
    }

    /// `∇_iW_ij` (Eq. 2.2) for `r = |r_ij| < h_i` (0 at `r = 0`): `r_ij ·` [`Self::grad_factor`].
    #[inline(always)]
    pub fn grad<V: Vector>(&self, rij: V, r: Real) -> V {
        rij * self.grad_factor(r)
    }

    /// `(1/r) ∂W/∂r = C_d h_i^{-d-1} f'(r/h_i) / r` for `r < h_i`, 0 at `r = 0`, so that
    /// `∇_iW_ij = r_ij · grad_factor(r)` (Eq. 2.2).
    #[inline(always)]
    pub fn grad_factor(&self, r: Real) -> Real {
        Self::factor_of(self.kind, self.g_norm, self.inv_h, r)
    }

    #[inline(always)]
    pub(crate) fn factor_of(kind: KernelKind, g_norm: Real, inv_h: Real, r: Real) -> Real {
        Self::factor_lanes(kind, g_norm, inv_h, r)
    }

    /// [`Self::grad_factor`] for one pair or several side by side (see [`Lanes`]), the kind
    /// resolved by the caller: `C_d h_i^{-d-1} f'(r/h_i) / r`, zero at `r = 0`.
    #[inline(always)]
    pub(crate) fn factor_lanes<T: Lanes>(kind: KernelKind, g_norm: Real, inv_h: Real, r: T) -> T {
        let d = T::splat(g_norm) * kind.profile_derivative_lanes(r * T::splat(inv_h)) / r;
        let zero = T::splat(0.0);
        T::if_gt(r, zero, d, zero)
    }

    /// The kernel's kind and the two constants of [`Self::grad_factor`] (`C_d h_i^{-d-1}`,
    /// `1/h_i`), for loops that resolve the kind once.
    #[inline(always)]
    pub(crate) fn factor_parts(&self) -> (KernelKind, Real, Real) {
        (self.kind, self.g_norm, self.inv_h)
    }

    /// `(W_ij, ∇_iW_ij)` for `r = |r_ij| < h_i`.
    #[inline(always)]
    pub fn eval<V: Vector>(&self, rij: V, r: Real) -> (Real, V) {
        (self.w(r), self.grad(rij, r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    #[test]
    fn owner_kernel_matches_kernel_to_round_off() {
        for kind in KernelKind::ALL {
            // The viscosity kernel cannot be normalised in 1-D (scenes refuse it there).
            for dim in (1..=3).filter(|&d| kind.supports_dimension(d)) {
                let kernel = Kernel::new(kind, dim);
                for h in [0.013, 0.7, 2.9] {
                    let k = OwnerKernel::new(&kernel, h);
                    // Müller's viscosity profile −q³/2 + q² + 1/(2q) − 1 cancels to 0 at q = 1, so
                    // near the edge round-off is relative to the kernel's scale C_d/h^d, not to
                    // the tiny value; the other profiles are products of (1 − q) and need no floor.
                    let hd = h.powi(dim as i32);
                    let (w_floor, g_floor) = if kind == KernelKind::MullerViscosity {
                        (kernel.norm / hd, kernel.norm / (hd * h))
                    } else {
                        (1e-300, 0.0)
                    };
                    for i in 0..200 {
                        let r = h * i as Real / 200.0;
                        let (w0, w1) = (kernel.w(r, h), k.w(r));
                        if w0.is_finite() {
                            assert!((w0 - w1).abs() <= 1e-13 * w0.abs().max(w_floor), "{kind:?}");
                        } else {
                            // The viscosity kernel is singular at r = 0: both must say so.
                            assert_eq!(w0, w1, "{kind:?} {dim}D at r = 0");
                        }
                        let x = DVec3::new(0.6, -0.48, 0.64) * r;
                        let (g0, g1) = (kernel.grad(x, r, h), k.grad(x, r));
                        assert!(
                            (g0 - g1).length() <= 1e-13 * g0.length().max(g_floor),
                            "{kind:?} {dim}D"
                        );
                        let y = DVec2::new(0.8, -0.6) * r;
                        assert_eq!(k.eval(y, r).1, k.grad(y, r));
                    }
                }
            }
        }
    }
}
