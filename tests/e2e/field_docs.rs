//! Every field a scene may write is documented: `dualsph doc NAME` prints a line of meaning
//! for each, and a unit for each number.

use dualsph::core::plugin::fields::{Field, all_fields, is_number};
use dualsph::default_registry;

/// The units a number's doc comment may give, in parentheses: `(m/s)`, `(Pa; …)`,
/// `(dimensionless, ≥ 1)`.
const UNITS: [&str; 17] = [
    "m",
    "m/s",
    "m/s²",
    "kg/m³",
    "Pa",
    "Pa s",
    "s",
    "Hz",
    "rad",
    "rad/s",
    "J/kg",
    "J/(kg K)",
    "W/(m K)",
    "N/m",
    "N",
    "dimensionless",
    "in the quantity's unit",
];

/// True when `doc` gives one of [`UNITS`] in parentheses, alone or before `;` or `,`.
fn has_unit(doc: &str) -> bool {
    let flat = doc.replace('\n', " ");
    UNITS.iter().any(|u| {
        [")", ";", ","]
            .iter()
            .any(|end| flat.contains(&format!("({u}{end}")))
    })
}

/// True when the field holds numbers: a number, a list of them, an optional one.
fn holds_numbers(f: &Field) -> bool {
    let s = &f.schema;
    is_number(s)
        || s.get("items").is_some_and(is_number)
        || s.get("anyOf")
            .and_then(|a| a.as_array())
            .is_some_and(|a| a.iter().any(is_number))
}

/// Every field of every plugin, scene section and body kind of the default registry.
fn every_field() -> Vec<(String, Field)> {
    let r = default_registry();
    let mut out = Vec::new();
    let schemas = r
        .entries()
        .iter()
        .map(|e| (e.name, (e.schema)()))
        .chain(r.sections().iter().map(|e| (e.key, (e.schema)())))
        .chain(r.body_kinds().iter().map(|e| (e.name, (e.schema)())));
    for (name, schema) in schemas {
        for (path, f) in all_fields(&schema) {
            out.push((format!("{name}{path}"), f));
        }
    }
    out
}

#[test]
fn every_field_has_a_line_of_meaning() {
    let fields = every_field();
    assert!(fields.len() > 100, "{} fields", fields.len());
    let bare: Vec<&String> = fields
        .iter()
        .filter(|(_, f)| f.doc.trim().is_empty())
        .map(|(p, _)| p)
        .collect();
    assert!(bare.is_empty(), "fields without a doc comment: {bare:?}");
}

#[test]
fn every_number_gives_its_unit() {
    let missing: Vec<String> = every_field()
        .into_iter()
        .filter(|(_, f)| holds_numbers(f) && !has_unit(&f.doc))
        .map(|(p, f)| format!("{p}: {}", f.doc.lines().next().unwrap_or("")))
        .collect();
    assert!(
        missing.is_empty(),
        "numbers without a unit:\n{}",
        missing.join("\n")
    );
}

#[test]
fn units_are_read_in_parentheses_only() {
    assert!(has_unit("Velocity (m/s)."));
    assert!(has_unit("Bulk modulus p0 (Pa; alternative to c0)."));
    assert!(has_unit("Largest factor (dimensionless, ≥ 1)."));
    assert!(!has_unit("Velocity in m/s."));
    assert!(!has_unit("Position (one component per dimension)."));
}
