use super::*;
use dualsph_core::sampling::SamplingCloud;
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
        use dualsph_core::bodies::{Bodies, Body, install_bodies};
        let bodies = Bodies(vec![Body::fixed("floor"), Body::fluid("water")]);
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
    let samples = sim.world.resource::<ProbeSamples>();
    let steps: Vec<u64> = samples.rows.iter().map(|r| r.0).collect();
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
    assert_eq!(pngs.len(), 4); // density, velocity.y, water_height, line "col"
    assert_eq!(table.meta[1].2, "velocity.y");
    assert!(dir.path().join("probes_water_height.png").exists());
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
        sim.world.resource::<ProbeSamples>().rows[0].2.clone()
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
        let h = sim.world.resource::<ProbeSamples>().rows[0].2[0];
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
    // unknown fields and malformed quantity names are parse errors
    assert!(
        parse(r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: "a b")])"#).is_err()
    );
    assert!(parse(r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: 3)])"#).is_err());
    assert!(
        parse(r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: Density, x: 1)])"#)
            .is_err()
    );
}

#[test]
fn old_and_new_spellings_name_the_same_quantities() {
    let q = |text: &str| {
        let p = parse(&format!(
            r#"(every: 1, probes: [Point(name: "a", at: [0.0], quantity: {text})])"#
        ))
        .unwrap();
        match &p.probes[0] {
            Probe::Point { quantity, .. } => quantity.name().to_string(),
            _ => unreachable!(),
        }
    };
    assert_eq!(q("Density"), "density");
    assert_eq!(q("density"), "density");
    assert_eq!(q(r#""density""#), "density");
    assert_eq!(q("VelocityX"), "velocity.x");
    assert_eq!(q(r#""velocity.x""#), "velocity.x");
    assert_eq!(q("ShepardSum"), "shepard_sum");
    assert_eq!(q("Speed"), "speed");
    assert_eq!(q("InternalEnergy"), "internal_energy");
    assert_eq!(q(r#""tracer""#), "tracer");
}

/// The error of building `quantity` on the resting block.
fn build_error(quantity: &str) -> String {
    let mut sim = block_sim(0.2, 0.05);
    let text =
        format!(r#"(every: 1, probes: [Point(name: "p", at: [0.5, 0.1], quantity: {quantity})])"#);
    parse(&text).unwrap().build(&mut sim).unwrap();
    sim.initialize().unwrap_err().to_string()
}

#[test]
fn an_unknown_quantity_is_a_build_error_listing_the_columns() {
    let err = build_error(r#""temperature""#);
    assert!(err.contains("probe `p`"), "{err}");
    assert!(err.contains("no column `temperature`"), "{err}");
    for name in [
        "density",
        "velocity.{x,y}",
        "smoothing_length",
        "speed",
        "shepard_sum",
    ] {
        assert!(err.contains(name), "{name} missing from: {err}");
    }
    let err = build_error(r#""velocity""#);
    assert!(err.contains("vector") && err.contains(".x"), "{err}");
    let err = build_error(r#""velocity.z""#);
    assert!(err.contains("2-D"), "{err}");
    let err = build_error(r#""density.x""#);
    assert!(err.contains("scalar"), "{err}");
}

/// Every value is the Shepard interpolant of the particles' own values, computed here from a
/// query of the store as the sampler's definition says, bit for bit.
#[test]
fn values_are_the_shepard_interpolant_bit_for_bit() {
    let mut sim = block_sim(0.4, 0.02);
    let text = r#"(every: 1, probes: [
        Point(name: "rho", at: [0.31, 0.17], quantity: Density),
        Point(name: "u", at: [0.31, 0.17], quantity: "velocity.x"),
        Point(name: "v", at: [0.31, 0.17], quantity: VelocityY),
        Point(name: "s", at: [0.31, 0.17], quantity: Speed),
        Point(name: "sigma", at: [0.31, 0.39], quantity: "shepard_sum"),
    ])"#;
    parse(text).unwrap().build(&mut sim).unwrap();
    sim.initialize().unwrap();
    // make the fields vary from particle to particle
    let mut q = sim
        .world
        .query::<(&Position<DVec2>, &mut Velocity<DVec2>, &mut Density)>();
    for (r, mut v, mut rho) in q.iter_mut(&mut sim.world) {
        v.0 = DVec2::new(libm::sin(r.0.x), r.0.y * r.0.x);
        rho.0 = 1000.0 + 7.0 * r.0.y + r.0.x * r.0.x;
    }
    sim.step().unwrap();
    let got = sim.world.resource::<ProbeSamples>().rows[1].2.clone();
    let mut q = sim.world.query::<(
        &Position<DVec2>,
        &Velocity<DVec2>,
        &Mass,
        &Density,
        &SmoothingLength,
    )>();
    let rows: Vec<_> = q.iter(&sim.world).collect();
    let kernel = sim.world.resource::<KernelRes>().0;
    let cloud = SamplingCloud::from_particles(
        kernel,
        rows.iter().map(|r| r.0.0).collect(),
        &rows.iter().map(|r| r.2.0).collect::<Vec<_>>(),
        &rows.iter().map(|r| r.3.0).collect::<Vec<_>>(),
        rows.iter().map(|r| r.4.0).collect(),
    );
    let x = DVec2::new(0.31, 0.17);
    let at = |values: Vec<Real>| cloud.sample(x, &values).shepard.unwrap();
    let want = [
        at(rows.iter().map(|r| r.3.0).collect()),
        at(rows.iter().map(|r| r.1.0.x).collect()),
        at(rows.iter().map(|r| r.1.0.y).collect()),
        at(rows.iter().map(|r| r.1.0.length()).collect()),
        cloud
            .sample(DVec2::new(0.31, 0.39), &vec![0.0; rows.len()])
            .shepard_sum,
    ];
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.to_bits(), w.to_bits(), "{g} against {w}");
    }
}

/// A column of a user's plugin.
#[derive(Component, Clone, Copy, Debug)]
struct Tracer(Real);
dualsph_core::scalar_column!(Tracer);

/// A user's plugin that registers the column `tracer` = 2 + x.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
struct TracerPlugin;

impl SimPlugin for TracerPlugin {
    const NAME: &'static str = "Tracer";
    const SUMMARY: &'static str = "a tracer column for the probes' tests";
    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let spec = dualsph_core::columns::ColumnSpec::state("tracer", "c");
        sim.add_column(spec, |seed| Tracer(2.0 + seed.init.pos.get(0)))
    }
}

#[test]
fn a_plugins_own_column_can_be_probed() {
    let mut sim = block_sim(0.4, 0.02);
    // the probes may come before the plugin that registers the column
    let text = r#"(every: 1, probes: [
        Line(name: "c", start: [0.2, 0.2], end: [0.8, 0.2], n: 4, quantity: "tracer"),
    ])"#;
    parse(text).unwrap().build(&mut sim).unwrap();
    TracerPlugin.build(&mut sim).unwrap();
    sim.initialize().unwrap();
    let row = &sim.world.resource::<ProbeSamples>().rows[0].2;
    for (k, v) in row.iter().enumerate() {
        let x = 0.2 + 0.2 * k as Real;
        // Shepard interpolation of a linear field is exact in the bulk
        assert!((v - (2.0 + x)).abs() < 1e-9, "c[{k}] = {v}");
    }
    let state = sim.world.resource::<ProbeState<DVec2>>();
    assert_eq!(state.columns[0].quantity, "tracer");
}

/// A sensor's mean: dry points as zero, left out or NaN; values below the floor raised.
#[test]
fn a_sensor_reads_the_mean_of_its_points_as_the_scene_chooses() {
    let v = [1.0, Real::NAN, -2.0, 3.0];
    let mean = |dry, floor| sensor_mean(v.into_iter(), dry, floor);
    assert_eq!(mean(Dry::Zero, None), 0.5);
    assert_eq!(mean(Dry::Zero, Some(0.0)), 1.0);
    assert_eq!(mean(Dry::Skip, Some(0.0)), 4.0 / 3.0);
    assert!(mean(Dry::Nan, None).is_nan());
    let dry = || [Real::NAN; 3].into_iter();
    assert_eq!(sensor_mean(dry(), Dry::Zero, None), 0.0);
    assert!(sensor_mean(dry(), Dry::Skip, None).is_nan());
}

/// A sensor across the free surface of the resting block (v_y = −0.1 in the water): of its
/// four points at y = 0.3, 0.4, 0.5, 0.6 the upper two are dry, so it reads −0.05 with dry
/// points as zero, −0.1 with them left out, and the floor −0.08 with them left out.
#[test]
fn a_sensor_across_the_surface_reads_its_wet_and_dry_points() {
    let mut sim = block_sim(0.4, 0.02);
    let sensor = |name: &str, dry: &str, floor: &str| {
        format!(
            "Sensor(name: \"{name}\", start: [0.5, 0.3], end: [0.5, 0.6], n: 4, \
             quantity: \"velocity.y\", dry: {dry}{floor})"
        )
    };
    let text = format!(
        "(every: 1, probes: [{}, {}, {}])",
        sensor("zero", "Zero", ""),
        sensor("skip", "Skip", ""),
        sensor("floor", "Skip", ", floor: -0.08"),
    );
    let probes = parse(&text).unwrap();
    SimPlugin::validate(&probes, &info(2)).unwrap();
    probes.build(&mut sim).unwrap();
    sim.initialize().unwrap();
    let row = &sim.world.resource::<ProbeSamples>().rows[0].2;
    assert!((row[0] + 0.05).abs() < 1e-12, "{row:?}");
    assert!((row[1] + 0.1).abs() < 1e-12, "{row:?}");
    assert!((row[2] + 0.08).abs() < 1e-12, "{row:?}");
    let state = sim.world.resource::<ProbeState<DVec2>>();
    let c = &state.columns[0];
    assert_eq!(c.kind, "sensor");
    assert!(
        (c.pos[1] - 0.45).abs() < 1e-15 && c.pos[0] == 0.5,
        "{:?}",
        c.pos
    );
    let bad = "(every: 1, probes: [Sensor(name: \"s\", start: [0.5, 0.3], end: [0.5, 0.6], n: 1)])";
    let e = SimPlugin::validate(&parse(bad).unwrap(), &info(2)).unwrap_err();
    assert!(e.starts_with("probes[0].n"), "{e}");
}

/// A sensor with `reach: 2.0` and `clip: 0.0` reads, bit for bit, the mean of the Shepard
/// interpolants of the particles' values clipped at zero, with every support radius doubled
/// (TrixiParticles.jl's sensor; its cut-off finds no wall here); with neither it reads the
/// particles' own supports, unclipped.
#[test]
fn a_sensor_interpolates_with_its_reach_and_clipped_values() {
    let mut sim = block_sim(0.4, 0.02);
    let text = r#"(every: 1, probes: [
        Sensor(name: "own", start: [0.3, 0.1], end: [0.3, 0.3], n: 3, quantity: "velocity.x"),
        Sensor(name: "trixi", start: [0.3, 0.1], end: [0.3, 0.3], n: 3, quantity: "velocity.x",
               clip: 0.0, reach: 2.0, cut_off: true),
    ])"#;
    let probes = parse(text).unwrap();
    SimPlugin::validate(&probes, &info(2)).unwrap();
    probes.build(&mut sim).unwrap();
    sim.initialize().unwrap();
    // a field of both signs that varies over the doubled support
    let mut q = sim
        .world
        .query::<(&Position<DVec2>, &mut Velocity<DVec2>)>();
    for (r, mut v) in q.iter_mut(&mut sim.world) {
        v.0 = DVec2::new(libm::sin(25.0 * r.0.y) + 0.3 * libm::cos(40.0 * r.0.x), 0.0);
    }
    sim.step().unwrap();
    let got = sim.world.resource::<ProbeSamples>().rows[1].2.clone();
    let mut q = sim.world.query::<(
        &Position<DVec2>,
        &Velocity<DVec2>,
        &Mass,
        &Density,
        &SmoothingLength,
    )>();
    let rows: Vec<_> = q.iter(&sim.world).collect();
    let kernel = sim.world.resource::<KernelRes>().0;
    let cloud = |r: Real| {
        SamplingCloud::from_particles(
            kernel,
            rows.iter().map(|p| p.0.0).collect(),
            &rows.iter().map(|p| p.2.0).collect::<Vec<_>>(),
            &rows.iter().map(|p| p.3.0).collect::<Vec<_>>(),
            rows.iter().map(|p| r * p.4.0).collect(),
        )
    };
    let mean = |cloud: &SamplingCloud<DVec2>, values: &[Real]| {
        let at = |y: Real| cloud.sample(DVec2::new(0.3, y), values).shepard.unwrap();
        (at(0.1) + at(0.2) + at(0.3)) / 3.0
    };
    let u: Vec<Real> = rows.iter().map(|p| p.1.0.x).collect();
    let clipped: Vec<Real> = u.iter().map(|v| v.max(0.0)).collect();
    let want = [mean(&cloud(1.0), &u), mean(&cloud(2.0), &clipped)];
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.to_bits(), w.to_bits(), "{g} against {w}");
    }
    // the doubled reach and the clip change the reading
    assert!((got[0] - got[1]).abs() > 1e-3, "{got:?}");
    let bad = |field: &str| {
        let text = format!(
            "(every: 1, probes: [Sensor(name: \"s\", start: [0.5, 0.3], end: [0.5, 0.6], \
             n: 2, {field})])"
        );
        SimPlugin::validate(&parse(&text).unwrap(), &info(2)).unwrap_err()
    };
    assert!(bad("reach: 0.0").starts_with("probes[0].reach"));
    assert!(bad("reach: 11.0").starts_with("probes[0].reach"));
    assert!(bad("clip: inf").starts_with("probes[0].clip"));
}

/// A sensor with `cut_off` reads a point dry where the walls' kernel-weighted mass outweighs
/// the water's: a film of one row of water (v_y = −0.1) on a floor of nineteen rows, sampled
/// on the row, is water with the particles' own supports and dry with three times their reach;
/// without `cut_off` both read the water.
#[test]
fn a_sensor_with_a_cut_off_reads_a_film_on_a_wall_as_dry() {
    let mut sim = block_on_floor(0.4, 0.02, 0.38);
    let sensor = |name: &str, more: &str| {
        format!(
            "Sensor(name: \"{name}\", start: [0.4, 0.39], end: [0.6, 0.39], n: 2, \
             quantity: \"velocity.y\", dry: Skip{more})"
        )
    };
    let text = format!(
        "(every: 1, probes: [{}, {}, {}])",
        sensor("own", ", cut_off: true"),
        sensor("wide", ", cut_off: true, reach: 3.0"),
        sensor("kept", ", reach: 3.0"),
    );
    let probes = parse(&text).unwrap();
    SimPlugin::validate(&probes, &info(2)).unwrap();
    probes.build(&mut sim).unwrap();
    sim.initialize().unwrap();
    let row = &sim.world.resource::<ProbeSamples>().rows[0].2;
    assert!((row[0] + 0.1).abs() < 1e-12, "{row:?}");
    assert!(row[1].is_nan(), "{row:?}");
    assert!((row[2] + 0.1).abs() < 1e-12, "{row:?}");
}

/// A gauge whose step would take more than a million samples over the domain's height per
/// reading is refused (a 1e-300 step read nothing but zeros before).
#[test]
fn a_gauge_step_too_fine_for_the_domain_is_refused() {
    let mut bounded = info(2);
    bounded.domain = (vec![0.0, 0.0], vec![1.0, 2.0]);
    let gauge = |dy: &str| {
        parse(&format!(
            r#"(every: 1, probes: [WaterHeight(name: "H", at: [0.5], dy: {dy})])"#
        ))
        .unwrap()
    };
    let e = SimPlugin::validate(&gauge("1e-300"), &bounded).unwrap_err();
    assert!(
        e.contains("probes[0].dy") && e.contains("2.000e300 samples"),
        "{e}"
    );
    assert!(SimPlugin::validate(&gauge("1e-5"), &bounded).is_ok());
    assert!(SimPlugin::validate(&gauge("1e-6"), &bounded).is_err());
}

#[test]
fn a_table_past_its_bound_is_refused_or_stops_the_run() {
    let line = |n: usize, every: u64| {
        parse(&format!(
            r#"(every: {every}, probes: [Line(name: "l", start: [0.1, 0.1], end: [0.3, 0.1], n: {n}, quantity: "density")])"#
        ))
        .unwrap()
    };
    let mut capped = info(2);
    capped.max_steps = Some(100_000);
    // 10^4 columns × (10^5 + 2) samples
    let e = SimPlugin::validate(&line(10_000, 1), &capped).unwrap_err();
    assert!(
        e.starts_with("every: 10000 columns") && e.contains("1.000e9 values"),
        "{e}"
    );
    // every 100: 10^4 × 1,002 ≈ 10^7 values fit
    assert!(SimPlugin::validate(&line(10_000, 100), &capped).is_ok());
    assert!(SimPlugin::validate(&line(10_000, 1), &info(2)).is_ok());
    // a run whose table would pass its bound stops with the cause at that sample
    let mut sim = block_sim(0.4, 0.02);
    line(4, 1).build(&mut sim).unwrap();
    sim.world.resource_mut::<ProbeState<DVec2>>().max_values = 8;
    sim.initialize().unwrap();
    sim.step().unwrap();
    let e = sim.step().unwrap_err().to_string();
    assert!(
        e.contains("step 2, t = 2.000000e-5: Probes: the table would hold 12 values (4 columns × 3 samples)"),
        "{e}"
    );
    assert_eq!(sim.world.resource::<ProbeSamples>().rows.len(), 2);
}
