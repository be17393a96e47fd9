//! The Taylor–Green vortex at Re = 100 in a box periodic on both axes
//! (`scenes/taylor_green_2d.ron`: one wavelength L = 1 m, U = 1 m/s, ν = 0.01 m²/s,
//! Δx = 0.01, 1 s), graded by the decay of its mode.
//!
//! The reference (Taylor & Green 1937, *Mechanism of the production of small eddies from
//! large ones*, Proc. R. Soc. Lond. A 158, 499–521): the velocity
//! `u = U e^{−2νk²t} (sin kx cos ky, −cos kx sin ky)`, `k = 2π/L`. The measure: the
//! projection of the velocity on the mode, `A(t) = Σ m v·û / Σ m |û|²` with
//! `û = (sin kx cos ky, −cos kx sin ky)`, and its decay rate, the least-squares slope of
//! `−ln A(t)` over the snapshots at t = 0.1, 0.2, …, 1 s, against `2νk²`.

use super::super::{
    COST_HEADERS, CaseRun, CaseSpec, Recording, ReportError, ReportOptions, Section, Table,
    cost_cells, failures, image,
};
use super::within;
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use std::f64::consts::PI;

/// Kinematic viscosity of the scene (m²/s).
pub const NU: f64 = 0.01;
/// Wavenumber `k = 2π/L` of the scene's vortex (1/m).
pub const K: f64 = 2.0 * PI;
/// Bound on `|rate / (2νk²) − 1|` over 0.1–1 s.
pub const RATE_BOUND: f64 = 0.02;

/// The analytic amplitude `e^{−2νk²t}`.
pub fn exact_amplitude(t: f64) -> f64 {
    libm::exp(-2.0 * NU * K * K * t)
}

/// The projection `A` (module docs) of particles given as `(x, y, v_x, v_y, m)`.
pub fn mode_amplitude(particles: impl IntoIterator<Item = (f64, f64, f64, f64, f64)>) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (x, y, vx, vy, m) in particles {
        let ((sx, cx), (sy, cy)) = (libm::sincos(K * x), libm::sincos(K * y));
        let (u, v) = (sx * cy, -cx * sy);
        num += m * (vx * u + vy * v);
        den += m * (u * u + v * v);
    }
    num / den
}

/// The least-squares slope of `−ln A(t)` over the amplitudes `(t, A)` given.
pub fn decay_rate(amplitudes: &[(f64, f64)]) -> f64 {
    let n = amplitudes.len() as f64;
    let (mt, ma) = amplitudes.iter().fold((0.0, 0.0), |(x, y), (t, a)| {
        (x + t / n, y + libm::log(*a) / n)
    });
    let sxy: f64 = amplitudes
        .iter()
        .map(|(t, a)| (t - mt) * (libm::log(*a) - ma))
        .sum();
    let sxx: f64 = amplitudes.iter().map(|(t, _)| (t - mt) * (t - mt)).sum();
    -sxy / sxx
}

/// The graded run.
#[derive(Clone, Debug)]
pub struct VortexCase {
    /// The run.
    pub run: CaseRun,
    /// `(t, A)` at every snapshot (every 0.02 s).
    pub amplitudes: Vec<(f64, f64)>,
    /// The decay rate over the snapshots at 0.1, 0.2, …, 1 s (1/s).
    pub rate: f64,
}

impl VortexCase {
    /// `rate / (2νk²) − 1`.
    pub fn rate_error(&self) -> f64 {
        self.rate / (2.0 * NU * K * K) - 1.0
    }
}

/// Grades a run: the amplitude at every snapshot, the rate over those at multiples of 0.1 s.
pub fn grade(run: CaseRun) -> VortexCase {
    let amplitudes: Vec<(f64, f64)> = run
        .snapshots
        .iter()
        .map(|(_, t, ps)| {
            let a = mode_amplitude(
                ps.rows()
                    .map(|p| (p.pos()[0], p.pos()[1], p.vel()[0], p.vel()[1], p.mass())),
            );
            (*t, a)
        })
        .collect();
    let tenths: Vec<(f64, f64)> = run
        .snapshots
        .iter()
        .zip(&amplitudes)
        .filter(|((want, _, _), _)| {
            let tenth = (want * 10.0).round();
            tenth >= 1.0 && (want * 10.0 - tenth).abs() < 1e-6
        })
        .map(|(_, a)| *a)
        .collect();
    let rate = decay_rate(&tenths);
    VortexCase {
        run,
        amplitudes,
        rate,
    }
}

/// Runs, grades, plots and writes the section.
pub fn run(opts: &ReportOptions) -> Result<(Section, Vec<VortexCase>), ReportError> {
    let spec = CaseSpec::new(
        "DualSupport, KernelCorrection",
        opts.scene("taylor_green_2d.ron")?,
        None,
    );
    let rec = Recording {
        every: 20,
        snapshot_times: (1..=50).map(|k| k as f64 * 0.02).collect(),
        ..Default::default()
    };
    let graded = vec![grade(opts.run(&spec, &rec)?)];
    let c = &graded[0];
    let png = plot(opts, c)?;
    let exact = 2.0 * NU * K * K;
    let mut table = Table::new(
        [
            "case",
            "decay rate 0.1–1 s (1/s)",
            "2νk² (1/s)",
            "rate / 2νk² − 1",
            "A(1 s) / e^(−2νk²)",
        ]
        .into_iter()
        .chain(COST_HEADERS),
    );
    let last = c.amplitudes.last().copied().unwrap_or((f64::NAN, f64::NAN));
    let mut cells = vec![
        c.run.label.clone(),
        format!("{:.4}", c.rate),
        format!("{exact:.4}"),
        format!("{:+.2} %", 100.0 * c.rate_error()),
        format!("{:.4}", last.1 / exact_amplitude(last.0)),
    ];
    cells.extend(cost_cells(&c.run));
    table.row(cells);
    let mut body = String::from(
        "One wavelength L = 1 m of the vortex in a box periodic on both axes, U = 1 m/s, \
         ν = 0.01 m²/s (Re = 100), Δx = 0.01 (10,000 particles), c0 = 10 U with a background \
         pressure of 2 ρU², kernel correction, to 1 s (scene `taylor_green_2d.ron`). \
         Reference: Taylor & Green (1937), whose mode decays as e^(−2νk²t). A is the \
         mass-weighted projection of the velocity on the mode, sampled every 0.02 s; the \
         rate is the least-squares slope of −ln A over t = 0.1, 0.2, …, 1 s.\n\n",
    );
    body += &table.render();
    body += &failures(graded.iter().map(|c| &c.run));
    body += &format!(
        "**Finding.** Over 0.1–1 s the mode decays {:.1} % {} than 2νk², {} the {:.0} % \
         bound.\n\n",
        100.0 * c.rate_error().abs(),
        if c.rate_error() < 0.0 {
            "more slowly"
        } else {
            "faster"
        },
        within(c.rate_error().abs() < RATE_BOUND),
        100.0 * RATE_BOUND,
    );
    body += &image("amplitude of the mode over the analytic one", &png);
    Ok((
        Section {
            title: "Taylor–Green vortex at Re = 100 (periodic)".into(),
            body,
        },
        graded,
    ))
}

/// `A(t) / e^{−2νk²t}` against t.
fn plot(opts: &ReportOptions, c: &VortexCase) -> Result<std::path::PathBuf, ReportError> {
    let mut plot = LinePlot::new(
        "Taylor–Green vortex: amplitude of the mode over the analytic one",
        "t (s)",
        "A(t) / exp(−2νk²t)",
    );
    let ratio = c
        .amplitudes
        .iter()
        .map(|&(t, a)| (t, a / exact_amplitude(t)))
        .collect();
    plot = plot
        .with(Series::new(
            c.run.label.clone(),
            ratio,
            SeriesStyle::LineMarkers,
            0,
        ))
        .with(Series::new(
            "Taylor & Green (1937)",
            vec![(0.0, 1.0), (1.0, 1.0)],
            SeriesStyle::Line,
            6,
        ));
    let png = opts.file("taylor_green_amplitude.png");
    plot.write_png(&png)?;
    Ok(png)
}
