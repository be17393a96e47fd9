//! The user docs against the code, quick tier: the plugin reference in `docs/plugins.md` is
//! what `dualsph doc` prints for the registry `dualsph` uses.
//!
//! `DUALSPH_BLESS=1 cargo test --release -p dualsph-run --test docs` rewrites the generated
//! section of `docs/plugins.md` instead of failing on it.

use dualsph_builtin::default_registry;
use std::path::{Path, PathBuf};

/// The line that opens the generated section of `docs/plugins.md` (the rest of its line is a
/// note for the reader).
const BEGIN: &str = "<!-- BEGIN GENERATED PLUGIN REFERENCE";
/// The line that closes it.
const END: &str = "<!-- END GENERATED PLUGIN REFERENCE -->";

/// The workspace root (the docs live there).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `text` with the generated section (between the [`BEGIN`] line and the [`END`] line)
/// replaced by `reference`, or why it cannot be found.
fn with_reference(text: &str, reference: &str) -> Result<String, String> {
    let begin = text.find(BEGIN).ok_or("no BEGIN marker")?;
    let body = begin + text[begin..].find('\n').ok_or("nothing after BEGIN")? + 1;
    let end = body + text[body..].find(END).ok_or("no END marker after BEGIN")?;
    Ok(format!("{}\n{reference}\n{}", &text[..body], &text[end..]))
}

#[test]
fn the_plugin_reference_in_the_docs_is_what_dualsph_doc_prints() {
    let path = root().join("docs/plugins.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let reference = dualsph_run::cli::reference_markdown(&default_registry());
    let want = with_reference(&text, &reference).unwrap_or_else(|e| panic!("docs/plugins.md: {e}"));
    if std::env::var_os("DUALSPH_BLESS").is_some_and(|v| v == "1") {
        if want != text {
            std::fs::write(&path, &want).unwrap();
        }
        return;
    }
    assert!(
        want == text,
        "docs/plugins.md: the generated plugin reference is not what `dualsph doc` prints; \
         regenerate it with `DUALSPH_BLESS=1 cargo test --release -p dualsph-run --test docs`"
    );
}
