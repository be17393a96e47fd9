//! Wall time per scheduled system, for `dualsph run --profile` and anyone asking where a
//! scene's step time goes.
//!
//! [`crate::sim::Sim::enable_profile`] puts a marker system between every two systems of the
//! step schedule (in sets of their own, ordered between the systems' slots) and one before the
//! first; each marker adds the wall time since the previous one to the system just finished.
//! A marker reads the clock once (tens of nanoseconds against steps of milliseconds) and
//! touches no particle data, so a profiled run computes bitwise the same state. Wall time, not
//! CPU time: a parallel system's time is the time the step waits for it.

use bevy_ecs::prelude::*;
use std::time::Instant;

/// Wall seconds per system of the step schedule, summed over the profiled steps.
#[derive(Resource, Clone, Debug, Default)]
pub struct SystemTimes {
    /// The systems' labels in execution order.
    pub labels: Vec<String>,
    /// Wall seconds spent in each system (same order as `labels`).
    pub seconds: Vec<f64>,
    /// Steps profiled.
    pub steps: u64,
    last: Option<Instant>,
}

impl SystemTimes {
    /// Zero times for systems `labels`.
    pub fn new(labels: Vec<String>) -> Self {
        SystemTimes {
            seconds: vec![0.0; labels.len()],
            labels,
            steps: 0,
            last: None,
        }
    }

    /// Sum of the systems' seconds.
    pub fn total(&self) -> f64 {
        self.seconds.iter().sum()
    }

    /// A table of the systems, most expensive first: seconds, share of the step, µs per step
    /// and ns per particle-step for `particles` particles.
    pub fn table(&self, particles: u64) -> String {
        let total = self.total().max(1e-12);
        let steps = self.steps.max(1) as f64;
        let mut rows: Vec<(&String, f64)> = self
            .labels
            .iter()
            .zip(self.seconds.iter().copied())
            .collect();
        rows.sort_by(|a, b| b.1.total_cmp(&a.1));
        let width = rows.iter().map(|r| r.0.len()).max().unwrap_or(6).max(6);
        let mut out = format!(
            "{:<width$}  {:>9}  {:>6}  {:>10}  {:>16}\n",
            "system", "wall s", "share", "µs/step", "ns/particle-step"
        );
        for (label, s) in rows {
            out += &format!(
                "{label:<width$}  {s:>9.3}  {:>5.1}%  {:>10.2}  {:>16.1}\n",
                100.0 * s / total,
                1e6 * s / steps,
                1e9 * s / (steps * particles.max(1) as f64),
            );
        }
        out
    }
}

/// Starts a step's timing (runs before the first system).
pub(crate) fn begin_step(mut t: ResMut<SystemTimes>, phase: Res<crate::phase::StepPhase>) {
    // a step's population and rates phases run the schedule before its main run
    if *phase == crate::phase::StepPhase::Step {
        t.steps += 1;
    }
    t.last = Some(Instant::now());
}

/// The marker after system `k`: credits it with the wall time since the previous marker.
pub(crate) fn marker(k: usize) -> impl FnMut(ResMut<SystemTimes>) {
    move |mut t: ResMut<SystemTimes>| {
        let now = Instant::now();
        if let Some(last) = t.last {
            t.seconds[k] += (now - last).as_secs_f64();
        }
        t.last = Some(now);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_lists_systems_by_cost_with_shares_and_rates() {
        let mut t = SystemTimes::new(vec!["cheap".into(), "sweep".into()]);
        t.seconds = vec![0.25, 0.75];
        t.steps = 1000;
        let table = t.table(500);
        let lines: Vec<&str> = table.lines().collect();
        assert!(
            lines[1].starts_with("sweep") && lines[2].starts_with("cheap"),
            "{table}"
        );
        // 0.75 s of 1 s; 750 µs per step; 0.75 s / (1000 × 500) = 1500 ns per particle-step
        assert!(
            lines[1].contains("75.0%") && lines[1].contains("750.00"),
            "{table}"
        );
        assert!(lines[1].ends_with("1500.0"), "{table}");
    }
}
