//! Specialised versions of bound terms ([`BoundTerm::specialise`]): what a version is handed
//! to, and a term by reference as a term (so that a fusion can hold its parts' versions). The
//! block loop run with a version is the sweep's (`crate::block`).

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
