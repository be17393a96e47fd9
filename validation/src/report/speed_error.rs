//! Speed against error: the Sod tube, the drop and the dam break at three resolutions each,
//! variable resolution with DualSupport against uniform resolution, as error against CPU
//! seconds. The question it answers: to reach a given error, how much cheaper is variable
//! resolution with DualSupport?

use super::{
    CaseRun, CaseSpec, Recording, ReportError, ReportOptions, Section, Table, coarsen, dam_break,
    drop, image, sod,
};
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_scene::Formulation;

/// One run of the study.
#[derive(Clone, Debug)]
pub struct Point {
    /// Variant label.
    pub variant: String,
    /// Spacing multiplier relative to the scene.
    pub factor: f64,
    /// Particles.
    pub particles: u64,
    /// Steps.
    pub steps: u64,
    /// CPU seconds of the stepping loop.
    pub cpu_seconds: f64,
    /// The benchmark's error measure.
    pub error: f64,
}

/// A benchmark of the study: its variants (label, scene file), the spacing multipliers, the
/// error measure and how to run it.
struct Study {
    name: &'static str,
    error_name: &'static str,
    /// `(label, scene file, formulation replacing the scene's)`.
    variants: Vec<(&'static str, &'static str, Option<Formulation>)>,
    factors: [f64; 3],
    end_time: Option<f64>,
    recording: Recording,
    error: fn(CaseRun) -> f64,
}

fn studies() -> [Study; 3] {
    [
        Study {
            name: "Sod shock tube",
            error_name: "density L1 on [−0.5, 0.5]",
            variants: vec![
                ("DualSupport, equal masses (variable h)", "sod_1d.ron", None),
                (
                    "grad-h, equal masses (variable h)",
                    "sod_1d.ron",
                    Some(Formulation::GradH),
                ),
                ("uniform spacing", "sod_1d_uniform.ron", None),
            ],
            factors: [4.0, 2.0, 1.0],
            end_time: None,
            recording: Recording {
                every: 10,
                ..Default::default()
            },
            error: |run| sod::grade(run).l1[0],
        },
        Study {
            name: "Elliptical drop",
            error_name: "|b/b_ODE − 1| at t = 0.008 s",
            variants: vec![
                ("DualSupport, half-spacing quadrant", "drop_2d.ron", None),
                ("uniform fine spacing", "drop_2d_uniform.ron", None),
            ],
            factors: [4.0, 2.0, 1.0],
            end_time: None,
            recording: Recording {
                every: 10,
                ..Default::default()
            },
            error: |run| {
                let g = drop::grade(run);
                (g.axes.1 / g.ode.1 - 1.0).abs()
            },
        },
        Study {
            name: "Dam break",
            error_name: "front RMS vs Koshizuka & Oka, t ≤ 0.70 s (m)",
            variants: vec![
                (
                    "Case II: DualSupport, two resolutions",
                    "dam_break_2d.ron",
                    None,
                ),
                (
                    "Case III: uniform fine, constant h",
                    "dam_break_2d_uniform.ron",
                    None,
                ),
            ],
            factors: [4.0, 2.0, 1.0],
            end_time: Some(0.75),
            recording: Recording {
                every: 20,
                front: true,
                ..Default::default()
            },
            error: |run| dam_break::grade(run).front_rms_experiment,
        },
    ]
}

fn run_study(study: &Study, opts: &ReportOptions) -> Result<Vec<Point>, ReportError> {
    let mut points = Vec::new();
    for &(label, file, formulation) in &study.variants {
        for factor in study.factors {
            let mut scene = opts.scene(file)?;
            coarsen(&mut scene, factor);
            if let Some(t) = study.end_time {
                scene.end_time = t;
            }
            let spec = CaseSpec::new(
                format!("{} — {label}, spacing × {factor}", study.name),
                scene,
                formulation,
            );
            let run = opts.run(&spec, &study.recording)?;
            let (particles, steps, cpu_seconds) = (run.particles, run.steps, run.cpu_seconds);
            points.push(Point {
                variant: label.into(),
                factor,
                particles,
                steps,
                cpu_seconds,
                error: (study.error)(run),
            });
        }
    }
    Ok(points)
}

/// Runs the study, plots error against CPU time per benchmark, and writes the section.
pub fn run(
    opts: &ReportOptions,
) -> Result<(Section, Vec<(&'static str, Vec<Point>)>), ReportError> {
    let mut body = String::from(
        "Each benchmark at three resolutions (particle spacing × 4, × 2, × 1 relative to its scene), with variable \
         resolution under DualSupport against uniform resolution. CPU seconds are of the stepping loop, all threads. \
         A variant is cheaper when its curve lies to the left at the same error.\n\n",
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
        for (k, (label, ..)) in study.variants.iter().enumerate() {
            let mine: Vec<&Point> = points.iter().filter(|p| p.variant == *label).collect();
            for p in &mine {
                table.row(vec![
                    p.variant.clone(),
                    format!("{}", p.factor),
                    p.particles.to_string(),
                    p.steps.to_string(),
                    format!("{:.2}", p.cpu_seconds),
                    format!("{:.3e}", p.error),
                ]);
            }
            let pts = mine
                .iter()
                .map(|p| (p.cpu_seconds.max(1e-3), p.error.max(1e-12)))
                .collect();
            plot = plot.with(Series::new(*label, pts, SeriesStyle::LineMarkers, k));
        }
        let png = opts.file(&format!(
            "speed_error_{}.png",
            study.name.to_lowercase().replace(' ', "_")
        ));
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

/// The uniform variant of a study (its last).
fn uniform(study: &Study) -> &'static str {
    study.variants.last().map_or("", |v| v.0)
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
    for &(label, ..) in &study.variants[..study.variants.len() - 1] {
        let Some(var) = finest(label) else { continue };
        md += &format!(
            "At the scenes' own resolution, {} reaches an error of {:.3e} in {:.1} CPU s with {} particles; {} \
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
        let t = (target.ln() - a.error.ln()) / (b.error.ln() - a.error.ln());
        Some((a.cpu_seconds.ln() + t * (b.cpu_seconds.ln() - a.cpu_seconds.ln())).exp())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(cpu: f64, error: f64) -> Point {
        Point {
            variant: "u".into(),
            factor: 1.0,
            particles: 1,
            steps: 1,
            cpu_seconds: cpu,
            error,
        }
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
}
