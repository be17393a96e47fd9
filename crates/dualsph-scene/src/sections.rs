//! Deserializing the scene sections plugin crates own (`integrator: (..)`, `health: (..)`)
//! through the [`Registry`](dualsph_core::plugin::Registry) of the parse call: the settings
//! type registered under the section's key parses it in place, so its errors carry their
//! line and column (see [`dualsph_core::plugin::section`]).

use crate::plugins_list::with_current;
use dualsph_core::plugin::{SectionConfig, SectionEntry};
use serde::de::{self, Deserializer};

/// The section registered under `key`, or why there is none.
fn lookup(key: &str) -> Result<SectionEntry, String> {
    with_current(|r| match r {
        None => Err(format!(
            "cannot parse section `{key}`: no plugin registry is installed \
             (parse scenes with `Scene::from_str` or `Scene::load`)"
        )),
        Some(reg) => reg.section(key).copied().ok_or_else(|| {
            format!(
                "no settings are registered for the section `{key}` (register them with \
                 `Registry::register_section`, as `dualsph_builtin::default_registry` does)"
            )
        }),
    })
}

/// The section `key`, parsed by its registered settings type.
fn section<'de, D: Deserializer<'de>>(key: &str, d: D) -> Result<Box<dyn SectionConfig>, D::Error> {
    let entry = lookup(key).map_err(de::Error::custom)?;
    let mut erased = <dyn erased_serde::Deserializer>::erase(d);
    (entry.parse)(&mut erased).map_err(de::Error::custom)
}

/// `deserialize_with` function for `Scene::integrator`.
pub(crate) fn integrator<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Box<dyn SectionConfig>, D::Error> {
    section("integrator", d)
}

/// The `integrator` section a scene leaves out: its registered settings type parsed from
/// `()` (its defaults). A registry without one (or whose type has no defaults) gives a
/// section that [`validate`](SectionConfig::validate) refuses, with why.
pub(crate) fn default_integrator() -> Box<dyn SectionConfig> {
    let parsed = lookup("integrator").and_then(|entry| {
        let mut d = ron::Deserializer::from_str("()").map_err(|e| e.to_string())?;
        let mut erased = <dyn erased_serde::Deserializer>::erase(&mut d);
        (entry.parse)(&mut erased).map_err(|e| {
            format!("the scene has no `integrator` section and its settings have no default: {e}")
        })
    });
    parsed.unwrap_or_else(|why| Box::new(Missing(why)))
}

/// A section that could not be given a default: `validate` says why.
#[derive(Debug, serde::Serialize)]
struct Missing(String);

impl SectionConfig for Missing {
    fn key(&self) -> &'static str {
        "integrator"
    }
    fn validate(
        &self,
        _: &dualsph_core::plugin::SceneInfo,
    ) -> Result<(), dualsph_core::plugin::SectionProblem> {
        Err(dualsph_core::plugin::SectionProblem::new(
            "integrator",
            self.0.clone(),
        ))
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn canonical(&self) -> Vec<u8> {
        self.0.as_bytes().to_vec()
    }
}

/// `deserialize_with` function for `Scene::health`.
pub(crate) fn health<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Box<dyn SectionConfig>>, D::Error> {
    section("health", d).map(Some)
}
