//! What the lattice generators (`Block`, `Disk`, `Shape`) share: the lattice kind, the clip
//! box and the initial velocity.

use crate::de::Ident;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// An axis-aligned box used by `clip` and `cut`; a point is inside when
/// `min_k <= x_k <= max_k` on every axis.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxRegion {
    /// Lower corner.
    pub min: Vec<f64>,
    /// Upper corner.
    pub max: Vec<f64>,
}

impl BoxRegion {
    /// Whether `p` lies in the box (bounds included) on the first `d` axes.
    pub fn contains(&self, p: &[f64; 3], d: usize) -> bool {
        (0..d).all(|k| {
            let lo = self.min.get(k).copied().unwrap_or(f64::NAN);
            let hi = self.max.get(k).copied().unwrap_or(f64::NAN);
            lo <= p[k] && p[k] <= hi
        })
    }
}

/// How lattice points fill a generator's box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize, Serialize)]
pub enum Lattice {
    /// Cell-centred square/cubic lattice: `min + (i + 0.5)·Δx` on every axis. The default.
    #[default]
    Square,
    /// Like `Square`, but alternate rows (index along axis 1; in 3-D alternate layers along
    /// axis 2, shifting axes 0 and 1) use offsets `0.25Δx` (even) and `0.75Δx` (odd) instead
    /// of `0.5Δx`. In 1-D it equals `Square`.
    Staggered,
}

/// The initial velocity of a generator's particles.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
pub enum Velocity {
    /// The same velocity for every particle.
    Uniform(Vec<f64>),
    /// `v = G·x` with `G` given by its rows (a d×d matrix) and `x` the absolute position.
    Linear(Vec<Vec<f64>>),
    /// The 2-D Taylor–Green vortex of wavelength `L` and peak speed `U`, with `k = 2π/L` and
    /// `x` the absolute position: `u = U sin(kx) cos(ky)`, `v = −U cos(kx) sin(ky)`
    /// (Taylor & Green 1937, *Proc. R. Soc. Lond. A* 158, 499). Divergence-free; with
    /// kinematic viscosity ν it is an exact Navier–Stokes solution decaying as `e^{−2νk²t}`.
    TaylorGreen {
        /// `U`.
        speed: f64,
        /// `L`.
        wavelength: f64,
    },
}

/// `clip` accepts `Some((min: .., max: ..))`, `Some(min: .., max: ..)`, `(min: .., max: ..)`
/// and `None`. (With ron's `UNWRAP_VARIANT_NEWTYPES` a derived struct inside `Some(..)`
/// would reject the double parentheses, hence this hand-written visitor that takes the box
/// from whatever map ron offers.)
pub(crate) fn deserialize_clip<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<BoxRegion>, D::Error> {
    Ok(Option::<AnyBox>::deserialize(d)?.map(|b| b.0))
}

struct AnyBox(BoxRegion);

impl<'de> Deserialize<'de> for AnyBox {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(AnyBoxVisitor)
    }
}

struct AnyBoxVisitor;

impl<'de> Visitor<'de> for AnyBoxVisitor {
    type Value = AnyBox;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a clip box `(min: [..], max: [..])`")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<AnyBox, A::Error> {
        let (mut min, mut max) = (None, None);
        while let Some(key) = map.next_key_seed(Ident)? {
            let slot = match key.as_str() {
                "min" => &mut min,
                "max" => &mut max,
                other => {
                    return Err(de::Error::custom(format!(
                        "unknown field `{other}` in clip box, expected `min` or `max`"
                    )));
                }
            };
            if slot.is_some() {
                return Err(de::Error::custom(format!(
                    "duplicate field `{key}` in clip box"
                )));
            }
            *slot = Some(map.next_value::<Vec<f64>>()?);
        }
        let missing = |f: &str| de::Error::custom(format!("clip box is missing field `{f}`"));
        let min = min.ok_or_else(|| missing("min"))?;
        let max = max.ok_or_else(|| missing("max"))?;
        Ok(AnyBox(BoxRegion { min, max }))
    }
}
