//! The fields of a plugin's (section's, body kind's) settings as a person reads them: name,
//! type, default and the doc comment's text, rendered from the settings' JSON schema.
//!
//! The schema is derived with `schemars::JsonSchema` beside `serde::Deserialize`, and
//! schemars reads the same serde attributes the parser obeys (`default`, `rename`,
//! `untagged`, `deny_unknown_fields`), so the listing cannot drift from what a scene may
//! write. Types are given in a scene's terms: `number`, `integer`, `[number; 2]`, the unit
//! variants of an enum as `Zero | Skip | Nan`, an optional field as `number (optional)`;
//! types of their own (an enum with settings in its variants, a nested struct) are listed
//! after the fields, each once.

use schemars::{JsonSchema, Schema};
use serde_json::{Map, Value};
use std::fmt::Write;

/// The root schema of `T`: its definitions inlined where schemars allows, the others under
/// `$defs`.
pub fn schema_of<T: JsonSchema>() -> Schema {
    schemars::SchemaGenerator::default().into_root_schema_for::<T>()
}

/// One field of a settings struct.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The name a scene writes.
    pub name: String,
    /// The type in a scene's terms (see the module's documentation).
    pub ty: String,
    /// The default as a scene would write it, or `None` for a required field.
    pub default: Option<String>,
    /// The doc comment's text.
    pub doc: String,
    /// The field's schema, for checks of its kind (`number` fields carry units).
    pub schema: Value,
}

/// The fields of the object `schema` (a settings struct, or a struct variant's body) with the
/// definitions of `root` to resolve references against.
pub fn fields(schema: &Value, root: &Value) -> Vec<Field> {
    let required: Vec<&str> = schema
        .get("required")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    let Some(props) = schema.get("properties").and_then(Value::as_object) else {
        return Vec::new();
    };
    props
        .iter()
        .map(|(name, s)| {
            let optional = !required.contains(&name.as_str());
            let default = match s.get("default") {
                Some(d) => Some(ron_value(d, s, root)),
                None if optional => Some("none".to_string()),
                None => None,
            };
            Field {
                name: name.clone(),
                ty: type_name(s, root),
                default,
                doc: description(s, root),
                schema: s.clone(),
            }
        })
        .collect()
}

/// The description of `s`, or of the definition it refers to when it has none of its own.
fn description(s: &Value, root: &Value) -> String {
    if let Some(d) = s.get("description").and_then(Value::as_str) {
        return d.to_string();
    }
    resolve(s, root)
        .and_then(|d| d.get("description"))
        .and_then(Value::as_str)
        .unwrap_or("")
        .to_string()
}

/// The definition `s` refers to (`{"$ref": "#/$defs/Name"}`), if it is a reference.
fn resolve<'a>(s: &Value, root: &'a Value) -> Option<&'a Value> {
    let name = ref_name(s)?;
    root.get("$defs")?.get(name)
}

fn ref_name(s: &Value) -> Option<&str> {
    s.get("$ref")?.as_str()?.strip_prefix("#/$defs/")
}

/// The unit variants of an enum schema, when all its variants are units.
fn unit_variants(s: &Value) -> Option<Vec<String>> {
    if let Some(e) = s.get("enum").and_then(Value::as_array) {
        return e.iter().map(|v| v.as_str().map(str::to_string)).collect();
    }
    let alts = s.get("oneOf").or_else(|| s.get("anyOf"))?.as_array()?;
    let mut out = Vec::new();
    for a in alts {
        if let Some(c) = a.get("const").and_then(Value::as_str) {
            out.push(c.to_string());
        } else if let Some(e) = a.get("enum").and_then(Value::as_array) {
            for v in e {
                out.push(v.as_str()?.to_string());
            }
        } else {
            return None;
        }
    }
    Some(out)
}

/// The type of `s` as a scene writes it.
pub fn type_name(s: &Value, root: &Value) -> String {
    if let Some(name) = ref_name(s) {
        return match resolve(s, root).and_then(unit_variants) {
            Some(v) => v.join(" | "),
            None => name.to_string(),
        };
    }
    if let Some(v) = unit_variants(s) {
        return v.join(" | ");
    }
    if let Some(alts) = s.get("anyOf").and_then(Value::as_array) {
        let some: Vec<&Value> = alts.iter().filter(|a| !is_null(a)).collect();
        if some.len() == 1 && some.len() < alts.len() {
            return format!("{} (optional)", type_name(some[0], root));
        }
        let names: Vec<String> = some.iter().map(|a| type_name(a, root)).collect();
        return names.join(" or ");
    }
    match s.get("type") {
        Some(Value::Array(ts)) => {
            let some: Vec<&str> = ts.iter().filter_map(Value::as_str).collect();
            let base: Vec<&str> = some.iter().copied().filter(|t| *t != "null").collect();
            let mut one = s.clone();
            if let (Some(o), [b]) = (one.as_object_mut(), base.as_slice()) {
                o.insert("type".into(), Value::String(b.to_string()));
                let t = type_name(&one, root);
                return if some.contains(&"null") {
                    format!("{t} (optional)")
                } else {
                    t
                };
            }
            base.join(" or ")
        }
        Some(Value::String(t)) if t == "array" => array_name(s, root),
        Some(Value::String(t)) if t == "object" => "(..)".to_string(),
        Some(Value::String(t)) => t.clone(),
        _ => "any".to_string(),
    }
}

fn array_name(s: &Value, root: &Value) -> String {
    let item = s
        .get("items")
        .map(|i| type_name(i, root))
        .unwrap_or_else(|| "any".to_string());
    let (lo, hi) = (
        s.get("minItems").and_then(Value::as_u64),
        s.get("maxItems").and_then(Value::as_u64),
    );
    match (lo, hi) {
        (Some(a), Some(b)) if a == b => format!("[{item}; {a}]"),
        _ => format!("[{item}]"),
    }
}

fn is_null(s: &Value) -> bool {
    s.get("type").and_then(Value::as_str) == Some("null")
}

/// A default value as a scene writes it: a string field's value quoted, an enum's unit
/// variant bare, `none` for an absent option.
fn ron_value(v: &Value, s: &Value, root: &Value) -> String {
    match v {
        Value::Null => "none".to_string(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => match (n.as_f64(), is_number(s)) {
            (Some(x), true) if x.fract() == 0.0 && x.abs() < 1e15 => format!("{x:.1}"),
            _ => n.to_string(),
        },
        Value::String(t) if is_string(s, root) => format!("{t:?}"),
        Value::String(t) => t.clone(),
        Value::Array(a) => {
            let item = s.get("items").unwrap_or(&Value::Null);
            let parts: Vec<String> = a.iter().map(|x| ron_value(x, item, root)).collect();
            format!("[{}]", parts.join(", "))
        }
        Value::Object(o) => ron_object(o, root),
    }
}

fn ron_object(o: &Map<String, Value>, root: &Value) -> String {
    // an externally tagged variant with settings: `{"Name": {..}}` or `{"Name": x}`
    if o.len() == 1 {
        let (k, v) = o.iter().next().expect("one entry");
        if k.chars().next().is_some_and(char::is_uppercase) {
            return match v {
                Value::Object(inner) => format!("{k}{}", ron_object(inner, root)),
                x => format!("{k}({})", ron_value(x, &Value::Null, root)),
            };
        }
    }
    let parts: Vec<String> = o
        .iter()
        .map(|(k, v)| format!("{k}: {}", ron_value(v, &Value::Null, root)))
        .collect();
    format!("({})", parts.join(", "))
}

/// True when `s` (or the non-null part of it) is a number.
pub fn is_number(s: &Value) -> bool {
    match s.get("type") {
        Some(Value::String(t)) => t == "number",
        Some(Value::Array(ts)) => ts.iter().any(|t| t == "number"),
        _ => false,
    }
}

fn is_string(s: &Value, root: &Value) -> bool {
    match s.get("type") {
        Some(Value::String(t)) => t == "string" && s.get("enum").is_none(),
        Some(Value::Array(ts)) => ts.iter().any(|t| t == "string"),
        _ => resolve(s, root).is_some_and(|d| is_string(d, root)),
    }
}

/// The text `dualsph doc NAME` prints for a plugin, section or body kind: the title line,
/// then each field (name, type, default, doc comment), then the types of its own it uses.
pub fn render(title: &str, schema: &Schema) -> String {
    let root = schema.as_value();
    let mut out = String::new();
    let _ = writeln!(out, "{title}");
    let doc = root
        .get("description")
        .and_then(Value::as_str)
        .unwrap_or("");
    if !doc.is_empty() {
        let _ = writeln!(out, "{}", indent(doc, 2));
    }
    let mut seen = Vec::new();
    render_body(&mut out, root, root, 2, &mut seen);
    let mut i = 0;
    while i < seen.len() {
        let name = seen[i].clone();
        i += 1;
        let Some(def) = root.get("$defs").and_then(|d| d.get(&name)) else {
            continue;
        };
        if unit_variants(def).is_some() && !has_variant_docs(def) {
            continue;
        }
        let _ = writeln!(out, "\n{name}:");
        let doc = def.get("description").and_then(Value::as_str).unwrap_or("");
        if !doc.is_empty() {
            let _ = writeln!(out, "{}", indent(doc, 2));
        }
        render_body(&mut out, def, root, 2, &mut seen);
    }
    out
}

fn has_variant_docs(def: &Value) -> bool {
    def.get("oneOf")
        .and_then(Value::as_array)
        .is_some_and(|a| a.iter().any(|v| v.get("description").is_some()))
}

/// The fields of an object, or the variants of an enum, indented by `pad`.
fn render_body(out: &mut String, s: &Value, root: &Value, pad: usize, seen: &mut Vec<String>) {
    let sp = " ".repeat(pad);
    if s.get("properties").is_some() {
        for f in fields(s, root) {
            note_refs(&f.schema, seen);
            let default = match &f.default {
                Some(d) => format!(" = {d}"),
                None => " (required)".to_string(),
            };
            let _ = writeln!(out, "{sp}{}: {}{default}", f.name, f.ty);
            if !f.doc.is_empty() {
                let _ = writeln!(out, "{}", indent(&f.doc, pad + 4));
            }
        }
        return;
    }
    let alts = s
        .get("oneOf")
        .or_else(|| s.get("anyOf"))
        .and_then(Value::as_array);
    for v in alts.into_iter().flatten() {
        render_variant(out, v, root, pad, seen);
    }
}

fn render_variant(out: &mut String, v: &Value, root: &Value, pad: usize, seen: &mut Vec<String>) {
    let sp = " ".repeat(pad);
    let doc = v.get("description").and_then(Value::as_str).unwrap_or("");
    if let Some(names) = unit_variants(&serde_json::json!({ "oneOf": [v] })) {
        let _ = writeln!(out, "{sp}{}", names.join(" | "));
    } else if let Some((name, body)) = v
        .get("properties")
        .and_then(Value::as_object)
        .filter(|p| p.len() == 1)
        .and_then(|p| p.iter().next())
    {
        if body.get("properties").is_some() {
            let _ = writeln!(out, "{sp}{name}(..)");
            if !doc.is_empty() {
                let _ = writeln!(out, "{}", indent(doc, pad + 4));
            }
            render_body(out, body, root, pad + 4, seen);
            return;
        }
        note_refs(body, seen);
        let _ = writeln!(out, "{sp}{name}({})", type_name(body, root));
    } else {
        note_refs(v, seen);
        let _ = writeln!(out, "{sp}{}", type_name(v, root));
    }
    if !doc.is_empty() {
        let _ = writeln!(out, "{}", indent(doc, pad + 4));
    }
}

/// Adds the definitions `s` refers to (at any depth) to `seen`, each once.
fn note_refs(s: &Value, seen: &mut Vec<String>) {
    match s {
        Value::Object(o) => {
            if let Some(n) = ref_name(s)
                && !seen.iter().any(|x| x == n)
            {
                seen.push(n.to_string());
            }
            o.values().for_each(|v| note_refs(v, seen));
        }
        Value::Array(a) => a.iter().for_each(|v| note_refs(v, seen)),
        _ => {}
    }
}

/// Every field of the settings `schema` describes, at any depth (the root's, its types',
/// their struct variants'), each with the path to it (`Probe::Sensor.floor`), and the
/// newtype variants (`TimeStep::Fixed`) as fields of their own.
pub fn all_fields(schema: &Schema) -> Vec<(String, Field)> {
    let root = schema.as_value();
    let mut out = Vec::new();
    collect(root, root, "", &mut out);
    if let Some(defs) = root.get("$defs").and_then(Value::as_object) {
        for (name, def) in defs {
            collect(def, root, name, &mut out);
        }
    }
    out
}

fn collect(s: &Value, root: &Value, at: &str, out: &mut Vec<(String, Field)>) {
    for f in fields(s, root) {
        out.push((format!("{at}.{}", f.name), f));
    }
    let alts = s
        .get("oneOf")
        .or_else(|| s.get("anyOf"))
        .and_then(Value::as_array);
    for v in alts.into_iter().flatten() {
        let Some((name, body)) = v
            .get("properties")
            .and_then(Value::as_object)
            .filter(|p| p.len() == 1)
            .and_then(|p| p.iter().next())
        else {
            continue;
        };
        let path = format!("{at}::{name}");
        if body.get("properties").is_some() {
            collect(body, root, &path, out);
        } else {
            let field = Field {
                name: name.clone(),
                ty: type_name(body, root),
                default: None,
                doc: v
                    .get("description")
                    .and_then(Value::as_str)
                    .unwrap_or("")
                    .into(),
                schema: body.clone(),
            };
            out.push((path, field));
        }
    }
}

/// A doc comment as plain text: rustdoc links (``[`X`]``, `[text](target)`) become their
/// text.
pub fn plain(doc: &str) -> String {
    let mut out = String::new();
    let mut rest = doc;
    while let Some(open) = rest.find('[') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        let Some(close) = after.find(']') else {
            out.push_str(&rest[open..]);
            return out;
        };
        let text = &after[..close];
        let tail = &after[close + 1..];
        let is_link = text.starts_with('`') && text.ends_with('`') && text.len() > 1;
        match tail
            .strip_prefix('(')
            .and_then(|t| t.find(')').map(|e| (t, e)))
        {
            Some((t, end)) if !text.is_empty() => {
                out.push_str(text);
                rest = &t[end + 1..];
            }
            _ if is_link => {
                out.push_str(text);
                rest = tail;
            }
            _ => {
                out.push('[');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

fn indent(text: &str, pad: usize) -> String {
    let sp = " ".repeat(pad);
    plain(text)
        .lines()
        .map(|l| format!("{sp}{l}").trim_end().to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
#[path = "fields_tests.rs"]
mod tests;
