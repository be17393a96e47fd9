//! The house keeps its layers (ARCHITECTURE.md): no crate of the workspace depends on a crate
//! of a layer above its own, and inside a crate no modules import each other in a circle
//! larger than a module and its own child. Both are read from the sources, so a change that
//! breaks either fails here, with the crates or modules named.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The layer of the plugins.
const PLUGINS: u32 = 5;

/// The layer of each workspace package, lowest first; plugins share one layer and may use
/// each other.
fn layer(package: &str) -> Option<u32> {
    Some(match package {
        "dualsph-math" | "dualsph-io" | "dualsph-reference" => 0,
        "dualsph-neighbours" | "dualsph-plot" => 1,
        "dualsph-core" => 2,
        "dualsph-sweep" | "dualsph-scene" | "dualsph-integrate" => 3,
        "dualsph-fluid" => 4,
        "dualsph-builtin" => 6,
        "dualsph-run" => 7,
        "dualsph" => 8,
        "dualsph-validation" | "custom-physics" => 9,
        p if p.starts_with("dualsph-") => PLUGINS,
        _ => return None,
    })
}

/// Arrows that point up today, each with its reason; the list may only shrink.
const KNOWN_UPWARD: &[(&str, &str)] = &[];

/// The package name and the engine crates among the `[dependencies]` of a manifest.
fn manifest(path: &Path) -> (String, Vec<String>) {
    let text = std::fs::read_to_string(path).unwrap();
    let (mut name, mut deps, mut section) = (String::new(), Vec::new(), String::new());
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            section = line.to_string();
        } else if section == "[package]" && line.starts_with("name") {
            name = line.split('"').nth(1).unwrap_or("").to_string();
        } else if section == "[dependencies]" {
            let dep = line.split(['=', '.', ' ']).next().unwrap_or("");
            if layer(dep).is_some() && !dep.is_empty() {
                deps.push(dep.to_string());
            }
        }
    }
    (name, deps)
}

/// Every package directory of the workspace.
fn packages() -> Vec<PathBuf> {
    let mut dirs = vec![
        root(),
        root().join("validation"),
        root().join("examples/custom-physics"),
    ];
    for group in ["crates", "plugins"] {
        let mut inside: Vec<PathBuf> = std::fs::read_dir(root().join(group))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.join("Cargo.toml").exists())
            .collect();
        inside.sort();
        dirs.extend(inside);
    }
    dirs
}

#[test]
fn no_crate_depends_on_a_layer_above_its_own() {
    let mut upward = Vec::new();
    for dir in packages() {
        let (name, deps) = manifest(&dir.join("Cargo.toml"));
        let own = layer(&name).unwrap_or_else(|| panic!("{name} has no layer in this test"));
        for dep in deps {
            let theirs = layer(&dep).unwrap();
            let plugins = own == PLUGINS && theirs == PLUGINS;
            if theirs > own || (theirs == own && !plugins) {
                upward.push((name.clone(), dep));
            }
        }
    }
    let known: Vec<(String, String)> = KNOWN_UPWARD
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    let new: Vec<_> = upward.iter().filter(|a| !known.contains(a)).collect();
    assert!(
        new.is_empty(),
        "dependencies that point up a layer: {new:?}"
    );
    let gone: Vec<_> = known.iter().filter(|k| !upward.contains(k)).collect();
    assert!(
        gone.is_empty(),
        "no longer there, take them off KNOWN_UPWARD: {gone:?}"
    );
}

/// The modules of one crate's `src` and the modules each names with `crate::` or `super::`.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut files = Vec::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                files.push(p);
            }
        }
    }
    let name_of = |p: &Path| {
        let rel = p.strip_prefix(src).unwrap().with_extension("");
        let mut parts: Vec<String> = rel.iter().map(|s| s.to_string_lossy().into()).collect();
        if matches!(
            parts.last().map(String::as_str),
            Some("lib" | "mod" | "main")
        ) {
            parts.pop();
        }
        parts.join("::")
    };
    let modules: BTreeSet<String> = files.iter().map(|p| name_of(p)).collect();
    let resolve = |path: &str| {
        let segs: Vec<&str> = path.split("::").collect();
        (1..=segs.len())
            .rev()
            .map(|k| segs[..k].join("::"))
            .find(|m| modules.contains(m) && !m.is_empty())
    };
    let mut graph = BTreeMap::new();
    for p in &files {
        let me = name_of(p);
        let parent = me.rsplit_once("::").map_or("", |(a, _)| a).to_string();
        let text: String = std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        let mut out = BTreeSet::new();
        for (prefix, base) in [("crate::", String::new()), ("super::", parent.clone())] {
            for (at, _) in text.match_indices(prefix) {
                let rest: String = text[at + prefix.len()..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                    .collect();
                let full = if base.is_empty() {
                    rest
                } else {
                    format!("{base}::{rest}")
                };
                if let Some(m) = resolve(&full).filter(|m| *m != me) {
                    out.insert(m);
                }
            }
        }
        graph.insert(me, out);
    }
    graph
}

/// The circles of a graph (its strongly connected components of more than one module) other
/// than a module and its own child.
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let reach = |from: &String| {
        let (mut seen, mut todo) = (BTreeSet::new(), vec![from.clone()]);
        while let Some(m) = todo.pop() {
            for n in graph.get(&m).into_iter().flatten() {
                if seen.insert(n.clone()) {
                    todo.push(n.clone());
                }
            }
        }
        seen
    };
    let reaches: BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|m| (m, reach(m))).collect();
    let mut out: Vec<Vec<String>> = Vec::new();
    for m in graph.keys() {
        let comp: Vec<String> = graph
            .keys()
            .filter(|n| *n == m || (reaches[m].contains(*n) && reaches[*n].contains(m)))
            .cloned()
            .collect();
        let child = |a: &str, b: &str| {
            b.strip_prefix(a)
                .is_some_and(|r| r.starts_with("::") && !r[2..].contains("::"))
        };
        let allowed = comp.len() < 2
            || (comp.len() == 2 && (child(&comp[0], &comp[1]) || child(&comp[1], &comp[0])));
        if !allowed && !out.contains(&comp) {
            out.push(comp);
        }
    }
    out
}

/// Module circles that exist today, by crate; the list may only shrink.
const KNOWN_CIRCLES: &[(&str, &[&str])] = &[];

#[test]
fn no_crate_has_modules_in_a_circle() {
    let mut found = Vec::new();
    for dir in packages() {
        let src = dir.join("src");
        let rel = dir
            .strip_prefix(root())
            .unwrap()
            .to_string_lossy()
            .to_string();
        for c in circles(&module_graph(&src)) {
            found.push((rel.clone(), c));
        }
    }
    let known: Vec<(String, Vec<String>)> = KNOWN_CIRCLES
        .iter()
        .map(|(k, c)| (k.to_string(), c.iter().map(|s| s.to_string()).collect()))
        .collect();
    let new: Vec<_> = found.iter().filter(|f| !known.contains(f)).collect();
    assert!(
        new.is_empty(),
        "modules that import each other in a circle: {new:?}"
    );
    let gone: Vec<_> = known.iter().filter(|k| !found.contains(k)).collect();
    assert!(
        gone.is_empty(),
        "no longer there, take them off KNOWN_CIRCLES: {gone:?}"
    );
}

/// The checks can fail: a made-up circle of three modules is found, a module and its child
/// are allowed.
#[test]
fn a_circle_is_found() {
    let g = |edges: &[(&str, &str)]| {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (a, b) in edges {
            g.entry(a.to_string()).or_default().insert(b.to_string());
            g.entry(b.to_string()).or_default();
        }
        g
    };
    let three = circles(&g(&[("a", "b"), ("b", "c"), ("c", "a")]));
    assert_eq!(three, vec![vec!["a".to_string(), "b".into(), "c".into()]]);
    assert!(circles(&g(&[("a", "a::b"), ("a::b", "a")])).is_empty());
    assert_eq!(circles(&g(&[("a", "c::b"), ("c::b", "a")])).len(), 1);
}
