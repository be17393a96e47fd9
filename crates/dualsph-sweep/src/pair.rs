//! The pair-term contract: a [`PairTerm`] declares, when it is bound for a sweep
//! ([`PairTerm::bind`] with a [`Binder`]), the columns it reads and the sums it writes
//! ([`crate::accum`]); its [`BoundTerm`] then adds, for one pair or two side by side
//! ([`Lanes`]), its contributions to the owner i and to the neighbour j ([`Out`]), from what
//! the sweep has formed for the pair ([`PairLanes`]). The sweep itself is in
//! [the sweep](crate), which runs every term of one place over each owner's support in one pass
//! and delivers each contribution to j through j's dual-support.

pub use crate::accum::{
    Acc, Binder, MAX_NEIGHBOUR_CHANNELS, MAX_OWNER_CHANNELS, Reaction, SCALAR_REGISTERS,
};
use dualsph_core::lanes::{LaneVec, Lanes};
use dualsph_core::math::{Matrix, Real, Vector};
pub use dualsph_core::store::ParticleData;

/// The value of an [`Out`] channel before any term adds to it: `−0`, not `+0`, because
/// `−0 + x` is `x` for every `x` (`+0 + x` turns a `−0` into `+0`), so the compiler drops the
/// first addition of every channel. The sign of an empty channel never shows: the sums it
/// goes into start at `+0` and only ever add, and a sum that starts at `+0` is never `−0`, so
/// adding `−0` or `+0` to it gives the same bits.
pub const EMPTY: Real = -0.0;

/// `T::N` pairs of one owner i (one per lane), as a term's [`BoundTerm::interact`] reads them:
/// the pair geometry the sweep formed once for all terms, and gathers of any column at the
/// lanes' neighbours.
#[derive(Clone, Copy, Debug)]
pub struct PairLanes<'a, T: Lanes, V: Vector> {
    i: usize,
    j: [u32; 2],
    rij: LaneVec<T>,
    r: T,
    vij: LaneVec<T>,
    grad_raw: LaneVec<T>,
    grad: LaneVec<T>,
    w: Option<T>,
    kernel: OwnerKernel,
    data: &'a ParticleData<'a, V>,
    /// The particle count, to which every gathered column is cut (see [`Self::gather`]).
    n: usize,
    /// True when `grad` is corrected (see [`Self::corrected`]).
    corrected: bool,
}

/// The geometry of `T::N` pairs of one owner: `(r_ij, |r_ij|, v_ij, ∇_iW_ij, L_i∇_iW_ij)`.
pub type Geometry<T> = (LaneVec<T>, T, LaneVec<T>, LaneVec<T>, LaneVec<T>);

impl<'a, T: Lanes, V: Vector> PairLanes<'a, T, V> {
    /// The pairs (i, `j[l]`) with their geometry; `W_ij` given (`w`) or, if `None`, from the
    /// owner's kernel on demand; `corrected` when the geometry's `L_i∇_iW_ij` applies the
    /// kernel-gradient correction.
    #[inline(always)]
    pub fn new(
        (i, j): (usize, [u32; 2]),
        (rij, r, vij, grad_raw, grad): Geometry<T>,
        (w, corrected): (Option<T>, bool),
        kernel: OwnerKernel,
        data: &'a ParticleData<'a, V>,
    ) -> Self {
        PairLanes {
            i,
            j,
            rij,
            r,
            vij,
            grad_raw,
            grad,
            w,
            kernel,
            data,
            n: data.len(),
            corrected,
        }
    }

    /// The same pairs with the particle count `n` given by the caller (`data.len()`, read
    /// once per row), so that the gathers of a whole row check against one value.
    #[inline(always)]
    pub(crate) fn with_len(mut self, n: usize) -> Self {
        debug_assert_eq!(n, self.data.len());
        self.n = n;
        self
    }

    /// The owner i.
    #[inline(always)]
    pub fn i(&self) -> usize {
        self.i
    }

    /// The neighbour of lane `l`.
    #[inline(always)]
    pub fn j(&self, l: usize) -> usize {
        self.j[l] as usize
    }

    /// The particles' core columns.
    #[inline(always)]
    pub fn data(&self) -> &'a ParticleData<'a, V> {
        self.data
    }

    /// `r_ij = r_i − r_j`.
    #[inline(always)]
    pub fn rij(&self) -> LaneVec<T> {
        self.rij
    }

    /// `|r_ij|`.
    #[inline(always)]
    pub fn r(&self) -> T {
        self.r
    }

    /// `v_ij = v_i − v_j`.
    #[inline(always)]
    pub fn vij(&self) -> LaneVec<T> {
        self.vij
    }

    /// `∇_iW_ij` (Eq. 2.2).
    #[inline(always)]
    pub fn grad_raw(&self) -> LaneVec<T> {
        self.grad_raw
    }

    /// `(1/r) ∂W/∂r` of the owner's kernel (so that `∇_iW_ij = r_ij ·` this; zero at `r = 0`).
    #[inline(always)]
    pub fn grad_factor(&self) -> T {
        self.kernel.grad_factor_lanes(self.r)
    }

    /// `L_i ∇_iW_ij` with the kernel-gradient correction (Eq. 2.10) when the scene computes
    /// it, `∇_iW_ij` otherwise.
    #[inline(always)]
    pub fn grad(&self) -> LaneVec<T> {
        self.grad
    }

    /// True when [`Self::grad`] is `L_i∇_iW_ij`, the scene applying the kernel-gradient
    /// correction (Eq. 2.10). The sweep's row loop is compiled for either case, so a term
    /// that tests this has no test left per pair.
    #[inline(always)]
    pub fn corrected(&self) -> bool {
        self.corrected
    }

    /// `W_ij` (Eq. 2.1).
    #[inline(always)]
    pub fn w(&self) -> T {
        match self.w {
            Some(w) => w,
            None => T::from_fn(|l| self.kernel.w(self.r.lane(l))),
        }
    }

    /// The owner's kernel.
    #[inline(always)]
    pub fn kernel(&self) -> OwnerKernel {
        self.kernel
    }

    /// `f(column[j])` in every lane: a gather of any column at the lanes' neighbours.
    ///
    /// The column is first cut to the particle count, so that every gather of a row checks
    /// j against the same length: the compiler keeps one bounds check per neighbour for all
    /// the columns a sweep reads, and the cut itself is the same for every pair of the row.
    #[inline(always)]
    pub fn gather<C>(&self, column: &[C], f: impl Fn(&C) -> Real) -> T {
        let column = &column[..self.n];
        T::from_fn(|l| f(&column[self.j[l] as usize]))
    }

    /// `f(column[j])` in every lane, for a vector-valued column (see [`Self::gather`]).
    #[inline(always)]
    pub fn gather_vec<C>(&self, column: &[C], f: impl Fn(&C) -> V) -> LaneVec<T> {
        let column = &column[..self.n];
        LaneVec::from_fn(|l| f(&column[self.j[l] as usize]))
    }

    /// `m_j`.
    #[inline(always)]
    pub fn m_j(&self) -> T {
        self.gather(self.data.mass, |m| m.0)
    }

    /// `ρ_j`.
    #[inline(always)]
    pub fn rho_j(&self) -> T {
        self.gather(self.data.rho, |r| r.0)
    }
}

/// What the terms of a sweep give for `T::N` pairs, [`EMPTY`] before the first term: the sums
/// it keeps in registers by place (the force, and the [`SCALAR_REGISTERS`] scalars to the
/// owner and to the neighbour: see [`crate::accum::Standard`]), and the channels of the
/// sweep's other accumulators ([`Acc`], see [`crate::accum`]).
#[derive(Debug)]
pub struct Out<'e, T: Lanes> {
    pub(crate) force: LaneVec<T>,
    pub(crate) scalar: [T; SCALAR_REGISTERS],
    pub(crate) scalar_j: [T; SCALAR_REGISTERS],
    pub(crate) extra: &'e mut Extra<T>,
}

/// The channels of a sweep's non-standard accumulators, apart from [`Out`]'s registers so
/// that those stay in registers.
#[derive(Clone, Copy, Debug)]
pub struct Extra<T: Lanes> {
    pub(crate) own: [T; MAX_OWNER_CHANNELS],
    pub(crate) nbr: [T; MAX_NEIGHBOUR_CHANNELS],
}

impl<T: Lanes> Default for Extra<T> {
    fn default() -> Self {
        let z = T::splat(EMPTY);
        Extra {
            own: [z; MAX_OWNER_CHANNELS],
            nbr: [z; MAX_NEIGHBOUR_CHANNELS],
        }
    }
}

impl<'e, T: Lanes> Out<'e, T> {
    /// Empty sums ([`EMPTY`]), the non-standard ones in `extra` (which must be empty).
    #[inline(always)]
    pub fn new(extra: &'e mut Extra<T>) -> Self {
        let z = T::splat(EMPTY);
        Out {
            force: LaneVec([z; 3]),
            scalar: [z; SCALAR_REGISTERS],
            scalar_j: [z; SCALAR_REGISTERS],
            extra,
        }
    }

    /// Empties the registers (the sweep does, after each lane group).
    #[inline(always)]
    pub(crate) fn clear_registers(&mut self) {
        let z = T::splat(EMPTY);
        self.force = LaneVec([z; 3]);
        self.scalar = [z; SCALAR_REGISTERS];
        self.scalar_j = [z; SCALAR_REGISTERS];
    }

    /// Adds `f` to the force on the owner (its reaction `−f` goes to the neighbour); the term
    /// declares it with [`Binder::force`].
    #[inline(always)]
    pub fn add_force<V: Vector>(&mut self, f: LaneVec<T>) {
        self.force = self.force.plus::<V>(f);
    }

    /// Adds `v` to the owner's scalar register `K` ([`Binder::scalar_register`]).
    #[inline(always)]
    pub fn add_scalar<const K: usize>(&mut self, v: T) {
        self.scalar[K] = self.scalar[K] + v;
    }

    /// Adds `v` to the neighbour's scalar register `K` ([`Binder::scalar_register`] with
    /// [`Reaction::Separate`]).
    #[inline(always)]
    pub fn react_scalar<const K: usize>(&mut self, v: T) {
        self.scalar_j[K] = self.scalar_j[K] + v;
    }

    #[inline(always)]
    fn own_at(&mut self, c: usize, v: T) {
        let x = &mut self.extra.own[c % MAX_OWNER_CHANNELS];
        *x = *x + v;
    }

    /// Adds `v` to the owner's scalar sum `acc`.
    #[inline(always)]
    pub fn add(&mut self, acc: Acc, v: T) {
        self.own_at(acc.i as usize, v);
    }

    /// Adds `v` to the owner's vector sum `acc` (`d` components).
    #[inline(always)]
    pub fn add_vec<V: Vector>(&mut self, acc: Acc, v: LaneVec<T>) {
        for c in 0..V::DIM {
            self.own_at(acc.i as usize + c, v.0[c]);
        }
    }

    /// Adds `m(l)` to the owner's matrix sum `acc` in lane `l` (`d × d` entries, row-major).
    #[inline(always)]
    pub fn add_mat<V: Vector>(&mut self, acc: Acc, m: impl Fn(usize) -> V::Mat) {
        let d = V::DIM;
        let ms: [V::Mat; 2] = [m(0), m(T::N - 1)];
        for a in 0..d {
            for b in 0..d {
                let v = T::from_fn(|l| ms[l].entry(a, b));
                self.own_at(acc.i as usize + a * d + b, v);
            }
        }
    }

    /// Adds `v` to the neighbour's scalar sum `acc` (an accumulator with
    /// [`Reaction::Separate`]): what j receives from this pair through its dual-support.
    #[inline(always)]
    pub fn react(&mut self, acc: Acc, v: T) {
        debug_assert!(
            acc.j != u16::MAX,
            "react on an accumulator without Separate"
        );
        let x = &mut self.extra.nbr[acc.j as usize % MAX_NEIGHBOUR_CHANNELS];
        *x = *x + v;
    }

    /// Adds `v` to the neighbour's vector sum `acc` ([`Reaction::Separate`]).
    #[inline(always)]
    pub fn react_vec<V: Vector>(&mut self, acc: Acc, v: LaneVec<T>) {
        debug_assert!(
            acc.j != u16::MAX,
            "react on an accumulator without Separate"
        );
        for c in 0..V::DIM {
            let x = &mut self.extra.nbr[(acc.j as usize + c) % MAX_NEIGHBOUR_CHANNELS];
            *x = *x + v.0[c];
        }
    }

    /// Component `c` of accumulator `s` for the owner.
    #[inline(always)]
    pub fn owner_value(&self, s: &crate::accum::AccumulatorSlot, c: usize) -> T {
        use crate::accum::Standard;
        match s.standard {
            Some(Standard::Force) => self.force.0[c],
            Some(Standard::Scalar(k)) => self.scalar[k],
            None => self.extra.own[s.chan + c],
        }
    }

    /// Component `c` of accumulator `s` for the neighbour (zero without one).
    #[inline(always)]
    pub fn neighbour_value(&self, s: &crate::accum::AccumulatorSlot, c: usize) -> T {
        use crate::accum::Standard;
        match s.standard {
            Some(Standard::Force) => -self.force.0[c],
            Some(Standard::Scalar(k)) => self.scalar_j[k],
            None => match (s.reaction, s.j) {
                (Reaction::Opposite, _) => -self.extra.own[s.chan + c],
                (_, Some(j)) => self.extra.nbr[j + c],
                _ => T::splat(0.0),
            },
        }
    }
}

/// The owner's sums before any pair (see [`BoundTerm::initialize`]).
#[derive(Debug)]
pub struct OwnerSums<'b> {
    sums: &'b mut [Real],
    layout: &'b crate::accum::Layout,
}

impl<'b> OwnerSums<'b> {
    /// The sums of one particle in a sweep with `layout`.
    pub fn new(sums: &'b mut [Real], layout: &'b crate::accum::Layout) -> Self {
        OwnerSums { sums, layout }
    }

    /// Adds `v` to the scalar sum `acc`.
    #[inline(always)]
    pub fn add(&mut self, acc: Acc, v: Real) {
        self.sums[acc.at as usize] += v;
    }

    /// Adds `v` to the vector sum `acc`.
    #[inline(always)]
    pub fn add_vec<V: Vector>(&mut self, acc: Acc, v: V) {
        for c in 0..V::DIM {
            self.sums[acc.at as usize + c] += v.get(c);
        }
    }

    /// Adds `v` to scalar register `K` ([`Binder::scalar_register`]).
    pub fn add_scalar<const K: usize>(&mut self, v: Real) {
        use crate::accum::Standard;
        if let Some(s) = self.layout.standard(Standard::Scalar(K)) {
            self.sums[s.i] += v;
        }
    }
}

/// A physics term that joins a pair sweep. For the pair (i owner, `j ∈ H_i`, evaluated once
/// with i's kernel) it adds its contributions to i's sums and, through j's dual-support, to
/// j's ([`Reaction`]); it inherits the sweep's conservation and determinism.
///
/// Once per sweep the term is **bound** ([`PairTerm::bind`]): it fetches the columns it reads
/// beyond the core ones (`b.require::<Pressure>()`) and declares the sums it writes
/// (`b.force()`, a scalar register with [`Binder::scalar_register`], or any column with
/// [`Binder::accumulate`]);
/// a missing column is a build error naming the term.
pub trait PairTerm<V: Vector>: Send + Sync + 'static {
    /// The term bound to its columns and sums for one sweep.
    type Bound<'w>: BoundTerm<V> + 'w;
    /// Name shown by `plan`.
    fn name(&self) -> &str;
    /// Binds the columns the term reads and declares the sums it writes (once per sweep).
    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<Self::Bound<'w>, String>;
}

/// A [`PairTerm`] bound for one sweep.
///
/// [`BoundTerm::interact`] is written once over [`Lanes`]: the sweep calls it two pairs at a
/// time (`f64x2`) and for an odd last pair alone (`f64`), with the same operations lane by
/// lane, so a term written this way is vectorised and bitwise the same on either path
/// ([`crate::check_lanes_2d`] tests a term for it).
pub trait BoundTerm<V: Vector>: Sync {
    /// What the term computes once per owner i for all of i's pairs (i's factors); `()`
    /// for a term with none.
    type Owner: Copy;

    /// The owner's part of the term, computed once per owner row.
    fn owner(&self, i: usize) -> Self::Owner;

    /// Adds the term's contributions for the lanes' pairs, `o` being [`BoundTerm::owner`]
    /// of their owner.
    fn interact<T: Lanes>(&self, o: &Self::Owner, p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>);

    /// True when the term overrides [`BoundTerm::initialize`] (the sweep skips the call
    /// otherwise).
    const INITIALIZES: bool = false;

    /// Adds the term's per-particle part to i's sums before any pair (e.g. the self term of
    /// a summation); nothing by default. A term that overrides it sets
    /// [`BoundTerm::INITIALIZES`].
    #[inline(always)]
    fn initialize(&self, _i: usize, _sums: &mut OwnerSums<'_>) {}

    /// False for a term with no pair part (only [`BoundTerm::initialize`]).
    fn has_pairs(&self) -> bool {
        true
    }
}

mod owner_kernel;
pub use owner_kernel::OwnerKernel;

#[cfg(test)]
mod tests;
