//! Speed against error: the Sod tube (static and adaptive variable resolution and uniform),
//! the drop, the dam break in a specular box, the dam break with walls of particles
//! (adaptive, static two-level and uniform), Buchner's wall pressure and the 3-D dam break
//! (adaptive and uniform) at several resolutions each, variable resolution with
//! DualSupport against uniform resolution, as error against CPU seconds. The question it
//! answers: to reach a given error, how much cheaper is variable resolution with DualSupport?

use super::walls::wall_pressure;
use super::{
    CaseRun, CaseSpec, Recording, ReportError, ReportOptions, Section, Table, coarsen, dam_break,
    drop, image, sod,
};
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_probes::ProbeTable;
use dualsph_scene::Formulation;

/// One run of the study.
#[derive(Clone, Debug)]
pub struct Point {
    /// Variant label.
    pub variant: String,
    /// Spacing multiplier relative to the variant's scene at the study's own resolution.
    pub factor: f64,
    /// Particles at the start.
    pub particles: u64,
    /// Particles at the end (they differ when the run splits and merges particles).
    pub particles_end: u64,
    /// Steps.
    pub steps: u64,
    /// CPU seconds of the stepping loop.
    pub cpu_seconds: f64,
    /// The benchmark's error measure.
    pub error: f64,
    /// Why the run stopped before its end time, if it did (its error is then of the part
    /// it ran).
    pub failure: Option<String>,
}

/// A variant of a study: its label, its scene, the formulation replacing the scene's, the
/// spacing multiplier that brings the scene to the study's own resolution, and the
/// multipliers it runs at when not the study's.
struct Variant {
    label: &'static str,
    file: &'static str,
    formulation: Option<Formulation>,
    scale: f64,
    factors: Option<&'static [f64]>,
}

impl Variant {
    const fn new(label: &'static str, file: &'static str) -> Self {
        Variant {
            label,
            file,
            formulation: None,
            scale: 1.0,
            factors: None,
        }
    }
}

/// A benchmark of the study: its variants (the uniform one last), the spacing multipliers,
/// the error measure and how to run it.
struct Study {
    name: &'static str,
    error_name: &'static str,
    variants: Vec<Variant>,
    factors: &'static [f64],
    end_time: Option<f64>,
    recording: Recording,
    /// A run the errors are measured against (a scene and its spacing multiplier), run once.
    reference: Option<(&'static str, f64)>,
    /// Whether the error is read from the run's probes (written to a scratch directory).
    probes: bool,
    error: fn(Measured<'_>) -> f64,
}

impl Study {
    /// A study at spacing × 4, × 2 and × 1, to its scenes' end, with diagnostics every 10
    /// steps, no reference run and no probes.
    fn new(
        name: &'static str,
        error_name: &'static str,
        variants: Vec<Variant>,
        error: fn(Measured<'_>) -> f64,
    ) -> Self {
        Study {
            name,
            error_name,
            variants,
            factors: &[4.0, 2.0, 1.0],
            end_time: None,
            recording: Recording {
                every: 10,
                ..Default::default()
            },
            reference: None,
            probes: false,
            error,
        }
    }
}

/// What a study's error is measured from: the run, the study's reference run, and the run's
/// probes when the study reads them.
struct Measured<'a> {
    run: CaseRun,
    reference: Option<&'a CaseRun>,
    probes: Option<ProbeTable>,
}

/// Buchner's sensor P1 as TrixiParticles.jl measures it: the mean |Δp*| of the scene's
/// `P1_sensor` against the experiment over t* 2–6.5 ([`wall_pressure::grade`]); NaN without
/// the probe.
fn buchner_p1(m: Measured<'_>) -> f64 {
    m.probes.map_or(f64::NAN, |table| {
        let trixi = wall_pressure::trixi_sensor(&table);
        wall_pressure::grade(wall_pressure::sensor(&table), trixi.as_deref())
            .trixi
            .0
    })
}

/// The dam breaks' recording: the water front every 20 steps.
fn fronts() -> Recording {
    Recording {
        every: 20,
        front: true,
        ..Default::default()
    }
}

fn studies() -> [Study; 6] {
    [
        sod_tube(),
        elliptical_drop(),
        dam_break_box(),
        dam_break_walls(),
        buchner(),
        dam_break_3d(),
    ]
}

/// The Sod tube: equal masses (variable h) under DualSupport and grad-h, and the adaptive
/// tube, against uniform spacing.
fn sod_tube() -> Study {
    Study::new(
        "Sod shock tube",
        "density L1 on [−0.5, 0.5]",
        vec![
            Variant::new("DualSupport, equal masses (variable h)", "sod_1d.ron"),
            Variant {
                formulation: Some(Formulation::GradH),
                ..Variant::new("grad-h, equal masses (variable h)", "sod_1d.ron")
            },
            Variant::new(
                "adaptive: splits at the shock and the contact",
                "sod_1d_adaptive.ron",
            ),
            Variant::new("uniform spacing", "sod_1d_uniform.ron"),
        ],
        |m| sod::grade(m.run).l1[0],
    )
}

/// The elliptical drop: a half-spacing quadrant against uniform fine spacing.
fn elliptical_drop() -> Study {
    Study::new(
        "Elliptical drop",
        "|b/b_ODE − 1| at t = 0.008 s",
        vec![
            Variant::new("DualSupport, half-spacing quadrant", "drop_2d.ron"),
            Variant::new("uniform fine spacing", "drop_2d_uniform.ron"),
        ],
        |m| {
            let g = drop::grade(m.run);
            (g.axes.1 / g.ode.1 - 1.0).abs()
        },
    )
}

/// The paper's dam break in a specular box: Case II (two resolutions) against Case III.
fn dam_break_box() -> Study {
    Study {
        end_time: Some(0.75),
        recording: fronts(),
        ..Study::new(
            "Dam break",
            "front RMS vs Koshizuka & Oka, t ≤ 0.70 s (m)",
            vec![
                Variant::new("Case II: DualSupport, two resolutions", "dam_break_2d.ron"),
                Variant::new(
                    "Case III: uniform fine, constant h",
                    "dam_break_2d_uniform.ron",
                ),
            ],
            |m| dam_break::grade(m.run).front_rms_experiment,
        )
    }
}

/// The dam break with walls of particles: adaptive and static two-level against uniform, every front against a uniform run at half the finest spacing.
fn dam_break_walls() -> Study {
    let variants = vec![
        Variant::new(
            "adaptive: 0.025 m, split to 0.0125 m at the surface and walls",
            "dam_break_2d_walls_adaptive.ron",
        ),
        Variant::new(
            "static: 0.0125 m below y = 0.5 m, 0.025 m above",
            "dam_break_2d_walls_two_level.ron",
        ),
        Variant {
            scale: 0.5,
            ..Variant::new("uniform 0.0125 m", "dam_break_2d_walls.ron")
        },
    ];
    Study {
        end_time: Some(0.75),
        recording: fronts(),
        reference: Some(("dam_break_2d_walls.ron", 0.25)),
        ..Study::new(
            "Dam break, walls of particles",
            "front RMS vs uniform Δx = 0.00625 m, t ≤ 0.70 s (m)",
            variants,
            |m| {
                m.reference
                    .map_or(f64::NAN, |r| dam_break::front_rms_between(&m.run, r))
            },
        )
    }
}

/// An adaptive scene at its own resolution only, and a uniform one labelled "uniform" at
/// the study's factors.
fn adaptive_and_uniform(
    label: &'static str,
    adaptive: &'static str,
    uniform: &'static str,
) -> Vec<Variant> {
    vec![
        Variant {
            factors: Some(&[1.0]),
            ..Variant::new(label, adaptive)
        },
        Variant::new("uniform", uniform),
    ]
}

/// Buchner's wall pressure: the adaptive scene at its own resolution against the uniform tank at H/20, H/40 and H/80.
fn buchner() -> Study {
    let variants = adaptive_and_uniform(
        "adaptive: H/40, split to H/80 by the impact wall and the surface",
        "dam_break_buchner_2d_adaptive.ron",
        "dam_break_buchner_2d.ron",
    );
    Study {
        factors: &[2.0, 1.0, 0.5],
        end_time: Some(BUCHNER_END),
        recording: Recording {
            every: 200,
            ..Default::default()
        },
        probes: true,
        ..Study::new(
            "Buchner's wall pressure",
            "mean |Δp*| at P1 vs Buchner, t* 2–6.5",
            variants,
            buchner_p1,
        )
    }
}

/// The 3-D dam break (specular walls): the adaptive column at its own resolution against the
/// uniform column at 0.1, 0.05 and 0.025 m, every front against Koshizuka & Oka's.
fn dam_break_3d() -> Study {
    let variants = adaptive_and_uniform(
        "adaptive: 0.05 m, split to 0.025 m in the lowest 0.25 m",
        "dam_break_3d_adaptive.ron",
        "dam_break_3d_uniform.ron",
    );
    Study {
        factors: &[2.0, 1.0, 0.5],
        end_time: Some(0.75),
        recording: fronts(),
        ..Study::new(
            "Dam break in 3-D",
            "front RMS vs Koshizuka & Oka, t ≤ 0.70 s (m)",
            variants,
            |m| dam_break::grade(m.run).front_rms_experiment,
        )
    }
}

/// The end of Buchner's record (s): t* = 6.5, the end of TrixiParticles.jl's window.
const BUCHNER_END: f64 = 1.6;

/// The study's scene `file` with every spacing multiplied by `factor`, to the study's end.
fn scene_at(
    study: &Study,
    opts: &ReportOptions,
    file: &str,
    factor: f64,
) -> Result<dualsph_scene::Scene, ReportError> {
    let mut scene = opts.scene(file)?;
    coarsen(&mut scene, factor);
    if let Some(t) = study.end_time {
        scene.end_time = t;
    }
    Ok(scene)
}

fn run_study(study: &Study, opts: &ReportOptions) -> Result<Vec<Point>, ReportError> {
    let reference = match study.reference {
        Some((file, factor)) => {
            let spec = CaseSpec::new(
                format!("{} — reference, {file} spacing × {factor}", study.name),
                scene_at(study, opts, file, factor)?,
                None,
            );
            let run = opts.run(&spec, &study.recording)?;
            // a reference cut short would measure every error over part of the window
            if let Some(why) = &run.failure {
                return Err(ReportError::Run(format!(
                    "{}: the reference run stopped early: {why}",
                    spec.label
                )));
            }
            Some(run)
        }
        None => None,
    };
    let mut points = Vec::new();
    for v in &study.variants {
        for &factor in v.factors.unwrap_or(study.factors) {
            let spec = CaseSpec::new(
                format!("{} — {}, spacing × {factor}", study.name, v.label),
                scene_at(study, opts, v.file, factor * v.scale)?,
                v.formulation,
            );
            let (run, probes) = run_with_probes(study, opts, &spec)?;
            points.push(Point {
                variant: v.label.into(),
                factor,
                particles: run.particles,
                particles_end: run.last.len() as u64,
                steps: run.steps,
                cpu_seconds: run.cpu_seconds,
                failure: run.failure.clone(),
                error: (study.error)(Measured {
                    run,
                    reference: reference.as_ref(),
                    probes,
                }),
            });
        }
    }
    Ok(points)
}

/// Runs one case of the study; when the study reads probes, they are written to a scratch
/// directory, read back and the directory removed.
fn run_with_probes(
    study: &Study,
    opts: &ReportOptions,
    spec: &CaseSpec,
) -> Result<(CaseRun, Option<ProbeTable>), ReportError> {
    if !study.probes {
        return Ok((opts.run(spec, &study.recording)?, None));
    }
    let dir = tempfile::tempdir().map_err(|e| ReportError::Run(format!("scratch: {e}")))?;
    let rec = Recording {
        output_dir: Some(dir.path().to_path_buf()),
        ..study.recording.clone()
    };
    let run = opts.run(spec, &rec)?;
    let table = dualsph_probes::read_probes(dir.path()).map_err(ReportError::Output)?;
    Ok((run, Some(table)))
}

/// Runs the study, plots error against CPU time per benchmark, and writes the section.
pub fn run(
    opts: &ReportOptions,
) -> Result<(Section, Vec<(&'static str, Vec<Point>)>), ReportError> {
    let mut body = String::from(
        "Each benchmark at three resolutions (particle spacing × 4, × 2, × 1 relative to its scene; Buchner's \
         uniform tank at × 2, × 1, × 0.5, that is H/20, H/40 and H/80, and the 3-D uniform column likewise, \
         at 0.1, 0.05 and 0.025 m; their adaptive scenes at their own resolution only), with variable resolution under DualSupport against uniform resolution. CPU seconds are \
         of the stepping loop, all threads. A variant is cheaper when its curve lies to the left at the same error. \
         The walls dam break's fronts are measured against a uniform run at half its finest spacing \
         (Δx = 0.00625 m, run once); Buchner's sensor P1 against the experiment, as TrixiParticles.jl measures it \
         (the scenes' `P1_sensor`, mean |Δp*| over t* 2–6.5, as in the walls report). The adaptive variants split \
         and merge particles during the run (`Refinement`): their particle counts are given at the start and at \
         the end.\n\n",
    );
    let mut all = Vec::new();
    for study in studies() {
        let points = run_study(&study, opts)?;
        let mut table = Table::new([
            "variant",
            "spacing ×",
            "particles",
            "steps",
            "CPU s",
            study.error_name,
        ]);
        let mut plot = LinePlot::new(
            format!("{}: error against CPU time", study.name),
            "CPU seconds",
            study.error_name,
        );
        plot.log_x = true;
        plot.log_y = true;
        for (k, v) in study.variants.iter().enumerate() {
            let label = v.label;
            let mine: Vec<&Point> = points.iter().filter(|p| p.variant == label).collect();
            for p in &mine {
                table.row(row(p));
            }
            let pts = mine
                .iter()
                .map(|p| (p.cpu_seconds.max(1e-3), p.error.max(1e-12)))
                .collect();
            plot = plot.with(Series::new(label, pts, SeriesStyle::LineMarkers, k));
        }
        let png = opts.file(&format!("speed_error_{}.png", file_stem(study.name)));
        plot.write_png(&png)?;
        body += &format!(
            "### {}\n\n{}{}",
            study.name,
            table.render(),
            image(&format!("{} error against CPU time", study.name), &png)
        );
        body += &compare(&points, &study);
        all.push((study.name, points));
    }
    Ok((
        Section {
            title: "Speed against error".into(),
            body,
        },
        all,
    ))
}

/// The study's name as a file name: its words in lower case (apostrophes dropped), joined
/// by `_`.
fn file_stem(name: &str) -> String {
    name.to_lowercase()
        .replace(['\'', '’'], "")
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .collect::<Vec<_>>()
        .join("_")
}

/// A table row: the particles as start → end where they changed, and a run that stopped
/// early marked beside its error.
fn row(p: &Point) -> Vec<String> {
    let particles = if p.particles_end == p.particles {
        p.particles.to_string()
    } else {
        format!("{} → {}", p.particles, p.particles_end)
    };
    let error = match &p.failure {
        None => format!("{:.3e}", p.error),
        Some(why) => format!("{:.3e} (stopped early: {why})", p.error),
    };
    vec![
        p.variant.clone(),
        format!("{}", p.factor),
        particles,
        p.steps.to_string(),
        format!("{:.2}", p.cpu_seconds),
        error,
    ]
}

/// The uniform variant of a study (its last).
fn uniform(study: &Study) -> &'static str {
    study.variants.last().map_or("", |v| v.label)
}

/// Each variable-resolution variant's finest run against the uniform runs: CPU ratio at
/// comparable error.
fn compare(points: &[Point], study: &Study) -> String {
    let finest = |label: &str| {
        points
            .iter()
            .filter(|p| p.variant == label)
            .min_by(|a, b| a.factor.total_cmp(&b.factor))
    };
    let Some(uni) = finest(uniform(study)) else {
        return String::new();
    };
    let mut md = String::new();
    for v in &study.variants[..study.variants.len() - 1] {
        let Some(var) = finest(v.label) else { continue };
        md += &format!(
            "At the finest resolution each ran, {} reaches an error of {:.3e} in {:.1} CPU s with {} particles; {} \
             reaches {:.3e} in {:.1} CPU s with {} particles (CPU ratio {:.2}).\n\n",
            var.variant,
            var.error,
            var.cpu_seconds,
            var.particles,
            uni.variant,
            uni.error,
            uni.cpu_seconds,
            uni.particles,
            var.cpu_seconds / uni.cpu_seconds.max(1e-9)
        );
        md += &matched(points, study, var);
    }
    md
}

/// CPU seconds the uniform variant would need to reach the variable-resolution run's error:
/// log-log interpolation between the two uniform runs whose errors bracket it.
fn matched(points: &[Point], study: &Study, var: &Point) -> String {
    let mut uni: Vec<&Point> = points
        .iter()
        .filter(|p| p.variant == uniform(study))
        .collect();
    uni.sort_by(|a, b| a.cpu_seconds.total_cmp(&b.cpu_seconds));
    match cpu_at_error(&uni, var.error) {
        Some(cpu) => {
            let ratio = cpu / var.cpu_seconds.max(1e-9);
            let verdict = if ratio >= 1.0 {
                format!("{} is {ratio:.1}× cheaper", var.variant)
            } else {
                format!("{} costs {:.1}× more", var.variant, 1.0 / ratio)
            };
            format!(
                "To reach the same error ({:.3e}), {} would need about {:.1} CPU s (log-log \
                 interpolation between its runs): {verdict}.\n\n",
                var.error,
                uniform(study),
                cpu,
            )
        }
        None => format!(
            "The error {:.3e} lies outside the range the uniform runs span, so no CPU time at \
             equal error is interpolated.\n\n",
            var.error
        ),
    }
}

/// Interpolates `log cpu` linearly in `log error` between consecutive runs (sorted by CPU)
/// whose errors bracket `target`.
fn cpu_at_error(runs: &[&Point], target: f64) -> Option<f64> {
    runs.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        let (lo, hi) = (a.error.min(b.error), a.error.max(b.error));
        if !(target > 0.0 && lo > 0.0 && (lo..=hi).contains(&target)) || a.error == b.error {
            return None;
        }
        let t =
            (libm::log(target) - libm::log(a.error)) / (libm::log(b.error) - libm::log(a.error));
        Some(libm::exp(
            libm::log(a.cpu_seconds) + t * (libm::log(b.cpu_seconds) - libm::log(a.cpu_seconds)),
        ))
    })
}

#[cfg(test)]
mod tests;
