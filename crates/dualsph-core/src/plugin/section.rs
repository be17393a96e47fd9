//! Scene sections: settings that a plugin crate owns and a scene gives as a top-level section
//! of its own (`integrator: (dt: Fixed(1e-4))`, `health: (density_below: 100.0)`) instead of
//! in its `plugins` list.
//!
//! The owning crate defines the settings type ([`SceneSection`]: the section's key, its
//! serde form with its defaults and the checks of its values) and a registry holds it
//! ([`Registry::register_section`](super::Registry::register_section)); the scene parser
//! looks the section up by its key and parses it in place, so a bad value is reported at its
//! line and column. The crate that builds the simulation reads the typed settings back with
//! `<dyn SectionConfig>::section`.

use super::SceneInfo;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::any::Any;
use std::fmt::Debug;

/// A bad value of a section: the field (`integrator.dt.courant`) and what is wrong with it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SectionProblem {
    /// The field, starting with the section's key.
    pub field: String,
    /// What is wrong with its value.
    pub message: String,
}

impl SectionProblem {
    /// A problem of `field`.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        SectionProblem {
            field: field.into(),
            message: message.into(),
        }
    }
}

/// The settings of a scene section, owned by the crate that uses them.
pub trait SceneSection:
    Serialize + DeserializeOwned + schemars::JsonSchema + Debug + Send + Sync + 'static
{
    /// The section's field name in a scene.
    const KEY: &'static str;
    /// Rejects meaningless settings (checked with the rest of the scene, in order).
    fn validate(&self, _info: &SceneInfo) -> Result<(), SectionProblem> {
        Ok(())
    }
}

/// A parsed section, with its type erased so a scene can hold sections of any crate.
pub trait SectionConfig: Debug + Send + Sync {
    /// The section's key.
    fn key(&self) -> &'static str;
    /// See [`SceneSection::validate`].
    fn validate(&self, info: &SceneInfo) -> Result<(), SectionProblem>;
    /// The settings, to downcast to their type.
    fn as_any(&self) -> &dyn Any;
    /// The settings as they were resolved (defaults filled in) in postcard's encoding: two
    /// spellings of the same settings give the same bytes (see
    /// [`PluginConfig::canonical`](super::PluginConfig::canonical), which also prefixes the
    /// name).
    fn canonical(&self) -> Vec<u8>;
}

impl<S: SceneSection> SectionConfig for S {
    fn key(&self) -> &'static str {
        S::KEY
    }
    fn validate(&self, info: &SceneInfo) -> Result<(), SectionProblem> {
        SceneSection::validate(self, info)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn canonical(&self) -> Vec<u8> {
        // as `PluginConfig::canonical`: the `Debug` text for what postcard cannot encode
        postcard::to_stdvec(self).unwrap_or_else(|_| format!("{self:?}").into_bytes())
    }
}

impl dyn SectionConfig + '_ {
    /// The settings as `S`, if they are of that type.
    pub fn section<S: SceneSection>(&self) -> Option<&S> {
        self.as_any().downcast_ref::<S>()
    }
}

/// Parses a section's settings from any serde deserializer (type-erased).
pub type SectionParseFn = fn(
    &mut dyn erased_serde::Deserializer<'_>,
) -> Result<Box<dyn SectionConfig>, erased_serde::Error>;

/// One registered section.
#[derive(Clone, Copy)]
pub struct SectionEntry {
    /// The section's field name in a scene.
    pub key: &'static str,
    /// Settings parser.
    pub parse: SectionParseFn,
    /// The settings' schema (see [`super::fields`]).
    pub schema: fn() -> schemars::Schema,
}

impl Debug for SectionEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SectionEntry({})", self.key)
    }
}

pub(super) fn parse_section<S: SceneSection>(
    d: &mut dyn erased_serde::Deserializer<'_>,
) -> Result<Box<dyn SectionConfig>, erased_serde::Error> {
    let s: S = erased_serde::deserialize(d)?;
    Ok(Box::new(s))
}
