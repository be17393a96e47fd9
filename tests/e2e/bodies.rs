//! Bodies and materials: two fluids of different ρ0 stay stratified at rest with their own
//! equations of state and per-body totals; a fixed body holds still under a fluid's load; a
//! prescribed lid moves by its law and drags the water under it; a kind of body from the
//! user's crate drives its body like a built-in one.

use dualsph::io::read_particles;
use dualsph::runner::{self, Progress, RunOptions};
use dualsph::scene::Scene;
use std::path::Path;

fn load(text: &str) -> Scene {
    Scene::from_str(text, Path::new("test.ron"), &dualsph::default_registry()).unwrap()
}

fn run(scene: &Scene) -> (tempfile::TempDir, runner::RunSummary) {
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions {
        out: dir.path().to_path_buf(),
        progress: Progress::Silent,
        profile: false,
    };
    let summary = runner::run(scene, &opts).unwrap();
    (dir, summary)
}

/// `scenes/two_fluids_2d.ron` to t = 1 s: water (ρ0 = 1000) under a fluid of ρ0 = 500, each
/// with its own Tait EOS. Away from the side walls (whose truncated kernels let the light
/// fluid creep down along them by about 2Δx), every column of width 2Δx keeps all water
/// below all of the light fluid; each body keeps its mass exactly; the columns settle
/// (largest speed 0.085 m/s at t = 1 s, against √(gH) = 2 m/s for a free fall over the
/// tank's fluid height).
#[test]
fn two_fluids_stay_stratified() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/two_fluids_2d.ron");
    let scene = Scene::load(&path, &dualsph::default_registry()).unwrap();
    let (dir, s) = run(&scene);
    let bodies: Vec<_> = s.last.per_body.iter().map(|b| b.mass).collect();
    assert_eq!(bodies.len(), 2);
    let initial: Vec<_> = s.initial.per_body.iter().map(|b| b.mass).collect();
    assert_eq!(bodies, initial, "each body's mass");
    assert!((initial[0] - 80.0).abs() < 1e-9 && (initial[1] - 40.0).abs() < 1e-9);

    let table = std::fs::read_to_string(dir.path().join("final.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (x, y, vx, vy, body) = (col("x"), col("y"), col("vx"), col("vy"), col("body"));
    let rows: Vec<Vec<f64>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let dx = 0.01;
    let mut columns = 0;
    let mut x0 = 2.0 * dx;
    while x0 < 0.4 - 2.0 * dx - 1e-9 {
        let inside = |r: &&Vec<f64>| (x0..x0 + 2.0 * dx).contains(&r[x]);
        let top_water = rows.iter().filter(inside).filter(|r| r[body] == 0.0);
        let bottom_light = rows.iter().filter(inside).filter(|r| r[body] == 1.0);
        let w = top_water.map(|r| r[y]).fold(f64::NEG_INFINITY, f64::max);
        let l = bottom_light.map(|r| r[y]).fold(f64::INFINITY, f64::min);
        assert!(
            w < l,
            "column at x = {x0}: water up to {w}, light fluid down to {l}"
        );
        columns += 1;
        x0 += 2.0 * dx;
    }
    assert_eq!(columns, 18);
    let vmax = rows
        .iter()
        .map(|r| libm::hypot(r[vx], r[vy]))
        .fold(0.0, f64::max);
    assert!(vmax < 0.1, "largest speed {vmax} m/s");
}

/// A water block resting on a fixed body (three rows of particles, density by continuity
/// like the fluid's, the dynamic boundary of Crespo, Gómez-Gesteira & Dalrymple 2007,
/// *CMC* 5(3), 173): the fixed particles end bitwise where they started with zero velocity,
/// the water stays above them, and the per-body totals report the fixed body at rest.
#[test]
fn a_fixed_body_holds_still_under_a_fluid() {
    let scene = load(
        r#"Scene(
    name: "water on a fixed floor",
    dimension: 2,
    domain: (min: [0.0, -0.05], max: [0.3, 0.4]),
    kernel: CubicSpline,
    formulation: DualSupport,
    bodies: [Body(name: "floor", kind: Fixed), Body(name: "water")],
    particles: [
        Block(min: [0.0, -0.03], max: [0.3, 0.0], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "floor"),
        Block(min: [0.0, 0.0], max: [0.3, 0.15], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "water"),
    ],
    plugins: [
        ContinuityDensity(form: Pairwise),
        TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0),
        PressureForce(),
        ArtificialViscosity(alpha: 0.5, beta: 0.0),
        Gravity(g: [0.0, -9.81]),
        SpecularWalls(clearance: 0.25),
    ],
    integrator: (dt: Adaptive(courant: 0.1, force: 0.25, viscous: 0.125)),
    end_time: 0.3,
    output: (snapshot_every: 0),
)"#,
    );
    let first = scene.generate();
    let (dir, s) = run(&scene);
    let last = read_particles(&dir.path().join("final.csv")).unwrap();
    let floor = first.iter().filter(|p| p.body == 0).count();
    assert_eq!(floor, 90);
    let mut top_floor = f64::NEG_INFINITY;
    for (p0, p) in first.iter().zip(last.rows()).filter(|(p0, _)| p0.body == 0) {
        assert_eq!(
            p.pos().map(f64::to_bits),
            p0.pos.map(f64::to_bits),
            "id {}",
            p.id()
        );
        assert_eq!(p.vel(), [0.0; 3]);
        top_floor = top_floor.max(p.pos()[1]);
    }
    let lowest_water = last
        .rows()
        .skip(floor)
        .map(|p| p.pos()[1])
        .fold(1.0, f64::min);
    assert!(
        lowest_water > top_floor,
        "water at {lowest_water}, floor up to {top_floor}"
    );
    let fixed = s.last.per_body[0];
    assert_eq!((fixed.momentum, fixed.e_kin), ([0.0; 3], 0.0));
}

/// A lid of three particle rows on a layer of water at rest, moved by the law
/// `x = x_0 + (0.2 m/s, 0) t` (a prescribed body): at t = 0.1 s every lid particle is at its
/// law's position to round-off with exactly the law's velocity, the lid's momentum is its
/// mass times that velocity, and the water under it has been dragged along by the viscous
/// pair forces — the lid's velocity enters the pair terms like a fluid particle's: almost all
/// of the water's x-momentum is in its upper half (measured 0.330 against 0.004 kg m/s), and
/// the total is 0.74 of Stokes' first problem for a plate of the lid's length.
#[test]
fn a_prescribed_lid_moves_by_its_law_and_drags_the_water() {
    let scene = load(&lid_scene("PhysicalViscosity(mu: 1.0)"));
    let first = scene.generate();
    let (dir, s) = run(&scene);
    let last = read_particles(&dir.path().join("final.csv")).unwrap();
    let lid = first.iter().filter(|p| p.body == 0).count();
    assert_eq!(lid, 60);
    let t = 0.1;
    for (p0, p) in first.iter().zip(last.rows()).take(lid) {
        let want = [p0.pos[0] + 0.2 * t, p0.pos[1]];
        assert!(
            (p.pos()[0] - want[0]).abs() < 1e-12 && p.pos()[1] == want[1],
            "id {}: {:?} vs {want:?}",
            p.id(),
            p.pos()
        );
        assert_eq!(p.vel(), [0.2, 0.0, 0.0], "id {}", p.id());
    }
    let lid_mass: f64 = first.iter().take(lid).map(|p| p.mass).sum();
    let m = s.last.per_body[0].momentum;
    assert!(
        (m[0] - 0.2 * lid_mass).abs() < 1e-12 * lid_mass && m[1] == 0.0,
        "{m:?}"
    );
    let water = last.rows().skip(lid);
    let px = |rows: &mut dyn Iterator<Item = dualsph::io::ParticleRow<'_>>| {
        rows.map(|p| p.mass() * p.vel()[0]).sum::<f64>()
    };
    let upper = px(&mut water.clone().filter(|p| p.pos()[1] > 0.05));
    let lower = px(&mut water.clone().filter(|p| p.pos()[1] <= 0.05));
    // Stokes' first problem (a plate started impulsively at U over fluid of kinematic
    // viscosity ν): u(y, t) = U erfc(y / 2√(νt)), so the fluid's x-momentum per unit plate
    // length is ρ U 2√(νt/π) (Batchelor 1967, *An Introduction to Fluid Dynamics*, §4.3).
    let (rho, u, nu) = (1000.0, 0.2, 1.0 / 1000.0);
    let stokes = rho * u * 2.0 * (nu * t / std::f64::consts::PI).sqrt() * 0.2;
    let ratio = (upper + lower) / stokes;
    eprintln!(
        "water x-momentum: upper half {upper:.3e}, lower half {lower:.3e} kg m/s; \
         {ratio:.3} of Stokes' {stokes:.3e}"
    );
    assert!(
        upper > 0.0 && upper > 10.0 * lower,
        "upper {upper}, lower {lower}"
    );
    // below 1: a lid of finite length (the water past its ends is not driven), a wall whose
    // position is uncertain by Δx/2 against a layer 2√(νt) = 2Δx thick, weak compressibility
    assert!((0.65..0.85).contains(&ratio), "{ratio} of Stokes' solution");
}

/// The lid of [`a_prescribed_lid_moves_by_its_law_and_drags_the_water`] with `viscosity`.
fn lid_scene(viscosity: &str) -> String {
    format!(
        r#"Scene(
    name: "moving lid",
    dimension: 2,
    domain: (min: [0.0, -0.01], max: [0.3, 0.2]),
    kernel: CubicSpline,
    formulation: DualSupport,
    bodies: [Body(name: "lid", kind: Prescribed(Translate(velocity: [0.2, 0.0]))), Body(name: "water")],
    particles: [
        Block(min: [0.0, 0.1], max: [0.2, 0.13], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "lid"),
        Block(min: [0.0, 0.0], max: [0.3, 0.1], spacing: 0.01, lattice: Square,
              density: 1000.0, h_factor: 2.0, body: "water"),
    ],
    plugins: [
        ContinuityDensity(form: Pairwise),
        TaitEos(rho0: 1000.0, gamma: 7.0, c0: 10.0),
        PressureForce(),
        {viscosity},
        SpecularWalls(clearance: 0.25),
    ],
    integrator: (dt: Adaptive(courant: 0.1, force: 0.25, viscous: 0.125)),
    end_time: 0.1,
    output: (snapshot_every: 0),
)"#
    )
}

/// A viscosity given per body, every body the same value as the uniform one, gives bitwise
/// the same run as the uniform viscosity (each pair takes its owner's μ_i or α_i, β_i).
#[test]
fn viscosities_given_per_body_equal_to_the_uniform_one_give_the_same_run() {
    let final_of = |viscosity: &str| {
        let (dir, _) = run(&load(&lid_scene(viscosity)));
        std::fs::read(dir.path().join("final.csv")).unwrap()
    };
    let uniform =
        final_of("PhysicalViscosity(mu: 1.0), ArtificialViscosity(alpha: 0.1, beta: 0.0)");
    let per_body = final_of(
        "PhysicalViscosity(mu: 0.0, materials: [(body: \"lid\", mu: 1.0), (body: \"water\", mu: 1.0)]), \
         ArtificialViscosity(alpha: 0.3, beta: 1.0, materials: [(body: \"lid\", alpha: 0.1, beta: 0.0), \
         (body: \"water\", alpha: 0.1, beta: 0.0)])",
    );
    assert!(uniform == per_body, "the runs differ");
}

/// A kind of body from outside the engine: the lid accelerates uniformly along x,
/// `x(t) = x_0 + a t²/2`, `v = a t` (`Glide(accel: a)`).
#[derive(Debug, serde::Deserialize, serde::Serialize, dualsph::core::schemars::JsonSchema)]
#[schemars(crate = "dualsph::core::schemars")]
#[serde(deny_unknown_fields)]
struct Glide {
    accel: f64,
}

/// The law of [`Glide`].
#[derive(Debug)]
struct GlideLaw(f64);

impl dualsph::core::bodies::BodyMotion for GlideLaw {
    fn at(&self, x0: [f64; 3], t: f64) -> ([f64; 3], [f64; 3]) {
        let a = self.0;
        ([x0[0] + 0.5 * a * t * t, x0[1], x0[2]], [a * t, 0.0, 0.0])
    }
    fn acceleration(&self, _x0: [f64; 3], _t: f64) -> [f64; 3] {
        [self.0, 0.0, 0.0]
    }
}

impl dualsph::core::bodies::BodyKind for Glide {
    const NAME: &'static str = "Glide";
    const SUMMARY: &'static str = "accelerates uniformly along x (a test's own kind)";
    fn motion(&self) -> Option<std::sync::Arc<dyn dualsph::core::bodies::BodyMotion>> {
        Some(std::sync::Arc::new(GlideLaw(self.accel)))
    }
}

/// A body kind registered by the user's crate is named by the scene and drives its body
/// with no edit of the engine: the lid of the tests above, given `Glide(accel: 4.0)`, ends
/// at `x_0 + a t²/2` with `v = a t` at t = 0.1 s, and its load is reported like a built-in
/// kind's.
#[test]
fn a_users_own_body_kind_drives_its_body() {
    let mut registry = dualsph::default_registry();
    registry.register_body_kind::<Glide>();
    let text = lid_scene("PhysicalViscosity(mu: 1.0)").replace(
        "Prescribed(Translate(velocity: [0.2, 0.0]))",
        "Glide(accel: 4.0)",
    );
    let scene = Scene::from_str(&text, Path::new("test.ron"), &registry).unwrap();
    let first = scene.generate();
    let (dir, s) = run(&scene);
    let last = read_particles(&dir.path().join("final.csv")).unwrap();
    let (a, t) = (4.0, 0.1);
    let lid: Vec<_> = first.iter().filter(|p| p.body == 0).collect();
    assert_eq!(lid.len(), 60);
    for (p0, p) in lid.iter().zip(last.rows()) {
        let x = p0.pos[0] + 0.5 * a * t * t;
        assert!(
            (p.pos()[0] - x).abs() < 1e-12,
            "id {}: {:?}",
            p.id(),
            p.pos()
        );
        assert!(
            (p.vel()[0] - a * t).abs() < 1e-12,
            "id {}: {:?}",
            p.id(),
            p.vel()
        );
    }
    let loads: Vec<_> = s.last.loads.iter().map(|l| l.body).collect();
    assert_eq!(loads, [0], "the lid's load is reported");
}
