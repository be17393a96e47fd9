//! The light per-particle loops (predictor, corrector, gather, write-backs, dt and health
//! reductions) run over bevy's contiguous table slices (`Query::contiguous_iter_mut`) and are
//! split across the rayon pool that runs the pair sweep.
//!
//! A per-entity query loop costs a fetch per entity, and bevy's `par_iter_mut` calls its
//! closure per entity without inlining it (~80 instructions per particle, more than these
//! updates cost). On slices the loops are plain array loops, and rayon splits them into pieces
//! of at least [`MIN_LEN`] particles. Every update is per particle and every reduction is a
//! minimum (exact and order-free), so the results are bitwise the same on any number of
//! threads.

use crate::components::ParticleId;
use rayon::prelude::*;

/// Fewest particles per rayon piece of a light loop: below this, splitting costs more than it
/// saves.
pub const MIN_LEN: usize = 4096;

/// The message of the `expect` on `contiguous_iter_mut`: every particle component is a table
/// component (bevy's default storage), so a query of them is dense by construction.
pub const DENSE: &str = "particle components are table components, so the query is dense";

/// `Some(start)` when `ids` are `start, start + 1, …`: the table's rows are in id order (as
/// particles are spawned), so its slices map onto `start..start + ids.len()` of the dense
/// arrays.
pub fn id_run(ids: &[ParticleId]) -> Option<usize> {
    let start = ids.first()?.0 as usize;
    let consecutive = ids
        .iter()
        .zip(start..)
        .fold(true, |ok, (id, k)| ok & (id.0 as usize == k));
    consecutive.then_some(start)
}

/// Calls `f(row, i)` for every row of a table chunk, `i` being the row's particle id (`ids`
/// holds the chunk's ids): in parallel pieces when the ids are a run ([`id_run`]), else in
/// order.
pub fn for_rows<T: Send>(ids: &[ParticleId], rows: &mut [T], f: impl Fn(&mut T, usize) + Sync) {
    match id_run(ids) {
        Some(a) => rows
            .par_iter_mut()
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(k, row)| f(row, a + k)),
        None => rows
            .iter_mut()
            .zip(ids)
            .for_each(|(row, id)| f(row, id.0 as usize)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn id_run_finds_consecutive_ids_only() {
        let ids = |v: &[u32]| v.iter().map(|&i| ParticleId(i)).collect::<Vec<_>>();
        assert_eq!(id_run(&ids(&[4, 5, 6])), Some(4));
        assert_eq!(id_run(&ids(&[0])), Some(0));
        assert_eq!(id_run(&ids(&[])), None);
        assert_eq!(id_run(&ids(&[4, 6, 7])), None);
        assert_eq!(id_run(&ids(&[1, 0])), None);
    }

    #[test]
    fn for_rows_passes_each_rows_id() {
        for ids in [vec![3u32, 4, 5, 6], vec![6, 3, 5, 4]] {
            let ids: Vec<ParticleId> = ids.into_iter().map(ParticleId).collect();
            let mut rows = vec![0usize; ids.len()];
            for_rows(&ids, &mut rows, |r, i| *r = i);
            let want: Vec<usize> = ids.iter().map(|id| id.0 as usize).collect();
            assert_eq!(rows, want);
        }
    }
}
