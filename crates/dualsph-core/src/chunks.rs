//! The light per-particle loops (predictor, corrector, EOS, write-backs, dt and health
//! reductions) run over bevy's contiguous table slices (`Query::contiguous_iter_mut`) and are
//! split across the rayon pool that runs the pair sweep.
//!
//! A per-entity query loop costs a fetch per entity, and bevy's `par_iter_mut` calls its
//! closure per entity without inlining it (~80 instructions per particle, more than these
//! updates cost). On slices the loops are plain array loops, and rayon splits them into pieces
//! of at least [`MIN_LEN`] particles. Every update is per particle and every reduction is a
//! minimum (exact and order-free), so the results are bitwise the same on any number of
//! threads.
//!
//! The engine reads no change ticks (`Changed<C>`): its loops write columns through
//! `bypass_change_detection`, because marking a column changed writes a tick per particle, a
//! pass over the column per system (about 1 % of a step of the dam break). A plugin that
//! wants `Changed<C>` of an engine column cannot rely on it.

/// Fewest particles per rayon piece of a light loop: below this, splitting costs more than it
/// saves.
pub const MIN_LEN: usize = 4096;

/// The message of the `expect` on `contiguous_iter_mut`: every particle component is a table
/// component (bevy's default storage), so a query of them is dense by construction.
pub const DENSE: &str = "particle components are table components, so the query is dense";
