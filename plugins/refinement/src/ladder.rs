//! The density at which a particle's size is read against the ladder of sizes: its density
//! now (liquids) or the density the scene generated it at (gases), and the column that keeps
//! the latter.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// The density at which a particle's size `(m/ρ)^{1/d}` is read where it is compared with
/// the ladder of sizes and its targets.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
pub enum LadderSize {
    /// Its density now: for liquids, whose density moves by per cents.
    #[default]
    Current,
    /// The density the scene generated it at (its block's `density`; a child's is its
    /// parent's): for gases, whose density moves by factors, so that expansion and
    /// compression do not move a particle along the ladder and only splits and merges do.
    /// The regions' sizes are then sizes at that density.
    Nominal,
}

/// A particle's nominal density: the density the scene generated it at, copied to the
/// children of a split (the column [`LadderSize::Nominal`] reads; kept in checkpoints).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct NominalDensity(pub Real);
dualsph_core::scalar_column!(NominalDensity);
