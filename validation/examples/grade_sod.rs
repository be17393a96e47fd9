//! Runs Sod shock-tube scenes and grades them against the exact solution: `cargo run
//! --release -p dualsph-validation --example grade_sod -- SCENE[:FACTOR]...` (each SCENE a
//! variant of `scenes/sod_1d.ron`, FACTOR the spacing multiplier, default 1). Prints the
//! particles at the end, the steps, the stepping loop's CPU seconds and the L1 errors of
//! density, velocity, pressure and internal energy on [−0.5, 0.5].
use dualsph_validation::report::{CaseSpec, Recording, coarsen, run_case, sod};

fn main() {
    for arg in std::env::args().skip(1) {
        let (path, factor) = match arg.rsplit_once(':') {
            Some((p, f)) => (p.to_string(), f.parse().expect("FACTOR: a number")),
            None => (arg.clone(), 1.0),
        };
        let text = std::fs::read_to_string(&path).expect("a readable scene");
        let mut scene = dualsph_scene::Scene::from_str(
            &text,
            std::path::Path::new(&path),
            &dualsph::default_registry(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        if factor != 1.0 {
            coarsen(&mut scene, factor);
        }
        let spec = CaseSpec::new(&path, scene, None);
        let rec = Recording {
            every: 10,
            ..Default::default()
        };
        let run = run_case(&spec, &rec).unwrap_or_else(|e| panic!("{e}"));
        if let Some(why) = &run.failure {
            println!("{arg}: failed: {why}");
            continue;
        }
        let g = sod::grade(run);
        println!(
            "{arg}: {} particles, {} steps, {:.2} CPU-s, L1 rho {:.3e} u {:.3e} p {:.3e} e {:.3e}",
            g.run.particles, g.run.steps, g.run.cpu_seconds, g.l1[0], g.l1[1], g.l1[2], g.l1[3]
        );
    }
}
