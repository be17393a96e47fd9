//! Arithmetic written once for one pair (`f64`) or for two pairs side by side
//! ([`wide::f64x2`], two SSE2 lanes): the kernel profiles, the sweep's pair geometry and every
//! pair term are generic over [`Lanes`], so the two-pair loop performs, lane by lane,
//! exactly the floating-point operations of the one-pair code. Every operation used here
//! (`+ − × ÷ √`, negation, comparisons, selects) is correctly rounded per lane in IEEE 754, so both give
//! bitwise the same numbers; `tests` below check it, and `sweep::check_lanes_2d` for a term.

use crate::{Real, Vector};
use std::ops::{Add, Div, Mul, Neg, Sub};
use wide::f64x2;

/// One value per pair for `N` pairs at once.
pub trait Lanes:
    Copy
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Pairs per value.
    const N: usize;
    /// The same value in every lane.
    fn splat(x: Real) -> Self;
    /// Lane `l` from `f(l)`.
    fn from_fn(f: impl Fn(usize) -> Real) -> Self;
    /// Lane `l`.
    fn lane(self, l: usize) -> Real;
    /// `√x` per lane.
    fn sqrt(self) -> Self;
    /// `if a < b { t } else { f }` per lane.
    fn if_lt(a: Self, b: Self, t: Self, f: Self) -> Self;
    /// `if a > b { t } else { f }` per lane.
    fn if_gt(a: Self, b: Self, t: Self, f: Self) -> Self;
    /// `if 0 ≤ q < 1 { d } else { 0 }` per lane (false for NaN, as `(0.0..1.0).contains`).
    fn in_unit(q: Self, d: Self) -> Self;
}

impl Lanes for Real {
    const N: usize = 1;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        x
    }
    #[inline(always)]
    fn from_fn(f: impl Fn(usize) -> Real) -> Self {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _: usize) -> Real {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Real::sqrt(self)
    }
    #[inline(always)]
    fn if_lt(a: Self, b: Self, t: Self, f: Self) -> Self {
        if a < b { t } else { f }
    }
    #[inline(always)]
    fn if_gt(a: Self, b: Self, t: Self, f: Self) -> Self {
        if a > b { t } else { f }
    }
    #[inline(always)]
    fn in_unit(q: Self, d: Self) -> Self {
        if (0.0..1.0).contains(&q) { d } else { 0.0 }
    }
}

impl Lanes for f64x2 {
    const N: usize = 2;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        f64x2::splat(x)
    }
    #[inline(always)]
    fn from_fn(f: impl Fn(usize) -> Real) -> Self {
        f64x2::new([f(0), f(1)])
    }
    #[inline(always)]
    fn lane(self, l: usize) -> Real {
        self.to_array()[l]
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64x2::sqrt(self)
    }
    #[inline(always)]
    fn if_lt(a: Self, b: Self, t: Self, f: Self) -> Self {
        a.simd_lt(b).select(t, f)
    }
    #[inline(always)]
    fn if_gt(a: Self, b: Self, t: Self, f: Self) -> Self {
        a.simd_gt(b).select(t, f)
    }
    #[inline(always)]
    fn in_unit(q: Self, d: Self) -> Self {
        let inside = q.simd_ge(f64x2::splat(0.0)) & q.simd_lt(f64x2::splat(1.0));
        inside.select(d, f64x2::splat(0.0))
    }
}

/// A vector per lane, by components (`0..V::DIM` used).
#[derive(Clone, Copy, Debug)]
pub struct LaneVec<T: Lanes>(pub [T; 3]);

impl<T: Lanes> LaneVec<T> {
    /// Lane `l` is `f(l)`.
    #[inline(always)]
    pub fn from_fn<V: Vector>(f: impl Fn(usize) -> V) -> Self {
        let mut c = [T::splat(0.0); 3];
        for (k, c) in c.iter_mut().enumerate().take(V::DIM) {
            *c = T::from_fn(|l| f(l).get(k));
        }
        LaneVec(c)
    }

    /// `v` in every lane.
    #[inline(always)]
    pub fn splat<V: Vector>(v: V) -> Self {
        let mut c = [T::splat(0.0); 3];
        for (k, c) in c.iter_mut().enumerate().take(V::DIM) {
            *c = T::splat(v.get(k));
        }
        LaneVec(c)
    }

    /// Lane `l` as a vector.
    #[inline(always)]
    pub fn lane<V: Vector>(self, l: usize) -> V {
        let mut v = V::zero();
        for k in 0..V::DIM {
            v.set(k, self.0[k].lane(l));
        }
        v
    }

    /// `a − b` per component.
    #[inline(always)]
    pub fn minus<V: Vector>(self, b: Self) -> Self {
        let mut c = self.0;
        for (k, c) in c.iter_mut().enumerate().take(V::DIM) {
            *c = *c - b.0[k];
        }
        LaneVec(c)
    }

    /// `a + b` per component.
    #[inline(always)]
    pub fn plus<V: Vector>(self, b: Self) -> Self {
        let mut c = self.0;
        for (k, c) in c.iter_mut().enumerate().take(V::DIM) {
            *c = *c + b.0[k];
        }
        LaneVec(c)
    }

    /// `a s` per component.
    #[inline(always)]
    pub fn scale<V: Vector>(self, s: T) -> Self {
        let mut c = self.0;
        for c in c.iter_mut().take(V::DIM) {
            *c = *c * s;
        }
        LaneVec(c)
    }

    /// `a·b` summed in the order of the vector types' own `dot`: `((a₀b₀ + a₁b₁) + a₂b₂)`.
    #[inline(always)]
    pub fn dot<V: Vector>(self, b: Self) -> T {
        let mut s = self.0[0] * b.0[0];
        for k in 1..V::DIM {
            s = s + self.0[k] * b.0[k];
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    fn bits(x: Real) -> u64 {
        x.to_bits()
    }

    /// Two lanes against one value at a time, bitwise, on values with signed zeros, NaN and
    /// infinities among them.
    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        let xs = [
            0.0,
            -0.0,
            1.0,
            -2.5,
            0.999_999_999,
            1e-300,
            3.7e12,
            Real::NAN,
            Real::INFINITY,
        ];
        for &a in &xs {
            for &b in &xs {
                let (x, y) = (f64x2::new([a, b]), f64x2::new([b, a]));
                let pairs = [(a, b), (b, a)];
                for (l, &(p, q)) in pairs.iter().enumerate() {
                    assert_eq!(bits((x + y).lane(l)), bits(p + q));
                    assert_eq!(bits((x - y).lane(l)), bits(p - q));
                    assert_eq!(bits((x * y).lane(l)), bits(p * q));
                    assert_eq!(bits((x / y).lane(l)), bits(p / q));
                    assert_eq!(bits(x.sqrt().lane(l)), bits(p.sqrt()));
                    assert_eq!(bits((-x).lane(l)), bits(-p));
                    let lt = <f64x2 as Lanes>::if_lt(x, y, x, y).lane(l);
                    assert_eq!(bits(lt), bits(<Real as Lanes>::if_lt(p, q, p, q)));
                    let gt = <f64x2 as Lanes>::if_gt(x, y, x, y).lane(l);
                    assert_eq!(bits(gt), bits(<Real as Lanes>::if_gt(p, q, p, q)));
                    let iu = <f64x2 as Lanes>::in_unit(x, y).lane(l);
                    assert_eq!(bits(iu), bits(<Real as Lanes>::in_unit(p, q)));
                }
            }
        }
    }

    #[test]
    fn lane_vectors_match_glam_dot_and_arithmetic() {
        let a = [DVec3::new(0.1, -2.0, 3.3), DVec3::new(1e-3, 7.0, -0.25)];
        let b = [DVec3::new(4.0, 0.5, -1.1), DVec3::new(-3.0, 2.0, 9.5)];
        let (la, lb) = (
            LaneVec::<f64x2>::from_fn(|l| a[l]),
            LaneVec::<f64x2>::from_fn(|l| b[l]),
        );
        for l in 0..2 {
            assert_eq!(bits(la.dot::<DVec3>(lb).lane(l)), bits(a[l].dot(b[l])));
            assert_eq!(la.minus::<DVec3>(lb).lane::<DVec3>(l), a[l] - b[l]);
            assert_eq!(la.plus::<DVec3>(lb).lane::<DVec3>(l), a[l] + b[l]);
            assert_eq!(
                la.scale::<DVec3>(f64x2::splat(0.3)).lane::<DVec3>(l),
                a[l] * 0.3
            );
        }
        let (p, q) = (DVec2::new(0.7, -0.1), DVec2::new(1.9, 2.2));
        let (lp, lq) = (LaneVec::<Real>::splat(p), LaneVec::<Real>::splat(q));
        assert_eq!(bits(lp.dot::<DVec2>(lq)), bits(p.dot(q)));
    }
}
