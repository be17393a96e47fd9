//! The one wrapper of kiddo's `ImmutableKdTree` in the engine: the index for every input
//! (clouds with wildly varying h, sparse or clustered sets, non-finite coordinates), used by the
//! neighbour lists ([`kd_radius_csr`]) and by sampling at arbitrary points
//! ([`crate::sampling`]).
//!
//! kiddo's tree is generic over a const dimension `K`; [`Vector`] has no const generic, so the
//! tree is held as one variant per dimension and chosen by [`Vector::as_points`].

use super::{Csr, SEARCH_CHUNK, assemble};
use dualsph_math::{Points, Real, Vector};
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use kiddo::{NearestNeighbour, SquaredEuclidean};
use rayon::prelude::*;

/// Items per leaf of every tree.
const BUCKET: usize = 32;

/// A k-d tree over a set of points (items are the indices `0..n`).
pub enum KdTree {
    /// Over 1-D points.
    One(ImmutableKdTree<Real, u32, 1, BUCKET>),
    /// Over 2-D points.
    Two(ImmutableKdTree<Real, u32, 2, BUCKET>),
    /// Over 3-D points.
    Three(ImmutableKdTree<Real, u32, 3, BUCKET>),
}

impl std::fmt::Debug for KdTree {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let dim = match self {
            KdTree::One(_) => 1,
            KdTree::Two(_) => 2,
            KdTree::Three(_) => 3,
        };
        f.debug_struct("KdTree").field("dim", &dim).finish()
    }
}

/// The first `K` coordinates of a point.
#[inline]
fn coords<const K: usize, V: Vector>(p: V) -> [Real; K] {
    std::array::from_fn(|k| p.get(k))
}

impl KdTree {
    /// Builds the tree over `points`.
    pub fn new<V: Vector>(points: &[V]) -> Self {
        match V::as_points(points) {
            Points::One(p) => KdTree::One(ImmutableKdTree::new_from_slice(
                &p.iter().map(|x| [x.0]).collect::<Vec<_>>(),
            )),
            Points::Two(p) => KdTree::Two(ImmutableKdTree::new_from_slice(
                &p.iter().map(|x| x.to_array()).collect::<Vec<_>>(),
            )),
            Points::Three(p) => KdTree::Three(ImmutableKdTree::new_from_slice(
                &p.iter().map(|x| x.to_array()).collect::<Vec<_>>(),
            )),
        }
    }

    /// Calls `f` with the index of every point within distance `r` of `x`, and possibly a few
    /// just outside (the tree is asked with a hair of slack, `r²(1 + 10⁻¹²)`): callers decide
    /// with their own arithmetic. In no particular order.
    #[inline]
    pub fn for_each_within<V: Vector>(&self, x: V, r: Real, mut f: impl FnMut(u32)) {
        for nn in self.within(x, r * r * (1.0 + 1e-12)) {
            f(nn.item);
        }
    }

    /// The points within squared distance `r2` of `x`, with their squared distances.
    #[inline]
    fn within<V: Vector>(&self, x: V, r2: Real) -> Vec<NearestNeighbour<Real, u32>> {
        match self {
            KdTree::One(t) => t.within_unsorted::<SquaredEuclidean>(&coords(x), r2),
            KdTree::Two(t) => t.within_unsorted::<SquaredEuclidean>(&coords(x), r2),
            KdTree::Three(t) => t.within_unsorted::<SquaredEuclidean>(&coords(x), r2),
        }
    }

    /// The distance from `x` to the nearest point of the tree within `r` of it, or infinity
    /// when there is none: a search bounded by `r` returns at once where no point is near,
    /// which an unbounded nearest-neighbour search does not, and one that keeps only the
    /// nearest point found so far prunes every branch farther than it, where a search for
    /// all the points within `r` visits them all.
    #[inline]
    pub fn nearest_within<V: Vector>(&self, x: V, r: Real) -> Real {
        let r2 = r * r;
        let nearest = match self {
            KdTree::One(t) => t.nearest_n_within::<SquaredEuclidean>(&coords(x), r2, ONE, true),
            KdTree::Two(t) => t.nearest_n_within::<SquaredEuclidean>(&coords(x), r2, ONE, true),
            KdTree::Three(t) => t.nearest_n_within::<SquaredEuclidean>(&coords(x), r2, ONE, true),
        };
        nearest
            .first()
            .map(|nn| nn.distance)
            .filter(|&d2| d2 <= r2)
            .map_or(Real::INFINITY, Real::sqrt)
    }
}

/// A search that keeps one point.
const ONE: std::num::NonZero<usize> = std::num::NonZero::<usize>::MIN;

/// For every point i, the sorted indices `j != i` with `|x_i − x_j| <= radii[i]`, as a CSR
/// (rows in point order), searched in a [`KdTree`].
pub fn kd_radius_csr<V: Vector>(points: &[V], radii: &[Real]) -> Csr {
    let tree = KdTree::new(points);
    let chunks: Vec<(Vec<u32>, Vec<u32>)> = points
        .par_chunks(SEARCH_CHUNK)
        .enumerate()
        .map(|(c, qs)| {
            let (mut flat, mut lens) = (Vec::new(), Vec::with_capacity(qs.len()));
            for (k, &q) in qs.iter().enumerate() {
                let i = c * SEARCH_CHUNK + k;
                let r = radii[i];
                let start = flat.len();
                tree.for_each_within(q, r, |j| {
                    if j as usize != i && (q - points[j as usize]).length_squared() <= r * r {
                        flat.push(j);
                    }
                });
                flat[start..].sort_unstable();
                lens.push((flat.len() - start) as u32);
            }
            (flat, lens)
        })
        .collect();
    assemble(points.len(), chunks)
}
