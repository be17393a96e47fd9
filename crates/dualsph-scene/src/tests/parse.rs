//! Parsing: the schema, defaults, plugins and the parse errors.

use super::*;
use crate::{Formulation, Generator, KernelKind, Lattice, OutputFormat, Velocity, VtkEncoding};

#[test]
fn base_scene_parses_with_defaults() {
    let s = load(BASE).unwrap();
    assert_eq!(s.name, "test");
    assert_eq!(s.dimension, 2);
    assert_eq!(s.domain.max, vec![4.0, 3.0]);
    assert_eq!(s.kernel, KernelKind::CubicSpline);
    assert_eq!(s.formulation, Formulation::DualSupport);
    assert_eq!(s.neighbours.skin, 0.15);
    assert!(s.neighbours.tune_skin);
    assert_eq!(s.particles.len(), 2);
    assert!(
        matches!(&s.particles[0], Generator::Block(b) if b.lattice == Lattice::Staggered && b.clip.is_none() && b.cut.is_empty() && b.velocity.is_none() && b.body.is_none())
    );
    assert!(matches!(&s.particles[1], Generator::Disk(d) if d.radius == 0.5));
    let names: Vec<_> = s.plugins.iter().map(|p| p.name()).collect();
    assert_eq!(names, ["Gravity", "SpecularWalls"]);
    let steps = s.section::<Steps>().unwrap();
    assert_eq!((&steps.dt, steps.max_dt), (&Dt::Fixed(1e-4), None));
    assert!(s.health.is_none() && s.section::<Health>().is_none());
    assert_eq!(s.end_time, 1.0);
    assert_eq!(s.max_steps, None);
    assert_eq!(
        (
            s.output.diagnostics_every,
            s.output.snapshot_every,
            s.output.snapshot_dt
        ),
        (10, 200, None)
    );
    assert_eq!(s.output.formats, [OutputFormat::Csv, OutputFormat::Vtk]);
    assert_eq!(s.output.vtk_encoding, VtkEncoding::Binary);
    assert_eq!(s.output.columns, None);
}

#[test]
fn plugin_settings_reach_the_plugin() {
    let s = load(BASE).unwrap();
    let dbg = format!("{:?}", s.plugins[0]);
    assert!(dbg.contains("-9.81"), "{dbg}");
}

#[test]
fn every_optional_field_parses() {
    let text = edit(&[
        (
            "formulation: DualSupport,",
            "formulation: AveragedKernel, neighbours: (skin: 0.3, tune_skin: false),\n    bodies: [Body(name: \"seven\")],",
        ),
        (
            "lattice: Staggered, density: 1000.0, h_factor: 2.0)",
            "lattice: Staggered, density: 1000.0, h_factor: 2.0, clip: Some((min: [0.0, 0.0], max: [0.5, 0.5])), \
             cut: [(min: [0.0, 0.0], max: [0.1, 0.1])], velocity: Linear([[1.0, 0.0], [0.0, -1.0]]), \
             internal_energy: 2.5, body: \"seven\")",
        ),
        (
            "h_factor: 1.5)",
            "h_factor: 1.5, clip: (min: [2.5, 1.5], max: [3.5, 2.0]), velocity: Uniform([1.0, 2.0]))",
        ),
        (
            "(dt: Fixed(1e-4))",
            "(dt: Adaptive(courant: 0.2), max_dt: Some(1e-3))",
        ),
        (
            "end_time: 1.0,",
            "end_time: 1.0, max_steps: Some(100), output: (snapshot_every: 0, snapshot_dt: 0.25, formats: [Vtk], \
             vtk_encoding: Compressed, columns: [\"pressure\", \"velocity\"]),",
        ),
    ]);
    let s = load(&text).unwrap();
    assert_eq!(s.formulation, Formulation::AveragedKernel);
    assert_eq!(s.neighbours.skin, 0.3);
    assert!(!s.neighbours.tune_skin);
    let Generator::Block(b) = &s.particles[0] else {
        panic!()
    };
    assert_eq!(b.clip.as_ref().unwrap().max, vec![0.5, 0.5]);
    assert_eq!(b.cut.len(), 1);
    assert_eq!(
        b.velocity,
        Some(Velocity::Linear(vec![vec![1.0, 0.0], vec![0.0, -1.0]]))
    );
    assert_eq!((b.internal_energy, b.body.as_deref()), (2.5, Some("seven")));
    let Generator::Disk(d) = &s.particles[1] else {
        panic!()
    };
    assert_eq!(d.clip.as_ref().unwrap().min, vec![2.5, 1.5]);
    assert_eq!(d.velocity, Some(Velocity::Uniform(vec![1.0, 2.0])));
    let steps = s.section::<Steps>().unwrap();
    assert_eq!(steps.dt, Dt::Adaptive { courant: 0.2 });
    assert_eq!(steps.max_dt, Some(1e-3));
    assert_eq!(s.max_steps, Some(100));
    assert_eq!(
        (
            s.output.diagnostics_every,
            s.output.snapshot_every,
            s.output.snapshot_dt
        ),
        (10, 0, Some(0.25))
    );
    assert_eq!(s.output.formats, [OutputFormat::Vtk]);
    assert_eq!(s.output.vtk_encoding, VtkEncoding::Compressed);
    assert_eq!(
        s.output.columns.as_deref(),
        Some(&["pressure".to_string(), "velocity".to_string()][..])
    );
}

#[test]
fn clip_accepts_every_spelling() {
    for clip in [
        "Some((min: [0.0, 0.0], max: [0.5, 0.5]))",
        "Some( ( min: [0.0, 0.0], max: [0.5, 0.5] ) )",
        "Some(min: [0.0, 0.0], max: [0.5, 0.5])",
        "(min: [0.0, 0.0], max: [0.5, 0.5])",
    ] {
        let text = edit(&[("h_factor: 2.0)", &format!("h_factor: 2.0, clip: {clip})"))]);
        let s = load(&text).unwrap_or_else(|e| panic!("{clip}: {e}"));
        let Generator::Block(b) = &s.particles[0] else {
            panic!()
        };
        assert_eq!(b.clip.as_ref().unwrap().max, vec![0.5, 0.5], "{clip}");
    }
    let text = edit(&[("h_factor: 2.0)", "h_factor: 2.0, clip: None)")]);
    let Generator::Block(b) = &load(&text).unwrap().particles[0] else {
        panic!()
    };
    assert!(b.clip.is_none());
}

#[test]
fn clip_box_errors_are_precise() {
    let text = edit(&[(
        "h_factor: 2.0)",
        "h_factor: 2.0, clip: Some((min: [0.0, 0.0], mux: [1.0, 1.0])))",
    )]);
    let (line, col, msg) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "mux"));
    assert!(
        msg.contains("unknown field `mux` in clip box") && msg.contains("`max`"),
        "{msg}"
    );
    let text = edit(&[("h_factor: 2.0)", "h_factor: 2.0, clip: (min: [0.0, 0.0]))")]);
    assert!(
        parse_error(&text)
            .2
            .contains("clip box is missing field `max`")
    );
}

#[test]
fn sections_are_parsed_by_their_registered_settings() {
    let text = edit(&[("end_time: 1.0,", "end_time: 1.0, health: (limit: 3.0),")]);
    let s = load(&text).unwrap();
    assert_eq!(s.section::<Health>(), Some(&Health { limit: 3.0 }));
    assert_eq!(s.health.as_ref().map(|h| h.key()), Some("health"));
    // an error inside a section is reported where it stands
    let text = edit(&[("end_time: 1.0,", "end_time: 1.0, health: (limt: 3.0),")]);
    let (line, col, msg) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "limt"));
    assert!(msg.contains("limt") && msg.contains("`limit`"), "{msg}");
    let text = edit(&[("(dt: Fixed(1e-4))", "(dt: Fixed(\"small\"))")]);
    assert_eq!(parse_error(&text).0, line_col(&text, "small").0);
}

#[test]
fn a_section_without_registered_settings_says_so() {
    let mut r = Registry::new();
    r.register::<Gravity>().register::<Walls>();
    let e = Scene::parse_only(BASE, path(), &r).unwrap_err().to_string();
    assert!(
        e.contains("no settings are registered for the section `integrator`"),
        "{e}"
    );
}

#[test]
fn plugins_may_be_omitted_or_empty() {
    for plugins in ["", "plugins: [],"] {
        let text = edit(&[(
            "plugins: [Gravity(g: [0.0, -9.81]), SpecularWalls()],",
            plugins,
        )]);
        assert!(load(&text).unwrap().plugins.is_empty());
    }
}

#[test]
fn typo_in_field_reports_line_column_and_expected_fields() {
    let text = edit(&[(
        "spacing: 0.05, lattice: Staggered",
        "spacng: 0.05, lattice: Staggered",
    )]);
    let (line, col, msg) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "spacng"));
    assert!(msg.contains("spacng") && msg.contains("`spacing`"), "{msg}");
}

#[test]
fn unknown_plugin_lists_registered_names() {
    let text = edit(&[("SpecularWalls()", "Viscosity(alpha: 0.1)")]);
    let (line, _, msg) = parse_error(&text);
    assert_eq!(line, line_col(&text, "Viscosity").0);
    assert!(msg.contains("unknown plugin `Viscosity`"), "{msg}");
    assert!(msg.contains("Gravity, SpecularWalls"), "{msg}");
}

#[test]
fn plugin_setting_errors_are_reported_with_position() {
    let text = edit(&[("Gravity(g: [0.0, -9.81])", "Gravity(gg: [0.0, -9.81])")]);
    let (line, col, msg) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "gg:"));
    assert!(msg.contains("gg") && msg.contains("`g`"), "{msg}");
    let text = edit(&[("SpecularWalls()", "SpecularWalls(x: 1)")]);
    assert!(parse_error(&text).2.contains("`x`"));
    let text = edit(&[("Gravity(g: [0.0, -9.81])", "Gravity(g: \"down\")")]);
    assert_eq!(parse_error(&text).0, line_col(&text, "down").0);
}

#[test]
fn wrong_type_is_a_parse_error() {
    let text = edit(&[("density: 1000.0", "density: \"water\"")]);
    let (line, col, msg) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "\"water\""));
    assert!(msg.to_lowercase().contains("expected float"), "{msg}");
    let text = edit(&[("dimension: 2", "dimension: 2.5")]);
    let (line, col, msg) = parse_error(&text);
    assert_eq!((line, col), line_col(&text, "2.5"));
    assert!(
        msg.contains("Expected a non-negative integer but found the floating point number `2.5`"),
        "{msg}"
    );
    for (from, to) in [
        ("end_time: 1.0,", "end_time: 1.0, max_steps: Some(-3),"),
        ("end_time: 1.0,", "end_time: 1.0, max_steps: 1e9,"),
        (
            "end_time: 1.0,",
            "end_time: 1.0, output: (snapshot_every: \"often\"),",
        ),
        ("end_time: 1.0,", "end_time: 1.0, max_steps: 1.5,"),
    ] {
        let text = edit(&[(from, to)]);
        let (line, _, msg) = parse_error(&text);
        assert!(
            line > 1 && (msg.contains("non-negative integer") || msg.contains("out of range")),
            "{to}: {msg}"
        );
    }
    let text = edit(&[(
        "end_time: 1.0,",
        "end_time: 1.0, max_steps: 7, output: (diagnostics_every: 3),",
    )]);
    let s = load(&text).unwrap();
    assert_eq!((s.max_steps, s.output.diagnostics_every), (Some(7), 3));
}

#[test]
fn missing_field_is_named() {
    let text = edit(&[(" density: 500.0,", "")]);
    let (line, _, msg) = parse_error(&text);
    assert!(
        msg.contains("`density`") && msg.contains("missing"),
        "{msg}"
    );
    assert_eq!(line, line_col(&text, "Disk(").0);
    let text = edit(&[("    end_time: 1.0,\n", "")]);
    assert!(parse_error(&text).2.contains("`end_time`"));
}

#[test]
fn unknown_variant_and_top_level_field_list_alternatives() {
    let text = edit(&[("kernel: CubicSpline", "kernel: Gaussian")]);
    let (line, _, msg) = parse_error(&text);
    assert_eq!(line, 5);
    assert!(
        msg.contains("Gaussian") && msg.contains("WendlandC2"),
        "{msg}"
    );
    let text = edit(&[("end_time: 1.0,", "end_time: 1.0, colour: 3,")]);
    let (_, col, msg) = parse_error(&text);
    assert_eq!(col, line_col(&text, "colour").1);
    assert!(
        msg.contains("colour") && msg.contains("`max_steps`"),
        "{msg}"
    );
}

#[test]
fn syntax_errors_do_not_panic() {
    for text in [
        "",
        "Scene(",
        &BASE.replace("end_time: 1.0,", "end_time: 1.0 max_steps: None,"),
        &BASE[..BASE.len() / 2],
        "Scene(name: \"x\" /* unterminated",
    ] {
        let e = Scene::parse_only(text, path(), &registry()).unwrap_err();
        assert!(matches!(e, SceneError::Parse { .. }), "{e:?}");
    }
}

#[test]
fn parse_error_display_is_path_line_col_message() {
    let text = edit(&[(
        "spacing: 0.05, lattice: Staggered",
        "spacng: 0.05, lattice: Staggered",
    )]);
    let e = Scene::from_str(&text, path(), &registry()).unwrap_err();
    let (line, col) = line_col(&text, "spacng");
    let shown = e.to_string();
    assert!(
        shown.starts_with(&format!("scenes/test.ron:{line}:{col}: ")),
        "{shown}"
    );
}

#[test]
fn load_reads_files_and_reports_io_errors() {
    let dir = std::env::temp_dir().join(format!("dualsph-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("base.ron");
    std::fs::write(&file, BASE).unwrap();
    let s = Scene::load(&file, &registry()).unwrap();
    assert_eq!(s.name, "test");
    let missing = dir.join("missing.ron");
    let e = Scene::load(&missing, &registry()).unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }));
    assert!(e.to_string().contains("missing.ron"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn plugins_without_registry_fail_cleanly() {
    // Plain ron, no registry installed: a clear error, not a panic.
    let opts = ron::Options::default().with_default_extension(
        ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES
            | ron::extensions::Extensions::IMPLICIT_SOME,
    );
    let e = opts.from_str::<Scene>(BASE).unwrap_err();
    assert!(e.code.to_string().contains("no plugin registry"), "{e}");
    // ...and the registry of a finished parse does not linger.
    load(BASE).unwrap();
    assert!(opts.from_str::<Scene>(BASE).is_err());
}

#[test]
fn empty_registry_says_so() {
    let e = Scene::parse_only(BASE, path(), &Registry::new()).unwrap_err();
    assert!(e.to_string().contains("no plugins are registered"), "{e}");
}

#[test]
fn plugins_with_and_without_settings() {
    for walls in ["SpecularWalls()", "SpecularWalls( )", "SpecularWalls(\n)"] {
        let text = edit(&[("SpecularWalls()", walls)]);
        let s = load(&text).unwrap_or_else(|e| panic!("{walls}: {e}"));
        let names: Vec<_> = s.plugins.iter().map(|p| p.name()).collect();
        assert_eq!(names, ["Gravity", "SpecularWalls"]);
    }
    let text = edit(&[("SpecularWalls()", "SpecularWalls")]);
    let (line, _, msg) = parse_error(&text);
    assert_eq!(line, line_col(&text, "SpecularWalls").0);
    assert!(
        msg.contains("write `SpecularWalls(field: value, ...)`, or `SpecularWalls()`"),
        "{msg}"
    );
    let text = edit(&[("Gravity(g: [0.0, -9.81])", "Gravity()")]);
    let msg = parse_error(&text).2;
    assert!(
        msg.contains("plugin `Gravity`") && msg.contains("missing field named `g`"),
        "{msg}"
    );
}

#[test]
fn a_byte_order_mark_is_accepted_and_positions_count_without_it() {
    let with_bom = format!("\u{feff}{BASE}");
    assert_eq!(load(&with_bom).unwrap().name, "test");
    let e = load("\u{feff}Scene(name 1)").unwrap_err().to_string();
    assert!(e.contains(":1:12"), "{e}");
}

/// `formulation` (DualSupport) and a generator's `lattice` (Square) may be left out.
#[test]
fn formulation_and_lattice_have_defaults() {
    let text = r#"Scene(
        name: "defaults", dimension: 2,
        domain: (min: [0.0, 0.0], max: [1.0, 1.0]),
        kernel: WendlandC2,
        particles: [
            Block(min: [0.0, 0.0], max: [0.5, 0.5], spacing: 0.1, density: 1.0, h_factor: 3.0),
            Disk(center: [0.7, 0.7], radius: 0.2, spacing: 0.1, density: 1.0, h_factor: 3.0),
        ],
        integrator: (dt: Fixed(1e-3)), end_time: 0.1,
    )"#;
    let s = load(text).unwrap();
    assert_eq!(s.formulation, Formulation::DualSupport);
    assert!(
        matches!(&s.particles[0], Generator::Block(b) if b.lattice == Lattice::Square && b.jitter == 0.0)
    );
    assert!(matches!(&s.particles[1], Generator::Disk(d) if d.lattice == Lattice::Square));
}
