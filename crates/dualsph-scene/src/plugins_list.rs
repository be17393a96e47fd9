//! Deserializing the scene's `plugins: [Name(field: value, ...), ...]` list through a
//! [`Registry`].
//!
//! Serde's `Deserialize` has no way to receive extra arguments, so the registry reaches the
//! plugin-list deserializer through a thread-local: [`with_registry`] installs a copy of the
//! registry on the current thread for exactly the duration of one parse call and restores the
//! previous value afterwards (also on unwinding). Deserializing a `Scene` with a plugin list
//! outside [`crate::Scene::from_str`] / [`crate::Scene::parse_only`] fails with a clear error
//! instead of guessing.
//!
//! Each plugin is taken from the scene as its RON text (`Name(field: value, ...)`) and its
//! settings are parsed by RON itself through the registry's parse function, not through a
//! type-erased deserializer: RON gives a bare word (`quantity: density`) its name only to a
//! deserializer whose type it sees. An error inside the settings is kept with its position in
//! the scene's text, so the message points at the offending token.

use dualsph_core::plugin::{PluginConfig, PluginEntry, Registry};
use ron::value::RawValue;
use serde::de::{self, DeserializeSeed, Deserializer, SeqAccess, Visitor};
use std::cell::{Cell, RefCell};
use std::fmt;

thread_local! {
    /// The registry of the parse call running on this thread, if any.
    static REGISTRY: RefCell<Option<Registry>> = const { RefCell::new(None) };
    /// The parse call's text, as the address range of its bytes (to place a plugin's text).
    static TEXT: Cell<(usize, usize)> = const { Cell::new((0, 0)) };
    /// The first error inside a plugin's settings: its byte offset in the text and message.
    static PENDING: RefCell<Option<(usize, String)>> = const { RefCell::new(None) };
}

/// An error inside a plugin's settings, placed in the scene's text.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PluginError {
    /// Byte offset in the text.
    pub at: usize,
    /// What is wrong, naming the plugin.
    pub message: String,
}

/// Runs `f`, parsing `text`, with `registry` visible to the plugin-list deserializer on this
/// thread; also returns the first error found inside a plugin's settings, if any.
pub(crate) fn with_registry<T>(
    registry: &Registry,
    text: &str,
    f: impl FnOnce() -> T,
) -> (T, Option<PluginError>) {
    struct Restore(Option<Registry>, (usize, usize));
    impl Drop for Restore {
        fn drop(&mut self) {
            let previous = self.0.take();
            REGISTRY.with(|r| *r.borrow_mut() = previous);
            TEXT.with(|t| t.set(self.1));
            PENDING.with(|p| p.borrow_mut().take());
        }
    }
    let previous = REGISTRY.with(|r| r.replace(Some(registry.clone())));
    let previous_text = TEXT.with(|t| t.replace((text.as_ptr() as usize, text.len())));
    let _restore = Restore(previous, previous_text);
    PENDING.with(|p| p.borrow_mut().take());
    let out = f();
    let pending = PENDING.with(|p| p.borrow_mut().take());
    (
        out,
        pending.map(|(at, message)| PluginError { at, message }),
    )
}

/// The byte offset of `part` in the parse call's text, when it lies there.
fn offset_in_text(part: &str) -> Option<usize> {
    let (start, len) = TEXT.with(Cell::get);
    let at = (part.as_ptr() as usize).checked_sub(start)?;
    (at + part.len() <= len).then_some(at)
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

/// One list element, written like an enum variant `Name(...)`: its text, split into the name
/// and the settings, which the registry's parse function reads.
struct PluginSeed;

impl<'de> DeserializeSeed<'de> for PluginSeed {
    type Value = Box<dyn PluginConfig>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        let raw = <&'de RawValue as serde::Deserialize<'de>>::deserialize(d)?;
        let text = raw.trim().get_ron();
        let name_len = text
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(text.len());
        let (name, rest) = text.split_at(name_len);
        if name.is_empty() || name.starts_with(|c: char| c.is_ascii_digit()) {
            return Err(placed(
                text,
                0,
                "expected a plugin written as `Name(field: value, ...)` or `Name()`".into(),
            ));
        }
        let entry = lookup(name).map_err(|m| placed(text, 0, m))?;
        let settings = rest.trim_start();
        if !settings.starts_with('(') {
            return Err(placed(
                text,
                0,
                format!(
                    "plugin `{name}`: write `{name}(field: value, ...)`, or `{name}()` when it \
                     has no settings"
                ),
            ));
        }
        (entry.parse)(&crate::ron_options(), settings).map_err(|e| {
            let at =
                crate::overrides::offset_of(settings, e.span.start.line, e.span.start.col.max(1));
            placed(
                settings,
                at,
                format!("in settings of plugin `{name}`: {}", e.code),
            )
        })
    }
}

/// The error `message` at byte `at` of `part` (a piece of the parse call's text), kept with
/// its place for the scene's error (ron would place it after the whole plugin).
fn placed<E: de::Error>(part: &str, at: usize, message: String) -> E {
    if let Some(base) = offset_in_text(part) {
        PENDING.with(|p| {
            p.borrow_mut().get_or_insert((base + at, message.clone()));
        });
    }
    E::custom(message)
}
