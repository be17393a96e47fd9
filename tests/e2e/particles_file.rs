//! `File(path: ..)`: a run's `final.csv`, or its last snapshot as `.vtp`, read as the
//! particles of a new scene, starts that scene with every particle's position, velocity,
//! mass, density, h and internal energy bit for bit as written, and with the file's value of
//! every other registered column it holds (here the dissipated energy, `e_diss` in the CSV,
//! `dissipated` in the `.vtp`); its first snapshot writes them back unchanged. (The pressure is
//! not state: the file's is the one of the last force evaluation, at the corrector's
//! predicted density; the new run computes it from the density read.)

use crate::common;

use dualsph::io::{ParticleRow, read_particles};
use dualsph::scene::Scene;
use std::path::Path;

/// Water stretched along x and squeezed along y, falling in a box for `steps` steps
/// (continuity density, so the density is state), its particles given by `particles`; a
/// snapshot at every step.
fn scene(particles: &str, steps: u64, dir: &Path) -> Scene {
    let text = format!(
        r#"Scene(
    name: "falling water",
    dimension: 2,
    domain: (min: [0.0, 0.0], max: [0.4, 0.4]),
    kernel: CubicSpline,
    formulation: DualSupport,
    particles: [{particles}],
    plugins: [
        ContinuityDensity(),
        TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0),
        PressureForce(),
        ArtificialViscosity(alpha: 0.1, beta: 0.0, dissipation: true),
        Gravity(g: [0.0, -9.81]),
        SpecularWalls(clearance: 0.25),
    ],
    integrator: (dt: Fixed(1e-4)),
    end_time: {end},
    output: (diagnostics_every: 1, snapshot_every: 1, formats: [Csv, Vtk],
             vtk_encoding: Compressed),
)"#,
        end = steps as f64 * 1e-4
    );
    Scene::from_str(&text, &dir.join("scene.ron"), &dualsph::default_registry())
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The fields a particle file carries, as bits.
fn bits(r: &ParticleRow) -> Vec<u64> {
    let mut v: Vec<f64> = r.pos().iter().chain(&r.vel()).copied().collect();
    v.extend([r.mass(), r.rho(), r.h(), r.e()]);
    v.into_iter().map(f64::to_bits).collect()
}

#[test]
fn a_final_csv_read_as_particles_starts_a_scene_bitwise() {
    let block = "Block(min: [0.05, 0.05], max: [0.25, 0.2], spacing: 0.01, lattice: Staggered, \
                 density: 1000.0, h_factor: 2.0, velocity: Linear([[0.5, 0.0], [0.0, -1.0]]))";
    let first = tempfile::tempdir().unwrap();
    let (out, _) = common::run_on_threads(&scene(block, 30, first.path()), 1);
    let written = read_particles(&out.path().join("final.csv")).unwrap();
    let dissipated = e_diss(&out.path().join("final.csv"));
    // the particles moved, at different densities, and the viscosity heated them
    assert!(
        written
            .rows()
            .any(|r| r.vel()[1] < -1e-3 && r.rho() != 1000.0)
    );
    assert!(written.rows().any(|r| r.e() > 0.0) && dissipated.iter().any(|&d| d > 0.0));

    // the file next to the new scene, read relative to its directory
    std::fs::copy(out.path().join("final.csv"), first.path().join("end.csv")).unwrap();
    let vtp = out.path().join("particles_000030.vtp");
    std::fs::copy(vtp, first.path().join("end.vtp")).unwrap();
    for file in ["end.csv", "end.vtp"] {
        let next = scene(&format!("File(path: {file:?})"), 1, first.path());
        let specs = next.generate();
        assert_eq!(specs.len(), written.len());
        for (s, r) in specs.iter().zip(written.rows()) {
            let mut spec: Vec<f64> = s.pos.iter().chain(&s.vel).copied().collect();
            spec.extend([s.mass, s.density, s.h, s.internal_energy]);
            let spec: Vec<u64> = spec.into_iter().map(f64::to_bits).collect();
            assert_eq!(spec, bits(&r), "{file}: particle {}", r.id());
        }
        // the run's snapshot at step 0 holds them unchanged
        let (again, _) = common::run_on_threads(&next, 1);
        let start = read_particles(&again.path().join("particles_000000.csv")).unwrap();
        assert_eq!(start.len(), written.len());
        for (a, b) in start.rows().zip(written.rows()) {
            assert_eq!(a.id(), b.id());
            assert_eq!(bits(&a), bits(&b), "{file}: particle {}", a.id());
        }
        let again = e_diss(&again.path().join("particles_000000.csv"));
        let same = again
            .iter()
            .zip(&dissipated)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "{file}: the dissipated energy");
    }
}

/// The `e_diss` column of a particle CSV.
fn e_diss(path: &Path) -> Vec<f64> {
    let table = dualsph::io::read_particle_table_csv(path).unwrap();
    table.column("e_diss").unwrap().values.clone()
}
