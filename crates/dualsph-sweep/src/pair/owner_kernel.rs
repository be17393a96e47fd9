//! The kernel of one owner row, its normalisations computed once per row.

use dualsph_core::kernels::{Kernel, KernelKind};
use dualsph_core::lanes::Lanes;
use dualsph_core::math::{Real, Vector};

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

    /// [`Self::grad_factor`] for one pair or several side by side.
    #[inline(always)]
    pub fn grad_factor_lanes<T: Lanes>(&self, r: T) -> T {
        Self::factor_lanes(self.kind, self.g_norm, self.inv_h, r)
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
