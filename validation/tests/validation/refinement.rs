//! Stability under refinement (second tier): the walls dam break at twice its shipped
//! resolution runs to 1.5 s without a blow-up (`dualsph_validation::report::walls::refinement`;
//! Buchner's dam break at its shipped H/40 to t* = 8 is checked by the wall-pressure test,
//! which runs it). The finer runs (Δx/4, H/80, H/160; about 13, 7 and 50 CPU-minutes) are in
//! the walls report's "Stability under refinement".

use crate::common;

use dualsph_validation::report::walls::refinement::{reached_end, refined, run_one};

#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): the walls dam break at Δx/2 to 1.5 s"]
fn the_wall_flows_run_to_their_end_refined() {
    let opts = common::report_options(1.0, None);
    for r in refined(false) {
        let run = run_one(&opts, &r).unwrap();
        assert!(
            reached_end(&run, &r),
            "{} stopped at t = {}: {:?}",
            run.label,
            run.final_diagnostics().t,
            run.failure
        );
        // the water stays water: no particle far out of its density range (measured: 0.016
        // for the walls dam break, whose water cavitates at −99 kPa; 0.43 at Δx/2 without
        // cavitation)
        assert!(
            run.max_density_variation() < 0.03,
            "{}: max |ρ/ρ0 − 1| = {}",
            run.label,
            run.max_density_variation()
        );
        eprintln!(
            "{}: t = {:.3} s, {} steps, max |ρ/ρ0 − 1| = {:.3}, max |ΔE/E| = {:.1e}, {:.0} CPU-s",
            run.label,
            run.final_diagnostics().t,
            run.steps,
            run.max_density_variation(),
            run.max_energy_variation(),
            run.cpu_seconds
        );
    }
}
