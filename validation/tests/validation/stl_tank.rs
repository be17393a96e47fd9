//! The 3-D tank with an STL obstacle (`scenes/tank_stl_3d.ron`): at t = 0 the load on the
//! submerged obstacle is the buoyancy of the water it displaces.
//!
//! The displaced volume `V = N Δx³`, the load and why it equals `ρ0 |g| V` with the wall
//! pressure of Adami, Hu & Adams (2012) are derived in the report's section, whose measure
//! this test asserts on (`dualsph_validation::report::walls::stl_tank`). Measured at t = 0: 0.015 %
//! under `ρ0 g V` (0.20 % under the weight at the hydrostatic density); bound 0.05 %. With
//! the obstacle left out of `WallPressure` its particles keep `ρ0`, zero pressure (the
//! dynamic boundary of Crespo et al. 2007 at t = 0), and the same check fails: 21 % under.

use crate::common;

use dualsph_validation::report::walls::stl_tank::{
    DYNAMIC_OFF, LOAD_BOUND, OBSTACLE, SIDEWAYS, cases, dynamic_is_off, run_cases,
};

#[test]
fn the_load_on_a_submerged_stl_obstacle_is_its_buoyancy() {
    let opts = common::report_options(1.0, None);
    // the obstacle's particles are the water lattice points the mesh removed
    let particles = cases(&opts, Some(1)).unwrap()[0].scene.generate();
    let obstacle = particles.iter().filter(|p| p.body as usize == OBSTACLE);
    let water = particles.iter().filter(|p| p.body == 0).count();
    assert_eq!(obstacle.clone().count(), 32);
    assert!(obstacle.clone().all(|p| p.generator == 2));
    assert_eq!(water + 32, 12 * 12 * 12);

    // one step each: the load at t = 0 is the first diagnostics row's
    let graded = run_cases(&opts, Some(1)).unwrap();
    let (adami, dynamic) = (&graded[0], &graded[1]);
    let d = adami.displaced;
    eprintln!(
        "V = N dx^3 = {:.3e} m^3, rho0 g V = {:.4} N, at the hydrostatic density {:.4} N",
        d.volume, d.buoyancy, d.compressed
    );
    assert_eq!(d.particles, 32);
    assert_eq!(adami.run.diagnostics[0].t, 0.0);
    let [fx, fy, fz] = adami.load;
    eprintln!(
        "load at t = 0: fz = {fz:.4} N ({:+.3} % of rho0 g V), fx = {fx:.2e}, fy = {fy:.2e}",
        100.0 * adami.error()
    );
    eprintln!(
        "  against the weight at the hydrostatic density: {:+.2} %",
        100.0 * adami.error_compressed()
    );
    assert!(
        adami.error().abs() < LOAD_BOUND,
        "{fz} N vs {} N",
        d.buoyancy
    );
    // the octahedron and the tank are symmetric about the vertical axis: no sideways load
    // beyond round-off (measured 9e-16 of the buoyancy)
    assert!(adami.sideways() < SIDEWAYS, "{fx}, {fy}");
    assert!(adami.within_bounds());

    // without the wall pressure on it the obstacle's particles carry no pressure
    eprintln!(
        "without WallPressure on the obstacle: fz = {:.4} N ({:+.1} % of rho0 g V)",
        dynamic.load[2],
        100.0 * dynamic.error()
    );
    assert!(
        dynamic_is_off(dynamic),
        "{} N vs {} N: not more than {DYNAMIC_OFF} off",
        dynamic.load[2],
        d.buoyancy
    );
}
