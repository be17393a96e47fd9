//! What the scene's `output` section asks of a run's snapshots: when they are written
//! ([`SnapshotSchedule`]), in which files ([`output_options`]) and with which columns
//! ([`select_columns`]).

use bevy_ecs::prelude::{Resource, World};
use dualsph_core::columns::{Column, Columns, ids_by_row};
use dualsph_core::output::DerivedColumns;
use dualsph_fluid::prelude::*;
use dualsph_io::{OutputOptions, POSITION, TableColumn, VtkEncoding};
use dualsph_scene::{OutputFormat, OutputSettings};

/// Relative tolerance of the time cadence: a step whose t is within `1e-9·snapshot_dt` below a
/// multiple of `snapshot_dt` counts as reaching it (t accumulated over many steps lands a
/// rounding error away from the exact multiple).
const TIME_TOLERANCE: f64 = 1e-9;

/// When snapshots are written.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cadence {
    /// Never (no snapshot format, or `snapshot_every: 0` without `snapshot_dt`).
    Never,
    /// At every step that is a multiple of this.
    Steps(u64),
    /// At the first step whose t reaches each multiple of this many seconds.
    Time(f64),
}

/// Decides after which steps the runner writes a snapshot: the initial state (step 0), the
/// steps of the cadence, and the final state (unless the last step was one of them).
///
/// The step cadence writes every step that is a multiple of `snapshot_every`. The time
/// cadence writes at the first step whose t reaches each multiple `k·snapshot_dt` (one
/// snapshot when a step passes several multiples). It keeps only how many multiples the
/// current t has reached, which [`SnapshotSchedule::resume_at`] recomputes from t: a run
/// resumed from a checkpoint writes the snapshots the uninterrupted run would have written.
#[derive(Clone, Debug, PartialEq)]
pub struct SnapshotSchedule {
    cadence: Cadence,
    /// Multiples of `snapshot_dt` reached by the current t.
    reached: u64,
    /// The step of the last snapshot this schedule asked for.
    last: Option<u64>,
}

impl SnapshotSchedule {
    /// The schedule of an `output` section, counting time from t = 0.
    pub fn new(output: &OutputSettings) -> Self {
        let cadence = match (output.formats.is_empty(), output.snapshot_dt) {
            (true, _) => Cadence::Never,
            (false, Some(dt)) => Cadence::Time(dt),
            (false, None) if output.snapshot_every > 0 => Cadence::Steps(output.snapshot_every),
            (false, None) => Cadence::Never,
        };
        SnapshotSchedule {
            cadence,
            reached: 0,
            last: None,
        }
    }

    /// Whether a fresh run writes its initial state (step 0); recorded as written.
    pub fn initial(&mut self) -> bool {
        self.due(0, true)
    }

    /// Continues the time cadence from `t` (the checkpoint's time when a run resumes): the
    /// next snapshot is at the first step that reaches a multiple of `snapshot_dt` above `t`.
    pub fn resume_at(&mut self, t: Real) {
        self.reached = self.multiples(t);
    }

    /// Whether the state after `step`, at time `t`, is written; recorded as written.
    pub fn after_step(&mut self, step: u64, t: Real) -> bool {
        let due = match self.cadence {
            Cadence::Never => false,
            Cadence::Steps(n) => step.is_multiple_of(n),
            Cadence::Time(_) => {
                let reached = self.multiples(t);
                let due = reached > self.reached;
                self.reached = self.reached.max(reached);
                due
            }
        };
        self.due(step, due)
    }

    /// Whether the final state, at `step`, is written: with any cadence, unless it was just
    /// written.
    pub fn at_end(&mut self, step: u64) -> bool {
        let due = self.last != Some(step);
        self.due(step, due)
    }

    fn due(&mut self, step: u64, due: bool) -> bool {
        let due = due && self.cadence != Cadence::Never;
        if due {
            self.last = Some(step);
        }
        due
    }

    /// How many multiples of `snapshot_dt` (k >= 1) `t` has reached (0 for a step cadence).
    fn multiples(&self, t: Real) -> u64 {
        match self.cadence {
            Cadence::Time(dt) if t.is_finite() && t > 0.0 => (t / dt + TIME_TOLERANCE) as u64,
            _ => 0,
        }
    }
}

/// The snapshot files of an `output` section.
pub fn output_options(output: &OutputSettings) -> OutputOptions {
    OutputOptions {
        csv: output.writes(OutputFormat::Csv),
        vtk: output.writes(OutputFormat::Vtk),
        encoding: match output.vtk_encoding {
            dualsph_scene::VtkEncoding::Binary => VtkEncoding::Binary,
            dualsph_scene::VtkEncoding::Compressed => VtkEncoding::Compressed,
            dualsph_scene::VtkEncoding::Ascii => VtkEncoding::Ascii,
        },
    }
}

/// The names of the output columns chosen by the scene (always with `position`); absent: all.
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct SnapshotColumns(pub Vec<String>);

/// Checks the scene's `output.columns` against the simulation's registered output columns
/// (plugins register theirs when they are built) and keeps the choice in the world, where
/// [`chosen_columns`] reads it. `position` and `id` are always written and may be named. An
/// unknown name is an error that names it and lists the available columns.
pub fn select_columns<V: Vector>(sim: &mut Sim<V>, output: &OutputSettings) -> Result<(), String> {
    let Some(names) = &output.columns else {
        sim.world.remove_resource::<SnapshotColumns>();
        return Ok(());
    };
    let derived = sim.world.get_resource::<DerivedColumns>();
    let available: Vec<&str> = (sim.world.resource::<Columns>().output())
        .map(|c| c.spec.name)
        .chain(derived.into_iter().flat_map(|d| d.names()))
        .collect();
    if let Some(unknown) = names
        .iter()
        .find(|n| n.as_str() != "id" && !available.contains(&n.as_str()))
    {
        return Err(format!(
            "output.columns: no output column is named `{unknown}`; this scene's output columns \
             are {} (`id` and `{POSITION}` are always written)",
            available.join(", ")
        ));
    }
    let chosen = std::iter::once(POSITION.to_string())
        .chain(names.iter().cloned())
        .collect();
    sim.world.insert_resource(SnapshotColumns(chosen));
    Ok(())
}

/// The output columns written to snapshots, in registration order: those of
/// [`SnapshotColumns`] when the world has it, else every output column.
pub fn chosen_columns(world: &World) -> Vec<Column> {
    let chosen = world.get_resource::<SnapshotColumns>();
    world
        .resource::<Columns>()
        .output()
        .filter(|c| chosen.is_none_or(|s| s.0.iter().any(|n| n == c.spec.name)))
        .cloned()
        .collect()
}

/// The plugins' derived columns ([`DerivedColumns`]) that the snapshots write (those of
/// [`SnapshotColumns`] when the world has it, else all), rows in id order.
pub fn derived_columns(world: &mut World) -> Vec<TableColumn> {
    let Some(derived) = world.get_resource::<DerivedColumns>() else {
        return Vec::new();
    };
    let chosen = world.get_resource::<SnapshotColumns>();
    let keep = |n: &str| chosen.is_none_or(|s| s.0.iter().any(|c| c == n));
    let values = derived.values(world, keep);
    if values.is_empty() {
        return Vec::new();
    }
    let ids = ids_by_row(world);
    let mut order: Vec<usize> = (0..ids.len()).collect();
    order.sort_unstable_by_key(|&r| ids[r]);
    (values.into_iter())
        .map(|(name, v)| TableColumn {
            labels: vec![name.clone()],
            name,
            values: order
                .iter()
                .map(|&r| v.get(r).copied().unwrap_or(Real::NAN))
                .collect(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn output(every: u64, dt: Option<f64>) -> OutputSettings {
        OutputSettings {
            snapshot_every: every,
            snapshot_dt: dt,
            ..OutputSettings::default()
        }
    }

    /// The steps a schedule writes for the given step times (t of step 1, 2, …).
    fn written(s: &mut SnapshotSchedule, first_step: u64, times: &[f64]) -> Vec<u64> {
        let mut steps: Vec<u64> = (first_step..)
            .zip(times)
            .filter(|&(step, &t)| s.after_step(step, t))
            .map(|(step, _)| step)
            .collect();
        let last = first_step + times.len() as u64 - 1;
        if s.at_end(last) {
            steps.push(last);
        }
        steps
    }

    #[test]
    fn the_step_cadence_writes_multiples_and_the_end() {
        let mut s = SnapshotSchedule::new(&output(3, None));
        assert!(s.initial());
        let times: Vec<f64> = (1..=7).map(|k| k as f64).collect();
        assert_eq!(written(&mut s, 1, &times), [3, 6, 7]);
        let mut s = SnapshotSchedule::new(&output(0, None));
        assert!(!s.initial());
        assert!(written(&mut s, 1, &times).is_empty());
        let mut none = output(3, None);
        none.formats.clear();
        assert!(!SnapshotSchedule::new(&none).initial());
    }

    #[test]
    fn the_time_cadence_writes_the_first_step_reaching_each_multiple() {
        let mut s = SnapshotSchedule::new(&output(200, Some(0.1)));
        assert!(s.initial());
        s.resume_at(0.0);
        // irregular steps; 0.35 → 0.52 passes 0.4 and 0.5: one snapshot
        let times = [0.04, 0.099_999_999_999_9, 0.13, 0.2, 0.35, 0.52, 0.55];
        assert_eq!(written(&mut s, 1, &times), [2, 4, 5, 6, 7]);
    }

    #[test]
    fn a_resumed_time_cadence_writes_what_the_uninterrupted_one_does() {
        let times = [0.03, 0.08, 0.11, 0.17, 0.26, 0.29, 0.31, 0.44];
        let mut whole = SnapshotSchedule::new(&output(0, Some(0.1)));
        whole.resume_at(0.0);
        let all = written(&mut whole, 1, &times);
        assert_eq!(all, [3, 5, 7, 8]);
        for cut in 1..times.len() {
            // resumed after step `cut` (a checkpoint at times[cut - 1])
            let mut resumed = SnapshotSchedule::new(&output(0, Some(0.1)));
            resumed.resume_at(times[cut - 1]);
            let after = written(&mut resumed, cut as u64 + 1, &times[cut..]);
            let want: Vec<u64> = all.iter().copied().filter(|&s| s > cut as u64).collect();
            assert_eq!(after, want, "resumed after step {cut}");
        }
    }
}
