//! The bottom layer of dualsph: dimension-generic vectors and matrices (this module), one or
//! two pairs at once ([`lanes`]) and the kernels ([`kernels`]). It depends on no other crate
//! of the engine.
//!
//! Dimension-generic vectors and matrices: one code base for 1, 2 and 3 dimensions.
//!
//! `Real = f64`. Two and three dimensions use glam's [`DVec2`]/[`DVec3`] and
//! [`DMat2`]/[`DMat3`]; one dimension uses the small [`Vec1`]/[`Mat1`] types below.
//! Everything the engine does with positions goes through the [`Vector`] and
//! [`Matrix`] traits, so a system written once runs in every dimension.

#![warn(missing_docs)]

use glam::{DMat2, DMat3, DVec2, DVec3};
use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

pub mod kernels;
pub mod lanes;

/// The floating-point type of every physical quantity.
pub type Real = f64;

/// The size of a particle of mass `m` and density `ρ` in `dim` dimensions, the side of the
/// cube (square, segment) of its volume: `Δx = (m/ρ)^{1/d}`, the length the smoothing length
/// is a multiple of (Ren, Dai, Zhuang & Rabczuk, *Dual-support smoothed particle
/// hydrodynamics*, Eq. 6.1: `h_i = n (m_i/ρ_i)^{1/d}`).
#[inline]
pub fn particle_size(dim: usize, mass: Real, density: Real) -> Real {
    libm::pow(mass / density, 1.0 / dim as Real)
}

/// A point or vector in 1, 2 or 3 dimensions.
pub trait Vector:
    Copy
    + Clone
    + Debug
    + Default
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<Real, Output = Self>
    + Div<Real, Output = Self>
    + AddAssign
    + SubAssign
{
    /// Number of spatial dimensions d.
    const DIM: usize;
    /// The d × d matrix type that goes with this vector.
    type Mat: Matrix<Self>;
    /// The zero vector.
    fn zero() -> Self;
    /// Component k (0-based, `k < DIM`).
    fn get(self, k: usize) -> Real;
    /// Sets component k.
    fn set(&mut self, k: usize, value: Real);
    /// Euclidean inner product.
    fn dot(self, other: Self) -> Real;
    /// |v|².
    #[inline]
    fn length_squared(self) -> Real {
        self.dot(self)
    }
    /// |v|.
    #[inline]
    fn length(self) -> Real {
        self.length_squared().sqrt()
    }
    /// Embeds the vector in 3-D space (unused components are 0).
    #[inline]
    fn to_xyz(self) -> [Real; 3] {
        let mut out = [0.0; 3];
        for (k, o) in out.iter_mut().enumerate().take(Self::DIM) {
            *o = self.get(k);
        }
        out
    }
    /// Builds a vector from exactly `DIM` components (`None` on a length mismatch).
    #[inline]
    fn from_slice(s: &[Real]) -> Option<Self> {
        if s.len() != Self::DIM {
            return None;
        }
        let mut v = Self::zero();
        for (k, x) in s.iter().enumerate() {
            v.set(k, *x);
        }
        Some(v)
    }
    /// Outer product `a ⊗ b`, the matrix with entries `a_k b_l`.
    fn outer(a: Self, b: Self) -> Self::Mat;
    /// The slice at its concrete type, so that code written once per dimension (the k-d
    /// tree of `dualsph-neighbours`) serves a generic caller without a trait of its own.
    fn as_points(points: &[Self]) -> Points<'_>;
    /// `a × b` with both embedded in 3-D (angular momentum, torque).
    #[inline]
    fn cross3(a: Self, b: Self) -> DVec3 {
        DVec3::from_array(a.to_xyz()).cross(DVec3::from_array(b.to_xyz()))
    }
    /// True when every component is finite.
    #[inline]
    fn is_finite(self) -> bool {
        (0..Self::DIM).all(|k| self.get(k).is_finite())
    }
}

/// A slice of points at its concrete type (see [`Vector::as_points`]).
#[derive(Clone, Copy, Debug)]
pub enum Points<'a> {
    /// One dimension.
    One(&'a [Vec1]),
    /// Two dimensions.
    Two(&'a [DVec2]),
    /// Three dimensions.
    Three(&'a [DVec3]),
}

/// A d × d matrix (velocity gradients, stresses, kernel-gradient corrections).
pub trait Matrix<V>:
    Copy
    + Clone
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Real, Output = Self>
    + AddAssign
{
    /// The zero matrix.
    fn zero() -> Self;
    /// The identity.
    fn identity() -> Self;
    /// Matrix–vector product `A v`.
    fn mul_vec(self, v: V) -> V;
    /// Transpose.
    fn transpose(self) -> Self;
    /// Trace.
    fn trace(self) -> Real;
    /// Determinant.
    fn determinant(self) -> Real;
    /// Inverse, or `None` when `|det|` is below `tol` times the scale `‖A‖^d`.
    fn try_inverse(self, tol: Real) -> Option<Self>;
    /// Entry (row k, column l).
    fn entry(self, k: usize, l: usize) -> Real;
    /// Sets entry (row k, column l) to exactly `value` (checkpoint restore).
    fn set_entry(&mut self, k: usize, l: usize, value: Real);
}

/// A one-dimensional vector.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
pub struct Vec1(pub Real);

/// A 1 × 1 matrix.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Mat1(pub Real);

macro_rules! scalar_newtype_ops {
    ($t:ident) => {
        impl Add for $t {
            type Output = Self;
            #[inline]
            fn add(self, o: Self) -> Self {
                $t(self.0 + o.0)
            }
        }
        impl Sub for $t {
            type Output = Self;
            #[inline]
            fn sub(self, o: Self) -> Self {
                $t(self.0 - o.0)
            }
        }
        impl Neg for $t {
            type Output = Self;
            #[inline]
            fn neg(self) -> Self {
                $t(-self.0)
            }
        }
        impl Mul<Real> for $t {
            type Output = Self;
            #[inline]
            fn mul(self, s: Real) -> Self {
                $t(self.0 * s)
            }
        }
        impl Div<Real> for $t {
            type Output = Self;
            #[inline]
            fn div(self, s: Real) -> Self {
                $t(self.0 / s)
            }
        }
        impl AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: Self) {
                self.0 += o.0;
            }
        }
        impl SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: Self) {
                self.0 -= o.0;
            }
        }
    };
}
scalar_newtype_ops!(Vec1);
scalar_newtype_ops!(Mat1);

impl Vector for Vec1 {
    const DIM: usize = 1;
    type Mat = Mat1;
    #[inline]
    fn zero() -> Self {
        Vec1(0.0)
    }
    #[inline]
    fn get(self, _k: usize) -> Real {
        self.0
    }
    #[inline]
    fn set(&mut self, _k: usize, value: Real) {
        self.0 = value;
    }
    #[inline]
    fn dot(self, o: Self) -> Real {
        self.0 * o.0
    }
    #[inline]
    fn outer(a: Self, b: Self) -> Mat1 {
        Mat1(a.0 * b.0)
    }
    #[inline]
    fn as_points(points: &[Self]) -> Points<'_> {
        Points::One(points)
    }
}

impl Matrix<Vec1> for Mat1 {
    #[inline]
    fn zero() -> Self {
        Mat1(0.0)
    }
    #[inline]
    fn identity() -> Self {
        Mat1(1.0)
    }
    #[inline]
    fn mul_vec(self, v: Vec1) -> Vec1 {
        Vec1(self.0 * v.0)
    }
    #[inline]
    fn transpose(self) -> Self {
        self
    }
    #[inline]
    fn trace(self) -> Real {
        self.0
    }
    #[inline]
    fn determinant(self) -> Real {
        self.0
    }
    #[inline]
    fn try_inverse(self, tol: Real) -> Option<Self> {
        (self.0.abs() > tol && self.0.is_finite()).then(|| Mat1(1.0 / self.0))
    }
    #[inline]
    fn entry(self, _k: usize, _l: usize) -> Real {
        self.0
    }
    #[inline]
    fn set_entry(&mut self, _k: usize, _l: usize, value: Real) {
        self.0 = value;
    }
}

macro_rules! glam_vector {
    ($v:ty, $m:ty, $d:expr, $points:ident) => {
        impl Vector for $v {
            const DIM: usize = $d;
            type Mat = $m;
            #[inline]
            fn zero() -> Self {
                <$v>::ZERO
            }
            #[inline]
            fn get(self, k: usize) -> Real {
                self[k]
            }
            #[inline]
            fn set(&mut self, k: usize, value: Real) {
                self[k] = value;
            }
            #[inline]
            fn dot(self, o: Self) -> Real {
                <$v>::dot(self, o)
            }
            #[inline]
            fn outer(a: Self, b: Self) -> $m {
                // column l of a ⊗ b is a * b_l
                let mut m = <$m>::ZERO;
                for l in 0..$d {
                    *m.col_mut(l) = a * b[l];
                }
                m
            }
            #[inline]
            fn as_points(points: &[Self]) -> Points<'_> {
                Points::$points(points)
            }
        }

        impl Matrix<$v> for $m {
            #[inline]
            fn zero() -> Self {
                <$m>::ZERO
            }
            #[inline]
            fn identity() -> Self {
                <$m>::IDENTITY
            }
            #[inline]
            fn mul_vec(self, v: $v) -> $v {
                self * v
            }
            #[inline]
            fn transpose(self) -> Self {
                <$m>::transpose(&self)
            }
            #[inline]
            fn trace(self) -> Real {
                (0..$d).map(|k| self.col(k)[k]).sum()
            }
            #[inline]
            fn determinant(self) -> Real {
                <$m>::determinant(&self)
            }
            #[inline]
            fn try_inverse(self, tol: Real) -> Option<Self> {
                let det = <$m>::determinant(&self);
                let scale = (0..$d)
                    .map(|l| self.col(l).abs().max_element())
                    .fold(0.0, Real::max)
                    .powi($d);
                (det.is_finite() && det.abs() > tol * scale && scale > 0.0)
                    .then(|| <$m>::inverse(&self))
            }
            #[inline]
            fn entry(self, k: usize, l: usize) -> Real {
                self.col(l)[k]
            }
            #[inline]
            fn set_entry(&mut self, k: usize, l: usize, value: Real) {
                self.col_mut(l)[k] = value;
            }
        }
    };
}
glam_vector!(DVec2, DMat2, 2, Two);
glam_vector!(DVec3, DMat3, 3, Three);

#[cfg(test)]
mod tests {
    use super::*;

    fn check_outer<V: Vector>(a: V, b: V) {
        let m = V::outer(a, b);
        for k in 0..V::DIM {
            for l in 0..V::DIM {
                assert_eq!(m.entry(k, l), a.get(k) * b.get(l));
            }
        }
        // (a ⊗ b) c = a (b · c)
        let c = b * 0.5 + a;
        let lhs = m.mul_vec(c);
        let rhs = a * b.dot(c);
        assert!((lhs - rhs).length() <= 1e-12 * rhs.length().max(1.0));
    }

    #[test]
    fn outer_product_matches_definition() {
        check_outer(Vec1(2.0), Vec1(-3.0));
        check_outer(DVec2::new(1.0, 2.0), DVec2::new(-0.5, 4.0));
        check_outer(DVec3::new(1.0, 2.0, 3.0), DVec3::new(-0.5, 4.0, 0.25));
    }

    #[test]
    fn inverse_rejects_singular() {
        assert!(
            DMat2::from_cols(DVec2::new(1.0, 2.0), DVec2::new(2.0, 4.0))
                .try_inverse(1e-12)
                .is_none()
        );
        let m = DMat3::from_diagonal(DVec3::new(2.0, 3.0, 4.0));
        let inv = m.try_inverse(1e-12).unwrap();
        assert!((Matrix::trace(inv) - (0.5 + 1.0 / 3.0 + 0.25)).abs() < 1e-15);
        assert!(Mat1(0.0).try_inverse(1e-12).is_none());
    }

    #[test]
    fn from_slice_checks_length() {
        assert!(<DVec2 as Vector>::from_slice(&[1.0, 2.0, 3.0]).is_none());
        assert_eq!(
            <DVec3 as Vector>::from_slice(&[1.0, 2.0, 3.0]),
            Some(DVec3::new(1.0, 2.0, 3.0))
        );
        assert_eq!(Vec1(4.0).to_xyz(), [4.0, 0.0, 0.0]);
    }
}
