//! Where the adaptive Sod tube's particles are refined, in the x–t plane, against the exact
//! solution's waves: `cargo run --release -p dualsph-validation --example sod_levels -- OUT.png`
//! (runs `scenes/sod_1d_adaptive.ron`, snapshots every 0.01 s; each particle on [−0.5, 0.5]
//! a marker coloured by its level, the exact contact, shock and rarefaction as lines).
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_validation::report::sod::{WAVE_WINDOW, adaptive_level, exact, wave_windows};
use dualsph_validation::report::{CaseSpec, Recording, run_case};

fn main() {
    let out = std::env::args().nth(1).expect("usage: sod_levels OUT.png");
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/sod_1d_adaptive.ron");
    let scene = dualsph_scene::Scene::load(&path, &dualsph::default_registry())
        .unwrap_or_else(|e| panic!("{e}"));
    let rec = Recording {
        every: 100,
        snapshot_times: (1..=20).map(|k| 0.01 * k as f64).collect(),
        ..Default::default()
    };
    let run =
        run_case(&CaseSpec::new("adaptive", scene, None), &rec).unwrap_or_else(|e| panic!("{e}"));
    let mut levels: [Vec<(f64, f64)>; 3] = Default::default();
    for (_, t, table) in &run.snapshots {
        for p in table.rows() {
            let x = p.pos()[0];
            let level = adaptive_level(&p).round() as usize;
            if x.abs() <= 0.5 {
                levels[level.min(2)].push((x, *t));
            }
        }
    }
    let r = exact();
    // the exact waves' positions: a window's edge less the margin `wave_windows` adds, or
    // its middle
    type Edge = fn((f64, f64, f64)) -> f64;
    let lines: [(&str, usize, Edge, usize); 4] = [
        ("rarefaction head (exact)", 0, |w| w.0 + WAVE_WINDOW, 3),
        ("rarefaction tail (exact)", 0, |w| w.1 - WAVE_WINDOW, 6),
        ("contact (exact)", 1, |w| 0.5 * (w.0 + w.1), 4),
        ("shock (exact)", 2, |w| 0.5 * (w.0 + w.1), 5),
    ];
    let mut plot = LinePlot::new(
        "Adaptive Sod tube: particle sizes against the exact waves",
        "x",
        "t",
    );
    plot.x_range = Some((-0.5, 0.5));
    plot.y_range = Some((0.0, 0.3)); // room for the legend above the run's 0.2 s
    let names = [
        "level 0 (Δx = 0.005)",
        "level 1 (0.0025)",
        "level 2 (0.00125)",
    ];
    for (k, pts) in levels.into_iter().enumerate() {
        plot = plot.with(Series::new(names[k], pts, SeriesStyle::Markers, k));
    }
    for (label, k, edge, colour) in lines {
        let pts = (0..=20)
            .map(|i| {
                let t = 0.01 * i as f64;
                (edge(wave_windows(&r, t.max(1e-9))[k]), t)
            })
            .collect();
        plot = plot.with(Series::new(label, pts, SeriesStyle::Line, colour));
    }
    plot.write_png(std::path::Path::new(&out))
        .unwrap_or_else(|e| panic!("{e}"));
    println!("{out}: {} snapshots", run.snapshots.len());
}
