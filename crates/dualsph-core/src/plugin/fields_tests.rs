use super::*;
use serde::Deserialize;

/// A probe-like settings struct.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
struct Demo {
    /// Reference density (kg/m³).
    rho0: f64,
    /// Polytropic exponent.
    #[serde(default = "seven")]
    gamma: f64,
    /// Lowest value read (Pa).
    #[serde(default)]
    floor: Option<f64>,
    /// Gravity (m/s²).
    g: [f64; 2],
    /// What a dry point counts as.
    #[serde(default)]
    dry: Dry,
    /// The shape.
    shape: Shape,
    /// A label.
    #[serde(default = "label")]
    label: String,
}

fn seven() -> f64 {
    7.0
}

fn label() -> String {
    "P1".into()
}

/// What a dry point counts as.
#[derive(Deserialize, serde::Serialize, JsonSchema, Default)]
enum Dry {
    /// Zero.
    #[default]
    Zero,
    /// Left out.
    Skip,
}

/// A shape.
#[derive(Deserialize, JsonSchema)]
#[allow(dead_code)]
enum Shape {
    /// A circle.
    Circle {
        /// Radius (m).
        radius: f64,
    },
    /// A polygon file.
    File(String),
}

fn demo() -> Vec<Field> {
    let s = schema_of::<Demo>();
    fields(s.as_value(), s.as_value())
}

#[test]
fn fields_come_in_declaration_order_with_types_defaults_and_docs() {
    let f = demo();
    let names: Vec<&str> = f.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(
        names,
        ["rho0", "gamma", "floor", "g", "dry", "shape", "label"]
    );
    assert_eq!(
        (f[0].ty.as_str(), f[0].default.as_deref()),
        ("number", None)
    );
    assert_eq!(f[0].doc, "Reference density (kg/m³).");
    assert_eq!(f[1].default.as_deref(), Some("7.0"));
    assert_eq!(f[2].ty, "number (optional)");
    assert_eq!(f[2].default.as_deref(), Some("none"));
    assert_eq!(f[3].ty, "[number; 2]");
    assert_eq!(
        (f[4].ty.as_str(), f[4].default.as_deref()),
        ("Zero | Skip", Some("Zero"))
    );
    assert_eq!(f[5].ty, "Shape");
    assert_eq!(f[6].default.as_deref(), Some("\"P1\""));
}

#[test]
fn the_rendering_lists_a_types_variants_with_their_fields() {
    let text = render("Demo: a demo", &schema_of::<Demo>());
    assert!(text.starts_with("Demo: a demo\n"), "{text}");
    assert!(
        text.contains("  rho0: number (required)\n      Reference density (kg/m³).\n"),
        "{text}"
    );
    assert!(text.contains("\nShape:\n"), "{text}");
    assert!(
        text.contains("  Circle(..)\n      A circle.\n      radius: number (required)\n"),
        "{text}"
    );
    assert!(
        text.contains("  File(string)\n      A polygon file.\n"),
        "{text}"
    );
    assert!(
        text.contains("\nDry:\n  What a dry point counts as.\n  Zero\n      Zero.\n  Skip\n"),
        "{text}"
    );
}

#[test]
fn rustdoc_links_read_as_their_text() {
    assert_eq!(
        plain("see [`TaitEos::materials`]."),
        "see `TaitEos::materials`."
    );
    assert_eq!(
        plain("the [module docs](self) and [`X`](crate::X)"),
        "the module docs and `X`"
    );
    assert_eq!(
        plain("[min/below, max·above] stays"),
        "[min/below, max·above] stays"
    );
}

#[test]
fn every_field_is_found_with_its_path() {
    let paths: Vec<String> = all_fields(&schema_of::<Demo>())
        .into_iter()
        .map(|(p, _)| p)
        .collect();
    assert!(paths.contains(&".rho0".to_string()), "{paths:?}");
    assert!(
        paths.contains(&"Shape::Circle.radius".to_string()),
        "{paths:?}"
    );
    assert!(paths.contains(&"Shape::File".to_string()), "{paths:?}");
}
