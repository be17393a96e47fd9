//! Deserializing a body's `kind` through the [`Registry`](dualsph_core::plugin::Registry) of
//! the parse call, like a plugin: the kind registered under the name parses its own settings
//! in place (`Prescribed(Slide(velocity: [1.0, 0.0]))`), or nothing for a bare kind
//! (`Fixed`), so a bad value is reported at its line and column (see
//! [`dualsph_core::bodies::kind`]).

use crate::de::Ident;
use crate::plugins_list::{unknown, with_current};
use dualsph_core::bodies::{BodyKindConfig, BodyKindEntry, Fluid};
use serde::de::{self, DeserializeSeed, Deserializer, EnumAccess, VariantAccess, Visitor};
use serde::{Serialize, Serializer};
use std::cell::Cell;
use std::fmt;
use std::sync::Arc;

/// The default kind: a fluid.
pub(crate) fn fluid() -> Arc<dyn BodyKindConfig> {
    Arc::new(Fluid)
}

/// The kind registered under `name`, or the list of those that are.
fn lookup(name: &str) -> Result<BodyKindEntry, String> {
    with_current(|r| match r {
        None => Err(format!(
            "cannot parse body kind `{name}`: no plugin registry is installed \
             (parse scenes with `Scene::from_str` or `Scene::load`)"
        )),
        Some(reg) => reg.body_kind(name).copied().ok_or_else(|| {
            let names: Vec<_> = reg.body_kinds().iter().map(|e| e.name).collect();
            unknown("body kind", "body kinds", name, &names)
        }),
    })
}

/// `deserialize_with` function for `BodySettings::kind`.
pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Arc<dyn BodyKindConfig>, D::Error> {
    d.deserialize_enum("BodyKind", &[], KindVisitor)
}

/// `serialize_with` function for `BodySettings::kind`: its canonical bytes (name and resolved
/// settings), so two spellings of one kind serialize alike.
pub(crate) fn serialize<S: Serializer>(
    kind: &Arc<dyn BodyKindConfig>,
    s: S,
) -> Result<S::Ok, S::Error> {
    kind.canonical().serialize(s)
}

struct KindVisitor;

impl<'de> Visitor<'de> for KindVisitor {
    type Value = Arc<dyn BodyKindConfig>;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a body kind such as `Fixed` or `Prescribed(Translate(velocity: [1.0, 0.0]))`")
    }
    fn visit_enum<A: EnumAccess<'de>>(self, data: A) -> Result<Self::Value, A::Error> {
        let (name, variant) = data.variant_seed(Ident)?;
        let entry = lookup(&name).map_err(de::Error::custom)?;
        let parsed = if entry.bare {
            variant.unit_variant().map_err(|e| {
                de::Error::custom(format_args!("body kind `{name}` has no settings: {e}"))
            })?;
            let unit = de::value::UnitDeserializer::<de::value::Error>::new();
            (entry.parse)(&mut <dyn erased_serde::Deserializer>::erase(unit))
                .map_err(de::Error::custom)?
        } else {
            let reached = Cell::new(false);
            variant
                .newtype_variant_seed(KindSeed(entry, &reached))
                .map_err(|e| {
                    if reached.get() {
                        e
                    } else {
                        // the parentheses around the settings are missing or malformed
                        de::Error::custom(format_args!(
                            "body kind `{name}`: {e}; write `{name}(...)` with its settings"
                        ))
                    }
                })?
        };
        Ok(Arc::from(parsed))
    }
}

/// A kind's settings, parsed by its registered (type-erased) parse function; sets the flag
/// once the settings' own parsing starts.
struct KindSeed<'a>(BodyKindEntry, &'a Cell<bool>);

impl<'de> DeserializeSeed<'de> for KindSeed<'_> {
    type Value = Box<dyn BodyKindConfig>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        self.1.set(true);
        let mut erased = <dyn erased_serde::Deserializer>::erase(d);
        let name = self.0.name;
        (self.0.parse)(&mut erased)
            .map_err(|e| de::Error::custom(format_args!("in body kind `{name}`: {e}")))
    }
}
