//! Particles through a periodic face are neighbours: two that come closer than half the
//! smaller spacing through a face (or a corner where two periodic faces meet) are refused,
//! naming the generators.

use super::shapes::scene;
use super::*;

fn periodic(particles: &[&str], axes: &str) -> String {
    scene(
        2,
        &format!("(min: [0.0, 0.0], max: [1.0, 1.0], periodic: {axes})"),
        "",
        particles,
    )
}

fn block(min: &str, max: &str, spacing: f64) -> String {
    format!(
        "Block(min: {min}, max: {max}, spacing: {spacing}, lattice: Square, density: 1000.0, \
         h_factor: 2.0)"
    )
}

fn refusal(text: &str) -> (String, String) {
    match load(text) {
        Err(SceneError::Invalid { field, message, .. }) => (field, message),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn lattices_that_fill_the_period_evenly_pass() {
    let b = block("[0.0, 0.0]", "[1.0, 0.5]", 0.1);
    assert!(load(&periodic(&[&b], "[true, true]")).is_ok());
    let two = [
        block("[0.0, 0.0]", "[0.5, 1.0]", 0.1),
        block("[0.5, 0.0]", "[1.0, 1.0]", 0.05),
    ];
    assert!(load(&periodic(&[&two[0], &two[1]], "[true, true]")).is_ok());
}

#[test]
fn rows_that_meet_through_a_periodic_face_are_refused() {
    // x = 0.01 … 0.41 and 0.57 … 0.97: 0.04 apart through the face x = 0 ≡ 1
    let a = block("[-0.04, 0.0]", "[0.46, 0.5]", 0.1);
    let b = block("[0.52, 0.0]", "[1.02, 0.5]", 0.1);
    let (field, m) = refusal(&periodic(&[&a, &b], "[true, false]"));
    assert_eq!(field, "particles[1]");
    assert!(
        m.contains("particles[1] comes too close to particles[0] through a periodic face"),
        "{m}"
    );
    assert!(m.contains("0.040000"), "{m}");
    // the same generators without the periodic axis are 0.16 apart
    assert!(load(&periodic(&[&a, &b], "[false, false]")).is_ok());
}

#[test]
fn particles_that_meet_through_a_periodic_corner_are_refused() {
    // (0.002, 0.002) and (0.997, 0.997): 0.005 apart on each axis through the corner only
    let a = block("[-0.008, -0.008]", "[0.012, 0.012]", 0.02);
    let b = block("[0.987, 0.987]", "[1.007, 1.007]", 0.02);
    let (_, m) = refusal(&periodic(&[&a, &b], "[true, true]"));
    assert!(m.contains("through a periodic face"), "{m}");
    assert!(load(&periodic(&[&a, &b], "[true, false]")).is_ok());
}
