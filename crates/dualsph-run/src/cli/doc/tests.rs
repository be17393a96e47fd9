//! The user docs against the code, quick tier: the plugin reference in `docs/plugins.md` is
//! what `dualsph doc` prints for the registry `dualsph` uses, and every fenced `ron` block of
//! `README.md` and `docs/` parses with the engine's scene parser: a `Scene(..)` as it is, a
//! scene field, plugin, generator or body entry inside a minimal scene. A block that shows a
//! deliberate mistake is fenced ` ```ron,ignore ` and skipped (the page says why); a failure
//! names the block's file and line.
//!
//! `DUALSPH_BLESS=1 cargo test --release -p dualsph-run --lib cli::doc::tests` rewrites the generated
//! section of `docs/plugins.md` instead of failing on it.

use dualsph_builtin::default_registry;
use dualsph_scene::{Registry, Scene, SceneError};
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
    let reference = crate::cli::reference_markdown(&default_registry());
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
         regenerate it with `DUALSPH_BLESS=1 cargo test --release -p dualsph-run --lib cli::doc::tests`"
    );
}

/// One fenced `ron` block: where it is and what it holds.
struct Snippet {
    /// `README.md` or `docs/….md`.
    file: String,
    /// 1-based line of the opening fence.
    fence: usize,
    text: String,
}

/// The `ron` blocks of the markdown `text`; a block opened with `ron,ignore` (a deliberately
/// wrong one) is skipped, as are the blocks of other languages.
fn snippets(file: &str, text: &str) -> Vec<Snippet> {
    let mut out = Vec::new();
    // inside a block: the `ron` one being read, or `None` in another language's
    let mut block: Option<Option<Snippet>> = None;
    for (k, line) in text.lines().enumerate() {
        let fence = line.trim_start().starts_with("```");
        match &mut block {
            None if fence => {
                let ron = line.trim() == "```ron";
                block = Some(ron.then(|| Snippet {
                    file: file.to_string(),
                    fence: k + 1,
                    text: String::new(),
                }));
            }
            Some(s) if fence => {
                out.extend(s.take());
                block = None;
            }
            Some(Some(s)) => {
                s.text.push_str(line);
                s.text.push('\n');
            }
            _ => {}
        }
    }
    out
}

/// The minimal scene a fragment is placed in: every required field, each on one line.
const WRAPPER: [(&str, &str); 6] = [
    ("name", "\"snippet\""),
    ("dimension", "2"),
    ("domain", "(min: [0.0, 0.0], max: [1.0, 1.0])"),
    ("kernel", "CubicSpline"),
    (
        "particles",
        "[Block(min: [0.0, 0.0], max: [0.5, 0.5], spacing: 0.1, density: 1000.0, h_factor: 2.0)]",
    ),
    ("end_time", "1.0"),
];

/// The generators a scene's `particles` list takes.
const GENERATORS: [&str; 4] = ["Block", "Disk", "Shape", "File"];

/// The first word of `text` after blank and comment lines, and the character after it
/// (`Scene` and `(`, `output` and `:`).
fn lead(text: &str) -> (&str, Option<char>) {
    let body = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with("//"))
        .unwrap_or("");
    let end = body
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(body.len());
    let next = body[end..].trim_start().chars().next();
    (&body[..end], next)
}

/// `snippet` as a whole scene and the number of lines put before it: a `Scene(..)` as it is,
/// a scene field (`output: (..)`) in the minimal scene, a plugin, generator or body entry in
/// that list of the minimal scene; `None` for text none of these.
fn as_scene(snippet: &str, registry: &Registry) -> Option<(String, usize)> {
    let (word, next) = lead(snippet);
    let body = snippet.trim_end();
    let body = body.strip_suffix(',').unwrap_or(body);
    let (key, text) = match next {
        Some('(') if word == "Scene" => return Some((snippet.to_string(), 0)),
        Some(':') => (word, format!("{body}\n,\n")),
        Some('(') if registry.get(word).is_some() => {
            ("plugins", format!("plugins: [\n{body}\n],\n"))
        }
        Some('(') if GENERATORS.contains(&word) => {
            ("particles", format!("particles: [\n{body}\n],\n"))
        }
        Some('(') if word == "Body" => ("bodies", format!("bodies: [\n{body}\n],\n")),
        _ => return None,
    };
    let mut scene = format!("Scene(\n{text}");
    for (field, value) in WRAPPER.iter().filter(|(f, _)| *f != key) {
        scene.push_str(&format!("{field}: {value},\n"));
    }
    scene.push_str(")\n");
    let before = if next == Some(':') { 1 } else { 2 };
    Some((scene, before))
}

/// Whether `s` parses with the engine's scene parser; else the error, at the snippet's line
/// in its file. Only syntax, names and types count: a file the snippet names (an STL mesh, an
/// outline) is looked for beside the shipped scenes, and one that is not there is not the
/// snippet's fault.
fn check(s: &Snippet, registry: &Registry) -> Result<(), String> {
    let Some((scene, before)) = as_scene(&s.text, registry) else {
        return Err(format!(
            "{}:{}: a `ron` block that is neither a `Scene(..)`, a scene field, nor a plugin, \
             generator or body entry (mark a deliberately wrong one ```ron,ignore)",
            s.file, s.fence
        ));
    };
    let path = root().join("scenes/snippet.ron");
    match Scene::parse_only(&scene, &path, registry) {
        Err(SceneError::Parse {
            line, col, message, ..
        }) => {
            let inside = line > before && line <= before + s.text.lines().count();
            let at = if inside {
                format!("{}:{}", s.fence + line - before, col)
            } else {
                format!("{} (the block)", s.fence)
            };
            Err(format!("{}:{at}: does not parse: {message}", s.file))
        }
        _ => Ok(()),
    }
}

/// `README.md` and every markdown file under `docs/`, as paths from the root.
fn markdown_files() -> Vec<String> {
    fn walk(dir: &Path, rel: &str, out: &mut Vec<String>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().collect();
        entries.sort_by_key(|e| e.file_name());
        for e in entries {
            let name = format!("{rel}/{}", e.file_name().to_string_lossy());
            if e.path().is_dir() {
                walk(&e.path(), &name, out);
            } else if name.ends_with(".md") {
                out.push(name);
            }
        }
    }
    let mut out = vec!["README.md".to_string()];
    walk(&root().join("docs"), "docs", &mut out);
    out
}

#[test]
fn every_ron_block_in_the_docs_parses() {
    let registry = default_registry();
    let (mut checked, mut failures) = (0, Vec::new());
    for file in markdown_files() {
        let text = std::fs::read_to_string(root().join(&file)).unwrap();
        for s in snippets(&file, &text) {
            checked += 1;
            failures.extend(check(&s, &registry).err());
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // the README's scene, the scene format, the tutorial's, the probes, shapes, output, ...
    assert!(checked >= 10, "only {checked} ron blocks found");
}

#[test]
fn a_misspelt_block_fails_at_its_line_in_its_file() {
    let registry = default_registry();
    let doc = "# A page\n\n```ron\nProbes(every: 50, probes: [\n    Point(name: \"P1\", at: [1.0, 0.1], quantiy: \"pressure\"),\n]),\n```\n\n```ron,ignore\nNoSuchPlugin()\n```\n\n```ron\noutput: (snapshot_every: 10)\n```\n";
    let found = snippets("docs/page.md", doc);
    assert_eq!(found.len(), 2, "the ignored block is skipped");
    let err = check(&found[0], &registry).unwrap_err();
    assert!(err.starts_with("docs/page.md:5:"), "{err}");
    assert!(err.contains("quantiy"), "{err}");
    check(&found[1], &registry).unwrap();
    let wrong = Snippet {
        file: "README.md".into(),
        fence: 10,
        text: "output: (snapshot_evry: 10)\n".into(),
    };
    let err = check(&wrong, &registry).unwrap_err();
    assert!(err.starts_with("README.md:11:"), "{err}");
    let scene = Snippet {
        file: "README.md".into(),
        fence: 1,
        text: "Scene(\n    name: 1,\n)\n".into(),
    };
    assert!(
        check(&scene, &registry)
            .unwrap_err()
            .starts_with("README.md:3:")
    );
}
