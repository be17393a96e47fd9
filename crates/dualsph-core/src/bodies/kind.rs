//! Body kinds: what a scene names as a body's `kind`, provided by the crate that defines the
//! motion and held by a [`Registry`](crate::plugin::Registry) like a plugin
//! ([`Registry::register_body_kind`](crate::plugin::Registry::register_body_kind)).
//!
//! A kind is a settings type ([`BodyKind`]): its name in scenes, its serde form (a bare name
//! such as `Fixed`, or settings such as `Prescribed(Slide(velocity: [1.0, 0.0]))`), the checks
//! of its values, and the [`BodyMotion`] it gives the body, or none for a fluid. The engine
//! keeps only the law ([`Body::motion`](super::Body::motion)); nothing downstream matches on
//! kinds. This module defines the two kinds without settings, [`Fluid`] and [`Fixed`].

use super::{BodyMotion, Hold};
use crate::plugin::{SceneInfo, SectionProblem};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::fmt::Debug;
use std::sync::Arc;

/// A kind of body, as a scene names it.
pub trait BodyKind:
    Serialize + DeserializeOwned + schemars::JsonSchema + Debug + Send + Sync + 'static
{
    /// The name used in scenes.
    const NAME: &'static str;
    /// One line for listings and error messages.
    const SUMMARY: &'static str;
    /// True for a kind written as a bare name (`Fixed`, deserialized from a unit), false for
    /// one written with its settings in parentheses (`Prescribed(..)`).
    const BARE: bool = false;
    /// True for a kind whose particles a plugin creates during the run (an open boundary's
    /// buffer): the scene may leave it without particles.
    const FILLED_DURING_RUN: bool = false;
    /// Rejects meaningless settings; the problem's field is relative to the kind (`axis`, or
    /// empty for the kind as a whole).
    fn validate(&self, _info: &SceneInfo) -> Result<(), SectionProblem> {
        Ok(())
    }
    /// The law that moves the body's particles, or `None` when the integrator moves them by
    /// the forces on them (a fluid).
    fn motion(&self) -> Option<Arc<dyn BodyMotion>>;
}

/// A parsed kind, with its type erased so a scene can hold kinds of any crate.
pub trait BodyKindConfig: Debug + Send + Sync {
    /// The registered name.
    fn name(&self) -> &'static str;
    /// See [`BodyKind::validate`].
    fn validate(&self, info: &SceneInfo) -> Result<(), SectionProblem>;
    /// See [`BodyKind::motion`].
    fn motion(&self) -> Option<Arc<dyn BodyMotion>>;
    /// True for a kind whose particles are integrated (no motion).
    fn is_fluid(&self) -> bool {
        self.motion().is_none()
    }
    /// See [`BodyKind::FILLED_DURING_RUN`].
    fn filled_during_run(&self) -> bool;
    /// The name, then the settings as resolved in postcard's encoding (see
    /// [`PluginConfig::canonical`](crate::plugin::PluginConfig::canonical)).
    fn canonical(&self) -> Vec<u8>;
}

impl<K: BodyKind> BodyKindConfig for K {
    fn name(&self) -> &'static str {
        K::NAME
    }
    fn validate(&self, info: &SceneInfo) -> Result<(), SectionProblem> {
        BodyKind::validate(self, info)
    }
    fn motion(&self) -> Option<Arc<dyn BodyMotion>> {
        BodyKind::motion(self)
    }
    fn filled_during_run(&self) -> bool {
        K::FILLED_DURING_RUN
    }
    fn canonical(&self) -> Vec<u8> {
        let mut bytes = K::NAME.as_bytes().to_vec();
        bytes.push(0);
        // as `PluginConfig::canonical`: the `Debug` text for what postcard cannot encode
        postcard::to_extend(self, bytes.clone()).unwrap_or_else(|_| {
            bytes.extend(format!("{self:?}").into_bytes());
            bytes
        })
    }
}

/// Parses a kind's settings from any serde deserializer (type-erased).
pub type BodyKindParseFn = fn(
    &mut dyn erased_serde::Deserializer<'_>,
) -> Result<Box<dyn BodyKindConfig>, erased_serde::Error>;

/// One registered kind.
#[derive(Clone, Copy)]
pub struct BodyKindEntry {
    /// The name used in scenes.
    pub name: &'static str,
    /// One-line description.
    pub summary: &'static str,
    /// See [`BodyKind::BARE`].
    pub bare: bool,
    /// Settings parser.
    pub parse: BodyKindParseFn,
    /// The settings' schema (see [`crate::plugin::fields`]).
    pub schema: fn() -> schemars::Schema,
}

impl Debug for BodyKindEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BodyKindEntry({})", self.name)
    }
}

impl BodyKindEntry {
    /// The entry of `K`.
    pub fn of<K: BodyKind>() -> Self {
        BodyKindEntry {
            name: K::NAME,
            summary: K::SUMMARY,
            bare: K::BARE,
            parse: parse_kind::<K>,
            schema: crate::plugin::fields::schema_of::<K>,
        }
    }
}

fn parse_kind<K: BodyKind>(
    d: &mut dyn erased_serde::Deserializer<'_>,
) -> Result<Box<dyn BodyKindConfig>, erased_serde::Error> {
    let k: K = erased_serde::deserialize(d)?;
    Ok(Box::new(k))
}

/// A body whose particles are integrated in time by the forces on them (the default kind).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Fluid;

impl BodyKind for Fluid {
    const NAME: &'static str = "Fluid";
    const SUMMARY: &'static str = "integrated in time by the forces on it (the default)";
    const BARE: bool = true;
    fn motion(&self) -> Option<Arc<dyn BodyMotion>> {
        None
    }
}

/// A body held at its initial positions with zero velocity: a wall, a fixed obstacle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Fixed;

impl BodyKind for Fixed {
    const NAME: &'static str = "Fixed";
    const SUMMARY: &'static str = "held at its initial position with zero velocity (a wall)";
    const BARE: bool = true;
    fn motion(&self) -> Option<Arc<dyn BodyMotion>> {
        Some(Arc::new(Hold))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_two_bare_kinds_give_no_law_and_hold() {
        assert!(BodyKindConfig::is_fluid(&Fluid));
        assert!(BodyKind::motion(&Fixed).is_some_and(|m| m.holds_still()));
        assert_ne!(
            BodyKindConfig::canonical(&Fluid),
            BodyKindConfig::canonical(&Fixed)
        );
    }

    /// A bare kind parses from a unit, as the scene gives it after its name.
    #[test]
    fn a_bare_kind_parses_from_a_unit() {
        let entry = BodyKindEntry::of::<Fixed>();
        let unit = serde::de::value::UnitDeserializer::<serde::de::value::Error>::new();
        let mut d = <dyn erased_serde::Deserializer>::erase(unit);
        let k = (entry.parse)(&mut d).unwrap();
        assert_eq!((k.name(), entry.bare), ("Fixed", true));
    }
}
