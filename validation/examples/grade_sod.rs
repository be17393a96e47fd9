//! Runs Sod shock-tube scenes and grades them against the exact solution: `cargo run
//! --release -p dualsph-validation --example grade_sod -- SCENE[:FACTOR]...` (each SCENE a
//! variant of `scenes/sod_1d.ron`, FACTOR the spacing multiplier, default 1). Prints the
//! particles at the start and at the end, the steps, the stepping loop's CPU seconds and the
//! L1 errors of density, velocity, pressure and internal energy on [−0.5, 0.5], then the
//! density error by zone: the constant states, the rarefaction, the plateaus on either side
//! of the contact, and the contact and the shock (the zones of `sod::wave_windows`, each wave
//! ± 0.05).
use dualsph_validation::report::sod::{self, wave_windows};
use dualsph_validation::report::{CaseSpec, Recording, coarsen, run_case};

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
            "{arg}: {} → {} particles, {} steps, {:.2} CPU-s, L1 rho {:.3e} u {:.3e} p {:.3e} e {:.3e}",
            g.run.particles,
            g.run.last.len(),
            g.run.steps,
            g.run.cpu_seconds,
            g.l1[0],
            g.l1[1],
            g.l1[2],
            g.l1[3]
        );
        let zones = zone_errors(&g.run);
        let names = ZONES.iter().zip(zones).map(|(n, e)| format!("{n} {e:.2e}"));
        println!(
            "  density L1 by zone: {}",
            names.collect::<Vec<_>>().join(", ")
        );
    }
}

const ZONES: [&str; 7] = [
    "left state",
    "rarefaction",
    "left plateau",
    "contact",
    "right plateau",
    "shock",
    "right state",
];

/// The density L1 error on [−0.5, 0.5] at the end, split by the zone each particle is in.
fn zone_errors(run: &dualsph_validation::report::CaseRun) -> [f64; 7] {
    let r = sod::exact();
    let t = run.final_diagnostics().t;
    let [fan, contact, shock] = wave_windows(&r, t);
    let edges = [fan.0, fan.1, contact.0, contact.1, shock.0, shock.1];
    let mut out = [0.0; 7];
    for p in run.last.rows().filter(|p| p.pos()[0].abs() <= sod::WINDOW) {
        let x = p.pos()[0];
        let zone = edges.iter().filter(|&&e| x >= e).count();
        out[zone] += p.mass() / p.rho() * (p.rho() - r.at(x, t, 0.0).rho).abs();
    }
    out
}
