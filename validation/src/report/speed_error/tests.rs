//! Unit tests of the speed-against-error report: plot file names, and the CPU time at an error
//! interpolated on the uniform runs.

use super::*;

fn point(cpu: f64, error: f64) -> Point {
    Point {
        variant: "u".into(),
        factor: 1.0,
        particles: 1,
        particles_end: 1,
        steps: 1,
        cpu_seconds: cpu,
        error,
        failure: None,
    }
}

#[test]
fn file_stems_are_the_names_words() {
    assert_eq!(
        file_stem("Dam break, walls of particles"),
        "dam_break_walls_of_particles"
    );
    assert_eq!(file_stem("Sod shock tube"), "sod_shock_tube");
    assert_eq!(
        file_stem("Buchner's wall pressure"),
        "buchners_wall_pressure"
    );
}

/// error ∝ cpu^(−1/2): the interpolation is exact on a power law.
#[test]
fn cpu_at_error_is_exact_on_a_power_law() {
    let runs: Vec<Point> = [1.0, 4.0, 16.0].map(|c| point(c, 0.1 / c.sqrt())).into();
    let refs: Vec<&Point> = runs.iter().collect();
    let cpu = cpu_at_error(&refs, 0.1 / 8.0f64.sqrt()).unwrap();
    assert!((cpu - 8.0).abs() < 1e-12, "{cpu}");
    assert!(
        cpu_at_error(&refs, 0.2).is_none(),
        "above the coarsest run's error"
    );
    assert!(
        cpu_at_error(&refs, 0.001).is_none(),
        "below the finest run's error"
    );
}
