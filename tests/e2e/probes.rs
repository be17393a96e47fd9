//! Probes and gridded output end to end: the shipped Sod and dam-break scenes with their
//! probes, `probes.csv` well-formed and consistent with the particles, plots and grids written.

use dualsph::io::read_particles;
use dualsph::probes::read_probes;
use dualsph::runner::{self, Progress, RunOptions};
use dualsph::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

fn run_short(name: &str, steps: u64) -> tempfile::TempDir {
    let mut scene = Scene::load(&scene_path(name), &dualsph::default_registry()).unwrap();
    scene.max_steps = Some(steps);
    scene.output.snapshot_every = 0;
    let dir = tempfile::tempdir().unwrap();
    runner::run(
        &scene,
        &RunOptions {
            out: dir.path().to_path_buf(),
            progress: Progress::Silent,
            profile: false,
        },
    )
    .unwrap();
    dir
}

/// Linear interpolation of the particle density (sorted by x) at x.
fn particle_density_at(xs: &[(f64, f64)], x: f64) -> f64 {
    let k = xs.partition_point(|p| p.0 < x).clamp(1, xs.len() - 1);
    let ((x0, r0), (x1, r1)) = (xs[k - 1], xs[k]);
    r0 + (r1 - r0) * (x - x0) / (x1 - x0)
}

#[test]
fn sod_density_line_matches_the_particles_and_the_initial_states() {
    let dir = run_short("sod_1d.ron", 60);
    let table = read_probes(dir.path()).unwrap();
    assert_eq!(table.columns.len(), 201);
    assert_eq!(table.columns[0], "rho[0]");
    assert_eq!(table.step, vec![0, 50, 60], "every 50 steps and the last");
    assert!(table.t.windows(2).all(|w| w[1] > w[0]));
    let last = table.values.last().unwrap();
    assert!(last.iter().all(|v| v.is_finite() && *v > 0.0));
    let mut xs: Vec<(f64, f64)> = read_particles(&dir.path().join("final.csv"))
        .unwrap()
        .rows()
        .map(|r| (r.pos()[0], r.rho()))
        .collect();
    xs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut checked = 0;
    for (c, (_, _, _, pos)) in table.meta.iter().enumerate() {
        let x = pos[0];
        assert!((x - (-0.5 + 0.005 * c as f64)).abs() < 1e-12);
        // smooth regions: the waves have moved < 0.05 from x = 0 after 60 steps
        if x.abs() < 0.1 {
            continue;
        }
        let initial = if x < 0.0 { 1.0 } else { 0.125 };
        let rho = last[c];
        assert!(
            (rho / initial - 1.0).abs() < 0.01,
            "x = {x}: probe ρ = {rho}, initial state {initial}"
        );
        let particles = particle_density_at(&xs, x);
        assert!(
            (rho / particles - 1.0).abs() < 0.005,
            "x = {x}: probe ρ = {rho}, particles {particles}"
        );
        checked += 1;
    }
    assert!(checked > 150);
    // the line goes through the contact: the probe sees both states
    assert!(last[100] < 0.9 && last[100] > 0.15, "ρ(0) = {}", last[100]);
}

#[test]
fn dam_break_gauges_and_wall_sensor_start_from_the_initial_column() {
    let dir = run_short("dam_break_2d.ron", 60);
    let table = read_probes(dir.path()).unwrap();
    assert_eq!(table.columns, ["P1", "H1", "H2", "H3", "H4"]);
    assert_eq!(table.step, vec![0, 50, 60]);
    let first = &table.values[0];
    // the wall sensor is dry at t = 0; H1 sees the 2 m column, H2–H4 the dry bed
    assert!(first[0].is_nan(), "P1 = {}", first[0]);
    assert!((first[1] - 2.0).abs() < 0.02, "H1 = {}", first[1]);
    for c in 2..5 {
        assert_eq!(first[c], 0.0, "{} = {}", table.columns[c], first[c]);
    }
    // gridded density of the final state, from final.csv, and the probe plots
    let scene = Scene::load(
        &scene_path("dam_break_2d.ron"),
        &dualsph::default_registry(),
    )
    .unwrap();
    let final_csv = dir.path().join("final.csv");
    let table = dualsph::gridded::read_particles(&scene, &final_csv).unwrap();
    let kernel = dualsph::KernelKind::CubicSpline;
    let (vti, png) =
        dualsph::gridded::write_density_grid(&table, 2, kernel, 0.02, dir.path()).unwrap();
    assert!(String::from_utf8_lossy(&std::fs::read(vti).unwrap()).contains("ImageData"));
    assert!(std::fs::metadata(png).unwrap().len() > 5000);
    let pngs = dualsph::probes::plot_probes(dir.path()).unwrap();
    assert_eq!(pngs.len(), 2, "{pngs:?}"); // pressure and water_height
}

#[test]
fn density_grid_of_a_live_sim() {
    let scene = Scene::load(
        &scene_path("dam_break_2d.ron"),
        &dualsph::default_registry(),
    )
    .unwrap();
    let mut sim = dualsph::build_sim::<glam::DVec2>(&scene).unwrap();
    sim.initialize().unwrap();
    let f = dualsph::gridded::sample_sim(&mut sim, &dualsph::probes::Quantity::density(), 0.05)
        .unwrap();
    // the domain box [0, 4] × [0, 3] at 0.05 m; the water column [0, 1] × [0, 2] at rest
    assert_eq!(f.grid.dims, [81, 61, 1]);
    for n in 0..f.grid.len() {
        let [x, y, _] = f.grid.point(n);
        if x > 0.1 && x < 0.9 && y > 0.1 && y < 1.9 {
            let rho = f.values[n].expect("inside the column");
            assert!((rho - 1000.0).abs() < 1e-6, "({x}, {y}): ρ = {rho}");
        } else if x > 1.1 || y > 2.1 {
            assert!(f.values[n].is_none(), "({x}, {y}) should be outside");
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let (vti, png) = dualsph::gridded::write_density_grid_sim(&mut sim, 0.05, dir.path()).unwrap();
    assert!(vti.is_file() && png.is_file());
}

#[test]
fn cli_grid_and_plot_probes() {
    let dir = run_short("sod_1d.ron", 10);
    let bin = || Command::new(env!("CARGO_BIN_EXE_dualsph"));
    // `dualsph grid` of one field over the run's last snapshot
    let grid = |field: &str| {
        let out = bin()
            .arg("grid")
            .arg(scene_path("sod_1d.ron"))
            .arg("--dir")
            .arg(dir.path())
            .args(["--dx", "0.01", "--field", field])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    grid("Density");
    assert!(dir.path().join("density_grid.vti").is_file());
    grid("velocity.x");
    assert!(dir.path().join("velocity_x_grid.vti").is_file());
    let out = bin().arg("plot-probes").arg(dir.path()).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("probe_rho.png").is_file());
    // a bad field name is a clear error
    let out = bin()
        .arg("grid")
        .arg(scene_path("sod_1d.ron"))
        .arg("--dir")
        .arg(dir.path())
        .args(["--dx", "0.01", "--field", "Temperature"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "a bad field is invalid input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--field") && err.contains("density"), "{err}");
    // a missing file is an I/O failure, exit status 4, as for `run`
    let out = bin()
        .arg("grid")
        .arg(scene_path("sod_1d.ron"))
        .arg("--dir")
        .arg(dir.path())
        .args(["--dx", "0.01", "--file", "particles_999999.csv"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(4),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let empty = tempfile::tempdir().unwrap();
    let out = bin().arg("plot-probes").arg(empty.path()).output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(4),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let missing_scene = bin()
        .arg("run")
        .arg(empty.path().join("absent.ron"))
        .output()
        .unwrap();
    assert_eq!(missing_scene.status.code(), Some(4));
}

/// The tutorial's tank with probes in the water (a point, a line, a sensor, a gauge),
/// sampled every 50 steps, snapshots every 50, 100 steps.
fn tank_with_probes(probes: &str) -> String {
    let text = std::fs::read_to_string(scene_path("tutorial_tank_2d.ron")).unwrap();
    let start = text.find("        Probes(every: 50, probes: [").unwrap();
    let end = start + text[start..].find("]),\n").unwrap() + 4;
    let text = format!(
        "{}        Probes(every: 50, probes: [{probes}]),\n{}",
        &text[..start],
        &text[end..]
    );
    text.replace("end_time: 1.0,", "end_time: 1.0, max_steps: Some(100),")
        .replace("snapshot_every: 500", "snapshot_every: 50")
}

const TANK_PROBES: &str = "Point(name: \"p\", at: [0.2, 0.1], quantity: \"pressure\"), \
    Line(name: \"u\", start: [0.05, 0.3], end: [0.35, 0.3], n: 4, quantity: \"velocity.y\"), \
    Sensor(name: \"s\", start: [0.395, 0.02], end: [0.395, 0.12], n: 5, floor: 0.0), \
    WaterHeight(name: \"h\", at: [0.2])";

fn dualsph(args: &[&std::ffi::OsStr]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_dualsph"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn probe_samples_a_finished_runs_snapshots_as_the_live_probes_did() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("tank.ron");
    std::fs::write(&scene, tank_with_probes(TANK_PROBES)).unwrap();
    let run = dir.path().join("run");
    let os = |s: &str| std::ffi::OsString::from(s);
    let (code, _, err) = dualsph(&[&os("run"), scene.as_os_str(), &os("--out"), run.as_os_str()]);
    assert_eq!(code, Some(0), "{err}");
    // the run's own scene (from its run.json): every probe, bitwise as sampled live
    let (code, out, err) = dualsph(&[&os("probe"), run.as_os_str()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("(3 snapshots)"), "{out}");
    let live = std::fs::read_to_string(run.join("probes.csv")).unwrap();
    let post = std::fs::read_to_string(run.join("snapshot_probes/probes.csv")).unwrap();
    assert_eq!(live.lines().count(), 4, "{live}");
    assert_eq!(post, live);
    assert!(
        live.lines()
            .nth(3)
            .unwrap()
            .split(',')
            .skip(2)
            .all(|v| v.parse::<f64>().unwrap().is_finite()),
        "{live}"
    );
    let points = std::fs::read_to_string(run.join("probes_points.csv")).unwrap();
    let post_points =
        std::fs::read_to_string(run.join("snapshot_probes/probes_points.csv")).unwrap();
    assert_eq!(post_points, points);
    // a probe added after the run, from another scene file, into another directory
    let later = dir.path().join("later.ron");
    let added =
        format!("{TANK_PROBES}, Point(name: \"q\", at: [0.1, 0.05], quantity: \"density\")");
    std::fs::write(&later, tank_with_probes(&added)).unwrap();
    let out_dir = dir.path().join("later");
    let (code, _, err) = dualsph(&[
        &os("probe"),
        run.as_os_str(),
        &os("--scene"),
        later.as_os_str(),
        &os("--out"),
        out_dir.as_os_str(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let table = read_probes(&out_dir).unwrap();
    assert_eq!(table.columns.last().map(String::as_str), Some("q"));
    assert_eq!(table.step, vec![0, 50, 100]);
    assert!(
        table
            .values
            .iter()
            .all(|r| (r.last().unwrap() - 1000.0).abs() < 50.0),
        "{:?}",
        table.values
    );
}

#[test]
fn probe_refuses_what_it_cannot_sample_with_the_exit_table() {
    let dir = tempfile::tempdir().unwrap();
    let os = |s: &str| std::ffi::OsString::from(s);
    // no run there: a missing file (4)
    let (code, _, err) = dualsph(&[&os("probe"), dir.path().join("nothing").as_os_str()]);
    assert_eq!(code, Some(4), "{err}");
    assert!(err.contains("run.json"), "{err}");
    // a scene without probes: invalid input (2)
    let scene = dir.path().join("tank.ron");
    std::fs::write(&scene, tank_with_probes(TANK_PROBES)).unwrap();
    let run = dir.path().join("run");
    let (code, _, err) = dualsph(&[
        &os("run"),
        scene.as_os_str(),
        &os("--out"),
        run.as_os_str(),
        &os("--set"),
        &os("max_steps=2"),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let bare = dir.path().join("bare.ron");
    let text = tank_with_probes(TANK_PROBES);
    let start = text.find("        Probes(").unwrap();
    let end = start + text[start..].find("]),\n").unwrap() + 4;
    std::fs::write(&bare, format!("{}{}", &text[..start], &text[end..])).unwrap();
    let (code, _, err) = dualsph(&[
        &os("probe"),
        run.as_os_str(),
        &os("--scene"),
        bare.as_os_str(),
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("has no Probes plugin"), "{err}");
    // a snapshot index that is not one: its line named
    std::fs::write(run.join("snapshots.csv"), "step,t,file\nfive,0.1,x.csv\n").unwrap();
    let (code, _, err) = dualsph(&[&os("probe"), run.as_os_str()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("snapshots.csv:2: expected `step,t,file`"),
        "{err}"
    );
}

#[test]
fn probe_reads_a_sensor_by_a_wall_of_particles_as_the_live_sensor() {
    // Buchner's dam break with its sensors moved to the left wall, under the water at rest:
    // the wide, clipped sensor with the walls' cut-off, bitwise as sampled live
    let text = std::fs::read_to_string(scene_path("dam_break_buchner_2d.ron"))
        .unwrap()
        .replace(
            "start: [3.2125, 0.07], end: [3.2125, 0.16]",
            "start: [0.0075, 0.07], end: [0.0075, 0.16]",
        )
        .replace(
            "start: [3.22, 0.07], end: [3.22, 0.16]",
            "start: [0.0, 0.07], end: [0.0, 0.16]",
        );
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("buchner.ron");
    std::fs::write(&scene, text).unwrap();
    let run = dir.path().join("run");
    let os = |s: &str| std::ffi::OsString::from(s);
    let args = [
        "max_steps=40",
        "output.snapshot_dt=None",
        "output.snapshot_every=20",
    ];
    let mut argv = vec![
        os("run"),
        scene.clone().into_os_string(),
        os("--out"),
        run.clone().into_os_string(),
    ];
    for a in args {
        argv.extend([os("--set"), os(a)]);
    }
    let argv: Vec<&std::ffi::OsStr> = argv.iter().map(|a| a.as_os_str()).collect();
    let (code, _, err) = dualsph(&argv);
    assert_eq!(code, Some(0), "{err}");
    let (code, _, err) = dualsph(&[&os("probe"), run.as_os_str()]);
    assert_eq!(code, Some(0), "{err}");
    let live = read_probes(&run).unwrap();
    let post = read_probes(&run.join("snapshot_probes")).unwrap();
    assert_eq!(live.step, vec![0, 20, 40]);
    let sensor = live.columns.iter().position(|c| c == "P1_sensor").unwrap();
    // ρ g (H − y) over y = 0.07-0.16: about 4.4 kPa
    assert!(
        live.values.iter().all(|r| (3e3..6e3).contains(&r[sensor])),
        "{:?}",
        live.values
    );
    let bits = |t: &dualsph::probes::ProbeTable| -> Vec<Vec<u64>> {
        t.values
            .iter()
            .map(|r| r.iter().map(|v| v.to_bits()).collect())
            .collect()
    };
    assert_eq!(bits(&post), bits(&live));
}
