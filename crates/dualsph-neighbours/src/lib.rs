//! Support and dual-support neighbour lists, and sampling fields at arbitrary points
//! ([`sampling`]): everything that searches space. Depends on `dualsph-math` only.
//!
//! The **support** of particle i is `H_i = { j : |r_ij| <= h_i }` (Eq. 3.1), found by a
//! fixed-radius search with each particle's *own* radius; it is stored as CSR. The
//! **dual-support** `H'_i = { j : i ∈ H_j }` (Eq. 3.2) is never searched for: it is the
//! transpose of the support lists, built by a counting sort, and each dual entry remembers the
//! slot of the support entry it mirrors so a pair value computed once in `H_i` can be read back
//! from j's side (§6).
//!
//! ## Rebuild rule (Verlet skin)
//! Lists are built with the enlarged radius `h_i (1 + s)` (`s` = skin). A pair outside that
//! radius at build time can only enter `H_i` after the two particles have approached each other
//! by more than `s·h_i >= s·h_min`, i.e. after `2·max_k |r_k − r_k^build| > s·h_min`. When h
//! changes between builds the same argument holds with each particle's margin between its
//! build radius `R_i = h_i^build (1 + s)` and its current `h_i`: the lists stay supersets of
//! the supports while `2·max_k |r_k − r_k^build| <= min_i (R_i − h_i)` (the *slack*, `s·h_min`
//! just after a build; a smoothing-length update recomputes it with
//! [`Neighbours::h_changed`], and a particle whose h grew past its build radius forces a
//! rebuild). The lists are therefore rebuilt only when that bound is crossed. Between rebuilds
//! the lists are a superset of the exact supports; the sweep skips candidates with
//! `r_ij > h_i`, which contribute nothing because every kernel vanishes at `q >= 1`. With
//! `s = 0` the lists are exactly `H_i`.
//!
//! ## Two spatial indexes, one result
//! [`Neighbours::index`] selects the search ([`NeighbourIndex`]): kiddo's k-d tree
//! ([`KdTree`], `kd.rs`), which handles any input, or a uniform cell grid ([`GridPlan`],
//! `cells.rs`), several times faster when h varies little and the set is not sparse. Both keep
//! `j != i` with `(x_i − x_j).length_squared() <= r_i²` evaluated with the same arithmetic, and
//! sort each row ascending, so their lists are identical bit for bit (tested against each other
//! and brute force); `Auto` picks by [`auto_uses_grid`].

#![warn(missing_docs)]

use bevy_ecs::prelude::Resource;
use dualsph_math::{Real, Vector};
use rayon::prelude::*;

mod cells;
mod kd;
mod periodic;
pub mod sampling;
mod skin;
#[cfg(test)]
mod tests;

pub use cells::GridPlan;
pub use kd::{KdTree, kd_radius_csr};
pub use periodic::{Period, periodic_radius_csr, separation};
pub use skin::{SkinRule, optimal_skin};

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
    /// entries, the slot in `self` of the mirrored entry. The result is unique, so it does not
    /// depend on the thread count; with several rayon threads the output is filled in parallel
    /// over blocks of columns (each block owns a contiguous part of the output).
    pub fn transpose_with_slots(&self) -> (Csr, Vec<u32>) {
        let n = self.rows();
        let mut offsets = vec![0u32; n + 1];
        for &j in &self.indices {
            offsets[j as usize + 1] += 1;
        }
        for k in 0..n {
            offsets[k + 1] += offsets[k];
        }
        let mut indices = vec![0u32; self.indices.len()];
        let mut slots = vec![0u32; self.indices.len()];
        let threads = rayon::current_num_threads();
        if threads <= 1 || self.indices.len() < 1 << 16 {
            self.fill_transpose(0..n, &offsets, &mut indices, &mut slots);
        } else {
            // column blocks of about equal entry counts, each with its slice of the output
            let blocks = 4 * threads;
            let per = self.indices.len().div_ceil(blocks) as u32;
            let mut cuts = vec![0usize];
            for b in 1..blocks as u32 {
                let c = offsets.partition_point(|&o| o < b * per).min(n);
                if c > *cuts.last().unwrap_or(&0) {
                    cuts.push(c);
                }
            }
            cuts.push(n);
            let mut parts = Vec::with_capacity(cuts.len());
            let (mut rest_i, mut rest_s) = (&mut indices[..], &mut slots[..]);
            for w in cuts.windows(2) {
                let len = (offsets[w[1]] - offsets[w[0]]) as usize;
                let (a, b) = std::mem::take(&mut rest_i).split_at_mut(len);
                let (c, d) = std::mem::take(&mut rest_s).split_at_mut(len);
                parts.push((w[0]..w[1], a, c));
                (rest_i, rest_s) = (b, d);
            }
            parts.into_par_iter().for_each(|(cols, idx, sl)| {
                self.fill_transpose(cols, &offsets, idx, sl);
            });
        }
        (Csr { offsets, indices }, slots)
    }

    /// Fills the transposed rows of the columns `cols` into `indices`/`slots`, which start at
    /// `offsets[cols.start]`. Rows i are visited ascending, so each transposed row comes out
    /// sorted; a row whose (sorted) entries all lie outside `cols` is skipped at once.
    fn fill_transpose(
        &self,
        cols: std::ops::Range<usize>,
        offsets: &[u32],
        indices: &mut [u32],
        slots: &mut [u32],
    ) {
        let base = offsets[cols.start];
        let mut fill: Vec<u32> = offsets[cols.clone()].iter().map(|o| o - base).collect();
        let (c0, c1) = (cols.start as u32, cols.end as u32);
        for i in 0..self.rows() {
            let row = self.row(i);
            match (row.first(), row.last()) {
                (Some(&first), Some(&last)) if last >= c0 && first < c1 => {}
                _ => continue,
            }
            let from = if cols.start == 0 {
                0
            } else {
                row.partition_point(|&j| j < c0)
            };
            let s0 = self.offsets[i] as usize;
            for (k, &j) in row.iter().enumerate().skip(from) {
                if j >= c1 {
                    break;
                }
                let f = &mut fill[(j - c0) as usize];
                indices[*f as usize] = i as u32;
                slots[*f as usize] = (s0 + k) as u32;
                *f += 1;
            }
        }
    }
}

/// Points per parallel work item of a search: each item fills one flat buffer (no `Vec`
/// per particle), and the buffers are concatenated in order.
const SEARCH_CHUNK: usize = 512;

/// Concatenates per-chunk `(flat indices, row lengths)` (in point order) into one CSR.
fn assemble(n: usize, chunks: Vec<(Vec<u32>, Vec<u32>)>) -> Csr {
    let total: usize = chunks.iter().map(|c| c.0.len()).sum();
    let mut offsets = Vec::with_capacity(n + 1);
    let mut indices = Vec::with_capacity(total);
    offsets.push(0u32);
    let mut last = 0u32;
    for (flat, lens) in chunks {
        indices.extend_from_slice(&flat);
        for l in lens {
            last += l;
            offsets.push(last);
        }
    }
    Csr { offsets, indices }
}

/// The spatial index [`Neighbours::rebuild`] searches with. Both give the same lists, bit for
/// bit (same inclusion test, same arithmetic, rows ascending); they differ only in speed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NeighbourIndex {
    /// The cell grid when it applies to the current configuration ([`auto_uses_grid`]), kiddo
    /// otherwise.
    #[default]
    Auto,
    /// Always the cell grid ([`GridPlan`]), except for input it cannot handle (non-finite
    /// coordinates or radii, a bounding box of infinite extent), which goes to kiddo.
    CellGrid,
    /// Always kiddo's k-d tree ([`KdTree`]).
    KdTree,
}

/// `Auto` uses the grid only while `r_max / r_min` stays within this bound. Measured with the
/// `neighbour_index` example (12,800 particles, 1 thread, load 8): on a lattice with h_i spread
/// pseudo-randomly over `[h, k·h]` the grid was 3.2–3.5× (k = 2), 2.8–3.2× (k = 4) and
/// 2.5–2.9× (k = 8) faster than kiddo in 2-D and 3-D; beyond 8 it is not measured, so kiddo.
pub const AUTO_MAX_RADIUS_RATIO: Real = 8.0;

/// The rule of [`NeighbourIndex::Auto`]: the grid when its cells are no larger than the
/// largest radius (the cell budget of `4n + 64` did not force coarser cells: not a sparse,
/// clustered or widely spread set) and the radii vary by at most [`AUTO_MAX_RADIUS_RATIO`].
pub fn auto_uses_grid(plan: &GridPlan) -> bool {
    plan.cell <= plan.r_max * (1.0 + 1e-9) && plan.r_max <= AUTO_MAX_RADIUS_RATIO * plan.r_min
}

/// For every point i, the sorted indices `j != i` with
/// `(points[i] - points[j]).length_squared() <= radii[i]²`, as a CSR, with the index `index`
/// asks for; also returns the index used (`CellGrid` or `KdTree`, never `Auto`).
pub fn radius_csr<V: Vector>(
    points: &[V],
    radii: &[Real],
    index: NeighbourIndex,
) -> (Csr, NeighbourIndex) {
    let plan = match index {
        NeighbourIndex::KdTree => None,
        _ => GridPlan::auto(points, radii),
    };
    match plan {
        Some(p) if index == NeighbourIndex::CellGrid || auto_uses_grid(&p) => {
            (p.radius_csr(points, radii), NeighbourIndex::CellGrid)
        }
        _ => (kd_radius_csr(points, radii), NeighbourIndex::KdTree),
    }
}

/// The neighbour lists of the current configuration and the state of the rebuild rule.
#[derive(Resource, Debug)]
pub struct Neighbours<V: Vector> {
    /// Candidate support lists (radius `h_i (1 + skin)`), a superset of `H_i`.
    pub support: Csr,
    /// Dual-support lists: the transpose of `support`.
    pub dual: Csr,
    /// For each dual entry, the slot in `support` of the same pair.
    pub dual_slot: Vec<u32>,
    /// Verlet skin `s` as a fraction of h: the skin of the current lists.
    pub skin: Real,
    /// How the skin of each build is chosen (see [`SkinRule`]).
    pub rule: SkinRule,
    /// Calls of [`Neighbours::update`] (steps) since the last build.
    pub steps_since_build: u64,
    /// Positions at the last build.
    pub build_positions: Vec<V>,
    /// Smallest h at the last build.
    pub h_min: Real,
    /// Each particle's search radius at the last build, `R_i = h_i (1 + skin)`.
    pub build_radii: Vec<Real>,
    /// `min_i (R_i − h_i)` with the current h (module docs): how far two particles may
    /// approach each other before the lists can miss a pair.
    pub slack: Real,
    /// Set when the lists must be rebuilt whatever the motion (h changed beyond what the
    /// slack tracks, or the particles changed).
    pub dirty: bool,
    /// Number of builds so far.
    pub builds: u64,
    /// Names the current lists: a number no other lists of this process have had, new with
    /// every build and every [`Neighbours::set_lists`]. What is derived from the lists and
    /// kept between sweeps (a sweep's routes) is kept under it.
    pub generation: u64,
    /// The spatial index searched with (default `Auto`).
    pub index: NeighbourIndex,
    /// The index the last build used (`CellGrid` or `KdTree`; `None` before the first).
    pub used_index: Option<NeighbourIndex>,
    /// The periodic axes of the domain: pairs are found, and separated, across them.
    pub period: Option<Period<V>>,
}

/// A generation number for new lists (see [`Neighbours::generation`]).
fn next_generation() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

impl<V: Vector> Neighbours<V> {
    /// Replaces the lists (a restored checkpoint's): `dual` and `dual_slot` must be the
    /// transpose of `support` ([`Csr::transpose_with_slots`]).
    pub fn set_lists(&mut self, support: Csr, dual: Csr, dual_slot: Vec<u32>) {
        self.support = support;
        self.dual = dual;
        self.dual_slot = dual_slot;
        self.generation = next_generation();
    }

    /// Empty lists with the given fixed skin; the first `update` builds them.
    pub fn new(skin: Real) -> Self {
        Neighbours {
            support: Csr::default(),
            dual: Csr::default(),
            dual_slot: Vec::new(),
            skin,
            rule: SkinRule::Fixed,
            steps_since_build: 0,
            build_positions: Vec::new(),
            h_min: 0.0,
            build_radii: Vec::new(),
            slack: 0.0,
            dirty: true,
            builds: 0,
            generation: next_generation(),
            index: NeighbourIndex::Auto,
            used_index: None,
            period: None,
        }
    }

    /// The lists searched, and pairs separated, across the periodic axes of `period`.
    pub fn with_period(self, period: Option<Period<V>>) -> Self {
        Neighbours { period, ..self }
    }

    /// The separation `x_i − x_j` (its minimum image on periodic axes).
    #[inline(always)]
    pub fn separation(&self, xi: V, xj: V) -> V {
        separation(self.period.as_ref(), xi, xj)
    }

    /// Empty lists whose first build uses `skin` and later builds follow `rule`.
    pub fn with_rule(skin: Real, rule: SkinRule) -> Self {
        Neighbours {
            rule,
            ..Self::new(skin)
        }
    }

    /// The largest displacement since the last build, when the lists were built for these
    /// `n` particles (`at(i)` is i's position).
    fn max_displacement(&self, n: usize, at: impl Fn(usize) -> V) -> Option<Real> {
        if self.build_positions.is_empty() || self.build_positions.len() != n {
            return None;
        }
        let max_d2 = self
            .build_positions
            .iter()
            .enumerate()
            .map(|(i, b)| self.separation(at(i), *b).length_squared())
            // a comparison, not `f64::max`: the same value (both skip a NaN; no square is -0), and the
            // loop stays a plain compare-and-select (f64::max cost 35 instructions per
            // particle here, the neighbour update 25 % more, callgrind)
            .fold(0.0, |m, d| if d > m { d } else { m });
        Some(max_d2.sqrt())
    }

    /// True when the rebuild rule (module docs) requires new lists.
    pub fn needs_rebuild(&self, positions: &[V]) -> bool {
        self.needs_rebuild_with(positions.len(), |i| positions[i])
    }

    /// [`Neighbours::needs_rebuild`] for `n` particles whose positions are `at(i)`.
    pub fn needs_rebuild_with(&self, n: usize, at: impl Fn(usize) -> V) -> bool {
        self.rule_fires(self.max_displacement(n, at))
    }

    /// The rebuild rule for the largest displacement `d` since the last build (`None`: no
    /// lists for these particles yet).
    fn rule_fires(&self, d: Option<Real>) -> bool {
        // a NaN slack (an h that is not a number at the build) fires the rule instead of
        // keeping the lists for ever
        d.is_none_or(|d| self.dirty || self.slack.is_nan() || 2.0 * d > self.slack)
    }

    /// Records that the particles' support radii are now `h` (in row order): the slack
    /// shrinks by what any h grew (module docs), and the lists are marked for a rebuild when
    /// they were built for other particles or an h outgrew its build radius.
    pub fn h_changed(&mut self, h: &[Real]) {
        if self.build_radii.len() != h.len() {
            self.dirty = true;
            return;
        }
        self.slack = slack(&self.build_radii, h);
        if self.slack.is_nan() || self.slack < 0.0 {
            self.dirty = true;
        }
    }

    /// Drops the lists because the particles changed (rows were added or removed): no loop
    /// can read stale rows, and the next [`Neighbours::update`] builds new lists.
    pub fn invalidate(&mut self) {
        self.support = Csr::default();
        self.dual = Csr::default();
        self.dual_slot = Vec::new();
        self.build_positions = Vec::new();
        self.build_radii = Vec::new();
        self.dirty = true;
    }

    /// Rebuilds the lists from scratch.
    pub fn rebuild(&mut self, positions: &[V], h: &[Real]) {
        let radii: Vec<Real> = h.iter().map(|&hi| hi * (1.0 + self.skin)).collect();
        // the old lists go first: never two generations in memory at once
        self.support = Csr::default();
        self.dual = Csr::default();
        self.dual_slot = Vec::new();
        let (support, used) = match &self.period {
            Some(p) => periodic_radius_csr(positions, &radii, self.index, p),
            None => radius_csr(positions, &radii, self.index),
        };
        self.support = support;
        self.used_index = Some(used);
        let (dual, slots) = self.support.transpose_with_slots();
        self.dual = dual;
        self.dual_slot = slots;
        self.generation = next_generation();
        self.build_positions = positions.to_vec();
        self.h_min = h.iter().copied().fold(Real::INFINITY, Real::min);
        self.slack = slack(&radii, h);
        self.build_radii = radii;
        self.dirty = false;
        self.builds += 1;
        self.steps_since_build = 0;
    }

    /// Called once per step: rebuilds if the rule says so, or, with [`SkinRule::Tuned`], when
    /// a rebuild with the optimal skin is cheaper than keeping the lists
    /// (`skin::retune_now`); a tuned rebuild first sets the skin to
    /// [`optimal_skin`] of the motion measured since the last build. Returns whether it
    /// rebuilt.
    pub fn update(&mut self, positions: &[V], h: &[Real]) -> bool {
        self.update_with(
            positions.len(),
            |i| positions[i],
            |p, r| {
                p.extend_from_slice(positions);
                r.extend_from_slice(h);
            },
        )
    }

    /// [`Neighbours::update`] for `n` particles whose positions are `at(i)`: `fill` puts the
    /// positions and support radii into the two (empty) vectors, and is called only when the
    /// lists are rebuilt (the rebuild reads them many times).
    pub fn update_with(
        &mut self,
        n: usize,
        at: impl Fn(usize) -> V,
        fill: impl FnOnce(&mut Vec<V>, &mut Vec<Real>),
    ) -> bool {
        self.steps_since_build += 1;
        let d = self.max_displacement(n, at);
        let rule = self.rule_fires(d);
        let steps = self.steps_since_build;
        let u = match (self.rule, d) {
            (SkinRule::Tuned, Some(d)) => Some(skin::motion_rate(d, self.h_min, steps)),
            _ => None,
        };
        let early = u.is_some_and(|u| skin::retune_now(self.skin, u, steps, V::DIM));
        if !(rule || early) {
            return false;
        }
        if let Some(u) = u {
            self.skin = optimal_skin(u, V::DIM);
        }
        let (mut positions, mut h) = (Vec::with_capacity(n), Vec::with_capacity(n));
        fill(&mut positions, &mut h);
        self.rebuild(&positions, &h);
        true
    }
}

/// `min_i (R_i − h_i)`: the least margin between a build radius and the current h (NaN
/// when an h is not a number; infinity without particles).
fn slack(radii: &[Real], h: &[Real]) -> Real {
    radii
        .iter()
        .zip(h)
        .map(|(r, h)| r - h)
        .fold(
            Real::INFINITY,
            |m, x| if x < m || x.is_nan() { x } else { m },
        )
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
