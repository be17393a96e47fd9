//! Support and dual-support neighbour lists.
//!
//! The **support** of particle i is `H_i = { j : |r_ij| <= h_i }` (Eq. 3.1), found with a kiddo
//! k-d tree queried with each particle's *own* radius; it is stored as CSR. The
//! **dual-support** `H'_i = { j : i ∈ H_j }` (Eq. 3.2) is never searched for: it is the
//! transpose of the support lists, built by a counting sort, and each dual entry remembers the
//! slot of the support entry it mirrors so a pair value computed once in `H_i` can be read back
//! from j's side (§6).
//!
//! ## Rebuild rule (Verlet skin)
//! Lists are built with the enlarged radius `h_i (1 + s)` (`s` = skin). A pair outside that
//! radius at build time can only enter `H_i` after the two particles have approached each other
//! by more than `s·h_i >= s·h_min`, i.e. after `2·max_k |r_k − r_k^build| > s·h_min`. The lists
//! are therefore rebuilt only when that bound is crossed, or when any `h` changed (the
//! smoothing-length update marks them dirty). Between rebuilds the lists are a superset of the
//! exact supports; the sweep skips candidates with `r_ij > h_i`, which contribute nothing
//! because every kernel vanishes at `q >= 1`. With `s = 0` the lists are exactly `H_i`.

use crate::math::{Real, Vector};
use bevy_ecs::prelude::Resource;
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use rayon::prelude::*;

/// A compressed-sparse-row adjacency: row i is `indices[offsets[i]..offsets[i+1]]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Csr {
    /// Row starts, length n + 1.
    pub offsets: Vec<u32>,
    /// Column indices (particle indices), each row sorted ascending.
    pub indices: Vec<u32>,
}

impl Csr {
    /// Builds a CSR from per-row lists.
    pub fn from_rows(rows: Vec<Vec<u32>>) -> Self {
        let mut offsets = Vec::with_capacity(rows.len() + 1);
        offsets.push(0u32);
        let total: usize = rows.iter().map(Vec::len).sum();
        let mut indices = Vec::with_capacity(total);
        for r in rows {
            indices.extend_from_slice(&r);
            offsets.push(indices.len() as u32);
        }
        Csr { offsets, indices }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Row i.
    #[inline]
    pub fn row(&self, i: usize) -> &[u32] {
        &self.indices[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Range of slots of row i.
    #[inline]
    pub fn slots(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
    }

    /// The transpose (row j lists every i with j in row i, ascending) and, for each of its
    /// entries, the slot in `self` of the mirrored entry.
    pub fn transpose_with_slots(&self) -> (Csr, Vec<u32>) {
        let n = self.rows();
        let mut counts = vec![0u32; n + 1];
        for &j in &self.indices {
            counts[j as usize + 1] += 1;
        }
        for k in 0..n {
            counts[k + 1] += counts[k];
        }
        let offsets = counts.clone();
        let mut fill = counts;
        let mut indices = vec![0u32; self.indices.len()];
        let mut slots = vec![0u32; self.indices.len()];
        // rows i visited in ascending order, so each transposed row comes out sorted
        for i in 0..n {
            for s in self.slots(i) {
                let j = self.indices[s] as usize;
                let at = fill[j] as usize;
                indices[at] = i as u32;
                slots[at] = s as u32;
                fill[j] += 1;
            }
        }
        (Csr { offsets, indices }, slots)
    }
}

/// Fixed-radius search with a per-point radius, implemented for each vector type.
pub trait KdSearch: Sized {
    /// For every point i, the sorted indices `j != i` with `|x_i − x_j| <= radii[i]`, as a CSR
    /// (rows in point order).
    fn radius_csr(points: &[Self], radii: &[Real]) -> Csr;
}

/// Points per parallel work item of the search: each item fills one flat buffer (no `Vec`
/// per particle), and the buffers are concatenated in order.
const SEARCH_CHUNK: usize = 512;

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
                let total: usize = chunks.iter().map(|c| c.0.len()).sum();
                let mut offsets = Vec::with_capacity(points.len() + 1);
                let mut indices = Vec::with_capacity(total);
                offsets.push(0u32);
                for (flat, lens) in chunks {
                    indices.extend_from_slice(&flat);
                    for l in lens {
                        let last = *offsets.last().unwrap_or(&0);
                        offsets.push(last + l);
                    }
                }
                Csr { offsets, indices }
            }
        }
    };
}
kd_search!(crate::math::Vec1, 1, |p: crate::math::Vec1| [p.0]);
kd_search!(glam::DVec2, 2, |p: glam::DVec2| p.to_array());
kd_search!(glam::DVec3, 3, |p: glam::DVec3| p.to_array());

/// The neighbour lists of the current configuration and the state of the rebuild rule.
#[derive(Resource, Debug)]
pub struct Neighbours<V: Vector> {
    /// Candidate support lists (radius `h_i (1 + skin)`), a superset of `H_i`.
    pub support: Csr,
    /// Dual-support lists: the transpose of `support`.
    pub dual: Csr,
    /// For each dual entry, the slot in `support` of the same pair.
    pub dual_slot: Vec<u32>,
    /// Verlet skin `s` as a fraction of h.
    pub skin: Real,
    /// Positions at the last build.
    pub build_positions: Vec<V>,
    /// Smallest h at the last build.
    pub h_min: Real,
    /// Set when h changed; forces a rebuild.
    pub dirty: bool,
    /// Number of builds so far.
    pub builds: u64,
}

impl<V: Vector> Neighbours<V> {
    /// Empty lists with the given skin; the first `update` builds them.
    pub fn new(skin: Real) -> Self {
        Neighbours {
            support: Csr::default(),
            dual: Csr::default(),
            dual_slot: Vec::new(),
            skin,
            build_positions: Vec::new(),
            h_min: 0.0,
            dirty: true,
            builds: 0,
        }
    }

    /// True when the rebuild rule (module docs) requires new lists.
    pub fn needs_rebuild(&self, positions: &[V]) -> bool {
        if self.dirty || self.build_positions.len() != positions.len() {
            return true;
        }
        let max_d2 = positions
            .iter()
            .zip(&self.build_positions)
            .map(|(a, b)| (*a - *b).length_squared())
            .fold(0.0, Real::max);
        2.0 * max_d2.sqrt() > self.skin * self.h_min
    }

    /// Rebuilds the lists from scratch.
    pub fn rebuild(&mut self, positions: &[V], h: &[Real]) {
        let radii: Vec<Real> = h.iter().map(|&hi| hi * (1.0 + self.skin)).collect();
        // the old lists go first: never two generations in memory at once
        self.support = Csr::default();
        self.dual = Csr::default();
        self.dual_slot = Vec::new();
        self.support = V::radius_csr(positions, &radii);
        let (dual, slots) = self.support.transpose_with_slots();
        self.dual = dual;
        self.dual_slot = slots;
        self.build_positions = positions.to_vec();
        self.h_min = h.iter().copied().fold(Real::INFINITY, Real::min);
        self.dirty = false;
        self.builds += 1;
    }

    /// Rebuilds if the rule says so; returns whether it did.
    pub fn update(&mut self, positions: &[V], h: &[Real]) -> bool {
        if self.needs_rebuild(positions) {
            self.rebuild(positions, h);
            true
        } else {
            false
        }
    }
}

/// The exact support lists by brute force, O(n²): the reference the tests compare against.
pub fn brute_force_support<V: Vector>(positions: &[V], h: &[Real]) -> Csr {
    let rows = (0..positions.len())
        .map(|i| {
            (0..positions.len())
                .filter(|&j| {
                    j != i && (positions[i] - positions[j]).length_squared() <= h[i] * h[i]
                })
                .map(|j| j as u32)
                .collect()
        })
        .collect();
    Csr::from_rows(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec1;
    use glam::{DVec2, DVec3};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn cloud<V: Vector>(n: usize, seed: u64) -> (Vec<V>, Vec<Real>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let side = (n as Real).powf(1.0 / V::DIM as Real);
        let pos = (0..n)
            .map(|_| {
                let mut v = V::zero();
                for k in 0..V::DIM {
                    v.set(k, rng.random_range(0.0..side));
                }
                v
            })
            .collect();
        // h varies by a factor 8 between particles
        let h = (0..n).map(|_| rng.random_range(0.4..3.2)).collect();
        (pos, h)
    }

    fn check_dim<V: Vector>() {
        let (pos, h) = cloud::<V>(700, 7 + V::DIM as u64);
        let mut nb = Neighbours::<V>::new(0.0);
        nb.rebuild(&pos, &h);
        let exact = brute_force_support(&pos, &h);
        assert_eq!(
            nb.support,
            exact,
            "{}-D support lists differ from brute force",
            V::DIM
        );
        // dual-support = transpose, checked against its definition H'_j = { i : j ∈ H_i }
        let mut asymmetric = 0;
        for j in 0..pos.len() {
            let expect: Vec<u32> = (0..pos.len())
                .filter(|&i| i != j && (pos[i] - pos[j]).length_squared() <= h[i] * h[i])
                .map(|i| i as u32)
                .collect();
            assert_eq!(nb.dual.row(j), &expect[..]);
            for (k, &i) in nb.dual.row(j).iter().enumerate() {
                let slot = nb.dual_slot[nb.dual.offsets[j] as usize + k] as usize;
                assert_eq!(nb.support.indices[slot] as usize, j);
                assert!(nb.support.slots(i as usize).contains(&slot));
                if !nb.support.row(j).contains(&i) {
                    asymmetric += 1; // j ∈ H_i but i ∉ H_j
                }
            }
        }
        assert!(
            asymmetric > 50,
            "test cloud must contain one-sided pairs ({asymmetric})"
        );
    }

    #[test]
    fn support_lists_match_brute_force_1d_2d_3d() {
        check_dim::<Vec1>();
        check_dim::<DVec2>();
        check_dim::<DVec3>();
    }

    #[test]
    fn skin_lists_stay_supersets_until_rebuild_rule_fires() {
        let (mut pos, h) = cloud::<DVec2>(500, 3);
        let mut nb = Neighbours::<DVec2>::new(0.2);
        nb.rebuild(&pos, &h);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut rebuilt = 0;
        for _ in 0..40 {
            for p in &mut pos {
                *p += DVec2::new(rng.random_range(-0.01..0.01), rng.random_range(-0.01..0.01));
            }
            if nb.update(&pos, &h) {
                rebuilt += 1;
            }
            let exact = brute_force_support(&pos, &h);
            for i in 0..pos.len() {
                for j in exact.row(i) {
                    assert!(nb.support.row(i).contains(j), "pair ({i},{j}) missing");
                }
            }
        }
        assert!((1..40).contains(&rebuilt), "rebuilt {rebuilt} times");
        nb.dirty = true;
        assert!(nb.needs_rebuild(&pos));
    }

    #[test]
    fn lattice_with_many_equal_coordinates() {
        // k-d trees can choke on many identical coordinates: a square lattice has them.
        let pos: Vec<DVec2> = (0..80)
            .flat_map(|a| (0..80).map(move |b| DVec2::new(a as Real * 0.1, b as Real * 0.1)))
            .collect();
        let h = vec![0.15; pos.len()];
        let mut nb = Neighbours::<DVec2>::new(0.0);
        nb.rebuild(&pos, &h);
        assert_eq!(nb.support, brute_force_support(&pos, &h));
        assert_eq!(nb.support.row(81).len(), 8);
    }
}
