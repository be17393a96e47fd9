//! Each validation rule, checked through the field path it reports.

use super::*;

/// Asserts that `edits` applied to `BASE` fail validation on `field` with a message
/// containing `needle`.
fn rejects(edits: &[(&str, &str)], field: &str, needle: &str) {
    let (f, m) = invalid(&edit(edits));
    assert_eq!(f, field, "message: {m}");
    assert!(m.contains(needle), "{field}: {m:?} lacks {needle:?}");
}

const BLOCK: &str = "min: [0.0, 0.0], max: [1.0, 0.5]";
const DISK_H: &str = "h_factor: 1.5)";
const BLOCK_H: &str = "h_factor: 2.0)";

#[test]
fn base_is_valid() {
    load(BASE).unwrap();
}

#[test]
fn dimension() {
    rejects(
        &[("dimension: 2", "dimension: 4")],
        "dimension",
        "must be 1, 2 or 3, got 4",
    );
    rejects(&[("dimension: 2", "dimension: 0")], "dimension", "got 0");
}

#[test]
fn domain() {
    rejects(
        &[(
            "min: [0.0, 0.0], max: [4.0, 3.0]",
            "min: [0.0, 0.0, 0.0], max: [4.0, 3.0]",
        )],
        "domain.min",
        "expected 2 components for dimension 2, got 3",
    );
    rejects(&[("max: [4.0, 3.0]", "max: [4.0]")], "domain.max", "got 1");
    rejects(
        &[("max: [4.0, 3.0]", "max: [inf, 3.0]")],
        "domain.max",
        "not finite",
    );
    rejects(
        &[("max: [4.0, 3.0]", "max: [4.0, NaN]")],
        "domain.max",
        "component 1 is not finite",
    );
    rejects(
        &[("max: [4.0, 3.0]", "max: [4.0, 0.0]")],
        "domain.max",
        "axis 1",
    );
}

#[test]
fn skin() {
    rejects(
        &[(
            "formulation: DualSupport,",
            "formulation: DualSupport, neighbours: (skin: -0.1),",
        )],
        "neighbours.skin",
        ">= 0",
    );
    let text = edit(&[(
        "formulation: DualSupport,",
        "formulation: DualSupport, neighbours: (skin: 0.0),",
    )]);
    load(&text).unwrap();
}

#[test]
fn particle_list_must_not_be_empty() {
    let text = BASE.split("particles: [").next().unwrap().to_owned()
        + "particles: [],\n"
        + BASE.split("    ],\n").nth(1).unwrap();
    let (f, m) = invalid(&text);
    assert_eq!(f, "particles");
    assert!(m.contains("no particle generators"), "{m}");
}

#[test]
fn block_geometry() {
    rejects(
        &[(BLOCK, "min: [0.0, 0.0, 0.0], max: [1.0, 0.5]")],
        "particles[0].min",
        "expected 2 components for dimension 2, got 3",
    );
    rejects(
        &[(BLOCK, "min: [0.0, 0.0], max: [1.0]")],
        "particles[0].max",
        "got 1",
    );
    rejects(
        &[(BLOCK, "min: [0.0, 0.0], max: [0.0, 0.5]")],
        "particles[0].max",
        "axis 0",
    );
}

#[test]
fn disk_geometry() {
    rejects(
        &[("center: [3.0, 2.0]", "center: [3.0]")],
        "particles[1].center",
        "expected 2 components",
    );
    rejects(
        &[("radius: 0.5", "radius: 0.0")],
        "particles[1].radius",
        "> 0",
    );
    rejects(
        &[("radius: 0.5", "radius: -1.0")],
        "particles[1].radius",
        "got -1",
    );
}

#[test]
fn spacing_density_h_factor() {
    rejects(
        &[("radius: 0.5, spacing: 0.05", "radius: 0.5, spacing: 0.0")],
        "particles[1].spacing",
        "> 0",
    );
    rejects(
        &[(
            "spacing: 0.05, lattice: Staggered",
            "spacing: inf, lattice: Staggered",
        )],
        "particles[0].spacing",
        "finite",
    );
    rejects(
        &[("density: 500.0", "density: -500.0")],
        "particles[1].density",
        "> 0",
    );
    rejects(
        &[("h_factor: 2.0", "h_factor: 0.0")],
        "particles[0].h_factor",
        "> 0",
    );
}

#[test]
fn clip_and_cut_boxes() {
    rejects(
        &[(
            BLOCK_H,
            "h_factor: 2.0, clip: (min: [0.0], max: [1.0, 1.0]))",
        )],
        "particles[0].clip.min",
        "expected 2 components",
    );
    rejects(
        &[(
            BLOCK_H,
            "h_factor: 2.0, clip: (min: [1.0, 0.0], max: [0.0, 1.0]))",
        )],
        "particles[0].clip.max",
        "axis 0",
    );
    rejects(
        &[(
            DISK_H,
            "h_factor: 1.5, cut: [(min: [0.0, 0.0], max: [1.0, 1.0]), (min: [0.0, 0.0], max: [1.0, 1.0, 1.0])])",
        )],
        "particles[1].cut[1].max",
        "got 3",
    );
}

#[test]
fn velocity_shapes() {
    rejects(
        &[(
            BLOCK_H,
            "h_factor: 2.0, velocity: Uniform([1.0, 2.0, 3.0]))",
        )],
        "particles[0].velocity",
        "expected 2 components for dimension 2, got 3",
    );
    rejects(
        &[(BLOCK_H, "h_factor: 2.0, velocity: Linear([[1.0, 0.0]]))")],
        "particles[0].velocity",
        "got 1 rows",
    );
    rejects(
        &[(
            BLOCK_H,
            "h_factor: 2.0, velocity: Linear([[1.0, 0.0], [0.0]]))",
        )],
        "particles[0].velocity[1]",
        "got 1",
    );
    rejects(
        &[(
            BLOCK_H,
            "h_factor: 2.0, velocity: Linear([[1.0, 0.0], [0.0, NaN]]))",
        )],
        "particles[0].velocity[1]",
        "not finite",
    );
}

#[test]
fn internal_energy() {
    rejects(
        &[(DISK_H, "h_factor: 1.5, internal_energy: -1.0)")],
        "particles[1].internal_energy",
        ">= 0",
    );
}

#[test]
fn a_section_is_checked_by_its_settings() {
    rejects(&[("Fixed(1e-4)", "Fixed(0.0)")], "integrator.dt", "> 0");
    load(&edit(&[("Fixed(1e-4)", "Adaptive(courant: 0.25)")])).unwrap();
}

#[test]
fn run_length_and_output() {
    rejects(&[("end_time: 1.0", "end_time: 0.0")], "end_time", "> 0");
    rejects(
        &[("end_time: 1.0,", "end_time: 1.0, max_steps: 0,")],
        "max_steps",
        "at least 1",
    );
    rejects(
        &[(
            "end_time: 1.0,",
            "end_time: 1.0, output: (diagnostics_every: 0),",
        )],
        "output.diagnostics_every",
        "at least 1",
    );
}

#[test]
fn plugin_validation_names_index_and_plugin() {
    rejects(
        &[
            ("plugins: [", "plugins: [SpecularWalls(), "),
            ("g: [0.0, -9.81]", "g: [0.0, -9.81, 0.0]"),
        ],
        "plugins[1] (Gravity)",
        "`g` needs 2 components, got 3",
    );
    let e = load(&edit(&[("g: [0.0, -9.81]", "g: [1.0]")])).unwrap_err();
    assert_eq!(
        e.to_string(),
        "scenes/test.ron: invalid value for `plugins[0] (Gravity)`: `g` needs 2 components, got 1"
    );
}

#[test]
fn generator_without_particles() {
    rejects(
        &[(
            DISK_H,
            "h_factor: 1.5, clip: (min: [0.0, 0.0], max: [1.0, 1.0]))",
        )],
        "particles[1]",
        "particles[1] generates no particles",
    );
    rejects(
        &[(
            BLOCK_H,
            "h_factor: 2.0, cut: [(min: [0.0, 0.0], max: [1.0, 0.5])])",
        )],
        "particles[0]",
        "particles[0] generates no particles",
    );
    rejects(
        &[(BLOCK, "min: [0.0, 0.0], max: [1.0, 0.02]")],
        "particles[0]",
        "generates no particles",
    );
}

#[test]
fn particles_outside_domain() {
    rejects(
        &[("center: [3.0, 2.0]", "center: [3.8, 2.0]")],
        "particles[1]",
        "particles[1] generates a particle at (4.025, 1.575) outside the domain",
    );
    rejects(
        &[(BLOCK, "min: [-1.0, 0.0], max: [1.0, 0.5]")],
        "particles[0]",
        "(-0.9875, 0.025)",
    );
}

#[test]
fn huge_scenes_are_refused_before_generating() {
    let start = std::time::Instant::now();
    // 1e12 particles: generating them would exhaust memory and time.
    let text = edit(&[
        ("max: [4.0, 3.0]", "max: [1000.0, 1000.0]"),
        (BLOCK, "min: [0.0, 0.0], max: [1000.0, 1000.0]"),
        (
            "spacing: 0.05, lattice: Staggered",
            "spacing: 0.001, lattice: Staggered",
        ),
        ("center: [3.0, 2.0]", "center: [-3.0, 2.0]"),
    ]);
    let (f, m) = invalid(&text);
    assert_eq!(f, "particles");
    assert!(m.contains("50000000") && m.contains("particles[0]"), "{m}");
    let s = Scene::parse_only(&text, path(), &registry()).unwrap();
    assert!(s.generate().is_empty());
    // The sum matters, not each generator: three blocks of 20 million each are too many.
    let many = edit(&[
        ("max: [4.0, 3.0]", "max: [30.0, 30.0]"),
        (BLOCK, "min: [0.0, 0.0], max: [10.0, 2.0]"),
        (
            "spacing: 0.05, lattice: Staggered",
            "spacing: 0.001, lattice: Staggered",
        ),
        (
            "        Disk(",
            "        Block(min: [10.0, 0.0], max: [20.0, 2.0], spacing: 0.001, lattice: Square, density: 1.0, h_factor: 2.0),\n        Block(min: [20.0, 0.0], max: [30.0, 2.0], spacing: 0.001, lattice: Square, density: 1.0, h_factor: 2.0),\n        Disk(",
        ),
        ("center: [3.0, 2.0]", "center: [15.0, 20.0]"),
    ]);
    let (f, m) = invalid(&many);
    assert_eq!(f, "particles");
    assert!(m.contains("6.000e7"), "{m}");
    assert!(start.elapsed().as_secs() < 30);
}

#[test]
fn overlapping_generators_are_refused() {
    let (f, m) = invalid(&edit(&[("center: [3.0, 2.0]", "center: [1.0, 0.5]")]));
    assert_eq!(f, "particles[1]");
    assert!(
        m.contains("overlaps particles[0]") && m.contains("half the smaller spacing"),
        "{m}"
    );
    // A fine block inside a coarse one, listed first: found from the fine side.
    let text = edit(&[(
        "particles: [\n",
        "particles: [\n        Block(min: [3.0, 2.0], max: [3.2, 2.2], spacing: 0.01, lattice: Square, density: 1.0, h_factor: 2.0),\n",
    )]);
    let (f, m) = invalid(&text);
    assert_eq!(f, "particles[2]");
    assert!(
        m.contains("overlaps particles[0]") && m.contains("(0.005)"),
        "{m}"
    );
}

#[test]
fn touching_generators_are_not_overlapping() {
    // Same spacing, sharing the face x = 1; and a coarser block on top sharing y = 0.5.
    let text = edit(&[(
        "particles: [\n",
        "particles: [\n        Block(min: [1.0, 0.0], max: [2.0, 0.5], spacing: 0.05, lattice: Staggered, density: 1.0, h_factor: 2.0),\n        Block(min: [0.0, 0.5], max: [2.0, 1.5], spacing: 0.1, lattice: Square, density: 1.0, h_factor: 2.0),\n",
    )]);
    load(&text).unwrap();
}

#[test]
fn overlap_check_agrees_with_brute_force() {
    let mut seen = [0, 0];
    for step in 0..40 {
        let x0 = 0.8 + 0.0077 * step as f64;
        let y0 = 0.0031 * step as f64;
        let block = format!(
            "particles: [\n        Block(min: [{x0}, {y0}], max: [{}, {}], spacing: 0.08, lattice: Staggered, density: 1.0, h_factor: 2.0),\n",
            x0 + 0.8,
            y0 + 0.4
        );
        let text = edit(&[("particles: [\n", &block)]);
        let s = Scene::parse_only(&text, path(), &registry()).unwrap();
        let ps = s.generate();
        let (coarse, fine): (Vec<&crate::ParticleSpec>, Vec<_>) = ps
            .iter()
            .filter(|p| p.generator < 2)
            .partition(|p| p.generator == 0);
        let brute = fine.iter().any(|a| {
            coarse
                .iter()
                .any(|b| libm::hypot(a.pos[0] - b.pos[0], a.pos[1] - b.pos[1]) < 0.5 * 0.05)
        });
        let fast = match s.validate(path()) {
            Err(SceneError::Invalid { field, .. }) => {
                assert_eq!(field, "particles[1]");
                true
            }
            Ok(()) => false,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(fast, brute, "x0 = {x0}, y0 = {y0}");
        seen[usize::from(fast)] += 1;
    }
    assert!(
        seen[0] > 0 && seen[1] > 0,
        "both outcomes exercised: {seen:?}"
    );
}

/// Fuzzing found 112 side-by-side blocks taking minutes in the overlap check (every pair of
/// generators was compared); pairs whose bounding boxes are apart are now skipped. This
/// checks that the shortcut still finds an overlap between two generators in a long row and
/// that a clean row passes.
#[test]
fn many_side_by_side_generators_overlap_check() {
    let row: String = (0..150)
        .map(|i| {
            let x = 0.02 * i as f64;
            format!(
                "        Block(min: [{x}, 1.0], max: [{}, 1.04], spacing: 0.01, lattice: Square, density: 1.0, h_factor: 2.0),\n",
                x + 0.02
            )
        })
        .collect();
    let clean = edit(&[("particles: [\n", &format!("particles: [\n{row}"))]);
    load(&clean).unwrap();
    let last = "        Block(min: [2.975, 1.0], max: [2.995, 1.04], spacing: 0.01, lattice: Square, density: 1.0, h_factor: 2.0),\n";
    let bad = edit(&[("particles: [\n", &format!("particles: [\n{row}{last}"))]);
    let (field, m) = invalid(&bad);
    assert_eq!(field, "particles[150]", "{m}");
    assert!(m.contains("overlaps particles[148]"), "{m}");
}

#[test]
fn body_kinds_are_the_registrys_and_check_their_settings() {
    let with = |kind: &str| {
        let bodies = format!(
            "    bodies: [Body(name: \"water\"), Body(name: \"wall\", kind: {kind})],\n    particles: ["
        );
        edit(&[
            ("    particles: [", &bodies),
            (BLOCK_H, "h_factor: 2.0, body: \"water\")"),
            (DISK_H, "h_factor: 1.5, body: \"wall\")"),
        ])
    };
    let s = load(&with("Spin(rate: 2.0)")).unwrap();
    assert_eq!(s.bodies[1].kind.name(), "Spin");
    assert!(!s.bodies[1].kind.is_fluid() && s.bodies[0].kind.is_fluid());
    let (field, message) = invalid(&with("Spin(rate: -1.0)"));
    assert_eq!(
        (field.as_str(), message.as_str()),
        ("bodies[1].kind.rate", "must be > 0")
    );
    let text = with("Floating(mass: 1.0)");
    let (line, col, message) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "Floating"));
    assert!(
        message.contains("unknown body kind `Floating`, expected one of: Fluid, Fixed, Spin"),
        "{message}"
    );
    let (_, _, message) = parse_error(&with("Spin"));
    assert!(message.contains("write `Spin(...)`"), "{message}");
}

#[test]
fn bodies() {
    let two =
        "    bodies: [Body(name: \"water\"), Body(name: \"wall\", kind: Fixed)],\n    particles: [";
    rejects(
        &[
            ("    particles: [", two),
            (BLOCK_H, "h_factor: 2.0, body: \"water\")"),
        ],
        "particles[1].body",
        "the scene has 2 bodies: say which",
    );
    rejects(
        &[
            ("    particles: [", two),
            (BLOCK_H, "h_factor: 2.0, body: \"watr\")"),
            (DISK_H, "h_factor: 1.5, body: \"wall\")"),
        ],
        "particles[0].body",
        "no body named `watr`; the scene's bodies are water, wall",
    );
    rejects(
        &[(BLOCK_H, "h_factor: 2.0, body: \"water\")")],
        "particles[0].body",
        "the scene declares no `bodies`",
    );
    let twice = "    bodies: [Body(name: \"a\"), Body(name: \"a\")],\n    particles: [";
    rejects(
        &[("    particles: [", twice)],
        "bodies[1].name",
        "the body `a` is declared twice",
    );
    let empty = "    bodies: [Body(name: \"\")],\n    particles: [";
    rejects(
        &[("    particles: [", empty)],
        "bodies[0].name",
        "must not be empty",
    );
    let ok = edit(&[
        ("    particles: [", two),
        (BLOCK_H, "h_factor: 2.0, body: \"water\")"),
        (DISK_H, "h_factor: 1.5, body: \"wall\")"),
    ]);
    let s = load(&ok).unwrap();
    let bodies: Vec<u16> = s.generate().iter().map(|p| p.body).collect();
    assert!(bodies.contains(&0) && bodies.contains(&1));
}
