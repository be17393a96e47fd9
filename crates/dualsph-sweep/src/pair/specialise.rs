//! Specialised versions of bound terms ([`BoundTerm::specialise`]): what a version is handed
//! to, a term by reference as a term (so that a fusion can hold its parts' versions), and the
//! block loop run with a version.

use super::{BoundTerm, Out, OwnerSums, PairLanes};
use dualsph_core::lanes::Lanes;
use dualsph_core::math::Vector;

/// What runs with the version of a term that [`BoundTerm::specialise`] hands over.
pub trait Specialised<V: Vector> {
    /// What it gives.
    type Out;
    /// Runs with `term`.
    fn with<B: BoundTerm<V>>(self, term: &B) -> Self::Out;
}

/// A bound term by reference is the term (so that a fusion can hold its parts' versions).
impl<V: Vector, B: BoundTerm<V>> BoundTerm<V> for &B {
    type Owner = B::Owner;
    const INITIALIZES: bool = B::INITIALIZES;

    #[inline(always)]
    fn owner(&self, i: usize) -> Self::Owner {
        (**self).owner(i)
    }

    #[inline(always)]
    fn interact<T: Lanes>(&self, o: &Self::Owner, p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        (**self).interact(o, p, out)
    }

    #[inline(always)]
    fn initialize(&self, i: usize, sums: &mut OwnerSums<'_>) {
        (**self).initialize(i, sums)
    }

    fn has_pairs(&self) -> bool {
        (**self).has_pairs()
    }
}

/// Runs one block of a sweep with the term [`BoundTerm::specialise`] hands over.
pub(super) struct RunBlock<'r, 'a, 'w, 'b, V: Vector> {
    pub(super) sweep: &'r crate::block::Sweep<'a, 'w, V>,
    pub(super) block: crate::block::Block<'b>,
    pub(super) s: &'r mut crate::row::RowScratch<V>,
}

impl<V: Vector> Specialised<V> for RunBlock<'_, '_, '_, '_, V> {
    type Out = Vec<u32>;

    #[inline(always)]
    fn with<B: BoundTerm<V>>(self, term: &B) -> Vec<u32> {
        let rows = crate::block::OneTermRows(term);
        crate::block::run_block(self.sweep, &rows, self.block, self.s)
    }
}
