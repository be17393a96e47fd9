//! `--set PATH=VALUE`: a value of the scene replaced (or added) from the command line.
//!
//! The path walks the scene as it is written: field names (`end_time`,
//! `integrator.dt.courant`), list indices (`particles[1].spacing`, `plugins[2].c0`), and the
//! name of a list member where it is the only one so named (`TaitEos.c0` is the `c0` of the
//! scene's one `TaitEos` plugin). A path that ends in `[+]` appends the value to that list
//! (`plugins[+]=Viscosity(alpha: 0.02)`; the list is added when the scene leaves it out). The value is RON text, parsed with the scene as if it were
//! written there (`0.01`, `Adaptive(courant: 0.1)`, `"name"`). A field the scene leaves out
//! (so at its default) is added. The edit is made on the text and the result is parsed and
//! validated as any scene, so an override can never produce a scene the file could not be.

mod tree;

use tree::{Body, Node};

/// One `PATH=VALUE`.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// As given, `PATH=VALUE`.
    pub given: String,
    path: Vec<Step>,
    value: String,
}

/// One step of a path: a field or list member's name, then indices.
#[derive(Clone, Debug, PartialEq)]
struct Step {
    name: String,
    indices: Vec<usize>,
    /// `[+]` after the indices: append to the list (only at the end of a path).
    append: bool,
}

impl std::str::FromStr for Override {
    type Err = String;

    /// Reads `PATH=VALUE`; the value must be one well-formed RON value.
    fn from_str(given: &str) -> Result<Self, String> {
        let (path, value) = given
            .split_once('=')
            .ok_or_else(|| format!("--set {given}: expected PATH=VALUE"))?;
        let path = parse_path(path.trim()).map_err(|m| format!("--set {given}: {m}"))?;
        let value = value.trim().to_owned();
        tree::parse(&value)
            .map_err(|(at, m)| format!("--set {given}: the value at character {}: {m}", at + 1))?;
        Ok(Override {
            given: given.to_owned(),
            path,
            value,
        })
    }
}

fn parse_path(path: &str) -> Result<Vec<Step>, String> {
    if path.is_empty() {
        return Err("empty path".into());
    }
    let steps: Vec<Step> = path.split('.').map(parse_step).collect::<Result<_, _>>()?;
    if steps[..steps.len() - 1].iter().any(|s| s.append) {
        return Err("`[+]` appends to a list, so it ends the path".into());
    }
    Ok(steps)
}

/// `name`, `name[2]`, `name[2][0]`, `name[+]`, `name[2][+]`.
fn parse_step(step: &str) -> Result<Step, String> {
    let (name, mut rest) = step.split_at(step.find('[').unwrap_or(step.len()));
    let valid = |c: char| c.is_ascii_alphanumeric() || c == '_';
    if name.is_empty() || !name.chars().all(valid) {
        return Err(format!(
            "`{step}`: a path step is a name (letters, digits, _) with optional [index]"
        ));
    }
    let mut indices = Vec::new();
    let mut append = false;
    while !rest.is_empty() {
        if append {
            return Err(format!(
                "`{step}`: `[+]` appends to a list, so it ends the path"
            ));
        }
        if rest.starts_with("[+]") {
            append = true;
            rest = &rest[3..];
            continue;
        }
        let close = rest.find(']').filter(|_| rest.starts_with('['));
        let index = close.and_then(|k| rest[1..k].parse::<usize>().ok());
        match (close, index) {
            (Some(k), Some(i)) => {
                indices.push(i);
                rest = &rest[k + 1..];
            }
            _ => {
                return Err(format!(
                    "`{step}`: expected [index] with a whole number, or [+] to append"
                ));
            }
        }
    }
    Ok(Step {
        name: name.to_owned(),
        indices,
        append,
    })
}

/// A replacement made in the text: bytes `start..start + old_len` became `new_len` bytes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Edit {
    start: usize,
    old_len: usize,
    new_len: usize,
    /// Which override made it.
    by: usize,
}

/// Where a byte of the edited text came from.
#[derive(Debug, PartialEq)]
pub(crate) enum Origin {
    /// This byte offset of the original text.
    File(usize),
    /// The value of this override.
    Set(usize),
}

/// The scene's text with the overrides applied, and how to trace positions back.
pub(crate) struct Edited {
    pub text: String,
    edits: Vec<Edit>,
}

impl Edited {
    /// Where byte `at` of the edited text came from.
    pub(crate) fn origin(&self, mut at: usize) -> Origin {
        for e in self.edits.iter().rev() {
            if at >= e.start + e.new_len {
                at = at - e.new_len + e.old_len;
            } else if at >= e.start {
                return Origin::Set(e.by);
            }
        }
        Origin::File(at)
    }
}

/// Why the overrides could not be applied.
#[derive(Debug, PartialEq)]
pub(crate) enum ApplyError {
    /// The scene's own text is not well formed at this byte offset (the scene parser says
    /// best how).
    Text(usize, String),
    /// This override names no value of the scene.
    Set(usize, String),
}

/// Applies `overrides` in order to the scene text.
pub(crate) fn apply(text: &str, overrides: &[Override]) -> Result<Edited, ApplyError> {
    let mut out = Edited {
        text: text.to_owned(),
        edits: Vec::new(),
    };
    for (k, o) in overrides.iter().enumerate() {
        // the values were read on their own, so only the file's own text can fail here
        let root = tree::parse(&out.text).map_err(|(at, m)| match out.origin(at) {
            Origin::File(at) => ApplyError::Text(at, m),
            Origin::Set(by) => ApplyError::Set(by, m),
        })?;
        let (start, end, new) =
            locate(&root, &o.path, &o.value).map_err(|m| ApplyError::Set(k, m))?;
        out.text.replace_range(start..end, &new);
        out.edits.push(Edit {
            start,
            old_len: end - start,
            new_len: new.len(),
            by: k,
        });
    }
    Ok(out)
}

/// 1-based line and column (in characters) of byte `at`.
pub(crate) fn line_col(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Byte offset of 1-based (`line`, `col`); the end of the text past it.
pub(crate) fn offset_of(text: &str, line: usize, col: usize) -> usize {
    let mut at = 0;
    for (k, l) in text.split_inclusive('\n').enumerate() {
        if k + 1 == line {
            return at + l.char_indices().nth(col - 1).map_or(l.len(), |(b, _)| b);
        }
        at += l.len();
    }
    text.len()
}

/// The span to replace and its new text: the value at `path`, or, for a field the scene
/// leaves out, the place to add `field: value`; for a path ending in `[+]`, the place to
/// append the value to the list.
fn locate(root: &Node, path: &[Step], value: &str) -> Result<(usize, usize, String), String> {
    let mut node = root;
    let mut walked = String::new();
    for (k, step) in path.iter().enumerate() {
        let last = k + 1 == path.len();
        node = match member(node, &step.name, &walked)? {
            Some(n) => n,
            None if last && step.indices.is_empty() && step.append => {
                return add_field(node, &step.name, &format!("[{value}]"));
            }
            None if last && step.indices.is_empty() => return add_field(node, &step.name, value),
            None if step.name.starts_with(char::is_uppercase) => {
                return Err(format!(
                    "{} has no field or list member `{}` (a plugin or generator is added in \
                     the scene file)",
                    describe(&walked),
                    step.name
                ));
            }
            None => {
                return Err(format!(
                    "{} does not give `{}` (it is at its default): set the whole `{}` instead",
                    describe(&walked),
                    step.name,
                    step.name
                ));
            }
        };
        push_name(&mut walked, &step.name);
        for &i in &step.indices {
            node = index(node, i, &walked)?;
            walked.push_str(&format!("[{i}]"));
        }
        if step.append {
            return append_item(node, value, &walked);
        }
    }
    Ok((node.start, node.end, value.to_owned()))
}

/// The place after the last member of the list `node` and the text that appends `value`.
fn append_item(node: &Node, value: &str, walked: &str) -> Result<(usize, usize, String), String> {
    match &node.body {
        Body::Items(g) if node.name.is_none() => {
            let text = match (g.members.last(), g.trailing_comma) {
                (None, _) => value.to_owned(),
                (Some(_), true) => format!("{value}, "),
                (Some(last), false) => return Ok((last.end, last.end, format!(", {value}"))),
            };
            Ok((g.close, g.close, text))
        }
        _ => Err(format!(
            "`{walked}` is not a list, so `[+]` cannot append to it"
        )),
    }
}

fn push_name(walked: &mut String, name: &str) {
    if !walked.is_empty() {
        walked.push('.');
    }
    walked.push_str(name);
}

fn describe(walked: &str) -> String {
    if walked.is_empty() {
        "the scene".into()
    } else {
        format!("`{walked}`")
    }
}

/// The field `name` of `node`, or its one list member named `name` (a plugin, a generator);
/// `None` when `node` takes fields but does not give this one.
fn member<'a>(node: &'a Node, name: &str, walked: &str) -> Result<Option<&'a Node>, String> {
    let fields: &[(String, Node)] = match &node.body {
        Body::Fields(g) => &g.members,
        _ => &[],
    };
    if let Some((_, n)) = fields.iter().find(|(f, _)| f == name) {
        return Ok(Some(n));
    }
    // members so named in the lists among the fields, or in the list itself
    let mut found: Vec<(String, &Node)> = Vec::new();
    let mut look = |list: &'a Node, at: &str| {
        if let Body::Items(g) = &list.body {
            for (i, n) in g.members.iter().enumerate() {
                if n.name.as_deref() == Some(name) {
                    found.push((format!("{at}[{i}]"), n));
                }
            }
        }
    };
    match &node.body {
        Body::Fields(g) => g.members.iter().for_each(|(f, n)| look(n, f)),
        Body::Items(_) => look(node, ""),
        _ => {}
    }
    match found.len() {
        1 => Ok(Some(found[0].1)),
        0 if matches!(node.body, Body::Fields(_)) || is_unit(node) => Ok(None),
        0 => Err(format!(
            "{} has no field or member `{name}`",
            describe(walked)
        )),
        _ => {
            let at: Vec<_> = found.iter().map(|(a, _)| a.as_str()).collect();
            Err(format!(
                "`{name}` is at {}: name one by its index (e.g. `{}`)",
                at.join(", "),
                at[0]
            ))
        }
    }
}

/// A bare name (`PressureForce`) or empty parentheses: a value that could take fields.
fn is_unit(node: &Node) -> bool {
    match &node.body {
        Body::Atom => node
            .name
            .as_deref()
            .is_some_and(|n| n.starts_with(char::is_alphabetic)),
        Body::Items(g) => g.members.is_empty(),
        _ => false,
    }
}

fn index<'a>(node: &'a Node, i: usize, walked: &str) -> Result<&'a Node, String> {
    match &node.body {
        Body::Items(g) => g
            .members
            .get(i)
            .ok_or_else(|| format!("`{walked}` has {} members, so no [{i}]", g.members.len())),
        _ => Err(format!("`{walked}` is not a list")),
    }
}

/// Adds `field: value` to `node`'s fields (before its closing parenthesis), or gives a bare
/// name its first field.
fn add_field(node: &Node, field: &str, value: &str) -> Result<(usize, usize, String), String> {
    let entry = format!("{field}: {value}");
    match &node.body {
        Body::Fields(g) if g.trailing_comma => Ok((g.close, g.close, format!(" {entry}"))),
        Body::Fields(g) => Ok((g.close, g.close, format!(", {entry}"))),
        Body::Items(g) => Ok((g.close, g.close, entry)),
        Body::Atom => Ok((node.end, node.end, format!("({entry})"))),
        Body::Map => Err("a map takes no fields".into()),
    }
}

#[cfg(test)]
mod tests;
