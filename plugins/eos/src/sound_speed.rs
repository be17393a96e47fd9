//! A liquid's reference sound speed as a scene gives it: a value in m/s (`c0: 48.5`), or
//! `c0: Auto(factor: 10.0)`, derived from the scene as `c0 = factor · U`, `U` the largest
//! speed it implies — the speed `√(2 g H)` of the fluid's fall under gravity, the fastest
//! initial fluid particle, an inlet's speed ([`crate::mach::implied_speed`]). The factor's
//! default, 10, keeps the Mach number at 0.1 and the density's variation near 1 % (Monaghan
//! 1994, *J. Comput. Phys.* 110, 399, §3). DualSPHysics derives its `cs0` the same way, as
//! `coefsound · √(g · hswl)` from the still-water height `hswl` (its `coefsound` 20 is
//! this factor 14.1, since `√(2 g H) = √2 · √(g H)`).

use crate::mach;
use dualsph_core::math::Real;
use dualsph_fluid::prelude::*;
use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// The default of [`SoundSpeedSetting::Auto`]'s factor.
pub const AUTO_FACTOR: Real = 10.0;

/// A liquid's reference sound speed `c0` (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum SoundSpeedSetting {
    /// The value (m/s).
    Value(Real),
    /// `factor` times the largest speed the scene implies.
    Auto {
        /// `c0 / U` (dimensionless; default 10).
        factor: Real,
    },
}

impl From<Real> for SoundSpeedSetting {
    fn from(c0: Real) -> Self {
        SoundSpeedSetting::Value(c0)
    }
}

impl SoundSpeedSetting {
    /// `Ok` when the value (or the factor) is a finite number > 0; the message names `field`.
    pub fn validate(&self, field: &str) -> Result<(), String> {
        match *self {
            SoundSpeedSetting::Value(c) => dualsph_core::plugin::positive(field, c),
            SoundSpeedSetting::Auto { factor } => {
                dualsph_core::plugin::positive(&format!("{field}: Auto.factor"), factor)
            }
        }
    }
}

/// The body of `Auto(..)`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AutoBody {
    #[serde(default = "auto_factor")]
    factor: Real,
}

fn auto_factor() -> Real {
    AUTO_FACTOR
}

struct SoundSpeedVisitor;

impl<'de> Visitor<'de> for SoundSpeedVisitor {
    type Value = SoundSpeedSetting;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a sound speed in m/s or `Auto(factor: 10.0)`")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<SoundSpeedSetting, E> {
        Ok(SoundSpeedSetting::Value(v))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<SoundSpeedSetting, E> {
        Ok(SoundSpeedSetting::Value(v as Real))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<SoundSpeedSetting, E> {
        Ok(SoundSpeedSetting::Value(v as Real))
    }
    /// `Auto(factor: ..)`: RON hands a named struct over as its fields.
    fn visit_map<A: MapAccess<'de>>(self, m: A) -> Result<SoundSpeedSetting, A::Error> {
        let body = AutoBody::deserialize(de::value::MapAccessDeserializer::new(m))?;
        Ok(SoundSpeedSetting::Auto {
            factor: body.factor,
        })
    }
    /// `Auto` with the default factor.
    fn visit_unit<E: de::Error>(self) -> Result<SoundSpeedSetting, E> {
        Ok(SoundSpeedSetting::Auto {
            factor: AUTO_FACTOR,
        })
    }
    fn visit_newtype_struct<D: Deserializer<'de>>(
        self,
        d: D,
    ) -> Result<SoundSpeedSetting, D::Error> {
        d.deserialize_any(SoundSpeedVisitor)
    }
}

impl<'de> Deserialize<'de> for SoundSpeedSetting {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(SoundSpeedVisitor)
    }
}

/// Written by hand: the form a scene writes (a number, or `Auto(factor: ..)`), which the
/// derive cannot infer from the hand-written `Deserialize`.
impl JsonSchema for SoundSpeedSetting {
    fn schema_name() -> Cow<'static, str> {
        "SoundSpeed".into()
    }

    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "A sound speed: a value, or derived from the speeds the scene implies.",
            "oneOf": [
                { "type": "number", "description": "The value (m/s)." },
                {
                    "type": "object",
                    "description": "c0 = factor · U, U the largest speed the scene implies: √(2 g H) of the\nfluid's fall under gravity, the fastest initial fluid particle, an inlet's speed\n(wherever Gravity and Inlet stand in the plugin list).",
                    "properties": { "Auto": {
                        "type": "object",
                        "properties": { "factor": {
                            "type": "number",
                            "default": AUTO_FACTOR,
                            "description": "c0 / U (dimensionless; default 10, Mach 0.1)."
                        } }
                    } },
                    "required": ["Auto"]
                }
            ]
        })
    }
}

/// The sound speed `c0` gives: its value, or one derived from the speeds the scene implies
/// (`Auto`, noted on the simulation; gravity and inlets are prepared before any plugin
/// builds, so their speeds count wherever they are listed); `None` when the scene gives `p0`
/// instead.
pub(crate) fn resolve<V: Vector>(
    sim: &mut Sim<V>,
    c0: Option<SoundSpeedSetting>,
    field: &str,
) -> Result<Option<Real>, SimError> {
    let factor = match c0 {
        None => return Ok(None),
        Some(SoundSpeedSetting::Value(c)) => return Ok(Some(c)),
        Some(SoundSpeedSetting::Auto { factor }) => factor,
    };
    let (u, what) = mach::implied_speed::<V>(&mut sim.world)
        .filter(|(u, _)| u.is_finite() && *u > 0.0)
        .ok_or_else(|| {
            SimError::Build(format!(
                "TaitEos.{field}: Auto(..) finds no speed in the scene (no fall under gravity, \
                 no initial velocity, no inlet): give c0 in m/s"
            ))
        })?;
    let c = factor * u;
    sim.note(format!(
        "TaitEos.{field} = {c:.4} m/s: Auto(factor: {factor}) × {u:.4} m/s, {what}"
    ));
    Ok(Some(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<SoundSpeedSetting, String> {
        ron::from_str(text).map_err(|e| e.to_string())
    }

    #[test]
    fn a_number_or_auto_with_its_factor() {
        assert_eq!(parse("48.5"), Ok(SoundSpeedSetting::Value(48.5)));
        assert_eq!(parse("60"), Ok(SoundSpeedSetting::Value(60.0)));
        assert_eq!(
            parse("Auto(factor: 14.0)"),
            Ok(SoundSpeedSetting::Auto { factor: 14.0 })
        );
        assert_eq!(parse("Auto"), Ok(SoundSpeedSetting::Auto { factor: 10.0 }));
        let e = parse("Auto(fctor: 2.0)").unwrap_err();
        assert!(e.contains("fctor"), "{e}");
        assert!(
            parse("\"fast\"")
                .unwrap_err()
                .contains("Auto(factor: 10.0)")
        );
    }

    #[test]
    fn the_value_or_factor_must_be_positive() {
        assert!(
            SoundSpeedSetting::Value(0.0)
                .validate("c0")
                .unwrap_err()
                .starts_with("c0")
        );
        let e = SoundSpeedSetting::Auto { factor: -1.0 }
            .validate("c0")
            .unwrap_err();
        assert!(e.starts_with("c0: Auto.factor"), "{e}");
    }
}
