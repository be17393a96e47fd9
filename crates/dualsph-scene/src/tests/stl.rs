//! `Stl` shapes: a unit cube read from binary and ASCII STL fills exactly as the `Box` does;
//! an icosphere fills its mesh volume and fills the same when its facets run the other way;
//! the distance to the mesh is the box's exact distance; open, misoriented, degenerate,
//! missing and 2-D meshes are refused naming the field.

use super::shapes::scene;
use super::*;
use crate::{ParticleSpec, Shape};
use std::path::PathBuf;

/// The directory of the fixtures (`unit_cube_binary.stl`, ...).
fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src/tests/data")
}

const DOM3: &str = "(min: [-0.5, -0.5, -0.5], max: [1.5, 1.5, 1.5])";

/// A 3-D scene of one `Shape` generator with this `shape` and `fill`, Δx = 0.1.
fn one_shape(shape: &str, fill: &str) -> String {
    scene(
        3,
        DOM3,
        "",
        &[&format!(
            "Shape(shape: {shape}, fill: {fill}, spacing: 0.1, density: 1000.0, h_factor: 2.0)"
        )],
    )
}

/// The scene `text` as if its file were in `dir`.
fn load_in(text: &str, dir: &Path) -> Result<Scene, SceneError> {
    Scene::from_str(text, &dir.join("scene.ron"), &registry())
}

fn particles_in(text: &str, dir: &Path) -> Vec<ParticleSpec> {
    load_in(text, dir)
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .generate()
}

/// The validation error of `text` in `dir` as (field, message).
fn invalid_in(text: &str, dir: &Path) -> (String, String) {
    match load_in(text, dir) {
        Err(SceneError::Invalid { field, message, .. }) => (field, message),
        other => panic!("expected a validation error, got {other:?}"),
    }
}

#[test]
fn a_unit_cube_from_binary_or_ascii_stl_fills_bitwise_as_the_box() {
    let unit_box = "Box(min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0])";
    for fill in ["Solid", "Layers(n: 2, side: Inside)"] {
        let want = particles_in(&one_shape(unit_box, fill), &data());
        assert!(want.len() > 500, "{}", want.len());
        for file in ["unit_cube_binary.stl", "unit_cube_ascii.stl"] {
            let got = particles_in(&one_shape(&format!("Stl(file: {file:?})"), fill), &data());
            assert_eq!(got, want, "{file}, {fill}");
        }
    }
    // placed by scale and translate: the box [0.2, 0.6] × [0.3, 0.7] × [0.1, 0.5]
    let moved = "Stl(file: \"unit_cube_binary.stl\", scale: 0.4, translate: [0.2, 0.3, 0.1])";
    let placed = "Box(min: [0.2, 0.3, 0.1], max: [0.6, 0.7, 0.5])";
    let want = particles_in(&one_shape(placed, "Solid"), &data());
    assert_eq!(want.len(), 64);
    assert_eq!(particles_in(&one_shape(moved, "Solid"), &data()), want);
}

#[test]
fn a_cube_mesh_cuts_a_block_as_the_box_does() {
    let block = |cut: &str| {
        scene(
            3,
            DOM3,
            "",
            &[&format!(
                "Block(min: [-0.5, -0.5, -0.5], max: [1.5, 1.5, 1.0], spacing: 0.1, \
                 lattice: Square, density: 1000.0, h_factor: 2.0, cut: [{cut}])"
            )],
        )
    };
    let want = particles_in(
        &block("Box(min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0])"),
        &data(),
    );
    let got = particles_in(&block("Stl(file: \"unit_cube_ascii.stl\")"), &data());
    assert_eq!(got.len(), 20 * 20 * 15 - 1000);
    assert_eq!(got, want);
}

/// The distance to the cube's mesh is the box's exact signed distance (Ericson's closest
/// point on each triangle, the nearest kept), inside, outside, near edges and corners.
#[test]
fn the_distance_to_a_cube_mesh_is_the_exact_box_distance() {
    let s = load_in(
        &one_shape("Stl(file: \"unit_cube_binary.stl\")", "Solid"),
        &data(),
    )
    .unwrap();
    let crate::Generator::Shape(g) = &s.particles[0] else {
        panic!("a Shape generator")
    };
    let mesh = g.shape.geometry(3);
    let cube = Shape::Box {
        min: vec![0.0; 3],
        max: vec![1.0; 3],
    }
    .geometry(3);
    let mut worst = 0.0f64;
    let mut x = 0.1234_f64;
    for _ in 0..3000 {
        // a deterministic spread of points over [-0.6, 1.6]^3
        let p: [f64; 3] = std::array::from_fn(|_| {
            x = (x * 7919.0 + 0.271).fract();
            -0.6 + 2.2 * x
        });
        let (a, b) = (mesh.signed_distance(&p), cube.signed_distance(&p));
        worst = worst.max((a - b).abs());
        assert_eq!(mesh.contains(&p), cube.contains(&p), "{p:?}");
    }
    assert!(worst < 1e-15, "{worst:e}");
    // on the surface: a face, an edge and a corner count as inside
    for p in [[0.5, 0.5, 1.0], [1.0, 0.3, 0.0], [1.0, 1.0, 1.0]] {
        assert!(mesh.contains(&p), "{p:?}");
    }
    assert!((mesh.surface() - 6.0).abs() < 1e-12);
}

/// The icosphere of radius `r` about `c`: an icosahedron's faces split in four `levels`
/// times, the new vertices pushed onto the sphere; facets counter-clockwise seen from outside.
fn icosphere(c: [f64; 3], r: f64, levels: usize) -> Vec<[[f64; 3]; 3]> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let v = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let f: [[usize; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let unit = |p: [f64; 3]| {
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        p.map(|x| x / n)
    };
    let mut tris: Vec<[[f64; 3]; 3]> = f.iter().map(|t| t.map(|i| unit(v[i]))).collect();
    for _ in 0..levels {
        let mid = |a: [f64; 3], b: [f64; 3]| unit(std::array::from_fn(|k| 0.5 * (a[k] + b[k])));
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    // place after subdividing, so the midpoints are exact on the unit sphere first
    tris.iter()
        .map(|t| t.map(|p| std::array::from_fn(|k| c[k] + r * p[k])))
        .collect()
}

/// Writes `tris` as a binary STL file.
fn write_stl(path: &Path, tris: &[[[f64; 3]; 3]]) {
    let facets: Vec<stl_io::Triangle> = tris
        .iter()
        .map(|t| stl_io::Triangle {
            normal: stl_io::Normal::new([0.0; 3]),
            vertices: t.map(|p| stl_io::Vertex::new(p.map(|x| x as f32))),
        })
        .collect();
    let mut file = std::fs::File::create(path).unwrap();
    stl_io::write_stl(&mut file, facets.iter()).unwrap();
}

/// The volume enclosed by `tris`, `Σ a·(b×c)/6` (the divergence theorem).
fn mesh_volume(tris: &[[[f64; 3]; 3]]) -> f64 {
    tris.iter()
        .map(|[a, b, c]| {
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

/// A 1280-triangle icosphere of radius 0.3 filled at Δx = 0.02 (about 14,000 particles):
/// the particles' volume `N Δx³` is the mesh volume within 0.25 % (0.17 % short measured),
/// and the mesh with every facet reversed (winding number −1 inside) gives the same
/// particles.
#[test]
fn an_icosphere_fills_its_volume_either_way_round() {
    let dir = tempfile::tempdir().unwrap();
    let tris = icosphere([0.5, 0.5, 0.5], 0.3, 3);
    assert_eq!(tris.len(), 1280);
    // the mesh as written: f32 vertices
    let f32_tris: Vec<[[f64; 3]; 3]> = tris
        .iter()
        .map(|t| t.map(|p| p.map(|x| f64::from(x as f32))))
        .collect();
    write_stl(&dir.path().join("ico.stl"), &tris);
    let flipped: Vec<_> = tris.iter().map(|&[a, b, c]| [a, c, b]).collect();
    write_stl(&dir.path().join("ico_flipped.stl"), &flipped);
    let text = |file: &str| {
        scene(
            3,
            "(min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0])",
            "",
            &[&format!(
                "Shape(shape: Stl(file: {file:?}), spacing: 0.02, density: 1000.0, h_factor: 2.0)"
            )],
        )
    };
    let start = std::time::Instant::now();
    let ps = particles_in(&text("ico.stl"), dir.path());
    let elapsed = start.elapsed();
    let volume = mesh_volume(&f32_tris);
    let filled = ps.len() as f64 * 0.02f64.powi(3);
    let error = filled / volume - 1.0;
    eprintln!(
        "icosphere: {} particles, N dx^3 = {filled:.6} vs mesh volume {volume:.6} \
         ({:+.3} %), load + check + fill in {:.2} s",
        ps.len(),
        100.0 * error,
        elapsed.as_secs_f64()
    );
    assert!(error.abs() < 2.5e-3, "{error}");
    assert_eq!(particles_in(&text("ico_flipped.stl"), dir.path()), ps);
}

/// `text` with a cube from `file` in a copy of the fixtures' directory.
fn refused(file: &str) -> (String, String) {
    invalid_in(
        &one_shape(&format!("Stl(file: {file:?})"), "Solid"),
        &data(),
    )
}

#[test]
fn open_misoriented_missing_and_2d_meshes_are_refused_naming_the_field() {
    let (field, m) = refused("cube_open.stl");
    assert_eq!(field, "particles[0].shape.file");
    assert!(
        m.contains("open STL: 3 edge(s) belong to one triangle only and 0 to more than two"),
        "{m}"
    );
    let (field, m) = refused("cube_misoriented.stl");
    assert_eq!(field, "particles[0].shape.file");
    assert!(
        m.contains("3 edge(s) join two triangles of opposite orientation"),
        "{m}"
    );
    let (field, m) = refused("no_such.stl");
    assert_eq!(field, "particles[0].shape.file");
    assert!(
        m.contains("cannot read STL file") && m.contains("no_such.stl"),
        "{m}"
    );
    // a cut names its own position
    let text = scene(
        3,
        DOM3,
        "",
        &[
            "Block(min: [0.0, 0.0, 0.0], max: [1.0, 1.0, 1.0], spacing: 0.1, lattice: Square, \
           density: 1000.0, h_factor: 2.0, cut: [Stl(file: \"cube_open.stl\")])",
        ],
    );
    assert_eq!(invalid_in(&text, &data()).0, "particles[0].cut[0].file");
    // a 2-D scene: refused by dimension, before any file is read
    let flat = scene(
        2,
        "(min: [0.0, 0.0], max: [1.0, 1.0])",
        "",
        &[
            "Shape(shape: Stl(file: \"no_such.stl\"), spacing: 0.1, density: 1000.0, \
           h_factor: 2.0)",
        ],
    );
    let (field, m) = invalid_in(&flat, &data());
    assert_eq!(field, "particles[0].shape");
    assert!(
        m.contains("a Stl is 3-D and the scene has dimension 2"),
        "{m}"
    );
}

#[test]
fn a_degenerate_triangle_a_bad_scale_and_a_mesh_leaving_the_domain_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    // a tetrahedron with one face folded flat: its four triangles hold collinear corners
    let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 0.0]);
    let d = [0.0, 1.0, 0.0];
    write_stl(
        &dir.path().join("flat.stl"),
        &[[a, c, b], [a, b, d], [b, c, d], [c, a, d]],
    );
    let (field, m) = invalid_in(&one_shape("Stl(file: \"flat.stl\")", "Solid"), dir.path());
    assert_eq!(field, "particles[0].shape.file");
    assert!(m.contains("1 degenerate triangle(s)"), "{m}");
    let (field, m) = refused_with("Stl(file: \"unit_cube_binary.stl\", scale: -1.0)");
    assert_eq!(field, "particles[0].shape.scale");
    assert!(m.contains("> 0"), "{m}");
    let (field, m) = refused_with("Stl(file: \"unit_cube_binary.stl\", translate: [1.0, 0.0])");
    assert_eq!(field, "particles[0].shape.translate");
    assert!(m.contains("expected 3 components"), "{m}");
    let (field, m) =
        refused_with("Stl(file: \"unit_cube_binary.stl\", translate: [1.0, 0.0, 0.0])");
    assert_eq!(field, "particles[0].shape");
    assert!(
        m.contains("the Stl spans [1, 2] on axis 0, leaving the domain"),
        "{m}"
    );
}

fn refused_with(shape: &str) -> (String, String) {
    invalid_in(&one_shape(shape, "Solid"), &data())
}
