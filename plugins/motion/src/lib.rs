//! Prescribed motions of bodies: the body kind `Prescribed`, a rigid law of time that moves a
//! body's particles whatever the forces on them (a piston, a flap, a lid, a paddle):
//! `Body(name: "lid", kind: Prescribed(Slide(velocity: [1.0, 0.0])))`.
//!
//! The settings ([`Prescribed`]) are checked against the scene's dimension and become a
//! [`Law`], the [`BodyMotion`] the engine drives the body by (see `dualsph_core::bodies`).
#![warn(missing_docs)]

mod law;

pub use law::Law;

use dualsph_core::bodies::{BodyKind, BodyMotion};
use dualsph_core::plugin::{SceneInfo, SectionProblem};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A prescribed body's law of motion (time from the start of the run; vectors with the
/// scene's dimension).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub enum Prescribed {
    /// `x = x_0 + velocity·t`.
    Translate {
        /// Velocity (m/s).
        velocity: Vec<f64>,
    },
    /// A surface moving along itself (a belt, a cavity's lid): the particles stay at `x_0`
    /// and carry `velocity` (m/s) into the fluid's equations.
    Slide {
        /// Velocity (m/s).
        velocity: Vec<f64>,
    },
    /// `x = x_0 + amplitude (sin(2π frequency t + phase) − sin(phase))`.
    Oscillate {
        /// Amplitude vector (m).
        amplitude: Vec<f64>,
        /// Frequency (Hz).
        frequency: f64,
        /// Phase (rad, default 0).
        #[serde(default)]
        phase: f64,
    },
    /// A rotation at `omega` (rad/s, counter-clockwise) about `center`, about the z axis in
    /// 2-D and about `axis` in 3-D.
    Rotate {
        /// The point on the axis (m).
        center: Vec<f64>,
        /// The axis direction (dimensionless; 3-D only).
        #[serde(default)]
        axis: Option<Vec<f64>>,
        /// Angular velocity (rad/s).
        omega: f64,
    },
}

impl BodyKind for Prescribed {
    const NAME: &'static str = "Prescribed";
    const SUMMARY: &'static str =
        "moved by a law of time: Translate, Slide, Oscillate or Rotate (a piston, a lid)";

    /// Vectors of the scene's dimension, finite numbers, a frequency ≥ 0, a rotation about
    /// the z axis in 2-D and about a non-zero `axis` in 3-D (none in 1-D).
    fn validate(&self, info: &SceneInfo) -> Result<(), SectionProblem> {
        let d = info.dimension;
        match self {
            Prescribed::Translate { velocity } | Prescribed::Slide { velocity } => {
                vector("velocity", velocity, d)
            }
            Prescribed::Oscillate {
                amplitude,
                frequency,
                phase,
            } => {
                vector("amplitude", amplitude, d)?;
                if !(frequency.is_finite() && *frequency >= 0.0) {
                    return Err(SectionProblem::new(
                        "frequency",
                        format!("must be a finite number >= 0, got {frequency}"),
                    ));
                }
                finite("phase", *phase)
            }
            Prescribed::Rotate {
                center,
                axis,
                omega,
            } => {
                vector("center", center, d)?;
                finite("omega", *omega)?;
                rotation_axis(axis.as_deref(), d)
            }
        }
    }

    fn motion(&self) -> Option<Arc<dyn BodyMotion>> {
        Some(Arc::new(Law::from(self)))
    }
}

/// A vector of `d` finite components.
fn vector(field: &str, v: &[f64], d: usize) -> Result<(), SectionProblem> {
    if v.len() != d {
        return Err(SectionProblem::new(
            field,
            format!("expected {d} components for dimension {d}, got {}", v.len()),
        ));
    }
    match v.iter().position(|x| !x.is_finite()) {
        Some(k) => Err(SectionProblem::new(
            field,
            format!("component {k} is not finite ({})", v[k]),
        )),
        None => Ok(()),
    }
}

/// A finite number.
fn finite(field: &str, x: f64) -> Result<(), SectionProblem> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(SectionProblem::new(
            field,
            format!("must be finite, got {x}"),
        ))
    }
}

/// A rotation's axis: none in 2-D (the z axis), a non-zero one in 3-D, no rotation in 1-D.
fn rotation_axis(axis: Option<&[f64]>, d: usize) -> Result<(), SectionProblem> {
    match (d, axis) {
        (1, _) => Err(SectionProblem::new(
            "",
            "a rotation needs 2 or 3 dimensions",
        )),
        (2, Some(_)) => Err(SectionProblem::new(
            "axis",
            "a 2-D rotation is about the z axis: leave `axis` out",
        )),
        (3, None) => Err(SectionProblem::new(
            "axis",
            "a 3-D rotation needs its axis, e.g. axis: [0.0, 0.0, 1.0]",
        )),
        (3, Some(n)) => {
            vector("axis", n, d)?;
            if n.iter().all(|&x| x == 0.0) {
                return Err(SectionProblem::new("axis", "must not be zero"));
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(p: &Prescribed, d: usize) -> String {
        p.validate(&SceneInfo::of_dimension(d)).unwrap_err().field
    }

    #[test]
    fn settings_are_checked_against_the_scenes_dimension() {
        let v3 = Prescribed::Translate {
            velocity: vec![1.0, 0.0, 0.0],
        };
        assert_eq!(field(&v3, 2), "velocity");
        assert!(v3.validate(&SceneInfo::of_dimension(3)).is_ok());
        let about = |axis: Option<Vec<f64>>| Prescribed::Rotate {
            center: vec![0.0; 2],
            axis,
            omega: 1.0,
        };
        assert_eq!(field(&about(Some(vec![0.0, 0.0, 1.0])), 2), "axis");
        assert!(about(None).validate(&SceneInfo::of_dimension(2)).is_ok());
        let still = Prescribed::Oscillate {
            amplitude: vec![0.1, 0.0],
            frequency: -1.0,
            phase: 0.0,
        };
        assert_eq!(field(&still, 2), "frequency");
    }

    /// A 3-D axis given unnormalised turns like the unit one.
    #[test]
    fn the_law_has_a_unit_axis() {
        let law = Law::from(&Prescribed::Rotate {
            center: vec![0.0; 3],
            axis: Some(vec![2.0, 0.0, 0.0]),
            omega: 1.0,
        });
        let Law::Rotate { axis, .. } = law else {
            panic!("{law:?}")
        };
        assert_eq!(axis, [1.0, 0.0, 0.0]);
    }
}
