//! `dualsph forces DIR --body NAME --density ρ --speed U --reference L`: the force coefficients
//! of a body from its loads in `DIR/bodies.csv`, `c_k = 2 F_k / (ρ U² L)` for a flow along +x
//! (c_D = c_x, c_L = c_y; in 3-D c_z too and L an area), written to
//! `DIR/force_coefficients.csv`, with their mean, extremes and the Strouhal number
//! `St = f L / U` of the lift over the window `t ≥ --from` (default: the second half of the run, and at
//! least its last two rows) — the quantities of the DFG benchmarks (Schäfer & Turek 1996, §2.2)
//! and of the cylinder's wake (Williamson 1996).

use super::exit::{self, Failure};
use dualsph_io::{BodyLoadRow, read_body_loads, write_atomic_with};
use std::io::Write;
use std::path::Path;

/// What `forces` reads from the command line.
#[derive(clap::Args)]
pub(crate) struct ForcesArgs {
    /// The run's output directory (its bodies.csv).
    pub dir: std::path::PathBuf,
    /// The body whose load is read (a fixed or prescribed body of the scene).
    #[arg(long)]
    pub body: String,
    /// The fluid's reference density ρ (kg/m³).
    #[arg(long)]
    pub density: f64,
    /// The reference speed U (m/s), e.g. the mean inflow speed.
    #[arg(long)]
    pub speed: f64,
    /// The reference length L (2-D, where the load is per unit depth: e.g. the diameter, m)
    /// or area (3-D, m²); also the length of the Strouhal number.
    #[arg(long)]
    pub reference: f64,
    /// Start of the window the summary is taken over (s); default: half the run's end time.
    #[arg(long)]
    pub from: Option<f64>,
}

/// The summary of the coefficients over the window.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The window's first and last time and its number of rows.
    pub window: (f64, f64, usize),
    /// Mean of c_x, c_y, c_z.
    pub mean: [f64; 3],
    /// Least c_x, c_y, c_z.
    pub min: [f64; 3],
    /// Largest c_x, c_y, c_z.
    pub max: [f64; 3],
    /// The lift's frequency (Hz), when it crosses its mean upwards at least three times.
    pub frequency: Option<f64>,
}

/// `2 F / (ρ U² L)` of every row: `(t, [c_x, c_y, c_z])`.
pub fn coefficients(rows: &[BodyLoadRow], dynamic: f64) -> Vec<(f64, [f64; 3])> {
    rows.iter()
        .map(|r| (r.t, r.force.map(|f| f / dynamic)))
        .collect()
}

/// The times at which `signal` crosses `level` upwards, each interpolated linearly between
/// the samples either side.
pub fn upward_crossings(signal: &[(f64, f64)], level: f64) -> Vec<f64> {
    signal
        .windows(2)
        .filter(|w| w[0].1 < level && w[1].1 >= level)
        .map(|w| {
            let ((t0, y0), (t1, y1)) = (w[0], w[1]);
            t0 + (t1 - t0) * (level - y0) / (y1 - y0)
        })
        .collect()
}

/// The frequency of a periodic signal from its upward crossings of its mean: `(n − 1)` periods
/// between the first and the last of n ≥ 3 crossings.
pub(crate) fn frequency(signal: &[(f64, f64)]) -> Option<f64> {
    let mean = signal.iter().map(|s| s.1).sum::<f64>() / signal.len().max(1) as f64;
    let c = upward_crossings(signal, mean);
    (c.len() >= 3).then(|| (c.len() - 1) as f64 / (c[c.len() - 1] - c[0]))
}

/// The default window's start: the second half of the run, widened to hold at least its last
/// two rows (a short run has few diagnostics rows).
fn default_from(series: &[(f64, [f64; 3])]) -> f64 {
    let end = series[series.len() - 1].0;
    let second_last = series[series.len().saturating_sub(2)].0;
    (0.5 * end).min(second_last)
}

/// The summary of `series` over `t ≥ from`; none when the window holds fewer than two rows.
pub fn summarise(series: &[(f64, [f64; 3])], from: f64) -> Option<Summary> {
    let w: Vec<_> = series.iter().filter(|s| s.0 >= from).copied().collect();
    if w.len() < 2 {
        return None;
    }
    let n = w.len() as f64;
    let (mut mean, mut min, mut max) = ([0.0; 3], [f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for (_, c) in &w {
        for k in 0..3 {
            mean[k] += c[k] / n;
            min[k] = min[k].min(c[k]);
            max[k] = max[k].max(c[k]);
        }
    }
    let lift: Vec<(f64, f64)> = w.iter().map(|(t, c)| (*t, c[1])).collect();
    Some(Summary {
        window: (w[0].0, w[w.len() - 1].0, w.len()),
        mean,
        min,
        max,
        frequency: frequency(&lift),
    })
}

/// The command: reads, writes `force_coefficients.csv`, prints the summary.
pub(crate) fn forces_command(a: &ForcesArgs) -> Result<(), Failure> {
    let invalid = |m: String| Failure::new(exit::INVALID_INPUT, m);
    for (name, v) in [
        ("--density", a.density),
        ("--speed", a.speed),
        ("--reference", a.reference),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(invalid(format!(
                "{name}: must be a positive number, got {v}"
            )));
        }
    }
    let path = a.dir.join(dualsph_io::BODIES_FILE);
    super::require_file(&path)?;
    let rows = read_body_loads(&path, &a.body).map_err(|e| invalid(e.to_string()))?;
    if rows.is_empty() {
        return Err(invalid(format!(
            "{}: no load of a body `{}` (the scene's fixed and prescribed bodies are listed \
             in its `body` column)",
            path.display(),
            a.body
        )));
    }
    let dynamic = 0.5 * a.density * a.speed * a.speed * a.reference;
    let series = coefficients(&rows, dynamic);
    let out = a.dir.join("force_coefficients.csv");
    write_table(&out, &series).map_err(|e| Failure::new(exit::IO, e.to_string()))?;
    crate::say!("wrote {}", out.display());
    let end = series[series.len() - 1].0;
    let from = a.from.unwrap_or_else(|| default_from(&series));
    let Some(s) = summarise(&series, from) else {
        return Err(invalid(format!(
            "--from {from}: fewer than two rows of `{}` at or after it (the last is at t = \
             {end})",
            a.body
        )));
    };
    print_summary(a, &s);
    Ok(())
}

fn print_summary(a: &ForcesArgs, s: &Summary) {
    let (t0, t1, n) = s.window;
    crate::say!(
        "{}: over t = {t0} to {t1} s ({n} rows), 2F/(ρU²L) with ρ = {}, U = {}, L = {}:",
        a.body,
        a.density,
        a.speed,
        a.reference
    );
    for (k, name) in ["c_D (x)", "c_L (y)", "c_z"].iter().enumerate() {
        crate::say!(
            "  {name}: mean {:.5}, min {:.5}, max {:.5}",
            s.mean[k],
            s.min[k],
            s.max[k]
        );
    }
    match s.frequency {
        Some(f) => crate::say!(
            "  lift frequency {f:.5} Hz, Strouhal number f L/U = {:.5}",
            f * a.reference / a.speed
        ),
        None => crate::say!(
            "  the lift is not periodic over the window (fewer than 3 upward crossings of its mean)"
        ),
    }
}

fn write_table(path: &Path, series: &[(f64, [f64; 3])]) -> Result<(), dualsph_io::OutputError> {
    write_atomic_with(path, |w: &mut dyn Write| {
        writeln!(w, "t,cd,cl,cz")?;
        for (t, c) in series {
            writeln!(w, "{t:?},{:?},{:?},{:?}", c[0], c[1], c[2])?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sampled sine of frequency 3.7 Hz (sampled at 0.01 s over 0–5 s) about a mean of 0.3.
    fn sine() -> Vec<(f64, f64)> {
        (0..=500)
            .map(|i| {
                let t = 0.01 * i as f64;
                (t, 0.3 + (2.0 * std::f64::consts::PI * 3.7 * t + 0.4).sin())
            })
            .collect()
    }

    #[test]
    fn the_frequency_of_a_sine_is_found_from_its_crossings() {
        let f = frequency(&sine()).unwrap();
        assert!((f / 3.7 - 1.0).abs() < 2e-3, "{f}");
        let flat: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 1.0)).collect();
        assert_eq!(frequency(&flat), None);
    }

    #[test]
    fn crossings_are_interpolated_between_samples() {
        let s = [(0.0, -1.0), (1.0, 3.0), (2.0, -1.0)];
        assert_eq!(upward_crossings(&s, 0.0), vec![0.25]);
    }

    #[test]
    fn the_summary_is_over_the_window_and_the_coefficient_scales_by_the_dynamic_pressure() {
        let rows: Vec<BodyLoadRow> = (0..=10)
            .map(|i| BodyLoadRow {
                t: i as f64,
                step: i,
                body: "c".into(),
                force: [0.002 * i as f64, 0.0, 0.0],
                moment: [0.0; 3],
            })
            .collect();
        // ρ = 1, U = 0.2, L = 0.1: ρU²L/2 = 0.002
        let series = coefficients(&rows, 0.002);
        assert!((series[3].1[0] - 3.0).abs() < 1e-12);
        let s = summarise(&series, 6.0).unwrap();
        assert_eq!(s.window, (6.0, 10.0, 5));
        assert!((s.mean[0] - 8.0).abs() < 1e-12 && s.min[0] == 6.0 && s.max[0] == 10.0);
        assert_eq!(summarise(&series, 10.0), None);
    }

    #[test]
    fn the_default_window_is_the_second_half_and_at_least_two_rows() {
        let series = |ts: &[f64]| ts.iter().map(|&t| (t, [0.0; 3])).collect::<Vec<_>>();
        assert_eq!(default_from(&series(&[0.0, 1.0, 2.0, 3.0, 4.0])), 2.0);
        // three rows at 0, 0.3, 0.6: the half (0.3) holds two; two rows: both
        assert_eq!(default_from(&series(&[0.0, 0.3, 0.6])), 0.3);
        assert_eq!(default_from(&series(&[0.0, 0.4, 1.0])), 0.4);
        assert_eq!(default_from(&series(&[0.0, 1.0])), 0.0);
    }
}
