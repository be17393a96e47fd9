//! `Refinement(..)`: adaptive resolution. Every `every` steps each particle of the refined
//! fluid bodies compares its size `Δx_i = (m_i/ρ_i)^{1/d}` (in a gas at the density it was
//! generated at, [`LadderSize::Nominal`]) with the size the scene asks for
//! where it is, the *target* ([`target`]), rounded down to the ladder of sizes
//! `coarsest·2^{-k}`: a particle larger than that splits into `2^d` children of half its
//! size, and two neighbouring particles of equal mass merge into one where the pair would
//! still be no larger than the target `buffer` beyond the regions ([`split`] gives the
//! arithmetic and what each conserves, [`apply`] the decisions and why nothing flips back
//! and forth).
//!
//! **Exact conservation.** A split keeps mass, momentum, angular momentum, kinetic, internal
//! and potential energy to round-off. A merge keeps mass and momentum to round-off; the
//! kinetic energy and angular momentum of the pair's relative motion are removed, reported
//! in `diagnostics.csv` (`merge_e_kin`, `merge_lz`) and, where the particles carry an
//! internal energy, the kinetic energy becomes heat (and is counted as dissipated), so the
//! total energy stays exact. Between decisions the dual-support sweep conserves exactly with
//! the particles' unequal smoothing lengths, as it does for any h field.
//!
//! **The target size** is the smallest the regions ask for, each region's `spacing` growing
//! by `grading` per unit distance away from it, within `[finest, coarsest]`. A region is a
//! box (moving at a velocity or not), the neighbourhood of a body, the neighbourhood of the
//! free surface (detected as the shifting plugin detects it), or where the gradient of the
//! density or of the velocity is steep.
//!
//! **Hysteresis.** A particle merges only where every region, grown by `buffer`, would
//! still leave the merged particle within its target: a particle does not split and merge
//! back as a region passes over it.
//!
//! **Every other column** of a child is its parent's (acceleration, rates, internal energy,
//! the integrator's records, a user's column), and of a merged particle the mass-weighted
//! mean of the two (see `dualsph_core::population`): per-unit-mass quantities stay
//! conserved, and a column that is recomputed every step (pressure, correction matrices) is
//! recomputed.
#![warn(missing_docs)]

pub mod apply;
pub mod density_error;
pub mod ladder;
pub mod settings;
pub mod split;
pub mod target;

pub use ladder::{LadderSize, NominalDensity};
pub use settings::{Indicator, Refinement, Region};

#[cfg(test)]
mod tests;
