//! Hard cases (scenes/hard/): each scene states what it tests and its pass criterion; these
//! tests assert it for the scenes run in-process (the two that `dualsph run` refuses are
//! asserted by the facade's tests/e2e/hard_cases_cli.rs). Results and figures:
//! docs/validation/hard_cases.md.

use crate::common::{assert_doc_quotes, thousands};
use std::path::Path;

/// The doc of the hard cases, whose table quotes each run's figures.
const DOC: &str = "docs/validation/hard_cases.md";

/// Runs `scenes/hard/FILE` in-process (diagnostics every `every` steps) and asserts that it
/// reached t = `end` without a blow-up.
fn run_in_process(file: &str, every: u64, end: f64) -> dualsph_validation::report::CaseRun {
    use dualsph_validation::report::{CaseSpec, Recording, ReportOptions};
    let opts = ReportOptions {
        scenes: Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/hard"),
        out: std::env::temp_dir(),
        coarsen: 1.0,
        end_time: None,
        log: false,
    };
    let scene = opts.scene(file).unwrap();
    let rec = Recording {
        every,
        ..Default::default()
    };
    let run = opts.run(&CaseSpec::new(file, scene, None), &rec).unwrap();
    assert!(run.failure.is_none(), "{file}: {:?}", run.failure);
    assert!((run.final_diagnostics().t - end).abs() < 1e-12);
    run
}

#[test]
fn strong_shock_tube_with_pressure_ratio_1e5_is_stable_conservative_and_accurate() {
    use dualsph_reference::riemann::{GasState, Riemann};
    use dualsph_validation::report::sod;
    let run = run_in_process("strong_shock_tube.ron", 10, 0.15);
    let (d0, d1) = (run.diagnostics[0].clone(), run.final_diagnostics().clone());
    let de = (d1.e_tot / d0.e_tot - 1.0).abs();
    // no walls: the ends stay at rest, so total momentum stays 0 to round-off
    let dp = d1.momentum[0].abs() / d0.momentum_scale.max(d1.momentum_scale);
    let exact = Riemann::new(
        GasState {
            rho: 1.0,
            u: 0.0,
            p: 1.0,
        },
        GasState {
            rho: 0.125,
            u: 0.0,
            p: 1e-5,
        },
        5.0 / 3.0,
    )
    .unwrap();
    let graded = sod::grade_against(run, &exact);
    println!(
        "strong shock: ΔE/E {de:.2e}, momentum {dp:.2e}, L1 ρ {:.4} u {:.4} p {:.4} e {:.4}",
        graded.l1[0], graded.l1[1], graded.l1[2], graded.l1[3]
    );
    let row = "| `strong_shock_tube.ron` |";
    let steps = thousands(d1.step);
    assert_doc_quotes(DOC, row, &format!("{steps} steps"));
    assert_doc_quotes(DOC, row, &format!("ΔE/E = {de:.1e}, momentum {dp:.1e}"));
    let l1 = &graded.l1;
    let quoted = format!(
        "ρ {:.4}, u {:.4}, p {:.4}, e {:.4}",
        l1[0], l1[1], l1[2], l1[3]
    );
    assert_doc_quotes(DOC, row, &quoted);
    // Measured: ΔE/E 5.0e-15 (the work-consistent energy update keeps the total to round-off;
    // 1e-12 leaves 200 × for round-off accumulating over the 788 steps), momentum 1.4e-15.
    assert!(de < 1e-12, "energy drift {de:e}");
    assert!(dp < 1e-12, "momentum {dp:e}");
    // Measured L1 ρ 0.0051, u 0.0136, p 0.0025, e 0.0082; the run is bitwise reproducible
    // (tests/e2e/determinism.rs) and these did not move (to the 4 digits printed) across the change
    // of the internal-energy update, so each bound is the measured value + about 20 %.
    let bounds = [("ρ", 0.006), ("u", 0.016), ("p", 0.003), ("e", 0.0098)];
    for (k, (name, bound)) in bounds.into_iter().enumerate() {
        assert!(graded.l1[k] < bound, "L1 {name} {}", graded.l1[k]);
    }
}

#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): eight seconds of sloshing"]
fn dam_break_runs_to_eight_seconds_through_the_sloshing() {
    let run = run_in_process("dam_break_8s.ron", 50, 8.0);
    let e0 = run.diagnostics[0].e_tot;
    let drift = |until: f64| {
        run.diagnostics
            .iter()
            .filter(|d| d.t <= until)
            .map(|d| (d.e_tot / e0 - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let (to_paper, to_end) = (drift(2.5), drift(8.0));
    println!(
        "dam break to 8 s: {} steps; |ΔE/E| ≤ {to_paper:.3e} to 2.5 s, {to_end:.3e} to 8 s",
        run.final_diagnostics().step
    );
    let row = "| `dam_break_8s.ron` |";
    let steps = thousands(run.final_diagnostics().step);
    assert_doc_quotes(DOC, row, &format!("{steps} steps"));
    let quoted = format!("{to_paper:.1e} to 2.5 s, {to_end:.1e} to 8 s");
    assert_doc_quotes(DOC, row, &quoted);
    // Measured: 1.4e-15 to 2.5 s, 2.4e-15 to 8 s (the work-consistent internal-energy update;
    // the walls' clearance reflection only reverses normal velocities): round-off, bounded at
    // 1e-12 over the whole run as in the conservation tests.
    assert!(
        to_paper <= 1e-12,
        "energy varies by {to_paper:e} before 2.5 s"
    );
    assert!(to_end <= 1e-12, "energy varies by {to_end:e} before 8 s");
    // the walls keep every particle in the tank
    for p in run.last.rows() {
        assert!(p.pos()[0] >= 0.0 && p.pos()[0] <= 4.0 && p.pos()[1] >= 0.0 && p.pos()[1] <= 3.0);
    }
}

mod drops {
    use dualsph_validation::report::drop;

    /// Runs a scenes/hard drop in-process to t = `end` and grades it against the ODE
    /// (Eq. 7.6) at that time.
    fn graded(file: &str, end: f64) -> drop::DropCase {
        let run = super::run_in_process(file, 10, end);
        let case = drop::grade(run);
        println!(
            "{file}: {} particles, {} steps; b = {:.5} (ODE {:.5}, {:+.2} %), a = {:.5} (ODE {:.5}); drifts P {:.1e} L {:.1e} E {:.1e}",
            case.run.last.len(),
            case.run.final_diagnostics().step,
            case.axes.1,
            case.ode.1,
            100.0 * (case.axes.1 / case.ode.1 - 1.0),
            case.axes.0,
            case.ode.0,
            case.momentum_drift,
            case.angular_momentum_drift,
            case.energy_drift
        );
        let row = format!("| `{file}` |");
        let steps = super::thousands(case.run.final_diagnostics().step);
        let quoted = format!("{steps} steps");
        super::assert_doc_quotes(super::DOC, &row, &quoted);
        let quoted = format!("b = {:.5} against the ODE's {:.5}", case.axes.1, case.ode.1);
        super::assert_doc_quotes(super::DOC, &row, &quoted);
        let quoted = format!(
            "momentum drift {:.1e}, angular momentum {:.1e}, energy {:.1e}",
            case.momentum_drift, case.angular_momentum_drift, case.energy_drift
        );
        super::assert_doc_quotes(super::DOC, &row, &quoted);
        case
    }

    fn assert_pass(case: &drop::DropCase, b_tolerance: f64) {
        assert!(
            case.momentum_drift <= 1e-12,
            "momentum drift {:e}",
            case.momentum_drift
        );
        assert!(
            case.angular_momentum_drift <= 1e-12,
            "angular momentum drift {:e}",
            case.angular_momentum_drift
        );
        // measured 3.3e-15 (1:4), 7.9e-15 (1:8), 5.8e-15 (stretched): round-off
        assert!(
            case.energy_drift <= 1e-12,
            "energy drift {:e}",
            case.energy_drift
        );
        let err = (case.axes.1 / case.ode.1 - 1.0).abs();
        assert!(
            err <= b_tolerance,
            "b = {} vs ODE {}",
            case.axes.1,
            case.ode.1
        );
    }

    #[test]
    fn drop_with_a_one_to_four_support_jump_conserves_and_follows_the_ode() {
        // b measured +0.02 % off the ODE; the bound 0.1 % is within the spread of the passing
        // variants of the harder drops (docs/validation/hard_cases.md: up to 0.13 %)
        assert_pass(&graded("drop_support_jump_1to4.ron", 0.008), 0.001);
    }

    /// The 1:8 jump needs h from the particle distribution (`isotropy`), see the scene.
    #[test]
    #[ignore = "second tier (cargo test --workspace --release -- --ignored): a long drop run"]
    fn drop_with_a_one_to_eight_support_jump_conserves_and_follows_the_ode() {
        // b measured −0.08 %; the passing isotropy variants of this scene spread over −0.11 % …
        // +0.02 % (docs/validation/hard_cases.md): bound 0.15 %
        assert_pass(&graded("drop_support_jump_1to8.ron", 0.008), 0.0015);
    }

    /// The drop to t = 0.02 s (b ≈ 3.7, the lattice sheared 13.5 : 1): h from the particle
    /// distribution (`isotropy`), see the scene.
    #[test]
    #[ignore = "second tier (cargo test --workspace --release -- --ignored): a long drop run"]
    fn stretched_drop_to_twenty_milliseconds_conserves_and_follows_the_ode() {
        let case = graded("drop_stretched.ron", 0.02);
        assert!(case.ode.1 > 3.6, "the ODE's b = {} at 0.02 s", case.ode.1);
        // b measured +0.05 %; the passing variants of this scene spread over −0.13 % … +0.08 %
        // (docs/validation/hard_cases.md): bound 0.15 %
        assert_pass(&case, 0.0015);
    }
}

/// Dam breaks with a support-radius jump (scenes/hard/dam_break_support_jump_1to{4,8}.ron).
mod dam_break_jumps {
    use dualsph::core::glam::DVec2;
    use dualsph::diagnostics::{PairBalance, track_pair_balance};
    use dualsph::prelude::*;
    use dualsph::run_loop::{EveryStep, Flow, run_to_end};
    use dualsph::scene::{Block, Generator, Lattice, Scene};
    use dualsph::{build_sim_with, default_registry};
    use dualsph_reference::dam_break::KOSHIZUKA_OKA_FRONT;

    /// What one run gives.
    struct Run {
        /// (t, largest x) every 20 steps.
        front: Vec<(f64, f64)>,
        /// max |E(t)/E(0) − 1| over the run (E kinetic + potential + internal).
        energy: f64,
        /// Largest relative imbalance of the pair forces, `|Σ f_i| / Σ |f_i|` and
        /// `|Σ r_i × f_i| / Σ |r_i × f_i|` (f_i = m_i (a_i − g), at the positions the forces were
        /// computed at), sampled every 500 steps.
        force: f64,
        torque: f64,
        particles: usize,
    }

    fn load(file: &str) -> Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes/hard")
            .join(file);
        Scene::load(&path, &default_registry()).unwrap()
    }

    /// `|Σ f| / Σ |f|` and `|Σ r × f| / Σ |r × f|` of the last sweep's pair forces.
    fn balance(sim: &Sim<DVec2>) -> (f64, f64) {
        let b = sim.world.resource::<PairBalance>();
        (b.force, b.torque)
    }

    fn run(scene: &Scene) -> Run {
        let mut sim = build_sim_with::<DVec2>(scene, |sim| {
            track_pair_balance(sim);
            Ok(())
        })
        .unwrap();
        sim.initialize().unwrap();
        let e0 = sim.diagnostics().e_tot;
        let largest_x = |sim: &mut Sim<DVec2>| {
            let mut q = sim.world.query::<&Position<DVec2>>();
            q.iter(&sim.world).map(|p| p.0.x).fold(0.0, f64::max)
        };
        let mut out = Run {
            front: vec![(0.0, largest_x(&mut sim))],
            energy: 0.0,
            force: 0.0,
            torque: 0.0,
            particles: sim.particle_count(),
        };
        let mut record = EveryStep(|sim: &mut Sim<DVec2>| {
            let step = sim.clock().step;
            if step.is_multiple_of(20) {
                let t = sim.clock().t;
                out.front.push((t, largest_x(sim)));
                out.energy = out.energy.max((sim.diagnostics().e_tot / e0 - 1.0).abs());
            }
            if step.is_multiple_of(500) {
                let (f, t) = balance(sim);
                (out.force, out.torque) = (out.force.max(f), out.torque.max(t));
            }
            Ok(Flow::Continue)
        });
        if let Err(e) = run_to_end(&mut sim, &mut [&mut record]) {
            panic!("blow-up: {e}");
        }
        out
    }

    /// Linear interpolation of a (t, x) history at `t`.
    fn at(front: &[(f64, f64)], t: f64) -> f64 {
        let k = front.partition_point(|p| p.0 < t).clamp(1, front.len() - 1);
        let ((t0, x0), (t1, x1)) = (front[k - 1], front[k]);
        x0 + (x1 - x0) * (t - t0) / (t1 - t0)
    }

    /// RMS of `a − b` at 0.01, 0.02, … s up to `end`.
    fn rms_between(a: &[(f64, f64)], b: &[(f64, f64)], end: f64) -> f64 {
        let n = (end / 0.01).round() as usize;
        let s: f64 = (1..=n)
            .map(|k| (at(a, k as f64 * 0.01) - at(b, k as f64 * 0.01)).powi(2))
            .sum();
        (s / n as f64).sqrt()
    }

    /// RMS of the front against Koshizuka & Oka's points up to `end`.
    fn rms_experiment(front: &[(f64, f64)], end: f64) -> f64 {
        let d: Vec<f64> = KOSHIZUKA_OKA_FRONT
            .iter()
            .filter(|p| p.0 <= end)
            .map(|&(t, x)| at(front, t) - x)
            .collect();
        (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
    }

    /// The same column at the coarse spacing alone (one Block, the scene's other settings).
    fn coarse_uniform(file: &str, spacing: f64) -> Scene {
        let mut s = load(file);
        s.particles = vec![Generator::Block(Block {
            min: vec![0.0, 0.0],
            max: vec![1.0, 2.0],
            spacing,
            lattice: Lattice::Staggered,
            jitter: 0.0,
            density: 1000.0,
            h_factor: 2.0,
            clip: None,
            cut: Vec::new(),
            velocity: None,
            internal_energy: 0.0,
            body: None,
        })];
        s
    }

    /// Runs the scene and the same column at its coarse spacing alone, and asserts the scene's
    /// pass criterion: pair forces and torques balance to round-off; |ΔE/E| ≤ `energy_tol`;
    /// the front within `experiment_tol` RMS of Koshizuka & Oka's up to the end time and
    /// closer to it than the coarse uniform column's (the fine layer under the interface
    /// carries the front: the jump must not spoil what the refinement gains).
    fn check(file: &str, coarse: f64, experiment_tol: f64, energy_tol: f64) {
        let scene = load(file);
        let end = scene.end_time;
        let jump = run(&scene);
        let uniform = run(&coarse_uniform(file, coarse));
        let vs_uniform = rms_between(&jump.front, &uniform.front, end);
        let (vs_ko, uniform_vs_ko) = (
            rms_experiment(&jump.front, end),
            rms_experiment(&uniform.front, end),
        );
        println!(
            "{file} ({} particles; uniform {}): front at {end} s {:.3} m (uniform {:.3} m); RMS vs uniform {vs_uniform:.3} m, vs K&O {vs_ko:.3} m (uniform {uniform_vs_ko:.3} m); |ΔE/E| ≤ {:.2e}; pair force {:.1e}, torque {:.1e}",
            jump.particles,
            uniform.particles,
            at(&jump.front, end),
            at(&uniform.front, end),
            jump.energy,
            jump.force,
            jump.torque
        );
        assert!(
            jump.force <= 1e-12,
            "pair forces do not balance: {:e}",
            jump.force
        );
        assert!(
            jump.torque <= 1e-12,
            "pair torques do not balance: {:e}",
            jump.torque
        );
        assert!(
            jump.energy <= energy_tol,
            "energy varies by {}",
            jump.energy
        );
        assert!(
            vs_ko <= experiment_tol,
            "front {vs_ko} m from the experiment"
        );
        assert!(
            vs_ko < uniform_vs_ko,
            "the jump's front ({vs_ko} m from the experiment) is no better than the coarse uniform one ({uniform_vs_ko} m)"
        );
    }

    // Energy: measured 1.6e-15 (1:4) and 6.7e-16 (1:8), round-off: bound 1e-12. Front RMS
    // against the experiment: measured 0.226 m (1:4) and 0.346 m (1:8), unchanged to the
    // millimetre across the change of the internal-energy update; bounds 0.25 m and 0.38 m
    // (about 10 %, a few particle spacings of the fine layer).
    #[test]
    fn dam_break_with_a_one_to_four_support_jump() {
        check("dam_break_support_jump_1to4.ron", 0.1, 0.25, 1e-12);
    }

    #[test]
    fn dam_break_with_a_one_to_eight_support_jump() {
        check("dam_break_support_jump_1to8.ron", 0.2, 0.38, 1e-12);
    }
}
