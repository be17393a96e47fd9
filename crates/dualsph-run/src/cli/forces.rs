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
    /// Smooth the coefficients by a centred moving average over this many seconds before the
    /// summary (their extremes and the lift's spectrum): the loads of a weakly compressible
    /// fluid carry noise. `force_coefficients.csv` keeps the unsmoothed values.
    #[arg(long)]
    pub smooth: Option<f64>,
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
    /// The lift's frequency (Hz): the peak of its amplitude spectrum over the window
    /// ([`spectral_peak`]).
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

/// The frequency of a periodic signal: the peak of its amplitude spectrum
/// `A(f) = (2/T) |∫ (s(t) − s̄) e^{−2πift} dt|` over the window T (the signal drawn linearly
/// through the samples, each segment integrated by the trapezoid rule), searched from two
/// periods per window to a quarter of the mean sampling rate on a grid of `1/(8T)`, then
/// refined by golden-section search within a grid step of the best point. A peak of the
/// spectrum, not the crossings of the mean, so that broadband noise does not add crossings
/// (the loads of a weakly compressible fluid carry it). `None` for fewer than eight samples
/// or a flat signal. Returns `(f, A(f))`.
pub fn spectral_peak(signal: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = signal.len();
    if n < 8 {
        return None;
    }
    let span = signal[n - 1].0 - signal[0].0;
    let mean = signal
        .windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum::<f64>()
        / span;
    let amplitude = |f: f64| {
        let w = 2.0 * std::f64::consts::PI * f;
        let (mut re, mut im) = (0.0, 0.0);
        for p in signal.windows(2) {
            let ((t0, y0), (t1, y1)) = (p[0], p[1]);
            let (a, b) = ((y0 - mean) * 0.5 * (t1 - t0), (y1 - mean) * 0.5 * (t1 - t0));
            re += a * libm::cos(w * t0) + b * libm::cos(w * t1);
            im += a * libm::sin(w * t0) + b * libm::sin(w * t1);
        }
        2.0 * libm::hypot(re, im) / span
    };
    let step = 1.0 / (8.0 * span);
    let (lo, hi) = (2.0 / span, 0.25 * (n - 1) as f64 / span);
    let grid = (0..).map(|k| lo + k as f64 * step).take_while(|&f| f <= hi);
    let (best, peak) = grid
        .map(|f| (f, amplitude(f)))
        .fold(
            (lo, f64::NEG_INFINITY),
            |b, c| if c.1 > b.1 { c } else { b },
        );
    if peak.is_nan() || peak <= 0.0 {
        return None;
    }
    // golden-section search for the maximum in [best − step, best + step]
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (best - step, best + step);
    for _ in 0..40 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if amplitude(c) > amplitude(d) {
            b = d;
        } else {
            a = c;
        }
    }
    let f = 0.5 * (a + b);
    Some((f, amplitude(f)))
}

/// The centred moving average of `series` over `width` seconds: each row whose window
/// `[t − width/2, t + width/2]` lies inside the series becomes the mean over the window of the
/// piecewise-linear signal through the rows (so rows unevenly spaced in time, as an adaptive
/// step writes them, weigh by the time they cover), and the rows nearer either end than
/// `width/2` are dropped. This boxcar passes a sinusoid of frequency f with the gain
/// `sin(π f T)/(π f T)` ([`boxcar_gain`]) and removes the components at multiples of `1/T`.
pub fn moving_average(series: &[(f64, [f64; 3])], width: f64) -> Vec<(f64, [f64; 3])> {
    let (Some(first), Some(last)) = (series.first(), series.last()) else {
        return Vec::new();
    };
    let half = 0.5 * width;
    (series.iter())
        .filter(|(t, _)| t - half >= first.0 && t + half <= last.0)
        .map(|&(t, _)| (t, integral(series, t - half, t + half).map(|v| v / width)))
        .collect()
}

/// `∫_a^b c(t) dt` of the piecewise-linear signal through `series` (`a ≤ b` inside it): the
/// trapezoids of the segments that overlap `[a, b]`, each clipped to it.
fn integral(series: &[(f64, [f64; 3])], a: f64, b: f64) -> [f64; 3] {
    let start = series.partition_point(|s| s.0 <= a).saturating_sub(1);
    let mut sum = [0.0; 3];
    for w in series[start..].windows(2) {
        let ((t0, c0), (t1, c1)) = (w[0], w[1]);
        if t0 >= b {
            break;
        }
        let (lo, hi) = (t0.max(a), t1.min(b));
        if hi <= lo {
            continue;
        }
        let at = |t: f64, k: usize| c0[k] + (c1[k] - c0[k]) * (t - t0) / (t1 - t0);
        for k in 0..3 {
            sum[k] += 0.5 * (at(lo, k) + at(hi, k)) * (hi - lo);
        }
    }
    sum
}

/// The gain of a boxcar average of width `width` at the frequency `f`:
/// `sin(π f T)/(π f T)`.
pub fn boxcar_gain(f: f64, width: f64) -> f64 {
    let x = std::f64::consts::PI * f * width;
    if x == 0.0 { 1.0 } else { libm::sin(x) / x }
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
        frequency: spectral_peak(&lift).map(|p| p.0),
    })
}

/// The command: reads, writes `force_coefficients.csv`, prints the summary.
pub(crate) fn forces_command(a: &ForcesArgs) -> Result<(), Failure> {
    let invalid = |m: String| Failure::new(exit::INVALID_INPUT, m);
    for (name, v) in [
        ("--density", a.density),
        ("--speed", a.speed),
        ("--reference", a.reference),
        ("--smooth", a.smooth.unwrap_or(1.0)),
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
    let smoothed = match a.smooth {
        Some(width) => moving_average(&series, width),
        None => series,
    };
    let Some(s) = summarise(&smoothed, from) else {
        return Err(invalid(format!(
            "--from {from}: fewer than two rows of `{}` at or after it (the last is at t = \
             {end}{})",
            a.body,
            match a.smooth {
                Some(w) => format!(
                    ", and --smooth {w} drops the rows within {} s of it",
                    w / 2.0
                ),
                None => String::new(),
            }
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
    if let Some(w) = a.smooth {
        crate::say!("  (smoothed by a moving average over {w} s)");
    }
    match s.frequency {
        Some(f) => {
            crate::say!(
                "  lift frequency {f:.5} Hz, Strouhal number f L/U = {:.5}",
                f * a.reference / a.speed
            );
            if let Some(w) = a.smooth {
                crate::say!(
                    "  the smoothing keeps {:.4} of an oscillation at that frequency",
                    boxcar_gain(f, w)
                );
            }
        }
        None => crate::say!("  the lift is flat or has too few rows for its spectrum"),
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
                (
                    t,
                    0.3 + libm::sin(2.0 * std::f64::consts::PI * 3.7 * t + 0.4),
                )
            })
            .collect()
    }

    #[test]
    fn the_frequency_of_a_noisy_sine_is_its_spectrums_peak() {
        let (f, a) = spectral_peak(&sine()).unwrap();
        assert!(
            (f / 3.7 - 1.0).abs() < 1e-3 && (a - 1.0).abs() < 0.01,
            "{f} {a}"
        );
        // twice the tone's amplitude in deterministic broadband noise (a linear congruential
        // sequence), which crosses the mean hundreds of times: the peak stays on the tone
        let mut x: u64 = 12345;
        let noisy: Vec<(f64, f64)> = sine()
            .into_iter()
            .map(|(t, y)| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (t, y + 4.0 * ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5))
            })
            .collect();
        let (f, a) = spectral_peak(&noisy).unwrap();
        assert!(
            (f / 3.7 - 1.0).abs() < 5e-3 && (a - 1.0).abs() < 0.15,
            "{f} {a}"
        );
        let flat: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 1.0)).collect();
        assert_eq!(spectral_peak(&flat), None);
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
    fn a_moving_average_removes_a_tone_at_its_width_and_keeps_a_slow_one_by_its_gain() {
        // 3.7 Hz plus a tone at 50 Hz, sampled every 1 ms; a 20 ms boxcar holds a whole period
        // of the fast tone and passes the slow one with sin(π f T)/(π f T), to the error of
        // the linear interpolation between samples
        let series: Vec<(f64, [f64; 3])> = (0..=2000)
            .map(|i| {
                let t = 1e-3 * i as f64;
                let w = |f: f64| libm::sin(2.0 * std::f64::consts::PI * f * t);
                (t, [w(3.7) + 0.5 * w(50.0), 1.0, 0.0])
            })
            .collect();
        let width = 0.02;
        let m = moving_average(&series, width);
        assert_eq!(m.len(), series.len() - 20);
        assert!((m[0].0 - 0.01).abs() < 1e-12 && (m[m.len() - 1].0 - 1.99).abs() < 1e-12);
        let gain = boxcar_gain(3.7, width);
        for (t, c) in &m {
            let exact = gain * libm::sin(2.0 * std::f64::consts::PI * 3.7 * t);
            assert!(
                (c[0] - exact).abs() < 2e-4,
                "t {t}: {} against {exact}",
                c[0]
            );
            assert!((c[1] - 1.0).abs() < 1e-12);
        }
        assert!(moving_average(&series, 5.0).is_empty());
        assert_eq!(boxcar_gain(0.0, 1.0), 1.0);
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
