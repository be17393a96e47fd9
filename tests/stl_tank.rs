//! The 3-D tank with an STL obstacle (`scenes/tank_stl_3d.ron`): at t = 0 the load on the
//! submerged obstacle is the buoyancy of the water it displaces.
//!
//! Which volume: the fluid is the lattice of the water block minus the points the mesh
//! contains, so the hole in it is the union of those points' cells, `V = N Δx³`, not the
//! mesh's volume (the octahedron's 32 cells hold 2.56e-4 m³, the mesh 2.88e-4 m³). The
//! obstacle is filled on the same lattice with the same inside test, so its particles are
//! those N points, each of mass `ρ0 Δx³`.
//!
//! What load: `F_B = Σ_{i∈B} Σ_{j∈fluid} f_ij`, the pairs inside the obstacle cancelling
//! whatever their pressures, so `F_B` is the sum over the obstacle's particles of each one's
//! pressure force `Σ_j f_ij` as if the obstacle's interior carried the field too. With the
//! wall pressure of Adami, Hu & Adams (2012) the particles that meet the fluid take the
//! hydrostatic pressure extrapolated to where they sit, and the pressure force on a particle
//! of mass `m_i` in a fluid at rest is `−m_i ∇p/ρ = m_i |g|` upward (the SPH momentum
//! equation at rest). So `F_B = |g| Σ_{i∈B} m_i = ρ0 |g| N Δx³ = ρ0 |g| V`: Archimedes'
//! weight of the displaced water at the reference density. (At its compressed hydrostatic
//! density, `|g| Σ_i ρ(s_i) Δx³`, it is 0.19 % more, `|g| s / c0²` on average: the obstacle's
//! particles keep the mass `ρ0 Δx³` and stand for the volume `m_i/ρ_i`.) Measured at t = 0:
//! 0.015 % under `ρ0 g V` (0.20 % under the compressed weight); bound 0.05 %. With the
//! obstacle left out of `WallPressure` its particles keep `ρ0`, zero pressure (the dynamic
//! boundary of Crespo et al. 2007 at t = 0), and the same check fails: 21 % under.

mod common;

use dualsph::scene::Scene;
use std::path::Path;

const RHO0: f64 = 1000.0;
const G: f64 = 9.81;
const DX: f64 = 0.02;
const SURFACE: f64 = 0.24;

/// The scene, with `WallPressure` on every fixed body or on the tank only, for one step.
fn tank(obstacle_pressure: bool) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/tank_stl_3d.ron");
    let mut text = std::fs::read_to_string(&path).unwrap();
    if !obstacle_pressure {
        assert!(text.contains("WallPressure(),"));
        text = text.replacen("WallPressure(),", "WallPressure(bodies: [\"tank\"]),", 1);
    }
    let mut scene = Scene::from_str(&text, &path, &dualsph::default_registry()).unwrap();
    scene.max_steps = Some(1);
    scene.output.diagnostics_every = 1;
    scene
}

/// Tait's density at depth `s` in a hydrostatic column (c0 = 25 m/s, γ = 7):
/// `ρ = ρ0 (1 + p/p0)^{1/γ}` with `p(s) = p0 [(1 + ((γ − 1)/γ) ρ0 g s / p0)^{γ/(γ−1)} − 1]`.
fn rho_at_depth(s: f64) -> f64 {
    let (gamma, c0) = (7.0, 25.0);
    let p0 = c0 * c0 * RHO0 / gamma;
    let p =
        p0 * ((1.0 + (gamma - 1.0) / gamma * RHO0 * G * s / p0).powf(gamma / (gamma - 1.0)) - 1.0);
    RHO0 * (1.0 + p / p0).powf(1.0 / gamma)
}

/// `(fz, fx, fy)` on the obstacle in the first diagnostics row (t = 0).
fn first_load(scene: &Scene) -> [f64; 3] {
    let (dir, _) = common::run_on_threads(scene, 1);
    let (header, rows) =
        dualsph::io::read_diagnostics_csv(&dir.path().join("diagnostics.csv")).unwrap();
    let col = |name: &str| {
        let k = header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{name}"));
        rows[0][k]
    };
    assert_eq!(col("t"), 0.0);
    [
        col("fz[obstacle]"),
        col("fx[obstacle]"),
        col("fy[obstacle]"),
    ]
}

#[test]
fn the_load_on_a_submerged_stl_obstacle_is_its_buoyancy() {
    let scene = tank(true);
    let particles = scene.generate();
    let obstacle: Vec<_> = particles.iter().filter(|p| p.generator == 2).collect();
    let water = particles.iter().filter(|p| p.generator == 0).count();
    // the obstacle's particles are the water lattice points the mesh removed
    assert_eq!(obstacle.len(), 32);
    assert_eq!(water + obstacle.len(), 12 * 12 * 12);
    let volume = obstacle.len() as f64 * DX.powi(3);
    let buoyancy = RHO0 * G * volume;
    let compressed: f64 = obstacle
        .iter()
        .map(|p| G * rho_at_depth(SURFACE - p.pos[2]) * DX.powi(3))
        .sum();
    eprintln!(
        "V = N dx^3 = {volume:.3e} m^3, rho0 g V = {buoyancy:.4} N, at the hydrostatic \
         density {compressed:.4} N"
    );
    let [fz, fx, fy] = first_load(&scene);
    let error = fz / buoyancy - 1.0;
    eprintln!(
        "load at t = 0: fz = {fz:.4} N ({:+.3} % of rho0 g V), fx = {fx:.2e}, fy = {fy:.2e}",
        100.0 * error
    );
    eprintln!(
        "  against the weight at the hydrostatic density: {:+.2} %",
        100.0 * (fz / compressed - 1.0)
    );
    assert!(error.abs() < 5e-4, "{fz} N vs {buoyancy} N");
    // the octahedron and the tank are symmetric about the vertical axis: no sideways load
    // beyond round-off (measured 9e-16 of the buoyancy)
    assert!(fx.abs().max(fy.abs()) < 1e-12 * buoyancy, "{fx}, {fy}");

    // without the wall pressure on it the obstacle's particles carry no pressure
    let [fz_dynamic, ..] = first_load(&tank(false));
    let error_dynamic = fz_dynamic / buoyancy - 1.0;
    eprintln!(
        "without WallPressure on the obstacle: fz = {fz_dynamic:.4} N ({:+.1} % of rho0 g V)",
        100.0 * error_dynamic
    );
    assert!(error_dynamic.abs() > 0.1, "{fz_dynamic} N vs {buoyancy} N");
}
