//! Validation of shapes, fills and cuts: every problem names its field; the typical tank and
//! an obstacle cut from the fluid pass.

use super::shapes::{of, scene};
use super::*;

const DOM2: &str = "(min: [-0.3, -0.3], max: [1.3, 0.8])";
const TAIL: &str = "spacing: 0.1, density: 1000.0, h_factor: 2.0";

/// A 2-D scene of one `Shape` generator with `shape` and `fill`.
fn one(shape: &str, fill: &str) -> String {
    scene(
        2,
        DOM2,
        "",
        &[&format!("Shape(shape: {shape}, fill: {fill}, {TAIL})")],
    )
}

fn rejects(text: &str, field: &str, needle: &str) {
    let (f, m) = invalid(text);
    assert_eq!(f, field, "message: {m}");
    assert!(m.contains(needle), "{field}: {m:?} lacks {needle:?}");
}

#[test]
fn a_shape_leaving_the_domain_with_its_layers() {
    let tank = "Box(min: [0.0, 0.0], max: [1.0, 0.5])";
    // the domain holds exactly 3 layers of 0.1 around the box
    load(&one(tank, "Layers(n: 3, side: Outside)")).unwrap();
    rejects(
        &one(tank, "Layers(n: 4, side: Outside)"),
        "particles[0].shape",
        "the Box with its outside layers (0.4 beyond its surface) spans [-0.4",
    );
    rejects(
        &one("Circle(center: [1.2, 0.25], radius: 0.2)", "Solid"),
        "particles[0].shape",
        "on axis 0, leaving the domain [-0.3, 1.3]: widen the domain, move the shape or clip it",
    );
    // clipped to the domain: an open-top tank
    let clipped = scene(
        2,
        DOM2,
        "",
        &[&format!(
            "Shape(shape: Box(min: [0.0, 0.0], max: [1.0, 0.6]), fill: Layers(n: 3, side: Outside), \
             clip: (min: [-0.3, -0.3], max: [1.3, 0.5]), {TAIL})"
        )],
    );
    assert_eq!(of(&clipped, 0).len(), 2 * 3 * 5 + 16 * 3);
}

#[test]
fn polygons_must_be_simple() {
    rejects(
        &one("Polygon(vertices: [[0.0, 0.0], [1.0, 0.0]])", "Solid"),
        "particles[0].shape.vertices",
        "at least 3 vertices, got 2",
    );
    rejects(
        &one(
            "Polygon(vertices: [[0.0, 0.0], [1.0, 0.5], [1.0, 0.0], [0.0, 0.5]])",
            "Solid",
        ),
        "particles[0].shape.vertices",
        "intersects itself: edge 0 (vertices 0 → 1) and edge 2 (vertices 2 → 3) meet",
    );
    rejects(
        &one(
            "Polygon(vertices: [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 0.5]])",
            "Solid",
        ),
        "particles[0].shape.vertices",
        "vertices 1 and 2 coincide",
    );
    rejects(
        &one(
            "Polygon(vertices: [[0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.5]])",
            "Solid",
        ),
        "particles[0].shape.vertices[1]",
        "expected 2 components",
    );
}

#[test]
fn shapes_of_the_wrong_dimension() {
    rejects(
        &one("Ball(center: [0.5, 0.25], radius: 0.2)", "Solid"),
        "particles[0].shape",
        "a Ball is 3-D and the scene has dimension 2: in 2-D use a Circle",
    );
    rejects(
        &one(
            "Cylinder(center: [0.5, 0.25], axis: [0.0, 1.0], radius: 0.2, length: 0.2)",
            "Solid",
        ),
        "particles[0].shape",
        "a Cylinder is 3-D",
    );
    let text = scene(
        3,
        "(min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0])",
        "",
        &[&format!(
            "Shape(shape: Circle(center: [0.5, 0.5, 0.5], radius: 0.2), {TAIL})"
        )],
    );
    rejects(&text, "particles[0].shape", "a Circle is 2-D");
    // a shape in a cut is checked where it stands
    let text = scene(
        2,
        DOM2,
        "",
        &[&format!(
            "Shape(shape: Box(min: [0.0, 0.0], max: [1.0, 0.5]), \
             cut: [(min: [0.0, 0.0], max: [0.1, 0.1]), Ball(center: [0.5, 0.5], radius: 0.1)], {TAIL})"
        )],
    );
    rejects(&text, "particles[0].cut[1]", "a Ball is 3-D");
}

#[test]
fn shape_values() {
    rejects(
        &one("Circle(center: [0.5, 0.25], radius: -0.2)", "Solid"),
        "particles[0].shape.radius",
        "must be a finite number > 0",
    );
    rejects(
        &one("Box(min: [0.0, 0.0], max: [1.0, 0.0])", "Solid"),
        "particles[0].shape.max",
        "max must exceed min",
    );
    rejects(
        &one(
            "Box(min: [0.0, 0.0], max: [1.0, 0.5])",
            "Layers(n: 0, side: Inside)",
        ),
        "particles[0].fill",
        "n >= 1",
    );
    let text = scene(
        3,
        "(min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0])",
        "",
        &[&format!(
            "Shape(shape: Cylinder(center: [0.5, 0.5, 0.5], axis: [0.0, 0.0, 0.0], radius: 0.2, length: 0.2), {TAIL})"
        )],
    );
    rejects(&text, "particles[0].shape.axis", "must not be zero");
    // the error names the file and the field
    let e = load(&one("Polygon(vertices: [])", "Solid")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "scenes/test.ron: invalid value for `particles[0].shape.vertices`: a polygon needs at \
         least 3 vertices, got 0"
    );
}

#[test]
fn unknown_shapes_and_fills_are_parse_errors_at_their_position() {
    let text = one("Triangle(vertices: [])", "Solid");
    let (line, col, m) = parse_error(&text);
    assert_eq!(line, line_col(&text, "Triangle").0, "{m}");
    assert!(m.contains("Triangle") && m.contains("Polygon"), "{m}");
    let _ = col;
    let text = one(
        "Box(min: [0.0, 0.0], max: [1.0, 0.5])",
        "Layers(n: 3, side: Outwards)",
    );
    let (line, col, m) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "Outwards"), "{m}");
    // a cut entry that is neither a plain box nor a shape
    let text = scene(
        2,
        DOM2,
        "",
        &[&format!(
            "Shape(shape: Box(min: [0.0, 0.0], max: [1.0, 0.5]),\n cut: [Circle(centre: [0.5, 0.2], radius: 0.1)], {TAIL})"
        )],
    );
    let (line, _, m) = parse_error(&text);
    assert_eq!(line, line_col(&text, "Circle(centre").0, "{m}");
    assert!(
        m.contains("a cut region: a box `(min: [..], max: [..])` or a shape"),
        "{m}"
    );
    let text = one(
        "Box(min: [0.0, 0.0], max: [1.0, 0.5])",
        "Layers(n: 2.5, side: Inside)",
    );
    let (line, col, m) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "2.5"), "{m}");
}

/// The scene of `scenes/`-style use: water in a tank of 3 outside layers, an obstacle cut
/// from the water as rings inside its surface or solid on the water's lattice.
fn tank(obstacle: &str, cut: &str) -> String {
    scene(
        2,
        DOM2,
        r#"Body(name: "water"), Body(name: "tank", kind: Fixed), Body(name: "post", kind: Fixed)"#,
        &[
            &format!(
                "Block(min: [0.0, 0.0], max: [1.0, 0.4], spacing: 0.05, lattice: Staggered, \
                 density: 1000.0, h_factor: 2.0, body: \"water\", cut: [{cut}])"
            ),
            "Shape(shape: Box(min: [0.0, 0.0], max: [1.0, 0.5]), fill: Layers(n: 3, side: Outside), \
             spacing: 0.1, density: 1000.0, h_factor: 2.0, body: \"tank\")",
            &format!(
                "Shape(shape: Circle(center: [0.5, 0.2], radius: 0.1), fill: {obstacle}, \
                 spacing: 0.05, density: 1000.0, h_factor: 2.0, body: \"post\")"
            ),
        ],
    )
}

#[test]
fn a_tank_with_an_obstacle_passes_and_overlaps_are_refused() {
    let circle = "Circle(center: [0.5, 0.2], radius: 0.1)";
    load(&tank("Layers(n: 2, side: Inside)", circle)).unwrap();
    // a solid obstacle whose lattice lines up with the water's (centre − R on its grid)
    let square = tank("Solid", circle).replace("lattice: Staggered", "lattice: Square");
    load(&square).unwrap();
    // not cut from the water: refused, naming both generators and their bodies
    let (f, m) = invalid(&tank("Layers(n: 2, side: Inside)", ""));
    assert_eq!(f, "particles[2]");
    assert!(
        m.contains(
            "particles[2] (Shape(Circle), body `post`) overlaps particles[0] (Block, body `water`)"
        ) && m.contains("cut the obstacle's shape"),
        "{m}"
    );
    // the tank walls inside the water
    let inside =
        tank("Layers(n: 2, side: Inside)", circle).replace("side: Outside", "side: Inside");
    let (f, m) = invalid(&inside);
    assert_eq!(f, "particles[2]", "{m}");
    assert!(
        m.contains("overlaps particles[1] (Shape(Box), body `tank`)"),
        "{m}"
    );
}
