//! The `File` generator: particles from a particle CSV keep every value bit for bit; a
//! missing file, a bad value and a particle overlapping another generator's are
//! refused naming the field (and the particle's line).

use super::shapes::scene;
use super::*;

const HEADER: &str = "id,x,y,z,vx,vy,vz,m,rho,p,h\n";

/// `text` loaded from a directory holding `particles.csv` with `rows` (after the header).
fn with_rows(text: &str, rows: &str) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("particles.csv"), format!("{HEADER}{rows}")).unwrap();
    Scene::from_str(text, &dir.path().join("scene.ron"), &registry())
}

fn invalid_with(text: &str, rows: &str) -> (String, String) {
    match with_rows(text, rows) {
        Err(SceneError::Invalid { field, message, .. }) => (field, message),
        other => panic!("expected a validation error, got {other:?}"),
    }
}

fn one(path: &str) -> String {
    scene(
        2,
        "(min: [0.0, 0.0], max: [1.0, 1.0])",
        "",
        &[&format!("File(path: {path:?})")],
    )
}

const ROWS: &str = "0,0.1,0.2,0,0.5,-1e-7,0,0.1,1000.0000000000001,0,0.02\n\
                    1,0.11,0.2,0,0,0,0,0.1,999.5,3.25,0.021\n\
                    2,0.1,0.21,0,0,0.1,0,0.12,1001,0,0.02\n";

#[test]
fn particles_from_a_file_keep_their_values_bitwise() {
    let specs = with_rows(&one("particles.csv"), ROWS).unwrap().generate();
    assert_eq!(specs.len(), 3);
    assert_eq!(specs[0].pos, [0.1, 0.2, 0.0]);
    assert_eq!(specs[0].vel, [0.5, -1e-7, 0.0]);
    assert_eq!(specs[0].density.to_bits(), 1000.0000000000001f64.to_bits());
    assert_eq!((specs[1].mass, specs[1].h), (0.1, 0.021));
    assert_eq!((specs[2].mass, specs[2].density), (0.12, 1001.0));
    assert!(
        specs
            .iter()
            .all(|s| s.internal_energy == 0.0 && s.generator == 0)
    );
}

#[test]
fn bad_particle_files_are_refused_naming_the_field_and_line() {
    let text = one("particles.csv");
    let (field, m) = invalid_with(
        &text,
        "0,0.1,0.2,0,0,0,0,0.1,1000,0,0.02\n1,0.2,0.2,0,0,0,0,-0.1,1000,0,0.02\n",
    );
    assert_eq!(field, "particles[0].path");
    assert!(
        m.contains("`particles.csv`, line 3 (particle id 1): `m` must be a finite number > 0"),
        "{m}"
    );
    let (_, m) = invalid_with(&text, "0,0.1,0.2,0.3,0,0,0,0.1,1000,0,0.02\n");
    assert!(
        m.contains("component 2 of the position or velocity is not 0 in a 2-D scene"),
        "{m}"
    );
    let (field, m) = invalid_with(&text, "0,0.1,abc,0,0,0,0,0.1,1000,0,0.02\n");
    assert_eq!(field, "particles[0].path");
    assert!(m.contains("line 2") && m.contains("`y`"), "{m}");
    let (_, m) = invalid_with(&text, "");
    assert!(m.contains("holds no particles"), "{m}");
    let (field, m) = invalid_with(&one("missing.csv"), ROWS);
    assert_eq!(field, "particles[0].path");
    assert!(
        m.contains("cannot read particles") && m.contains("missing.csv"),
        "{m}"
    );
    // a .vtp is read as VTK, whatever it holds
    let (_, m) = invalid_with(&one("particles.vtp"), ROWS);
    assert!(
        m.contains("cannot read particles") && m.contains("particles.vtp"),
        "{m}"
    );
    // a block whose first point is the first particle of the file
    let both = scene(
        2,
        "(min: [0.0, 0.0], max: [1.0, 1.0])",
        "",
        &[
            "File(path: \"particles.csv\")",
            "Block(min: [0.09, 0.19], max: [0.29, 0.39], spacing: 0.02, lattice: Square, \
             density: 1000.0, h_factor: 2.0)",
        ],
    );
    let (_, m) = invalid_with(&both, ROWS);
    assert!(
        m.contains("particles[0]") && m.contains("particles[1]"),
        "{m}"
    );
}

#[test]
fn an_internal_energy_below_zero_as_a_run_writes_it_is_read_back() {
    // round-off below zero, and the heat account of a liquid that gave energy back
    let header = "id,x,y,z,vx,vy,vz,m,rho,p,h,e\n";
    let rows =
        "0,0.1,0.2,0,0,0,0,0.1,1000,0,0.02,-1.8e-8\n1,0.2,0.2,0,0,0,0,0.1,1000,0,0.02,-0.07\n";
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("particles.csv"), format!("{header}{rows}")).unwrap();
    let s = Scene::from_str(
        &one("particles.csv"),
        &dir.path().join("s.ron"),
        &registry(),
    );
    let e: Vec<f64> = s
        .unwrap()
        .generate()
        .iter()
        .map(|p| p.internal_energy)
        .collect();
    assert_eq!(e, [-1.8e-8, -0.07]);
    std::fs::write(
        dir.path().join("particles.csv"),
        format!("{header}{}", rows.replace("-0.07", "NaN")),
    )
    .unwrap();
    let e = Scene::from_str(
        &one("particles.csv"),
        &dir.path().join("s.ron"),
        &registry(),
    );
    assert!(
        e.unwrap_err()
            .to_string()
            .contains("`e` must be a finite number")
    );
}

#[test]
fn coincident_particles_in_a_file_are_refused_and_close_ones_are_not() {
    let text = one("particles.csv");
    let twice = format!("{ROWS}{}", ROWS.replace("0,0.1,0.2,", "3,0.1,0.2,"));
    let (field, m) = invalid_with(&text, &twice);
    assert_eq!(field, "particles[0].path");
    assert!(
        m.contains("particles 1 and 4 of the file") && m.contains("same place"),
        "{m}"
    );
    // a pair a tenth of a spacing apart, as an impact may leave it, is a state, not an error
    let close = "0,0.1,0.2,0,0,0,0,0.1,1000,0,0.02\n1,0.101,0.2,0,0,0,0,0.1,1000,0,0.02\n";
    assert!(with_rows(&text, close).is_ok());
}
