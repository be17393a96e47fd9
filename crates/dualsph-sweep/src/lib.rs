//! The pair layer of dualsph: the pair-term contract ([`pair`]), the sums a sweep writes
//! into columns ([`accum`]) and the support / dual-support pair sweep (Ren et al.,
//! Dual-support SPH, §6). It builds on `dualsph-core` (the ECS layer) and extends [`Sim`](dualsph_core::sim::Sim) with
//! [`SimSweeps`]; a plugin that adds pair terms imports [`prelude`].
//!
//! # The sweep
//!
//! For every `j ∈ H_i` a pair quantity is evaluated **once** with i's kernel
//! (`W_ij = w(r_ij/h_i)`, `∇_i W_ij`); i receives it and j receives the reaction through its
//! dual-support `H'_j`. Implementation, free of atomics and data races:
//!
//! 1. in parallel over i, loop over i's support slots, evaluate every [`PairTerm`] of the
//!    sweep, add the results to i's own sums and store the reactions in a per-slot buffer;
//! 2. in parallel over j, gather the stored reactions through the transposed (dual-support)
//!    list, in ascending order of i.
//!
//! What a sweep sums is open: every term declares its sums when it is bound
//! ([`crate::accum`]), and the sweep stores per support slot only the channels that reach j
//! ([`Reaction`]). A plugin can add terms to the force sweep of the step ([`FORCES`]) or to a
//! sweep of its own at its own place ([`SimSweeps::add_pair_term_to`]).
//!
//! Every particle's sums are formed in a fixed order that does not depend on the number of
//! threads, so results are bitwise identical on 1 or N threads, and because each pair's
//! action and reaction are the same stored numbers with opposite sign, linear momentum (and
//! the energy exchanged by each pair) balances to round-off for any field of h.
//!
//! [`Formulation`] selects the paper's comparison cases:
//! * `DualSupport` — the method;
//! * `SingleSupport` — variable h, each particle sums the full classical expression over its own
//!   support only with its own kernel, no reaction (paper Cases I/II): the classical term
//!   `F_i = Σ_{j∈H_i} [T(i←j; ∇_iW_ij(h_i)) − T(j←i; −∇_iW_ij(h_i))]`;
//! * `ConstantH` — classical SPH with one h (run with the dual-support sweep, to which it is
//!   identical when every h is equal);
//! * `AveragedKernel` — the conventional reference, Eq. 2.13:
//!   `W̄_ij = ½[W(r, h_i) + W(r, h_j)]` over `H_i ∪ H'_i`, classical symmetric sums;
//! * `GradH` — grad-h SPH: `−m_i m_j [P_i/(Ω_i ρ_i²) ∇_iW_ij(h_i) + P_j/(Ω_j ρ_j²) ∇_iW_ij(h_j)]`
//!   is the sum of two support/dual-support pairs (i's term in `H_i`, j's in `H_j` with its
//!   reaction on i), so it runs on the dual-support sweep with `P/(Ωρ²)` as the owner's factor.

pub use crate::block::RowTerm;
pub use crate::ctx::{GradientCorrection, Support, SweepCtx};
pub use crate::erased::DynPairTerm;
pub use crate::pair::{
    Acc, Binder, BoundTerm, Out, OwnerKernel, PairLanes, PairTerm, ParticleData, Reaction,
};
pub use crate::sweep::{SweepBuffers, bind, evaluate};
pub use dualsph_core::sim::Formulation;

pub mod accum;
pub mod pair;

#[doc(hidden)]
pub mod block;
mod checks;
mod classical;
mod ctx;
mod erased;
mod fuse;
mod sweep;
mod system;
pub use checks::{
    check_block_loop_2d, check_block_loop_2d_with, check_lanes_2d, check_lanes_2d_with, lattice_2d,
};
pub use fuse::{Fused, FusedBound, Fusions};
pub use system::{FORCES, ForceSweep, PairSweep, PairSweeps, SimSweeps, sweep_into};

/// The most used items of the pair layer and of the core below it: what a plugin that adds
/// pair terms imports.
pub mod prelude {
    pub use crate::accum::{Acc, Binder, Reaction};
    pub use crate::pair::{BoundTerm, Out, OwnerSums, PairLanes, PairTerm};
    pub use crate::{FORCES, GradientCorrection, OwnerKernel, SimSweeps, SweepCtx};
    pub use dualsph_core::prelude::*;
}
