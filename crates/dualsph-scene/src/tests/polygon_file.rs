//! `PolygonFile`: an outline read from a file fills as the same inline `Polygon`; a bad row
//! is refused with its line, a crossing with the lines of its vertices.

use super::shapes::scene;
use super::*;
use crate::ParticleSpec;

const DOM: &str = "(min: [-0.5, -0.5], max: [1.5, 1.5])";

fn one(shape: &str) -> String {
    scene(
        2,
        DOM,
        "",
        &[&format!(
            "Shape(shape: {shape}, fill: Layers(n: 2, side: Inside), spacing: 0.05, \
             density: 1000.0, h_factor: 2.0)"
        )],
    )
}

/// `text` loaded as if it were in a directory holding `outline.csv` with `rows`.
fn with_file(text: &str, rows: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("outline.csv"), rows).unwrap();
    Scene::from_str(text, &dir.path().join("scene.ron"), &registry())
}

fn invalid_with(text: &str, rows: &str) -> (String, String) {
    match with_file(text, rows) {
        Err(SceneError::Invalid { field, message, .. }) => (field, message),
        other => panic!("expected a validation error, got {other:?}"),
    }
}

#[test]
fn an_outline_from_a_file_fills_as_the_inline_polygon() {
    let inline = "Polygon(vertices: [[0.0, 0.0], [1.0, 0.0], [1.0, 0.4], [0.3, 1.0]])";
    let want: Vec<ParticleSpec> = load(&one(inline)).unwrap().generate();
    assert!(want.len() > 100, "{}", want.len());
    let rows = "# a ramp\nx,y\n0.0, 0.0\n1.0,0.0\n\n1.0 0.4\n0.3;1.0\n";
    let got = with_file(&one("PolygonFile(file: \"outline.csv\")"), rows)
        .unwrap()
        .generate();
    assert_eq!(got, want);
}

#[test]
fn a_bad_row_or_a_crossing_is_refused_with_its_line() {
    let text = one("PolygonFile(file: \"outline.csv\")");
    let (field, m) = invalid_with(&text, "x,y\n0.0, 0.0\n1.0, 0.0, 2.0\n");
    assert_eq!(field, "particles[0].shape.file");
    assert!(
        m.contains("outline.csv`:3: expected a row of two finite numbers `x, y`, got 3 fields"),
        "{m}"
    );
    let (_, m) = invalid_with(&text, "0.0, 0.0\n1.0, abc\n");
    assert!(m.contains("outline.csv`:2: expected a row"), "{m}");
    assert!(!m.contains("abc"), "the file's text is not quoted: {m}");
    // a bow tie: edges 0 and 2 cross
    let (field, m) = invalid_with(&text, "x,y\n0,0\n1,1\n1,0\n0,1\n");
    assert_eq!(field, "particles[0].shape.file");
    assert!(
        m.contains(
            "edge 0 (vertices 0 (line 2 of `outline.csv`) → 1 (line 3 of `outline.csv`)) and \
             edge 2 (vertices 2 (line 4 of `outline.csv`) → 3 (line 5 of `outline.csv`)) meet"
        ),
        "{m}"
    );
    let (field, m) = invalid_with(&one("PolygonFile(file: \"missing.csv\")"), "");
    assert_eq!(field, "particles[0].shape.file");
    assert!(
        m.contains("cannot read polygon file") && m.contains("missing.csv"),
        "{m}"
    );
    // a 3-D scene: refused by dimension
    let solid = scene(
        3,
        "(min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0])",
        "",
        &[
            "Shape(shape: PolygonFile(file: \"outline.csv\"), spacing: 0.1, density: 1000.0, \
           h_factor: 2.0)",
        ],
    );
    let (field, m) = invalid_with(&solid, "0,0\n1,0\n0,1\n");
    assert_eq!(field, "particles[0].shape");
    assert!(m.contains("a PolygonFile is 2-D"), "{m}");
}
