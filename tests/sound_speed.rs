//! `check` and `run` warn when a liquid's c0 is below ten times the speed its scene implies
//! (a column of height H falls at √(2 g H)); they stay quiet where c0 is enough, and where
//! gravity drives a flow along a periodic axis instead of a fall.

use std::process::Command;

fn check(scene: &str) -> (bool, String) {
    let (code, err) = check_code(scene);
    (code == Some(0), err)
}

/// A column 0.5 m tall (particle centres 0.0125 … 0.4875: H = 0.475 m) in a box `width` wide.
fn column(c0: f64, g: &str, periodic: &str, width: f64) -> String {
    format!(
        "Scene(name: \"column\", dimension: 2,
           domain: (min: [0.0, 0.0], max: [{width}, 1.0], periodic: {periodic}), kernel: WendlandC2,
           particles: [Block(min: [0.0, 0.0], max: [0.5, 0.5], spacing: 0.025, lattice: Square,
                             density: 1000.0, h_factor: 3.0)],
           plugins: [Gravity(g: {g}), TaitEos(rho0: 1000.0, gamma: 7.0, c0: {c0}),
                     PressureForce(), SpecularWalls()],
           integrator: (dt: Adaptive(courant: 0.2)), end_time: 0.1)"
    )
}

#[test]
fn a_sound_speed_below_ten_times_the_fall_speed_is_warned_of() {
    // √(2 g H) = √(2 · 9.81 · 0.475) = 3.053 m/s
    // a dam break: the column stands at the left of a box twice its width
    let (ok, err) = check(&column(20.0, "[0.0, -9.81]", "[false, false]", 1.0));
    assert!(ok, "a warning does not refuse: {err}");
    assert!(
        err.contains("warning:") && err.contains("c0 = 20 m/s") && err.contains("3.053"),
        "{err}"
    );
    assert!(err.contains("c0 ≥ 30.6 m/s"), "{err}");
    let (ok, err) = check(&column(31.0, "[0.0, -9.81]", "[false, false]", 1.0));
    assert!(ok && !err.contains("warning"), "{err}");
}

#[test]
fn a_tank_at_rest_does_not_fall() {
    // the same water filling its box's width: a level surface, nothing to fall
    let (ok, err) = check(&column(20.0, "[0.0, -9.81]", "[false, false]", 0.5));
    assert!(ok && !err.contains("warning"), "{err}");
    // but a particle thrown upwards at 3 m/s needs c0 ≥ 30
    let thrown = column(20.0, "[0.0, -9.81]", "[false, false]", 0.5).replace(
        "h_factor: 3.0)",
        "h_factor: 3.0, velocity: Uniform([0.0, 3.0]))",
    );
    let (ok, err) = check(&thrown);
    assert!(
        ok && err.contains("the fastest initial fluid particle"),
        "{err}"
    );
}

#[test]
fn gravity_along_a_periodic_axis_is_a_driven_flow_not_a_fall() {
    let (ok, err) = check(&column(20.0, "[9.81, 0.0]", "[true, false]", 1.0));
    assert!(ok && !err.contains("warning"), "{err}");
}

/// The exit status and standard error of `dualsph check` on `scene`.
fn check_code(scene: &str) -> (Option<i32>, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("column.ron");
    std::fs::write(&path, scene).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_dualsph"))
        .arg("check")
        .arg(&path)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn auto_derives_c0_from_the_fall_and_says_so() {
    // c0 = 12 √(2 g H), H = 0.475 m: 36.6382 m/s
    let expected = 12.0 * (2.0f64 * 9.81 * 0.475).sqrt();
    let (ok, err) = check(&column_auto(
        "Auto(factor: 12.0)",
        "Gravity(g: [0.0, -9.81]), ",
        "",
    ));
    assert!(ok, "{err}");
    assert!(err.contains("note: "), "{err}");
    assert!(
        err.contains(&format!("TaitEos.c0 = {expected:.4} m/s: Auto(factor: 12)")),
        "{err}"
    );
    assert!(!err.contains("warning"), "{err}");
    // the default factor is 10; below 10 the Mach check still warns
    let (_, err) = check(&column_auto("Auto", "Gravity(g: [0.0, -9.81]), ", ""));
    assert!(
        err.contains(&format!("c0 = {:.4} m/s", expected / 1.2)),
        "{err}"
    );
    let (ok, err) = check(&column_auto(
        "Auto(factor: 5.0)",
        "Gravity(g: [0.0, -9.81]), ",
        "",
    ));
    assert!(
        ok && err.contains("warning:") && err.contains("Mach number reaches 0.20"),
        "{err}"
    );
}

#[test]
fn auto_counts_an_inlet_and_refuses_gravity_or_an_inlet_listed_after_it() {
    let inlet = "Inlet(min: [0.9, 0.0], max: [0.95, 0.2], spacing: 0.025, velocity: [-8.0, 0.0], \
                 density: 1000.0, h_factor: 3.0, until: 0.01), ";
    let (ok, err) = check(&column_auto("Auto", "Gravity(g: [0.0, -9.81]), ", inlet));
    assert!(ok, "{err}");
    assert!(
        err.contains("TaitEos.c0 = 80.0000 m/s: Auto(factor: 10) × 8.0000 m/s, Inlet"),
        "{err}"
    );
    let late_gravity = column_auto("Auto", "", inlet).replace(
        "PressureForce(),",
        "PressureForce(), Gravity(g: [0.0, -9.81]),",
    );
    let (code, err) = check_code(&late_gravity);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("Gravity: list it before TaitEos, whose c0: Auto(..) is derived"),
        "{err}"
    );
    let late_inlet = column_auto("Auto", "Gravity(g: [0.0, -9.81]), ", "")
        .replace("PressureForce(),", &format!("PressureForce(), {inlet}"));
    let (code, err) = check_code(&late_inlet);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("Inlet (its velocity): list it before TaitEos"),
        "{err}"
    );
    // nothing moves and nothing falls: no speed to derive c0 from
    let (code, err) = check_code(&column_auto("Auto", "", ""));
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("TaitEos.c0: Auto(..) finds no speed in the scene"),
        "{err}"
    );
}

/// [`column`]'s dam break with `c0` as given and `before` listed before the equation of state.
fn column_auto(c0: &str, gravity: &str, inlet: &str) -> String {
    format!(
        "Scene(name: \"column\", dimension: 2,
           domain: (min: [0.0, 0.0], max: [1.0, 1.0]), kernel: WendlandC2,
           particles: [Block(min: [0.0, 0.0], max: [0.5, 0.5], spacing: 0.025, lattice: Square,
                             density: 1000.0, h_factor: 3.0)],
           plugins: [{gravity}{inlet}TaitEos(rho0: 1000.0, gamma: 7.0, c0: {c0}),
                     PressureForce(), SpecularWalls()],
           end_time: 0.1)"
    )
}
