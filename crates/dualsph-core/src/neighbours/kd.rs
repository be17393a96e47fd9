//! The k-d tree search (kiddo's `ImmutableKdTree`), the index for every input: clouds with
//! wildly varying h, sparse or clustered sets, non-finite coordinates.

use super::{Csr, SEARCH_CHUNK, assemble};
use crate::math::{Real, Vector};
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use rayon::prelude::*;

/// Fixed-radius search with a per-point radius, implemented for each vector type.
pub trait KdSearch: Sized {
    /// For every point i, the sorted indices `j != i` with `|x_i − x_j| <= radii[i]`, as a CSR
    /// (rows in point order).
    fn radius_csr(points: &[Self], radii: &[Real]) -> Csr;
}

macro_rules! kd_search {
    ($v:ty, $k:expr, $arr:expr) => {
        impl KdSearch for $v {
            fn radius_csr(points: &[Self], radii: &[Real]) -> Csr {
                let to_arr = $arr;
                let pts: Vec<[Real; $k]> = points.iter().map(|p| to_arr(*p)).collect();
                let tree: ImmutableKdTree<Real, u32, $k, 32> =
                    ImmutableKdTree::new_from_slice(&pts);
                let chunks: Vec<(Vec<u32>, Vec<u32>)> = pts
                    .par_chunks(SEARCH_CHUNK)
                    .enumerate()
                    .map(|(c, qs)| {
                        let (mut flat, mut lens) = (Vec::new(), Vec::with_capacity(qs.len()));
                        for (k, q) in qs.iter().enumerate() {
                            let i = c * SEARCH_CHUNK + k;
                            let r = radii[i];
                            // ask kiddo with a hair of slack, then decide with our own arithmetic
                            let hits =
                                tree.within_unsorted::<SquaredEuclidean>(q, r * r * (1.0 + 1e-12));
                            let start = flat.len();
                            flat.extend(hits.into_iter().map(|nn| nn.item).filter(|&j| {
                                j as usize != i
                                    && (points[i] - points[j as usize]).length_squared() <= r * r
                            }));
                            flat[start..].sort_unstable();
                            lens.push((flat.len() - start) as u32);
                        }
                        (flat, lens)
                    })
                    .collect();
                assemble(points.len(), chunks)
            }
        }
    };
}
kd_search!(crate::math::Vec1, 1, |p: crate::math::Vec1| [p.0]);
kd_search!(glam::DVec2, 2, |p: glam::DVec2| p.to_array());
kd_search!(glam::DVec3, 3, |p: glam::DVec3| p.to_array());
