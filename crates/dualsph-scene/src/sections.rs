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

/// `deserialize_with` function for `Scene::health`.
pub(crate) fn health<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Box<dyn SectionConfig>>, D::Error> {
    section("health", d).map(Some)
}
