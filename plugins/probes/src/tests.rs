use super::*;
use glam::DVec2;

fn parse(text: &str) -> Result<Probes, String> {
    // the scene parser's extensions
    use ron::extensions::Extensions;
    ron::Options::default()
        .with_default_extension(Extensions::UNWRAP_VARIANT_NEWTYPES | Extensions::IMPLICIT_SOME)
        .from_str::<Probes>(text)
        .map_err(|e| e.to_string())
}

fn info(d: usize) -> SceneInfo {
    SceneInfo::of_dimension(d)
}

/// A resting 2-D water block [0, 1] × [0, depth] with spacing dx, h = 2 dx, velocity (0.3, −0.1).
fn block_sim(depth: Real, dx: Real) -> Sim<DVec2> {
    block_on_floor(depth, dx, 0.0)
}

/// [`block_sim`] whose particles below `floor` are a fixed body `floor` at rest (body 0), the
/// others the body `water` (body 1), when `floor > 0`.
fn block_on_floor(depth: Real, dx: Real, floor: Real) -> Sim<DVec2> {
    let mut sim = Sim::<DVec2>::new(SimConfig {
        kernel: KernelKind::CubicSpline,
        formulation: Formulation::DualSupport,
        domain: Domain::closed(DVec2::ZERO, DVec2::new(1.0, 1.0)),
        skin: 0.0,
        skin_rule: SkinRule::Fixed,
        time_stepping: TimeStepping::Fixed(1e-5),
    });
    let (nx, ny) = ((1.0 / dx).round() as usize, (depth / dx).round() as usize);
    let parts: Vec<ParticleInit<DVec2>> = (0..nx * ny)
        .map(|k| ParticleInit {
            pos: DVec2::new((k % nx) as Real + 0.5, (k / nx) as Real + 0.5) * dx,
            vel: DVec2::new(0.3, -0.1),
            mass: 1000.0 * dx * dx,
            density: 1000.0,
            h: 2.0 * dx,
            internal_energy: 0.0,
            body: 0,
        })
        .map(|mut p| {
            if floor > 0.0 {
                p.body = u16::from(p.pos.y > floor);
                p.vel *= Real::from(p.body);
            }
            p
        })
        .collect();
    sim.spawn_particles(&parts).expect("fresh particle ids");
    if floor > 0.0 {
        use dualsph_core::bodies::{Bodies, Body, BodyKind, install_bodies};
        let bodies = Bodies(vec![
            Body::new("floor", BodyKind::Fixed),
            Body::new("water", BodyKind::Fluid),
        ]);
        install_bodies(&mut sim, bodies).unwrap();
    }
    let integrator: &dyn PluginConfig = &dualsph_integrator::LeapfrogPC::default();
    sim.build_plugin(integrator).unwrap();
    sim
}

const GOOD: &str = r#"(every: 2, probes: [
    Point(name: "rho", at: [0.5, 0.2], quantity: Density),
    Point(name: "vy", at: [0.5, 0.2], quantity: VelocityY),
    Point(name: "dry", at: [0.5, 0.9], quantity: Density),
    WaterHeight(name: "H", at: [0.5]),
    Line(name: "col", start: [0.25, 0.05], end: [0.25, 0.35], n: 4, quantity: VelocityX),
])"#;

#[test]
fn samples_a_resting_block_against_its_known_state() {
    let dir = tempfile::tempdir().unwrap();
    let mut sim = block_sim(0.4, 0.02);
    let probes = parse(GOOD).unwrap();
    SimPlugin::validate(&probes, &info(2)).unwrap();
    probes.build(&mut sim).unwrap();
    sim.world
        .insert_resource(RunOutputDir(dir.path().to_path_buf()));
    sim.initialize().unwrap();
    for _ in 0..3 {
        sim.step().unwrap();
    }
    let state = sim.world.resource::<ProbeState<DVec2>>();
    assert!(state.write_error.is_none());
    let steps: Vec<u64> = state.rows.iter().map(|r| r.0).collect();
    assert_eq!(steps, vec![0, 2]);
    let table = read_probes(dir.path()).unwrap();
    assert_eq!(table.step, vec![0, 2]);
    assert_eq!(table.columns.len(), 8);
    assert_eq!(table.columns[4], "col[0]");
    let row = &table.values[0];
    // Shepard-normalised interpolation of uniform fields is exact
    assert!((row[0] - 1000.0).abs() < 1e-9, "ρ = {}", row[0]);
    assert!((row[1] + 0.1).abs() < 1e-12, "v_y = {}", row[1]);
    assert!(row[2].is_nan(), "a dry sensor reads NaN, got {}", row[2]);
    // the free surface of a 0.4 m deep block (σ = ½ there)
    assert!((row[3] - 0.4).abs() < 0.01, "H = {}", row[3]);
    for c in 4..8 {
        assert!((row[c] - 0.3).abs() < 1e-12);
    }
    assert_eq!(table.meta[5].3, [0.25, 0.15, 0.0]);
    let pngs = plot_probes(dir.path()).unwrap();
    assert_eq!(pngs.len(), 4); // Density, VelocityY, WaterHeight, line "col"
    for p in pngs {
        assert!(
            std::fs::metadata(&p).unwrap().len() > 1000,
            "{}",
            p.display()
        );
    }
}

/// By default the probes sample the fluid only: next to a floor of particles at rest, a
/// point in the water reads the water's velocity exactly, and the floor's particles are not
/// taken for water by a gauge. Naming both bodies mixes the floor's zero velocity in.
#[test]
fn probes_read_the_fluid_not_the_walls() {
    let sample = |bodies: &str| {
        let mut sim = block_on_floor(0.4, 0.02, 0.1);
        let text = format!(
            r#"(every: 1, bodies: [{bodies}], probes: [
                Point(name: "u", at: [0.5, 0.11], quantity: VelocityX),
                WaterHeight(name: "H", at: [0.5], dy: 0.001),
            ])"#
        );
        parse(&text).unwrap().build(&mut sim).unwrap();
        sim.initialize().unwrap();
        sim.world.resource::<ProbeState<DVec2>>().rows[0].2.clone()
    };
    let fluid = sample("");
    assert!((fluid[0] - 0.3).abs() < 1e-12, "u = {}", fluid[0]);
    assert!((fluid[1] - 0.4).abs() < 0.006, "H = {}", fluid[1]);
    let both = sample(r#""floor", "water""#);
    assert!(both[0] < 0.29, "u with the floor = {}", both[0]);
    let floor_only = sample(r#""floor""#);
    assert!(
        (floor_only[1] - 0.1).abs() < 0.006,
        "H of the floor = {}",
        floor_only[1]
    );
}

#[test]
fn water_height_follows_the_depth() {
    for depth in [0.2, 0.3, 0.5] {
        let mut sim = block_sim(depth, 0.02);
        parse(r#"(every: 1, probes: [WaterHeight(name: "H", at: [0.5], dy: 0.001)])"#)
            .unwrap()
            .build(&mut sim)
            .unwrap();
        sim.initialize().unwrap();
        let h = sim.world.resource::<ProbeState<DVec2>>().rows[0].2[0];
        assert!((h - depth).abs() < 0.006, "depth {depth}: H = {h}");
    }
}

#[test]
fn pressure_probe_without_an_eos_is_a_build_error() {
    let mut sim = block_sim(0.2, 0.05);
    parse(r#"(every: 1, probes: [Point(name: "p", at: [0.5, 0.1], quantity: Pressure)])"#)
        .unwrap()
        .build(&mut sim)
        .unwrap();
    let err = sim.initialize().unwrap_err().to_string();
    assert!(err.contains("equation of state"), "{err}");
}

#[test]
fn a_second_probes_entry_is_a_build_error() {
    let mut sim = block_sim(0.2, 0.05);
    let p = parse(r#"(every: 1, probes: [Point(name: "r", at: [0.5, 0.1], quantity: Density)])"#)
        .unwrap();
    p.build(&mut sim).unwrap();
    let err = p.build(&mut sim).unwrap_err().to_string();
    assert!(err.contains("twice"), "{err}");
}

#[test]
fn bad_settings_name_the_field() {
    let cases = [
        (
            r#"(every: 0, probes: [Point(name: "a", at: [0.0, 0.0], quantity: Density)])"#,
            2,
            "every",
        ),
        (
            r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: Density)])"#,
            2,
            "probes[0].at",
        ),
        (
            r#"(every: 1, probes: [Point(name: "a b", at: [0.0, 0.0], quantity: Density)])"#,
            2,
            "probes[0].name",
        ),
        (
            r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: VelocityY)])"#,
            1,
            "VelocityY",
        ),
        (
            r#"(every: 1, probes: [WaterHeight(name: "a", at: [])])"#,
            1,
            "dimension 2 or 3",
        ),
        (
            r#"(every: 1, probes: [WaterHeight(name: "a", at: [0.1], threshold: 1.5)])"#,
            2,
            "threshold",
        ),
        (
            r#"(every: 1, probes: [Line(name: "a", start: [0.0], end: [1.0], n: 1, quantity: Density)])"#,
            1,
            "probes[0].n",
        ),
        (
            r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: Density), Point(name: "a", at: [1.0], quantity: Density)])"#,
            1,
            "duplicate",
        ),
        (r#"(every: 1, probes: [])"#, 1, "empty"),
    ];
    for (text, d, expect) in cases {
        let err = SimPlugin::validate(&parse(text).unwrap(), &info(d)).unwrap_err();
        assert!(err.contains(expect), "{text}: {err}");
    }
    // unknown fields and quantities are parse errors
    assert!(
        parse(r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: Temperature)])"#)
            .is_err()
    );
    assert!(
        parse(r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: Density, x: 1)])"#)
            .is_err()
    );
}
