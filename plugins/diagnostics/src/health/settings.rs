//! The scene's optional `health` section, `health: (density_below: 100.0, dt_below: 1e4)`:
//! how far density and h may leave their initial ranges before a run counts as blown up,
//! and how far dt may fall below the first step's. Register it with
//! `registry.register_section::<HealthSettings>()` (the default registry of
//! `dualsph-builtin` does); a scene without it gets [`HealthSettings::default`].

use super::{DEFAULT_DENSITY_FACTORS, DEFAULT_H_FACTORS, HealthBounds};
use dualsph_core::plugin::SceneSection;
use dualsph_sweep::prelude::*;
use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

/// Default of [`HealthSettings::dt_below`].
pub const DEFAULT_DT_BELOW: Real = 1e6;

/// The `health` section: the sane ranges `[min/below, max·above]` of density and h around
/// their initial ranges (see [`HealthBounds`]), and the floor of dt. Each factor must be a
/// finite number > 1; a bad value is a parse error at its own position.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct HealthSettings {
    /// Factor (dimensionless) below the initial minimum density; default 300.
    #[serde(deserialize_with = "factor")]
    pub density_below: Real,
    /// Factor (dimensionless) above the initial maximum density; default 10.
    #[serde(deserialize_with = "factor")]
    pub density_above: Real,
    /// Factor (dimensionless) below the initial minimum h; default 10.
    #[serde(deserialize_with = "factor")]
    pub h_below: Real,
    /// Factor (dimensionless) above the initial maximum h; default 300.
    #[serde(deserialize_with = "factor")]
    pub h_above: Real,
    /// The run stops as a blow-up when dt falls this factor (dimensionless) below the dt of its first step;
    /// default 10^6.
    #[serde(deserialize_with = "factor")]
    pub dt_below: Real,
}

impl Default for HealthSettings {
    fn default() -> Self {
        HealthSettings {
            density_below: DEFAULT_DENSITY_FACTORS.0,
            density_above: DEFAULT_DENSITY_FACTORS.1,
            h_below: DEFAULT_H_FACTORS.0,
            h_above: DEFAULT_H_FACTORS.1,
            dt_below: DEFAULT_DT_BELOW,
        }
    }
}

impl HealthSettings {
    /// The bounds of the health check with these factors, around the initial h range
    /// `h_range` (the density range is taken at the initial evaluation).
    pub fn bounds(&self, h_range: Option<(Real, Real)>) -> HealthBounds {
        HealthBounds {
            density: (self.density_below, self.density_above),
            h: (self.h_below, self.h_above),
            rho_range: None,
            h_range,
        }
    }
}

impl SceneSection for HealthSettings {
    const KEY: &'static str = "health";
}

/// A finite number > 1, refused where it stands (so the error has its line and column).
fn factor<'de, D: Deserializer<'de>>(d: D) -> Result<Real, D::Error> {
    let x = Real::deserialize(d)?;
    if x.is_finite() && x > 1.0 {
        Ok(x)
    } else {
        Err(de::Error::custom(format!(
            "a sane-range factor must be a finite number > 1, got {x}"
        )))
    }
}
