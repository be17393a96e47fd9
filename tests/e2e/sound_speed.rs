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
fn auto_counts_an_inlet_and_gravity_wherever_they_are_listed() {
    let inlet = "Inlet(min: [0.9, 0.0], max: [0.95, 0.2], spacing: 0.025, velocity: [-8.0, 0.0], \
                 density: 1000.0, h_factor: 3.0, until: 0.01), ";
    let derived = "TaitEos.c0 = 80.0000 m/s: Auto(factor: 10) × 8.0000 m/s, Inlet";
    let (ok, err) = check(&column_auto("Auto", "Gravity(g: [0.0, -9.81]), ", inlet));
    assert!(ok, "{err}");
    assert!(err.contains(derived), "{err}");
    // gravity and the inlet listed after the equation of state count all the same
    let late = column_auto("Auto", "", "").replace(
        "PressureForce(),",
        &format!("PressureForce(), Gravity(g: [0.0, -9.81]), {inlet}"),
    );
    let (ok, err) = check(&late);
    assert!(ok, "{err}");
    assert!(err.contains(derived), "{err}");
    let late_gravity = column_auto("Auto(factor: 12.0)", "", "").replace(
        "PressureForce(),",
        "PressureForce(), Gravity(g: [0.0, -9.81]),",
    );
    let (ok, err) = check(&late_gravity);
    let expected = 12.0 * (2.0f64 * 9.81 * 0.475).sqrt();
    assert!(
        ok && err.contains(&format!("TaitEos.c0 = {expected:.4} m/s")),
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

/// `dualsph check` of a shipped scene with `--set`s: exit status and standard error.
fn check_shipped(scene: &str, sets: &[&str]) -> (Option<i32>, String) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(scene);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_dualsph"));
    cmd.arg("check").arg(&path);
    for s in sets {
        cmd.arg("--set").arg(s);
    }
    let out = cmd.output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The fall height `H` in a note `… H = 0.5925 m …`.
fn fall_in(note: &str) -> f64 {
    let at = note
        .find("H = ")
        .unwrap_or_else(|| panic!("no fall height: {note}"));
    let rest = &note[at + 4..];
    rest[..rest.find(' ').unwrap()].parse().unwrap()
}

#[test]
fn auto_finds_the_fall_of_a_column_in_a_closed_tank_of_particle_walls() {
    // Buchner's column (H = 0.6 m, Δx = 0.015 m: particle centres 0.0075 … 0.5925) in a tank
    // whose lid of wall particles spans the whole floor; gravity is listed after TaitEos
    let (code, err) = check_shipped("scenes/dam_break_buchner_2d.ron", &["TaitEos.c0=Auto"]);
    assert_eq!(code, Some(0), "{err}");
    let h = fall_in(&err);
    assert!((h - 0.585).abs() < 0.0151, "H = {h}: {err}");
    // the paper's column (2 m, Δx = 0.025 m) in its closed 4 m × 3 m tank
    let (code, err) = check_shipped("scenes/dam_break_2d_walls.ron", &["TaitEos.c0=Auto"]);
    assert_eq!(code, Some(0), "{err}");
    let h = fall_in(&err);
    assert!((h - 1.975).abs() < 0.026, "H = {h}: {err}");
}

#[test]
fn a_low_sound_speed_is_warned_of_in_a_tank_of_particle_walls() {
    // √(2 g H) with H ≈ 1.95 m is 6.2 m/s: c0 = 30 is below ten times it
    let (code, err) = check_shipped("scenes/dam_break_2d_walls.ron", &["TaitEos.c0=30.0"]);
    assert_eq!(code, Some(0), "a warning does not refuse: {err}");
    assert!(
        err.contains("warning:") && err.contains("c0 = 30 m/s") && err.contains("fall"),
        "{err}"
    );
    // the shipped c0 = 100 m/s is enough
    let (code, err) = check_shipped("scenes/dam_break_2d_walls.ron", &[]);
    assert!(code == Some(0) && !err.contains("warning"), "{err}");
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
