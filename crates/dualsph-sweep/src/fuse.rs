//! Fusion: several terms of one sweep as one term, so that the sweep's row loop is compiled
//! for all of them together (the pair geometry formed once, the terms' contributions added
//! in registers and on the stack, no dynamic call per pair). A sweep whose terms are one
//! term — or one fused chain — runs that loop; otherwise each term is called once per two
//! pairs. The results are bitwise the same either way: the terms add their contributions
//! in the same order.
//!
//! A fusion is declared for two term types that follow each other in a sweep
//! ([`crate::SimSweeps::fuse`]); chains fuse left to right (`Fused<Fused<A, B>, C>`). Any
//! term written against the contract can be fused, a user's as well as the built-in ones.

use super::{Binder, BoundTerm, DynPairTerm, Out, PairLanes, PairSweeps, PairTerm};
use crate::pair::OwnerSums;
use bevy_ecs::prelude::*;
use dualsph_core::lanes::Lanes;
use dualsph_core::math::Vector;
use dualsph_core::sim::Sim;
use std::any::{Any, TypeId};
use std::sync::Arc;

/// Terms `A` then `B` as one term.
pub struct Fused<A, B> {
    a: Arc<A>,
    b: Arc<B>,
    name: String,
}

/// [`Fused`] bound for a sweep.
#[derive(Debug)]
pub struct FusedBound<A, B>(A, B);

impl<V: Vector, A: PairTerm<V>, B: PairTerm<V>> PairTerm<V> for Fused<A, B> {
    type Bound<'w> = FusedBound<A::Bound<'w>, B::Bound<'w>>;

    fn name(&self) -> &str {
        &self.name
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<Self::Bound<'w>, String> {
        Ok(FusedBound(self.a.bind(b)?, self.b.bind(b)?))
    }
}

impl<V: Vector, A: BoundTerm<V>, B: BoundTerm<V>> BoundTerm<V> for FusedBound<A, B> {
    type Owner = (A::Owner, B::Owner);
    const INITIALIZES: bool = A::INITIALIZES || B::INITIALIZES;

    #[inline(always)]
    fn owner(&self, i: usize) -> Self::Owner {
        (self.0.owner(i), self.1.owner(i))
    }

    #[inline(always)]
    fn interact<T: Lanes>(&self, o: &Self::Owner, p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        self.0.interact(&o.0, p, out);
        self.1.interact(&o.1, p, out);
    }

    #[inline(always)]
    fn initialize(&self, i: usize, sums: &mut OwnerSums<'_>) {
        self.0.initialize(i, sums);
        self.1.initialize(i, sums);
    }

    fn has_pairs(&self) -> bool {
        self.0.has_pairs() || self.1.has_pairs()
    }
}

/// Makes the fused term of two terms (which the rule checked are its `A` and `B`).
type Make<V> =
    fn(Arc<dyn Any + Send + Sync>, Arc<dyn Any + Send + Sync>) -> Arc<dyn DynPairTerm<V>>;

/// The fusions declared for a simulation: `(A, B, make)`.
#[derive(Resource)]
pub struct Fusions<V: Vector> {
    rules: Vec<(TypeId, TypeId, Make<V>)>,
}

impl<V: Vector> Default for Fusions<V> {
    fn default() -> Self {
        Fusions { rules: Vec::new() }
    }
}

fn make<V: Vector, A: PairTerm<V>, B: PairTerm<V>>(
    a: Arc<dyn Any + Send + Sync>,
    b: Arc<dyn Any + Send + Sync>,
) -> Arc<dyn DynPairTerm<V>> {
    let (Ok(a), Ok(b)) = (a.downcast::<A>(), b.downcast::<B>()) else {
        unreachable!("a fusion rule is applied to the types it was declared for")
    };
    let name = format!("{} + {}", a.name(), b.name());
    Arc::new(Fused { a, b, name })
}

impl<V: Vector> Fusions<V> {
    /// Declares the fusion of `A` followed by `B`.
    pub(crate) fn declare<A: PairTerm<V>, B: PairTerm<V>>(&mut self) {
        let rule = (
            TypeId::of::<A>(),
            TypeId::of::<B>(),
            make::<V, A, B> as Make<V>,
        );
        self.rules.push(rule);
    }
}

/// Applies the declared fusions to every sweep (at [`Sim::finish`]).
pub(crate) fn apply_fusions<V: Vector>(sim: &mut Sim<V>) {
    let Some(fusions) = sim.world.remove_resource::<Fusions<V>>() else {
        return;
    };
    let mut sweeps = sim.world.resource_mut::<PairSweeps<V>>();
    for sweep in &mut sweeps.sweeps {
        let mut out: Vec<Arc<dyn DynPairTerm<V>>> = Vec::new();
        for t in sweep.terms.drain(..) {
            let rule = out.last().and_then(|last| {
                let pair = (last.term_type(), t.term_type());
                fusions.rules.iter().find(|r| (r.0, r.1) == pair)
            });
            match rule {
                Some(&(_, _, make)) => {
                    let last = out.pop().expect("matched the last term");
                    out.push(make(last.into_any(), t.into_any()));
                }
                None => out.push(t),
            }
        }
        sweep.terms = out;
    }
    sim.world.insert_resource(fusions);
}
