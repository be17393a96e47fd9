//! Bitwise-identical results on 1 and 2 threads.

use crate::common::*;
use dualsph::plugins::*;
use dualsph::prelude::*;
use glam::DVec2;

fn run_steps(threads: usize) -> Vec<(Real, DVec2, DVec2, DVec2, Real)> {
    run_steps_with(threads, &LeapfrogPC::default())
}

/// 20 steps of a cloud with every kind of term, advanced by `integrator`, on `threads` threads.
fn run_steps_with(
    threads: usize,
    integrator: &dyn PluginConfig,
) -> Vec<(Real, DVec2, DVec2, DVec2, Real)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let particles = cloud::<DVec2>(20, 1.5, 12.0, 3);
        let (eos, pf, av, heat, cont, hup) = (
            tait(),
            PressureForce {},
            ArtificialViscosity {
                alpha: 1.0,
                beta: 2.0,
                eta_factor: 0.1,
                materials: Vec::new(),
                dissipation: true,
            },
            HeatConduction {
                conductivity: 0.7,
                heat_capacity: 1.0,
            },
            ContinuityDensity {
                form: ContinuityForm::Pairwise,
            },
            SmoothingLengthUpdate {
                every: 5,
                n: 2.0,
                max_ratio: None,
                isotropy: None,
            },
        );
        let mut sim = sim_with::<DVec2>(
            &particles,
            Formulation::DualSupport,
            &[integrator, &cont, &eos, &pf, &av, &heat, &hup],
        );
        for _ in 0..20 {
            sim.step().unwrap();
        }
        rates(&mut sim)
    })
}

#[test]
fn one_and_two_threads_give_bitwise_identical_states() {
    let a = run_steps(1);
    let b = run_steps(2);
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            x.1.to_array().map(f64::to_bits),
            y.1.to_array().map(f64::to_bits)
        );
        assert_eq!(
            x.2.to_array().map(f64::to_bits),
            y.2.to_array().map(f64::to_bits)
        );
        assert_eq!(
            x.3.to_array().map(f64::to_bits),
            y.3.to_array().map(f64::to_bits)
        );
        assert_eq!(x.4.to_bits(), y.4.to_bits());
    }
}

/// The whole engine in separate processes on 1 and 2 threads (`RAYON_NUM_THREADS`): the
/// engine's loops run on rayon and any plugin's `par_iter_mut` loops on bevy's task pool,
/// whose size is fixed once per process, so only separate processes test both. The
/// 5,600-particle dam break of `scenes/dam_break_2d.ron` for 200 steps: the checkpoint
/// (every component of every particle, bit for bit), the final particles and the diagnostics
/// are byte-identical.
#[test]
fn the_position_verlet_gives_bitwise_identical_states_on_1_and_2_threads() {
    let (a, b) = (
        run_steps_with(1, &PositionVerlet::default()),
        run_steps_with(2, &PositionVerlet::default()),
    );
    assert!(a == b, "1 and 2 threads differ");
    // another scheme, another state
    assert!(a != run_steps(1));
}

#[test]
fn dam_break_processes_on_1_and_2_threads_write_identical_files() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/dam_break_2d.ron")).unwrap();
    assert!(!text.contains("max_steps"));
    let text = text.replacen("    end_time:", "    max_steps: 200,\n    end_time:", 1);
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("dam_200.ron");
    std::fs::write(&scene, text).unwrap();
    let run = |threads: usize| {
        let out = tmp.path().join(format!("t{threads}"));
        let threads = threads.to_string();
        let env = [("RAYON_NUM_THREADS", threads.as_str())];
        run_dualsph(&scene, &out, &["--checkpoint-every", "200"], &env);
        out
    };
    let (one, two) = (run(1), run(2));
    let ckpt = dualsph::checkpoint::checkpoint_file_name(200);
    for f in [ckpt.as_str(), "final.csv", "diagnostics.csv"] {
        let (a, b) = (std::fs::read(one.join(f)), std::fs::read(two.join(f)));
        let (a, b) = (a.unwrap(), b.unwrap());
        assert!(!a.is_empty(), "{f} is empty");
        assert!(a == b, "{f} differs between 1 and 2 threads");
    }
}

/// The Verlet skin changes how many candidates the lists hold and how often they are built,
/// never the result: a candidate outside `h_i` enters no sum (its reaction is zero, and a zero
/// added to a sum started at +0 changes no bit). The dam break of `scenes/dam_break_2d.ron`
/// for 300 steps with the skin fixed at 0.15, at 0 (exact lists, a build every step) and at
/// 0.4, and tuned from the motion (the scene's default): the final particles are
/// byte-identical.
#[test]
fn dam_break_state_does_not_depend_on_the_skin() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/dam_break_2d.ron")).unwrap();
    let text = text.replacen("    end_time:", "    max_steps: 300,\n    end_time:", 1);
    assert!(text.contains("neighbours: (skin: 0.15)"));
    let tmp = tempfile::tempdir().unwrap();
    let run = |name: &str, settings: &str| {
        let scene = tmp.path().join(format!("dam_skin_{name}.ron"));
        let with_skin = text.replace(
            "neighbours: (skin: 0.15)",
            &format!("neighbours: ({settings})"),
        );
        std::fs::write(&scene, with_skin).unwrap();
        let out = tmp.path().join(format!("skin_{name}"));
        run_dualsph(&scene, &out, &[], &[]);
        std::fs::read(out.join("final.csv")).unwrap()
    };
    let reference = run("fixed", "skin: 0.15, tune_skin: false");
    assert!(!reference.is_empty());
    for (name, settings) in [
        ("zero", "skin: 0.0, tune_skin: false"),
        ("wide", "skin: 0.4, tune_skin: false"),
        ("tuned", "skin: 0.15"),
    ] {
        assert!(
            run(name, settings) == reference,
            "skin {settings} changes the final state"
        );
    }
}

/// `--profile` times every system of the step and changes no bit of the state: the dam break
/// of `scenes/dam_break_2d.ron` for 200 steps with and without it gives the same `final.csv`,
/// and the profiled run prints one row per system of `dualsph plan`'s schedule (the same
/// labels), the sweep among them, with finite non-negative times that add up to the steps'
/// total.
#[test]
fn profiling_changes_no_bit_and_times_every_system() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/dam_break_2d.ron")).unwrap();
    let text = text.replacen("    end_time:", "    max_steps: 200,\n    end_time:", 1);
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("dam.ron");
    std::fs::write(&scene, text).unwrap();
    let (plain, profiled) = (tmp.path().join("plain"), tmp.path().join("profiled"));
    run_dualsph(&scene, &plain, &[], &[]);
    let stdout = run_dualsph(&scene, &profiled, &["--profile"], &[]);
    let (a, b) = (plain.join("final.csv"), profiled.join("final.csv"));
    assert!(std::fs::read(a).unwrap() == std::fs::read(b).unwrap());
    let table = stdout
        .split("wall time per system over 200 steps")
        .nth(1)
        .unwrap_or_else(|| panic!("no profile in {stdout}"));
    let rows: Vec<&str> = table
        .lines()
        .skip(2)
        .take_while(|l| !l.is_empty())
        .collect();
    let plan = std::process::Command::new(env!("CARGO_BIN_EXE_dualsph"))
        .arg("plan")
        .arg(&scene)
        .output()
        .unwrap();
    let plan = String::from_utf8_lossy(&plan.stdout);
    let numbered = |l: &&str| {
        l.trim_start()
            .split_once(". ")
            .is_some_and(|(k, _)| k.parse::<u32>().is_ok())
    };
    // "  N. Set  label  [plugin]" → label; profile row "label  wall s  share  µs  ns" → label
    let words = |s: &str| s.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut scheduled: Vec<String> = plan
        .lines()
        .filter(numbered)
        .map(|l| {
            let rest = l.trim_start().split_once(". ").unwrap().1.trim_start();
            let after_set = rest.split_once(' ').map_or("", |(_, t)| t);
            words(
                after_set
                    .rsplit_once(" [")
                    .map_or(after_set, |(label, _)| label),
            )
        })
        .collect();
    let fields = |r: &str| r.split_whitespace().map(str::to_string).collect::<Vec<_>>();
    let mut profiled: Vec<String> = rows
        .iter()
        .map(|r| {
            let f = fields(r);
            f[..f.len().saturating_sub(4)].join(" ")
        })
        .collect();
    let secs_of = |r: &str| fields(r)[fields(r).len() - 4].parse::<f64>().unwrap();
    scheduled.sort();
    profiled.sort();
    assert_eq!(profiled, scheduled, "{table}\n{plan}");
    assert!(
        profiled.iter().any(|l| l.starts_with("pair_sweep")),
        "no sweep in the profile: {table}"
    );
    // wall-clock ordering depends on the machine's load: only finiteness and sign are asserted
    for r in &rows {
        let s = secs_of(r);
        assert!(s.is_finite() && s >= 0.0, "{r}");
    }
    let secs: f64 = rows.iter().map(|r| secs_of(r)).sum();
    let total: f64 = table
        .split("steps ")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no total in {table}"));
    assert!(
        (secs - total).abs() <= 0.001 * rows.len() as f64,
        "{secs} vs {total}"
    );
}

/// `dualsph run SCENE --quiet --out OUT ARGS…` with the environment `env`: returns its
/// standard output; on failure, panics with the program's stderr.
fn run_dualsph(
    scene: &std::path::Path,
    out: &std::path::Path,
    args: &[&str],
    env: &[(&str, &str)],
) -> String {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_dualsph"))
        .arg("run")
        .arg(scene)
        .arg("--quiet")
        .arg("--out")
        .arg(out)
        .args(args)
        .envs(env.iter().copied())
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{} {args:?} {env:?}: {}",
        scene.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The same bits on another CPU: glibc picks the code path of its `pow`, `exp`, `sin`, … by
/// the CPU it finds (with or without FMA and AVX2), and `GLIBC_TUNABLES` hides those features
/// from it, as a CPU without them would. The drop with a 1:4 support jump (its h-update takes
/// `(m/ρ)^{1/d}` every step) to t = 1 ms, once as the machine is and once without FMA: the
/// final particles and the diagnostics are byte-identical. With the std functions (glibc's)
/// they differed. On a machine without FMA, or without glibc, the two runs are one case.
#[test]
fn a_run_gives_the_same_bits_with_or_without_fma() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = root.join("scenes/hard/drop_support_jump_1to4.ron");
    let tmp = tempfile::tempdir().unwrap();
    let run = |name: &str, tunables: &str| {
        let out = tmp.path().join(name);
        let env = [("GLIBC_TUNABLES", tunables)];
        run_dualsph(&scene, &out, &["--end-time", "0.001"], &env);
        out
    };
    let (plain, bare) = (run("plain", ""), run("bare", "glibc.cpu.hwcaps=-AVX2,-FMA"));
    for f in ["final.csv", "diagnostics.csv"] {
        let (a, b) = (std::fs::read(plain.join(f)), std::fs::read(bare.join(f)));
        let (a, b) = (a.unwrap(), b.unwrap());
        assert!(!a.is_empty(), "{f} is empty");
        assert!(a == b, "{f} differs with and without FMA");
    }
}
