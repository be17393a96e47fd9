//! Periodic axes of the domain box: the minimum-image separation, the wrap of a position into
//! the box, and the neighbour search across the period.
//!
//! On a periodic axis of length `L` a particle interacts with the nearest image of every other
//! particle: the pair separation is the **minimum image** `d − L·round(d/L)` of `d = x_i − x_j`
//! (Allen & Tildesley, *Computer Simulation of Liquids*, 2nd ed., OUP 2017, §1.6.3). `round`
//! rounds half away from zero, so the image of `−d` is exactly minus the image of `d`: the
//! reaction a pair sends through the dual-support is still the exact negative of its action,
//! and momentum is conserved to round-off across the period. The image is unique, and a
//! particle never meets itself, while every support radius stays below `L/2`
//! ([`Period::fits`]).
//!
//! **Search.** The spatial indexes search a point set with no notion of period, so the set is
//! extended with images: every point (wrapped into the box) within the largest search radius of
//! a periodic face is copied once per combination of the faces it is near, shifted by `±L` on
//! those axes. The real points are searched against the extended set, each image found is
//! mapped back to its particle, and the rows are sorted again — the same lists, bit for bit,
//! whichever index searched, on any number of threads.

use super::{Csr, NeighbourIndex, radius_csr};
use dualsph_math::{Real, Vector};
use rayon::prelude::*;

/// The periodic axes of a box `[lo, lo + L)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Period<V: Vector> {
    lo: V,
    len: V,
    inv_len: V,
    axes: [bool; 3],
}

impl<V: Vector> Period<V> {
    /// The period of the box `[min, max]` on the axes marked in `axes` (the first `V::DIM`
    /// are read), or `None` when no axis is periodic. `max − min` must be positive and finite
    /// on a periodic axis.
    pub fn new(min: V, max: V, axes: [bool; 3]) -> Option<Self> {
        let mut axes = axes;
        axes[V::DIM..].fill(false);
        if !axes.iter().any(|&a| a) {
            return None;
        }
        let (mut len, mut inv_len) = (V::zero(), V::zero());
        for k in (0..V::DIM).filter(|&k| axes[k]) {
            let l = max.get(k) - min.get(k);
            len.set(k, l);
            inv_len.set(k, 1.0 / l);
        }
        Some(Period {
            lo: min,
            len,
            inv_len,
            axes,
        })
    }

    /// The shortest period.
    pub fn shortest(&self) -> Real {
        (0..V::DIM)
            .filter(|&k| self.axes[k])
            .map(|k| self.len.get(k))
            .fold(Real::INFINITY, Real::min)
    }

    /// Whether a support (or search) radius `r` keeps the minimum image unique: `2r < L` on
    /// every periodic axis.
    pub fn fits(&self, r: Real) -> bool {
        2.0 * r < self.shortest()
    }

    /// The minimum image of the separation `d` (module docs): `d_k − L_k round(d_k/L_k)` on
    /// each periodic axis, `d_k` on the others.
    #[inline(always)]
    pub fn image(&self, mut d: V) -> V {
        for k in 0..V::DIM {
            if self.axes[k] {
                let x = d.get(k);
                d.set(k, x - self.len.get(k) * (x * self.inv_len.get(k)).round());
            }
        }
        d
    }

    /// `x` moved by whole periods into `[lo, lo + L)` on each periodic axis.
    #[inline]
    pub fn wrap(&self, mut x: V) -> V {
        for k in 0..V::DIM {
            if self.axes[k] {
                let (lo, l) = (self.lo.get(k), self.len.get(k));
                let mut y = x.get(k) - l * ((x.get(k) - lo) * self.inv_len.get(k)).floor();
                // the subtraction may round up onto the upper face itself
                if y >= lo + l {
                    y -= l;
                }
                x.set(k, y.max(lo));
            }
        }
        x
    }

    /// Whether axis `k` is periodic.
    pub fn is_periodic(&self, k: usize) -> bool {
        k < V::DIM && self.axes[k]
    }

    /// The shifts of the images of a wrapped point `x` that a search of radius `reach` must
    /// see: one per non-empty combination of the periodic faces within `reach` of it (`+L` on
    /// an axis whose lower face is near, `−L` on one whose upper face is), in a fixed order.
    pub fn image_shifts(&self, x: V, reach: Real) -> Vec<V> {
        let mut out = vec![V::zero()];
        for k in 0..V::DIM {
            if !self.axes[k] {
                continue;
            }
            let (lo, l) = (self.lo.get(k), self.len.get(k));
            let s = if x.get(k) - lo <= reach {
                l
            } else if lo + l - x.get(k) <= reach {
                -l
            } else {
                continue;
            };
            let more: Vec<V> = out
                .iter()
                .map(|&v| {
                    let mut w = v;
                    w.set(k, s);
                    w
                })
                .collect();
            out.extend(more);
        }
        out.remove(0);
        out
    }
}

/// The separation `x_i − x_j`: its minimum image when the domain has periodic axes.
#[inline(always)]
pub fn separation<V: Vector>(period: Option<&Period<V>>, xi: V, xj: V) -> V {
    match period {
        Some(p) => p.image(xi - xj),
        None => xi - xj,
    }
}

/// [`radius_csr`] across the period: for every point i, the sorted `j != i` whose nearest
/// image lies within `radii[i]` (module docs). Every radius must satisfy [`Period::fits`].
pub fn periodic_radius_csr<V: Vector>(
    points: &[V],
    radii: &[Real],
    index: NeighbourIndex,
    period: &Period<V>,
) -> (Csr, NeighbourIndex) {
    let n = points.len();
    let reach = radii.iter().copied().fold(0.0, Real::max);
    debug_assert!(
        period.fits(reach),
        "a search radius {reach} reaches half a period"
    );
    let mut pts: Vec<V> = points.par_iter().map(|&x| period.wrap(x)).collect();
    let mut rad = radii.to_vec();
    let mut image_of: Vec<u32> = Vec::new();
    for i in 0..n {
        for shift in period.image_shifts(pts[i], reach) {
            image_of.push(i as u32);
            pts.push(pts[i] + shift);
            rad.push(radii[i]);
        }
    }
    let (all, used) = radius_csr(&pts, &rad, index);
    let rows: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let row = all.row(i);
            if row.last().is_none_or(|&j| (j as usize) < n) {
                return row.to_vec();
            }
            let mut r: Vec<u32> = row
                .iter()
                .map(|&j| match (j as usize).checked_sub(n) {
                    Some(g) => image_of[g],
                    None => j,
                })
                .filter(|&j| j as usize != i)
                .collect();
            r.sort_unstable();
            r.dedup();
            r
        })
        .collect();
    (Csr::from_rows(rows), used)
}
