//! Deserializing the scene's `plugins: [Name(field: value, ...), ...]` list through a
//! [`Registry`].
//!
//! Serde's `Deserialize` has no way to receive extra arguments, so the registry reaches the
//! plugin-list deserializer through a thread-local: [`with_registry`] installs a copy of the
//! registry on the current thread for exactly the duration of one parse call and restores the
//! previous value afterwards (also on unwinding). Deserializing a `Scene` with a plugin list
//! outside [`crate::Scene::from_str`] / [`crate::Scene::parse_only`] fails with a clear error
//! instead of guessing.

use crate::de::Ident;
use dualsph_core::plugin::{PluginConfig, PluginEntry, Registry};
use serde::de::{
    self, DeserializeSeed, Deserializer, EnumAccess, SeqAccess, VariantAccess, Visitor,
};
use std::cell::{Cell, RefCell};
use std::fmt;

thread_local! {
    /// The registry of the parse call running on this thread, if any.
    static REGISTRY: RefCell<Option<Registry>> = const { RefCell::new(None) };
}

/// Runs `f` with `registry` visible to the plugin-list deserializer on this thread.
pub(crate) fn with_registry<T>(registry: &Registry, f: impl FnOnce() -> T) -> T {
    struct Restore(Option<Registry>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let previous = self.0.take();
            REGISTRY.with(|r| *r.borrow_mut() = previous);
        }
    }
    let previous = REGISTRY.with(|r| r.replace(Some(registry.clone())));
    let _restore = Restore(previous);
    f()
}

/// Runs `f` with the registry of the parse call running on this thread, if any.
pub(crate) fn with_current<T>(f: impl FnOnce(Option<&Registry>) -> T) -> T {
    REGISTRY.with(|r| f(r.borrow().as_ref()))
}

/// What the registry says about a name: the entry, or the list of registered names.
fn lookup(name: &str) -> Result<PluginEntry, String> {
    with_current(|r| match r {
        None => Err(format!(
            "cannot parse plugin `{name}`: no plugin registry is installed \
             (parse scenes with `Scene::from_str` or `Scene::load`)"
        )),
        Some(reg) => reg
            .get(name)
            .copied()
            .ok_or_else(|| unknown("plugin", "plugins", name, &reg.names())),
    })
}

/// The message for a name the registry does not hold: ``unknown <what> `name`, expected one
/// of: …`` with the registered names (or that there are no `<whats>` registered).
pub(crate) fn unknown(what: &str, whats: &str, name: &str, names: &[&str]) -> String {
    let list = if names.is_empty() {
        format!("(no {whats} are registered)")
    } else {
        names.join(", ")
    };
    format!("unknown {what} `{name}`, expected one of: {list}")
}

/// `deserialize_with` function for `Scene::plugins`.
pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Vec<Box<dyn PluginConfig>>, D::Error> {
    d.deserialize_seq(ListVisitor)
}

struct ListVisitor;

impl<'de> Visitor<'de> for ListVisitor {
    type Value = Vec<Box<dyn PluginConfig>>;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a list of plugins such as `[Gravity(g: [0.0, -9.81])]`")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut out = Vec::new();
        while let Some(p) = seq.next_element_seed(PluginSeed)? {
            out.push(p);
        }
        Ok(out)
    }
}

/// One list element, written like an enum variant `Name(...)`.
struct PluginSeed;

impl<'de> DeserializeSeed<'de> for PluginSeed {
    type Value = Box<dyn PluginConfig>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_enum("Plugin", &[], PluginVisitor)
    }
}

struct PluginVisitor;

impl<'de> Visitor<'de> for PluginVisitor {
    type Value = Box<dyn PluginConfig>;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a plugin written as `Name(field: value, ...)` or `Name()`")
    }
    fn visit_enum<A: EnumAccess<'de>>(self, data: A) -> Result<Self::Value, A::Error> {
        let (name, variant) = data.variant_seed(Ident)?;
        let entry = lookup(&name).map_err(de::Error::custom)?;
        let reached = Cell::new(false);
        variant
            .newtype_variant_seed(SettingsSeed(entry, &reached))
            .map_err(|e| {
                if reached.get() {
                    e
                } else {
                    // The parentheses around the settings are missing or malformed.
                    de::Error::custom(format_args!(
                        "plugin `{name}`: {e}; write `{name}(field: value, ...)`, or `{name}()` \
                         when it has no settings"
                    ))
                }
            })
    }
}

/// The plugin's settings, parsed by the registered (type-erased) parse function; sets the flag
/// once the settings' own parsing starts.
struct SettingsSeed<'a>(PluginEntry, &'a Cell<bool>);

impl<'de> DeserializeSeed<'de> for SettingsSeed<'_> {
    type Value = Box<dyn PluginConfig>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        self.1.set(true);
        let mut erased = <dyn erased_serde::Deserializer>::erase(d);
        let name = self.0.name;
        (self.0.parse)(&mut erased)
            .map_err(|e| de::Error::custom(format_args!("in settings of plugin `{name}`: {e}")))
    }
}
