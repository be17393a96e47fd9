//! The `Shape` generator: counts and positions of every shape and fill, cuts by shapes, and
//! the RON round trip.

use super::*;
use crate::generate::estimate_count;
use crate::{Generator, ParticleSpec, Region, ShapeGenerator};
use std::f64::consts::PI;

/// A scene of dimension `d` with these bodies and generators (one per line).
pub(super) fn scene(d: usize, domain: &str, bodies: &str, particles: &[&str]) -> String {
    format!(
        r#"Scene(
    name: "shapes",
    dimension: {d},
    domain: {domain},
    kernel: CubicSpline,
    formulation: DualSupport,
    bodies: [{bodies}],
    particles: [
        {},
    ],
    integrator: (dt: Fixed(1e-4)),
    end_time: 1.0,
)
"#,
        particles.join(",\n        ")
    )
}

/// The particles of generator `g` in the scene `text` (which must be valid).
pub(super) fn of(text: &str, g: u32) -> Vec<ParticleSpec> {
    let s = load(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    s.generate()
        .into_iter()
        .filter(|p| p.generator == g)
        .collect()
}

/// `x` is within `1e-9` of a half-integer multiple of `dx` from `origin`.
fn on_half_lattice(x: f64, origin: f64, dx: f64) -> bool {
    let u = (x - origin) / dx - 0.5;
    (u - u.round()).abs() < 1e-9
}

const DOM2: &str = "(min: [-0.5, -0.5], max: [1.5, 1.0])";

#[test]
fn box_outside_layers_fill_the_corners() {
    // 10 × 5 cells of Δx = 0.1, 3 layers outside: (10 + 6)(5 + 6) − 50 = 126
    let text = scene(
        2,
        DOM2,
        "",
        &[
            "Shape(shape: Box(min: [0.0, 0.0], max: [1.0, 0.5]), fill: Layers(n: 3, side: Outside), \
           spacing: 0.1, density: 1000.0, h_factor: 2.0)",
        ],
    );
    let ps = of(&text, 0);
    assert_eq!(ps.len(), 16 * 11 - 50);
    for p in &ps {
        let [x, y, _] = p.pos;
        assert!(
            on_half_lattice(x, 0.0, 0.1) && on_half_lattice(y, 0.0, 0.1),
            "{x} {y}"
        );
        // outside the box, at most 3Δx from it on each axis (mitred)
        assert!(!(0.0..=1.0).contains(&x) || !(0.0..=0.5).contains(&y));
        assert!((-0.3..=1.3).contains(&x) && (-0.3..=0.8).contains(&y));
        assert!((p.mass - 1000.0 * 0.01).abs() < 1e-12 && (p.h - 0.2).abs() < 1e-15);
    }
    // the first layer sits Δx/2 from the face: both corners of the block of layers are there
    let has = |x: f64, y: f64| {
        ps.iter()
            .any(|p| (p.pos[0] - x).abs() < 1e-9 && (p.pos[1] - y).abs() < 1e-9)
    };
    assert!(has(-0.05, 0.05) && has(-0.25, -0.25) && has(1.25, 0.75) && !has(-0.35, 0.05));
    let s = load(&text).unwrap();
    assert!(estimate_count(&s.particles[0], 2) >= ps.len() as f64);
}

#[test]
fn box_inside_layers_and_solid() {
    let gen_ = |fill: &str| {
        format!(
            "Shape(shape: Box(min: [0.0, 0.0], max: [1.0, 0.8]), fill: {fill}, spacing: 0.1, \
             density: 1000.0, h_factor: 2.0)"
        )
    };
    // 10 × 8 cells, 3 layers inside: 80 − 4·2
    let ps = of(
        &scene(2, DOM2, "", &[&gen_("Layers(n: 3, side: Inside)")]),
        0,
    );
    assert_eq!(ps.len(), 80 - 4 * 2);
    let ps = of(
        &scene(2, DOM2, "", &[&gen_("Layers(n: 1, side: Inside)")]),
        0,
    );
    assert_eq!(ps.len(), 80 - 8 * 6);
    // more layers than fit: the whole box, like Solid
    let ps = of(
        &scene(2, DOM2, "", &[&gen_("Layers(n: 9, side: Inside)")]),
        0,
    );
    assert_eq!(ps.len(), 80);
    assert_eq!(of(&scene(2, DOM2, "", &[&gen_("Solid")]), 0).len(), 80);
}

#[test]
fn solid_box_and_circle_equal_block_and_disk_bitwise() {
    for lattice in ["Square", "Staggered"] {
        let text = scene(
            2,
            "(min: [0.0, 0.0], max: [5.0, 5.0])",
            "",
            &[
                &format!(
                    "Block(min: [0.1, 0.2], max: [1.1, 0.7], spacing: 0.05, lattice: {lattice}, density: 1.0, h_factor: 2.0)"
                ),
                &format!(
                    "Shape(shape: Box(min: [2.1, 0.2], max: [3.1, 0.7]), spacing: 0.05, lattice: {lattice}, density: 1.0, h_factor: 2.0)"
                ),
                &format!(
                    "Disk(center: [1.0, 3.0], radius: 0.7, spacing: 0.05, lattice: {lattice}, density: 1.0, h_factor: 2.0)"
                ),
                &format!(
                    "Shape(shape: Circle(center: [3.0, 3.0], radius: 0.7), fill: Solid, spacing: 0.05, lattice: {lattice}, density: 1.0, h_factor: 2.0)"
                ),
            ],
        );
        let all = load(&text).unwrap().generate();
        let pos = |g: u32, dx: f64| -> Vec<[f64; 3]> {
            all.iter()
                .filter(|p| p.generator == g)
                .map(|p| [p.pos[0] - dx, p.pos[1], 0.0])
                .collect()
        };
        // the same lattice moved by 2.0 in x: compare the offsets from each origin
        let (block, shape_box) = (pos(0, 0.1), pos(1, 2.1));
        assert_eq!(block.len(), 200);
        assert_eq!(block.len(), shape_box.len());
        for (a, b) in block.iter().zip(&shape_box) {
            assert!((a[0] - b[0]).abs() < 1e-12 && a[1] == b[1], "{lattice}");
        }
        let (disk, circle) = (pos(2, 1.0), pos(3, 3.0));
        assert_eq!(disk.len(), circle.len(), "{lattice}");
        for (a, b) in disk.iter().zip(&circle) {
            assert!((a[0] - b[0]).abs() < 1e-12 && a[1] == b[1], "{lattice}");
        }
    }
}

#[test]
fn circle_solid_count_against_area() {
    // R = 1, Δx = 0.02: πR²/Δx² = 7854; a lattice disk is within 1 %
    let text = scene(
        2,
        "(min: [0.0, 0.0], max: [3.0, 3.0])",
        "",
        &[
            "Shape(shape: Circle(center: [1.5, 1.5], radius: 1.0), spacing: 0.02, density: 1.0, h_factor: 2.0)",
        ],
    );
    let ps = of(&text, 0);
    let expected = PI / (0.02 * 0.02);
    let rel = (ps.len() as f64 - expected).abs() / expected;
    println!(
        "circle R = 50Δx: {} points, πR²/Δx² = {expected:.1} ({rel:.2e})",
        ps.len()
    );
    assert!(rel < 0.01, "{} vs {expected}", ps.len());
    assert!(
        ps.iter()
            .all(|p| libm::hypot(p.pos[0] - 1.5, p.pos[1] - 1.5) <= 1.0 + 1e-12)
    );
}

/// Radii and counts of a circle's rings: `r_k = R ± (k + ½)Δx`, `round(2π r_k/Δx)` points each,
/// neighbours on a ring `2π r_k/N_k` apart (within 1 % of Δx here).
#[test]
fn circle_layers_are_rings() {
    let (r, dx) = (0.5, 0.05);
    for (side, sign) in [("Outside", 1.0), ("Inside", -1.0)] {
        let text = scene(
            2,
            DOM2,
            "",
            &[&format!(
                "Shape(shape: Circle(center: [0.5, 0.25], radius: {r}), fill: Layers(n: 3, side: {side}), \
                 spacing: {dx}, density: 1000.0, h_factor: 2.0)"
            )],
        );
        let ps = of(&text, 0);
        let mut start = 0;
        for k in 0..3 {
            let rk = r + sign * (k as f64 + 0.5) * dx;
            let n = (2.0 * PI * rk / dx).round() as usize;
            let ring = &ps[start..start + n];
            for p in ring {
                let dist = libm::hypot(p.pos[0] - 0.5, p.pos[1] - 0.25);
                assert!((dist - rk).abs() < 1e-12, "{side} ring {k}: {dist} vs {rk}");
                assert!((p.mass - 1000.0 * dx * dx).abs() < 1e-12);
            }
            let gap = libm::hypot(
                ring[1].pos[0] - ring[0].pos[0],
                ring[1].pos[1] - ring[0].pos[1],
            );
            assert!((gap / dx - 1.0).abs() < 0.01, "{side} ring {k}: gap {gap}");
            start += n;
        }
        assert_eq!(start, ps.len(), "{side}: three rings and nothing else");
    }
}

#[test]
fn polygon_fills() {
    // right triangle with legs 1, Δx = 0.02: cell centres with i + j ≤ 49, the 50 on the
    // hypotenuse included (closed inside test) → 50·51/2 = 1275 (area/Δx² = 1250)
    let tri = "Polygon(vertices: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])";
    let text = scene(
        2,
        DOM2,
        "",
        &[&format!(
            "Shape(shape: {tri}, spacing: 0.02, density: 1.0, h_factor: 2.0)"
        )],
    );
    assert_eq!(of(&text, 0).len(), 1275);
    // a square polygon's outside layers use the Euclidean distance: the four corner points
    // at (2.5Δx, 2.5Δx) from a corner (3.54Δx) are left out, unlike a Box's mitred layers
    let sq = "Polygon(vertices: [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]])";
    let text = scene(
        2,
        DOM2,
        "",
        &[&format!(
            "Shape(shape: {sq}, fill: Layers(n: 3, side: Outside), spacing: 0.1, density: 1.0, h_factor: 2.0)"
        )],
    );
    assert_eq!(of(&text, 0).len(), 16 * 11 - 50 - 4);
    // an L-shaped polygon of 3 unit squares at Δx = 0.1: 300 points, none in the notch
    let l = "Polygon(vertices: [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.5, 0.5], [0.5, 1.0], [0.0, 1.0]])";
    let text = scene(
        2,
        DOM2,
        "",
        &[&format!(
            "Shape(shape: {l}, spacing: 0.05, density: 1.0, h_factor: 2.0)"
        )],
    );
    let ps = of(&text, 0);
    assert_eq!(ps.len(), 300);
    assert!(!ps.iter().any(|p| p.pos[0] > 0.5 && p.pos[1] > 0.5));
}

const DOM3: &str = "(min: [-1.0, -1.0, -1.0], max: [2.0, 2.0, 2.0])";

#[test]
fn ball_and_cylinder_counts_against_volume() {
    let dx: f64 = 0.05;
    let count = |shape: &str, fill: &str| {
        of(
            &scene(
                3,
                DOM3,
                "",
                &[&format!(
                    "Shape(shape: {shape}, fill: {fill}, spacing: {dx}, density: 1.0, h_factor: 2.0)"
                )],
            ),
            0,
        )
        .len() as f64
    };
    let rel = |n: f64, v: f64| {
        let r = (n - v).abs() / v;
        println!("{n} points against {v:.1}: {r:.2e}");
        r
    };
    // ball R = 0.5: 4/3 π R³ / Δx³ = 4189, within 1 %
    let n = count("Ball(center: [0.5, 0.5, 0.5], radius: 0.5)", "Solid");
    assert!(rel(n, 4.0 / 3.0 * PI * 0.125 / dx.powi(3)) < 0.01, "{n}");
    // cylinder along z, R = 0.5, L = 1: π R² L / Δx³ = 6283, within 1 %
    let z = "Cylinder(center: [0.5, 0.5, 0.5], axis: [0.0, 0.0, 2.0], radius: 0.5, length: 1.0)";
    let n = count(z, "Solid");
    assert!(rel(n, PI * 0.25 / dx.powi(3)) < 0.01, "{n}");
    assert_eq!(n % 20.0, 0.0, "20 whole slices along the axis");
    // the same cylinder tilted in the x–y plane: within 2 %
    let tilted =
        "Cylinder(center: [0.5, 0.5, 0.5], axis: [1.0, 1.0, 0.0], radius: 0.5, length: 1.0)";
    let n = count(tilted, "Solid");
    assert!(rel(n, PI * 0.25 / dx.powi(3)) < 0.02, "{n}");
    // two outside layers of a ball: the shell between R and R + 2Δx, within 3 %
    let n = count(
        "Ball(center: [0.5, 0.5, 0.5], radius: 0.5)",
        "Layers(n: 2, side: Outside)",
    );
    let shell = 4.0 / 3.0 * PI * (0.6f64.powi(3) - 0.125) / dx.powi(3);
    assert!(rel(n, shell) < 0.03, "{n} vs {shell}");
}

#[test]
fn cut_by_shapes_and_by_plain_boxes() {
    let text = scene(
        2,
        DOM2,
        "",
        &[
            "Block(min: [0.0, 0.0], max: [1.0, 0.5], spacing: 0.05, lattice: Square, density: 1.0, \
           h_factor: 2.0, cut: [Circle(center: [0.5, 0.25], radius: 0.15), (min: [0.0, 0.0], max: [0.1, 0.5]), \
           Polygon(vertices: [[0.8, 0.0], [1.0, 0.0], [1.0, 0.2]])])",
        ],
    );
    let ps = of(&text, 0);
    for p in &ps {
        let [x, y, _] = p.pos;
        assert!(libm::hypot(x - 0.5, y - 0.25) > 0.15 && x > 0.1);
        assert!(
            !(x >= 0.8 && y <= x - 0.8),
            "({x}, {y}) is in the cut triangle"
        );
    }
    // 200 − 2 columns of 10 (x < 0.1) − the circle's lattice points − the triangle's
    // (1 + 2 + 3 + 4, its hypotenuse included)
    let lattice = (0..20)
        .flat_map(|i| (0..10).map(move |j| ((i as f64 + 0.5) * 0.05, (j as f64 + 0.5) * 0.05)));
    let circle = lattice
        .filter(|(x, y)| libm::hypot(x - 0.5, y - 0.25) <= 0.15)
        .count();
    assert_eq!(circle, 32);
    assert_eq!(ps.len(), 200 - 20 - circle - 10);
}

#[test]
fn ron_round_trip() {
    let text = "(shape: Polygon(vertices: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), \
                fill: Layers(n: 2, side: Inside), spacing: 0.1, lattice: Staggered, density: 2.0, \
                h_factor: 2.0, clip: (min: [0.0, 0.0], max: [1.0, 1.0]), \
                cut: [(min: [0.0, 0.0], max: [0.1, 0.1]), Ball(center: [0.0, 0.0, 0.0], radius: 1.0), \
                Cylinder(center: [0.0, 0.0, 0.0], axis: [0.0, 1.0, 0.0], radius: 1.0, length: 2.0)], \
                velocity: Uniform([1.0, 0.0]), internal_energy: 3.0, body: \"wall\")";
    let g: ShapeGenerator = crate::ron_options().from_str(text).unwrap();
    assert!(matches!(g.cut[0], Region::Box(_)) && matches!(g.cut[1], Region::Shape(_)));
    let back: ShapeGenerator = crate::ron_options()
        .from_str(&ron::ser::to_string(&g).unwrap())
        .unwrap();
    assert_eq!(back, g);
    // inside a scene, with the defaults (fill Solid, lattice Square)
    let text = scene(
        2,
        DOM2,
        "",
        &[
            "Shape(shape: Box(min: [0.0, 0.0], max: [1.0, 0.5]), spacing: 0.1, density: 1.0, h_factor: 2.0)",
        ],
    );
    let s = load(&text).unwrap();
    let Generator::Shape(g) = &s.particles[0] else {
        panic!("a Shape generator")
    };
    assert_eq!(
        (g.fill, g.lattice),
        (crate::Fill::Solid, crate::Lattice::Square)
    );
    assert_eq!(s.particles[0].kind(), "Shape(Box)");
}
