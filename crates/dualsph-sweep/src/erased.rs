//! A [`PairTerm`] with its type erased, as a sweep's list holds it ([`DynPairTerm`]); bound
//! to the particles it is a [`RowTerm`].

use crate::block::RowTerm;
use crate::pair::{Binder, PairTerm};
use dualsph_core::math::Vector;

/// A [`PairTerm`] with its type erased, as a sweep's list holds it.
pub trait DynPairTerm<V: Vector>: Send + Sync {
    /// See [`PairTerm::name`].
    fn name(&self) -> &str;
    /// The term's type.
    fn term_type(&self) -> std::any::TypeId;
    /// The term as `Any` (to be fused with another, see [`crate::Fused`]).
    fn into_any(self: std::sync::Arc<Self>) -> std::sync::Arc<dyn std::any::Any + Send + Sync>;
    /// See [`PairTerm::bind`].
    fn bind_dyn<'w>(
        &'w self,
        b: &mut Binder<'_, 'w, V>,
    ) -> Result<Box<dyn RowTerm<V> + 'w>, String>;
}

impl<V: Vector, T: PairTerm<V>> DynPairTerm<V> for T {
    fn name(&self) -> &str {
        PairTerm::name(self)
    }
    fn term_type(&self) -> std::any::TypeId {
        std::any::TypeId::of::<T>()
    }
    fn into_any(self: std::sync::Arc<Self>) -> std::sync::Arc<dyn std::any::Any + Send + Sync> {
        self
    }
    fn bind_dyn<'w>(
        &'w self,
        b: &mut Binder<'_, 'w, V>,
    ) -> Result<Box<dyn RowTerm<V> + 'w>, String> {
        Ok(Box::new(self.bind(b)?))
    }
}
