//! The scene's `integrator` section, `integrator: (dt: Fixed(1e-4))` or
//! `integrator: (dt: Adaptive(courant: 0.1), max_dt: 1e-3)`: the settings of the time-step
//! rule of [`time_step`](crate::time_step), with their defaults and checks. Register it with
//! `registry.register_section::<IntegratorSettings>()` (the default registry of
//! `dualsph-builtin` does).

use crate::time_step::CFL_LIMIT;
use dualsph_core::plugin::{SceneInfo, SceneSection, SectionProblem};
use dualsph_sweep::prelude::*;
use serde::{Deserialize, Serialize};

fn default_courant() -> f64 {
    // on the support radius h (= 2Δx for h_factor 2): 0.1 h/c = 0.2 Δx/c; 0.2 h/c blows up
    // the 2-D dam break near t = 0.22 s
    0.1
}
fn default_force() -> f64 {
    0.25
}
fn default_viscous() -> f64 {
    0.125
}

/// How the time step is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub enum TimeStep {
    /// A constant step (s): `Fixed(1e-4)`.
    Fixed(f64),
    /// CFL-type step from the three coefficients, each in (0, 1].
    Adaptive {
        /// Acoustic (Courant) coefficient (dimensionless) on the support radius h, at most [`CFL_LIMIT`];
        /// default 0.1.
        #[serde(default = "default_courant")]
        courant: f64,
        /// Force (acceleration) coefficient (dimensionless); default 0.25.
        #[serde(default = "default_force")]
        force: f64,
        /// Viscous-diffusion coefficient (dimensionless); default 0.125.
        #[serde(default = "default_viscous")]
        viscous: f64,
    },
}

/// The default time-step rule: `Adaptive` with its default coefficients.
fn default_dt() -> TimeStep {
    TimeStep::Adaptive {
        courant: default_courant(),
        force: default_force(),
        viscous: default_viscous(),
    }
}

/// The `integrator` section of a scene (optional: left out, or `()`, it is the adaptive step
/// with its default coefficients).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IntegratorSettings {
    /// Time-step rule (default `Adaptive(courant: 0.1, force: 0.25, viscous: 0.125)`).
    #[serde(default = "default_dt")]
    pub dt: TimeStep,
    /// Upper bound on an adaptive step (s; none when absent).
    #[serde(default)]
    pub max_dt: Option<f64>,
}

impl IntegratorSettings {
    /// The engine's time-step rule for these settings.
    pub fn time_stepping(&self) -> TimeStepping {
        match self.dt {
            TimeStep::Fixed(dt) => TimeStepping::Fixed(dt),
            TimeStep::Adaptive {
                courant,
                force,
                viscous,
            } => TimeStepping::Adaptive {
                courant,
                force,
                viscous,
                max_dt: self.max_dt.unwrap_or(Real::INFINITY),
            },
        }
    }
}

/// A finite number `> 0`.
fn positive(field: &str, x: f64) -> Result<(), SectionProblem> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        let message = format!("must be a finite number > 0, got {x}");
        Err(SectionProblem::new(field, message))
    }
}

/// A number in (0, 1].
fn fraction(field: &str, x: f64) -> Result<(), SectionProblem> {
    if x > 0.0 && x <= 1.0 {
        Ok(())
    } else {
        let message = format!("must lie in (0, 1], got {x}");
        Err(SectionProblem::new(field, message))
    }
}

impl SceneSection for IntegratorSettings {
    const KEY: &'static str = "integrator";

    /// A fixed dt finite and > 0; adaptive coefficients in (0, 1], the Courant number at most
    /// [`CFL_LIMIT`]; `max_dt` finite and > 0.
    fn validate(&self, _info: &SceneInfo) -> Result<(), SectionProblem> {
        match self.dt {
            TimeStep::Fixed(dt) => positive("integrator.dt", dt)?,
            TimeStep::Adaptive {
                courant,
                force,
                viscous,
            } => {
                fraction("integrator.dt.courant", courant)?;
                if courant > CFL_LIMIT {
                    return Err(SectionProblem::new(
                        "integrator.dt.courant",
                        format!(
                            "{courant} is above the CFL limit {CFL_LIMIT} (on the support radius h, = {} on the classical h/2)",
                            2.0 * CFL_LIMIT
                        ),
                    ));
                }
                fraction("integrator.dt.force", force)?;
                fraction("integrator.dt.viscous", viscous)?;
            }
        }
        if let Some(max_dt) = self.max_dt {
            positive("integrator.max_dt", max_dt)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(dt: TimeStep, max_dt: Option<f64>) -> Result<(), SectionProblem> {
        let info = SceneInfo::of_dimension(2);
        SceneSection::validate(&IntegratorSettings { dt, max_dt }, &info)
    }

    fn adaptive(courant: f64, force: f64, viscous: f64) -> TimeStep {
        TimeStep::Adaptive {
            courant,
            force,
            viscous,
        }
    }

    #[test]
    fn bad_values_are_refused_naming_the_field() {
        let field = |r: Result<(), SectionProblem>| r.unwrap_err().field;
        assert_eq!(field(check(TimeStep::Fixed(0.0), None)), "integrator.dt");
        let courant = check(adaptive(0.3, 0.25, 0.125), None).unwrap_err();
        assert_eq!(courant.field, "integrator.dt.courant");
        assert!(courant.message.contains("above the CFL limit 0.25"));
        assert_eq!(
            field(check(adaptive(0.1, 0.0, 0.125), None)),
            "integrator.dt.force"
        );
        assert_eq!(
            field(check(adaptive(0.1, 0.25, -0.1), None)),
            "integrator.dt.viscous"
        );
        assert_eq!(
            field(check(TimeStep::Fixed(1e-4), Some(0.0))),
            "integrator.max_dt"
        );
        check(adaptive(0.25, 1.0, 1.0), Some(1e-3)).unwrap();
    }

    #[test]
    fn adaptive_without_coefficients_takes_the_defaults() {
        let s: IntegratorSettings = ron::from_str("(dt: Adaptive())").unwrap();
        assert_eq!((s.dt, s.max_dt), (adaptive(0.1, 0.25, 0.125), None));
        let s: IntegratorSettings =
            ron::from_str("(dt: Adaptive(force: 0.5), max_dt: Some(1e-3))").unwrap();
        assert_eq!((s.dt, s.max_dt), (adaptive(0.1, 0.5, 0.125), Some(1e-3)));
        assert!(ron::from_str::<IntegratorSettings>("(dt: Fixed(1e-4), dtt: 1.0)").is_err());
    }

    #[test]
    fn the_rule_takes_max_dt_only_when_adaptive() {
        let s = IntegratorSettings {
            dt: adaptive(0.1, 0.25, 0.125),
            max_dt: None,
        };
        assert!(matches!(
            s.time_stepping(),
            TimeStepping::Adaptive { max_dt, .. } if max_dt == Real::INFINITY
        ));
        let fixed = IntegratorSettings {
            dt: TimeStep::Fixed(1e-4),
            max_dt: Some(1.0),
        };
        assert_eq!(fixed.time_stepping(), TimeStepping::Fixed(1e-4));
    }
}
