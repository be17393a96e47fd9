//! Runs that stall: a time step that collapses during the run, or one so small from the start
//! that the end time is out of reach. Both stop the run as a blow-up with the cause, instead
//! of stepping forever.

use bevy_ecs::prelude::{Res, ResMut, Resource};
use dualsph_core::output::StepLimit;
use dualsph_core::sim::{SimClock, StepFailure};
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// Key of [`DtFloor`] in checkpoints: a resumed run keeps the reference of the run it
/// continues.
pub const DT_FLOOR_KEY: &str = "dualsph.dt_floor";

/// Steps beyond which a run is taken as stalled from its first step (at the first step's dt,
/// the end time would need more steps than this) unless the scene sets `max_steps`. At the
/// engine's smallest per-step cost (~10 µs for a few hundred particles) that is more than a
/// day of stepping.
pub const MAX_PROJECTED_STEPS: f64 = 1e10;

/// The time-step floor of a run: the run stops when dt falls below
/// `reference / factor`, where `reference` is the dt of the run's first step.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DtFloor {
    /// `health.dt_below` of the scene (> 1).
    pub factor: Real,
    /// The dt of the first step, once it has been taken.
    pub reference: Option<Real>,
}

impl DtFloor {
    /// A floor `factor` below the first step's dt (not yet taken).
    pub fn new(factor: Real) -> Self {
        DtFloor {
            factor,
            reference: None,
        }
    }

    /// After a step of length `dt` ending at `t`: records the first step's dt, and says why
    /// the run cannot go on, if it cannot — `dt` below the floor, or (`capped` false: no
    /// `max_steps`) a first step so small that `t_end` needs more than
    /// [`MAX_PROJECTED_STEPS`].
    pub fn after_step(&mut self, dt: Real, t: Real, t_end: Real, capped: bool) -> Option<String> {
        let reference = match self.reference {
            Some(r) => r,
            None => {
                self.reference = Some(dt);
                let steps = (t_end - t) / dt;
                if !capped && steps > MAX_PROJECTED_STEPS {
                    return Some(format!(
                        "the first step's dt = {dt:.3e} s would need {steps:.1e} steps to reach end_time = {t_end} s \
                         (more than {MAX_PROJECTED_STEPS:.0e}; likely cause: an unphysical velocity, sound speed or \
                         force in the scene; set max_steps to run anyway)"
                    ));
                }
                dt
            }
        };
        let floor = reference / self.factor;
        (dt < floor || !dt.is_finite()).then(|| {
            format!(
                "dt = {dt:.3e} s fell below the floor {floor:.3e} s = the first step's dt {reference:.3e} s / health.dt_below {} \
                 (likely cause: particles accelerating without bound, e.g. a collapse or too few neighbours)",
                self.factor
            )
        })
    }
}

/// The stall check as a step system (with the diagnostics): after every step — not the
/// initial evaluation — the floor's verdict ([`DtFloor::after_step`]) is the step's failure, so
/// a stalled run stops as any blow-up does, naming the step and time.
pub(crate) fn check_dt_floor(
    clock: Res<SimClock>,
    limit: Option<Res<StepLimit>>,
    mut floor: ResMut<DtFloor>,
    mut failure: ResMut<StepFailure>,
) {
    if clock.initializing {
        return;
    }
    if let Some(why) = floor.after_step(clock.dt, clock.t, clock.t_end, limit.is_some()) {
        failure.fail(|| why);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_floor_is_relative_to_the_first_step() {
        let mut f = DtFloor::new(1e3);
        assert_eq!(f.after_step(1e-3, 1e-3, 1.0, false), None);
        assert_eq!(f.reference, Some(1e-3));
        // a thousandfold drop is still allowed, just under it is not
        assert_eq!(f.after_step(1e-6, 0.5, 1.0, false), None);
        let why = f
            .after_step(0.999e-6, 0.5, 1.0, false)
            .expect("below the floor");
        assert!(why.contains("dt_below 1000"), "{why}");
        assert!(f.after_step(f64::NAN, 0.5, 1.0, false).is_some());
    }

    #[test]
    fn an_unreachable_end_time_stops_the_first_step_unless_capped() {
        let why = DtFloor::new(1e6)
            .after_step(1e-202, 1e-202, 1.0, false)
            .expect("1e202 steps");
        assert!(why.contains("1.0e202 steps"), "{why}");
        assert_eq!(
            DtFloor::new(1e6).after_step(1e-202, 1e-202, 1.0, true),
            None
        );
        // 1e9 steps is long but within reach
        assert_eq!(DtFloor::new(1e6).after_step(1e-9, 1e-9, 1.0, false), None);
    }
}
