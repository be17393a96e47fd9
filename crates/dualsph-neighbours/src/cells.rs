//! Uniform-grid (cell-linked-list) fixed-radius search: the fast index for the common case.
//!
//! The bounding box of the points is cut into cubic cells of edge `c` (`r_max` or `r_max/2`,
//! [`GridPlan::auto`]); the point indices are counting-sorted by cell (ascending index inside
//! a cell) with a copy of the positions in the same order, so a run of cells along x is one
//! contiguous slice. Point i scans, for each (z, y) row of cells its sphere can reach, the
//! x-cells of the remaining half-chord, and keeps every j with
//! `(x_i − x_j).length_squared() <= r_i²` — the test of the k-d path with the same arithmetic —
//! written branch-free; the row is then sorted (a bitmap over its index span when that span is
//! narrow, `sort_unstable` otherwise) and `i` dropped, so the lists are bitwise kiddo's.
//! Parallel over chunks of points, one flat buffer per chunk, deterministic.
//!
//! **Why no neighbour is ever missed.** The cell coordinate of a point is `u = (x − lo)·(1/c)`
//! and its cell `min(⌊u⌋, dims − 1)`, a monotone function of `u`; every bound of the scan (the
//! box `u_i ± w_i` with `w_i = |r_i|/c`, the distance of a cell row from `u_i`, the half-chord)
//! is widened by an absolute slack. A pair that passes the test has `|x_i − x_j| <= |r_i|(1 +
//! 3ε)` per axis, and the rounding of `u_i`, `u_j` and of the bounds is at most a few ε times
//! `u + w <= dims + w`; the slack `10⁻¹²(dims + w + 1)` is a thousand times that. The slack
//! only adds candidates, which the exact test then rejects. (The lattice tests put distances
//! exactly on the radius; removing the slack makes them fail.)
//!
//! **When it applies.** Only to finite coordinates and radii whose bounding box has a finite
//! extent ([`GridPlan::new`] returns `None` otherwise). The number of cells is capped at
//! `4n + 64`; when the target cell would need more, the cell is enlarged until it fits
//! ([`GridPlan::coarsening`] > 1): still exact, but a clustered or sparse set then puts many
//! points in few cells, so `NeighbourIndex::Auto` uses kiddo once the cell exceeds `r_max`.

use super::{Csr, SEARCH_CHUNK, assemble};
use dualsph_math::{Real, Vector};
use rayon::prelude::*;

/// At most this many cells per point (plus [`CELLS_MIN`]).
const CELLS_PER_POINT: usize = 4;
/// Cells always allowed, whatever n.
const CELLS_MIN: usize = 64;

/// The geometry of a uniform grid over one point set.
#[derive(Clone, Debug, PartialEq)]
pub struct GridPlan {
    origin: [Real; 3],
    inv_cell: Real,
    dims: [usize; 3],
    /// Cell edge length.
    pub cell: Real,
    /// `cell /` the target edge: 1 when the cell budget allowed the target, larger when the
    /// grid had to be coarsened (a sparse or widely spread set).
    pub coarsening: Real,
    /// Smallest `|radius|`.
    pub r_min: Real,
    /// Largest `|radius|`.
    pub r_max: Real,
}

/// Bounding box and radius range of a point set, and whether everything is finite.
#[derive(Clone, Copy)]
struct Bounds {
    lo: [Real; 3],
    hi: [Real; 3],
    r_min: Real,
    r_max: Real,
    finite: bool,
    n: usize,
}

impl Bounds {
    fn empty() -> Self {
        Bounds {
            lo: [Real::INFINITY; 3],
            hi: [Real::NEG_INFINITY; 3],
            r_min: Real::INFINITY,
            r_max: 0.0,
            finite: true,
            n: 0,
        }
    }

    fn add<V: Vector>(mut self, p: V, r: Real) -> Self {
        self.finite &= p.is_finite() && r.is_finite();
        for k in 0..V::DIM {
            self.lo[k] = self.lo[k].min(p.get(k));
            self.hi[k] = self.hi[k].max(p.get(k));
        }
        self.r_min = self.r_min.min(r.abs());
        self.r_max = self.r_max.max(r.abs());
        self.n += 1;
        self
    }

    // min/max are exact, so the reduction gives the same bits in any grouping
    fn merge(mut self, o: Self) -> Self {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(o.lo[k]);
            self.hi[k] = self.hi[k].max(o.hi[k]);
        }
        self.r_min = self.r_min.min(o.r_min);
        self.r_max = self.r_max.max(o.r_max);
        self.finite &= o.finite;
        self.n += o.n;
        self
    }
}

/// The bounds of a non-empty set with one radius per point, or `None`.
fn bounds<V: Vector>(points: &[V], radii: &[Real]) -> Option<Bounds> {
    if points.is_empty() || radii.len() != points.len() {
        return None;
    }
    let b = points
        .par_iter()
        .zip(radii.par_iter())
        .with_min_len(4096)
        .fold(Bounds::empty, |b, (&p, &r)| b.add(p, r))
        .reduce(Bounds::empty, Bounds::merge);
    b.finite.then_some(b)
}

/// `min(⌊x⌋, dims − 1)` for `x >= 0`, 0 below (monotone in x).
#[inline]
fn cell_coord(x: Real, dims: usize) -> usize {
    if x > 0.0 {
        (x as usize).min(dims - 1)
    } else {
        0
    }
}

impl GridPlan {
    /// The grid for `points` with cells of edge `r_max / cells_per_radius` (enlarged to the
    /// cell budget when needed), or `None` when a coordinate, a radius or the extent of the
    /// bounding box is not finite, or the set is empty.
    pub fn new<V: Vector>(points: &[V], radii: &[Real], cells_per_radius: Real) -> Option<Self> {
        Self::from_bounds::<V>(bounds(points, radii)?, cells_per_radius)
    }

    /// The grid with the measured best cell for these radii: `r_max` when the radii are
    /// uniform within 1.5×, `r_max / 2` when they vary more (smaller particles then scan fewer
    /// candidates). `neighbour_index` example, 12,800 and 100,000 particles, 1 thread: uniform
    /// 2-D/3-D columns run 10–25 % faster with `r_max` cells than with `r_max / 2`, two-level
    /// (h ratio 2) 3-D columns 20–30 % slower.
    pub fn auto<V: Vector>(points: &[V], radii: &[Real]) -> Option<Self> {
        let b = bounds(points, radii)?;
        let cells_per_radius = if b.r_max <= 1.5 * b.r_min { 1.0 } else { 2.0 };
        Self::from_bounds::<V>(b, cells_per_radius)
    }

    fn from_bounds<V: Vector>(b: Bounds, cells_per_radius: Real) -> Option<Self> {
        let n = b.n;
        let d = V::DIM;
        let mut extent = [0.0; 3];
        for k in 0..d {
            extent[k] = b.hi[k] - b.lo[k];
            if !extent[k].is_finite() {
                return None;
            }
        }
        let max_extent = extent.iter().copied().fold(0.0, Real::max);
        let budget = (CELLS_PER_POINT * n + CELLS_MIN) as Real;
        if budget > u32::MAX as Real {
            return None;
        }
        let target = b.r_max / cells_per_radius;
        let mut cell = if target >= Real::MIN_POSITIVE {
            target
        } else if max_extent > 0.0 {
            max_extent / budget
        } else {
            1.0
        };
        let count = |inv: Real| -> Real {
            (0..d)
                .map(|k| {
                    if extent[k] > 0.0 {
                        (extent[k] * inv).floor() + 1.0
                    } else {
                        1.0
                    }
                })
                .product()
        };
        // grows by at least 2× per turn; once the cell exceeds the extent there are <= 2^d cells
        loop {
            let cells = count(1.0 / cell);
            if cells <= budget {
                break;
            }
            let grow = libm::pow(cells / budget, 1.0 / d as Real);
            cell *= grow.clamp(2.0, 1e6);
        }
        let inv_cell = 1.0 / cell;
        let mut dims = [1usize; 3];
        let mut origin = [0.0; 3];
        for k in 0..d {
            origin[k] = b.lo[k];
            if extent[k] > 0.0 {
                dims[k] = (extent[k] * inv_cell) as usize + 1;
            }
        }
        Some(GridPlan {
            origin,
            inv_cell,
            dims,
            cell,
            coarsening: if target > 0.0 {
                cell / target
            } else {
                Real::INFINITY
            },
            r_min: b.r_min,
            r_max: b.r_max,
        })
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.dims.iter().product()
    }

    /// The cell of a point.
    #[inline]
    fn cell_of<V: Vector>(&self, p: V) -> usize {
        let mut id = 0;
        for k in (0..V::DIM).rev() {
            let u = (p.get(k) - self.origin[k]) * self.inv_cell;
            id = id * self.dims[k] + cell_coord(u, self.dims[k]);
        }
        id
    }

    /// For every point i, the sorted `j != i` with `(x_i − x_j).length_squared() <= r_i²`, as
    /// a CSR. `self` must be a plan of these same points (its bounding box); the radii may be
    /// any (each point's scan uses its own radius), one per point.
    pub fn radius_csr<V: Vector>(&self, points: &[V], radii: &[Real]) -> Csr {
        let n = points.len();
        let cells: Vec<u32> = points
            .par_iter()
            .with_min_len(4096)
            .map(|&p| self.cell_of(p) as u32)
            .collect();
        // counting sort by cell, stable: ascending point index inside each cell
        let ncell = self.cells();
        let mut start = vec![0u32; ncell + 1];
        for &c in &cells {
            start[c as usize + 1] += 1;
        }
        for c in 0..ncell {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; n];
        let mut sorted = vec![V::zero(); n];
        for (i, &c) in cells.iter().enumerate() {
            let at = fill[c as usize] as usize;
            fill[c as usize] += 1;
            order[at] = i as u32;
            sorted[at] = points[i];
        }
        drop((cells, fill));
        let bins = Bins {
            start,
            order,
            sorted,
        };

        let slack = 1e-12 * (self.dims.iter().copied().max().unwrap_or(1) as Real + 1.0);
        let chunks: Vec<(Vec<u32>, Vec<u32>)> = points
            .par_chunks(SEARCH_CHUNK)
            .enumerate()
            .map(|(c, qs)| {
                let mut flat = Vec::new();
                let mut lens = Vec::with_capacity(qs.len());
                // scratch reused over the chunk: one row's hits, and a bitmap to sort them
                let (mut row, mut bits) = (Vec::new(), Vec::new());
                for (k, &p) in qs.iter().enumerate() {
                    let i = c * SEARCH_CHUNK + k;
                    let len = self.query(&bins, p, radii[i], slack, &mut row);
                    if k == 0 {
                        // the first row sizes the chunk's buffer (rows vary little nearby)
                        flat.reserve((len + len / 4 + 4) * qs.len());
                    }
                    let before = flat.len();
                    sorted_without(&mut row[..len], i as u32, &mut bits, &mut flat);
                    lens.push((flat.len() - before) as u32);
                }
                (flat, lens)
            })
            .collect();
        assemble(n, chunks)
    }

    /// Writes into `row[..len]` the j with `(p − x_j).length_squared() <= r²` (i among them:
    /// its distance is 0), in cell order, and returns `len`. Scans the cell rows along x that can hold such a j: the
    /// (z, y) rows whose distance from p in y and z leaves room inside the radius, each over
    /// the x-cells of the remaining half-chord (all in cell units, every bound widened by the
    /// absolute `slack` as in the module docs, so no neighbour is ever cut).
    #[inline]
    fn query<V: Vector>(
        &self,
        bins: &Bins<V>,
        p: V,
        r: Real,
        slack: Real,
        row: &mut Vec<u32>,
    ) -> usize {
        let dims = self.dims;
        let rr = r * r;
        let w0 = r.abs() * self.inv_cell;
        let s = slack + 1e-12 * w0;
        let w = w0 + s;
        let w0sq = w0 * w0 * (1.0 + 1e-9);
        let mut u = [0.0; 3];
        let (mut lo, mut hi) = ([0usize; 3], [0usize; 3]);
        for a in 0..V::DIM {
            u[a] = (p.get(a) - self.origin[a]) * self.inv_cell;
            lo[a] = cell_coord(u[a] - w, dims[a]);
            hi[a] = cell_coord(u[a] + w, dims[a]);
        }
        // distance from u to the cell [c, c + 1) along an axis, shortened by the slack
        let gap = |axis: usize, c: usize| -> Real {
            if axis >= V::DIM {
                return 0.0;
            }
            let c = c as Real;
            ((c - u[axis]).max(u[axis] - (c + 1.0)) - s).max(0.0)
        };
        let mut len = 0;
        for z in lo[2]..=hi[2] {
            let gz = gap(2, z);
            let rem_z = w0sq - gz * gz;
            if rem_z < 0.0 {
                continue;
            }
            for y in lo[1]..=hi[1] {
                let gy = gap(1, y);
                let rem = rem_z - gy * gy;
                if rem < 0.0 {
                    continue;
                }
                let wx = rem.sqrt() + s;
                let x0 = cell_coord(u[0] - wx, dims[0]);
                let x1 = cell_coord(u[0] + wx, dims[0]);
                let base = (z * dims[1] + y) * dims[0];
                let a = bins.start[base + x0] as usize;
                let b = bins.start[base + x1 + 1] as usize;
                if row.len() < len + (b - a) {
                    row.resize(len + (b - a), 0);
                }
                // branch-free compaction: a mispredicted push per candidate cost more than
                // the distance test itself
                let out = &mut row[len..len + (b - a)];
                let mut m = 0;
                for (&q, &j) in bins.sorted[a..b].iter().zip(&bins.order[a..b]) {
                    out[m] = j;
                    m += ((p - q).length_squared() <= rr) as usize;
                }
                len += m;
            }
        }
        len
    }
}

/// Appends `hits` without `i` to `out` in ascending order. `hits` are distinct and contain `i`.
/// When their span is narrow (points numbered along space, as generated) a bitmap over the span
/// sorts them in O(len + span/64), much cheaper than a comparison sort of ~50 entries;
/// otherwise `sort_unstable`. The result is the same either way. `bits` is all zero on entry
/// and on exit (each word is cleared as it is read).
fn sorted_without(hits: &mut [u32], i: u32, bits: &mut Vec<u64>, out: &mut Vec<u32>) {
    let (mut lo, mut hi) = (u32::MAX, 0);
    for &j in hits.iter() {
        lo = lo.min(j);
        hi = hi.max(j);
    }
    let words = (hi as usize + 1).saturating_sub(lo as usize).div_ceil(64);
    out.reserve(hits.len());
    if words <= 8 * hits.len() + 16 {
        if bits.len() < words {
            bits.resize(words, 0);
        }
        for &j in hits.iter() {
            let k = (j - lo) as usize;
            bits[k / 64] |= 1 << (k % 64);
        }
        if (lo..=hi).contains(&i) {
            let k = (i - lo) as usize;
            bits[k / 64] &= !(1 << (k % 64));
        }
        for (wi, b) in bits[..words].iter_mut().enumerate() {
            let mut w = std::mem::take(b);
            let base = lo + 64 * wi as u32;
            while w != 0 {
                out.push(base + w.trailing_zeros());
                w &= w - 1;
            }
        }
    } else {
        hits.sort_unstable();
        out.extend(hits.iter().copied().filter(|&j| j != i));
    }
}

/// Point indices counting-sorted by cell: cell c holds `order[start[c]..start[c + 1]]`
/// (ascending), whose positions are `sorted[start[c]..start[c + 1]]`.
struct Bins<V> {
    start: Vec<u32>,
    order: Vec<u32>,
    sorted: Vec<V>,
}
