//! `dualsph plugins [--fields]` and `dualsph doc NAME`: what a scene may write, from the
//! registry (the same settings types, and so the same serde attributes, the parser uses).

use super::exit::{self, Failure};
use dualsph_core::plugin::fields::{plain, render};
use dualsph_core::plugin::{Registry, SectionEntry};

/// The listing of `dualsph plugins`: one line per plugin, section and body kind, or with
/// `fields` the whole documentation of each.
pub(crate) fn listing(registry: &Registry, fields: bool) -> String {
    let mut out = String::new();
    if fields {
        for name in names(registry) {
            out.push_str(&doc(registry, &name).expect("a registered name"));
            out.push('\n');
        }
        return out;
    }
    for e in registry.entries() {
        out.push_str(&format!("{:<22} {}\n", e.name, e.summary));
    }
    out.push_str("\nscene sections (`key: (..)`):\n");
    for e in registry.sections() {
        out.push_str(&format!("{:<22} {}\n", e.key, section_summary(e)));
    }
    out.push_str("\nbody kinds (`Body(name: .., kind: ..)`):\n");
    for e in registry.body_kinds() {
        out.push_str(&format!("{:<22} {}\n", e.name, e.summary));
    }
    out.push_str("\n`dualsph doc NAME` prints a plugin's, section's or kind's fields.\n");
    out
}

/// The plugin reference that `docs/plugins.md` holds between its generated-section markers:
/// every name `dualsph doc` knows, grouped as plugins, scene sections and body kinds (in
/// registration order), each under a heading of its own with its text exactly as
/// `dualsph doc NAME` prints it, in a `text` block. Ends with one newline.
pub fn reference_markdown(registry: &Registry) -> String {
    let plugins = registry.entries().iter().map(|e| e.name.to_string());
    let sections = registry.sections().iter().map(|e| e.key.to_string());
    let kinds = registry.body_kinds().iter().map(|e| e.name.to_string());
    let groups: [(&str, Vec<String>); 3] = [
        ("Plugins", plugins.collect()),
        ("Scene sections", sections.collect()),
        ("Body kinds", kinds.collect()),
    ];
    let mut out = String::new();
    for (title, names) in groups {
        out.push_str(&format!("### {title}\n\n"));
        for name in names {
            let text = doc(registry, &name).expect("a registered name");
            out.push_str(&format!(
                "#### `{name}`\n\n```text\n{}\n```\n\n",
                text.trim_end()
            ));
        }
    }
    out.truncate(out.trim_end().len() + 1);
    out
}

/// Every name `doc` knows: plugins, then sections, then body kinds, in registration order.
pub(crate) fn names(registry: &Registry) -> Vec<String> {
    let plugins = registry.entries().iter().map(|e| e.name.to_string());
    let sections = registry.sections().iter().map(|e| e.key.to_string());
    let kinds = registry.body_kinds().iter().map(|e| e.name.to_string());
    plugins.chain(sections).chain(kinds).collect()
}

/// A section's one line: the first sentence of its settings type's doc comment.
fn section_summary(e: &SectionEntry) -> String {
    let schema = (e.schema)();
    let doc = schema
        .get("description")
        .and_then(|d| d.as_str())
        .unwrap_or("");
    let flat = plain(doc).replace('\n', " ");
    match flat.find(". ") {
        Some(end) => flat[..=end].to_string(),
        None => flat,
    }
}

/// The documentation of the plugin, section or body kind called `name`: its fields with
/// their types, defaults and doc comments.
pub(crate) fn doc(registry: &Registry, name: &str) -> Result<String, Failure> {
    if let Some(e) = registry.get(name) {
        let title = format!("{}(..) — plugin: {}", e.name, e.summary);
        return Ok(render(&title, &(e.schema)()));
    }
    if let Some(e) = registry.section(name) {
        let title = format!("{}: (..) — scene section", e.key);
        return Ok(render(&title, &(e.schema)()));
    }
    if let Some(e) = registry.body_kind(name) {
        let title = format!("kind: {} — body kind: {}", e.name, e.summary);
        return Ok(render(&title, &(e.schema)()));
    }
    Err(Failure::new(
        exit::INVALID_INPUT,
        format!(
            "no plugin, scene section or body kind named `{name}`; known: {}",
            names(registry).join(", ")
        ),
    ))
}

#[cfg(test)]
mod tests;
