//! The lid-driven cavity at Re = 100 (`scenes/cavity_2d.ron`: a unit square, lid speed
//! U = 1 m/s, ν = 0.01 m²/s, Δx = 0.02, 20 s) against the centreline velocities of Ghia,
//! Ghia & Shin (1982), *High-Re solutions for incompressible flow using the Navier–Stokes
//! equations and a multigrid method*, J. Comput. Phys. 48, 387–411, Tables I–II
//! ([`dualsph_reference::cavity`]); the grading also serves the cavity at Re = 1000
//! (`scenes/cavity_2d_re1000.ron`, [`RE1000`], `validation/tests/validation/cavity.rs`).
//!
//! The measure: the largest difference, in units of U, between the simulated and Ghia's
//! velocity at Ghia's interior points — u on x = 0.5, v on y = 0.5 — with the scene's probe
//! lines (linearly interpolated to Ghia's points) averaged over the samples once the flow is
//! steady (at Re = 100 from t = 16 s; it is steady from about 10 s on). The walls' viscous
//! velocity is the no-slip one of Adami, Hu & Adams (2012), J. Comput. Phys. 231, 7057,
//! Eqs. 22–23; the same walls with their own velocity (the fixed walls at rest, the lid at U)
//! are run beside it.

use super::super::{
    COST_HEADERS, CaseRun, CaseSpec, Recording, ReportError, ReportOptions, Section, Table,
    cost_cells, failures, image,
};
use super::within;
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_probes::ProbeTable;
use dualsph_reference::cavity::{GHIA_U_RE100, GHIA_U_RE1000, GHIA_V_RE100, GHIA_V_RE1000};

/// Bound on the largest centreline difference, in units of U, with no-slip walls.
pub const BOUND: f64 = 0.03;

/// A cavity flow's reference: Ghia et al.'s tables at its Reynolds number and the time from
/// which its flow is steady.
#[derive(Clone, Copy, Debug)]
pub struct Ghia {
    /// `(y, u)` on x = 0.5 (Table I).
    pub u: &'static [(f64, f64)],
    /// `(x, v)` on y = 0.5 (Table II).
    pub v: &'static [(f64, f64)],
    /// The probe samples averaged are those at or after this time (s).
    pub from: f64,
}

/// Re = 100 (`scenes/cavity_2d.ron`): steady from about 10 s on, averaged from 16 s.
pub const RE100: Ghia = Ghia {
    u: &GHIA_U_RE100,
    v: &GHIA_V_RE100,
    from: 16.0,
};

/// Re = 1000 (`scenes/cavity_2d_re1000.ron`): its wall jets settle over some 30 s, averaged
/// from 30 s.
pub const RE1000: Ghia = Ghia {
    u: &GHIA_U_RE1000,
    v: &GHIA_V_RE1000,
    from: 30.0,
};

/// The two centrelines averaged over the late samples. Each probe line has n points at
/// `(m + 1)/(n + 1)`, m = 0..n−1 (the scenes' lines end half a spacing or a spacing off the
/// walls).
#[derive(Clone, Debug)]
pub struct CentreLines {
    /// u at (0.5, (m + 1)/(n + 1)).
    pub u: Vec<f64>,
    /// v at ((m + 1)/(n + 1), 0.5).
    pub v: Vec<f64>,
    /// How many samples were averaged.
    pub samples: usize,
    /// The reference the lines are graded against.
    pub reference: Ghia,
}

impl CentreLines {
    /// The probe lines "u" and "v" of `table` averaged over the samples at t ≥
    /// `reference.from`.
    pub fn of(table: &ProbeTable, reference: Ghia) -> Result<Self, String> {
        let late: Vec<usize> = (0..table.t.len())
            .filter(|&k| table.t[k] >= reference.from)
            .collect();
        let mean = |prefix: &str| -> Result<Vec<f64>, String> {
            let columns: Vec<usize> = (0..)
                .map_while(|m| {
                    let name = format!("{prefix}[{m}]");
                    table.columns.iter().position(|c| *c == name)
                })
                .collect();
            if columns.len() < 2 {
                return Err(format!("no probe line {prefix} of two points or more"));
            }
            Ok(columns
                .iter()
                .map(|&c| late.iter().map(|&k| table.values[k][c]).sum::<f64>() / late.len() as f64)
                .collect())
        };
        Ok(CentreLines {
            u: mean("u")?,
            v: mean("v")?,
            samples: late.len(),
            reference,
        })
    }

    /// The position of point m of a line of n points, `(m + 1)/(n + 1)`.
    pub fn position(m: usize, n: usize) -> f64 {
        (m + 1) as f64 / (n + 1) as f64
    }

    /// A line linearly interpolated at `s`.
    pub fn at(line: &[f64], s: f64) -> f64 {
        let n = line.len();
        let f = s * (n + 1) as f64 - 1.0;
        let m = (f.max(0.0).floor() as usize).min(n - 2);
        let w = f - m as f64;
        line[m] * (1.0 - w) + line[m + 1] * w
    }

    /// `(s, simulated, Ghia's)` at Ghia's interior points of u (on x = 0.5, s = y).
    pub fn u_points(&self) -> Vec<(f64, f64, f64)> {
        points(&self.u, self.reference.u)
    }

    /// `(s, simulated, Ghia's)` at Ghia's interior points of v (on y = 0.5, s = x).
    pub fn v_points(&self) -> Vec<(f64, f64, f64)> {
        points(&self.v, self.reference.v)
    }

    /// `(largest |u − u_Ghia|, largest |v − v_Ghia|)` over Ghia's interior points, in units
    /// of U (= 1 m/s).
    pub fn errors(&self) -> (f64, f64) {
        let [(_, u, u_ghia), (_, v, v_ghia)] = self.worst();
        ((u - u_ghia).abs(), (v - v_ghia).abs())
    }

    /// The points of u and of v, `(s, simulated, Ghia's)`, where the line is furthest from
    /// Ghia's value.
    pub fn worst(&self) -> [(f64, f64, f64); 2] {
        let worst = |pts: Vec<(f64, f64, f64)>| {
            pts.into_iter()
                .max_by(|a, b| (a.1 - a.2).abs().total_cmp(&(b.1 - b.2).abs()))
                .unwrap_or_default()
        };
        [worst(self.u_points()), worst(self.v_points())]
    }
}

fn points(line: &[f64], table: &[(f64, f64)]) -> Vec<(f64, f64, f64)> {
    table
        .iter()
        .filter(|(s, _)| *s > 0.0 && *s < 1.0)
        .map(|&(s, expect)| (s, CentreLines::at(line, s), expect))
        .collect()
}

/// One graded run.
#[derive(Clone, Debug)]
pub struct CavityCase {
    /// The run.
    pub run: CaseRun,
    /// Its averaged centrelines.
    pub lines: CentreLines,
}

/// The scene with no-slip walls, then with the walls' own velocity.
pub fn cases(opts: &ReportOptions) -> Result<Vec<CaseSpec>, ReportError> {
    super::no_slip_and_own(opts, "cavity_2d.ron")
}

/// Runs both cases, each writing its probes into a folder of its own beside the report.
fn run_cases(opts: &ReportOptions) -> Result<Vec<CavityCase>, ReportError> {
    let dirs = ["cavity_no_slip", "cavity_own"];
    cases(opts)?
        .iter()
        .zip(dirs)
        .map(|(c, d)| {
            let dir = opts.file(d);
            let rec = Recording {
                every: 200,
                output_dir: Some(dir.clone()),
                ..Default::default()
            };
            let run = opts.run(c, &rec)?;
            let table = dualsph_probes::read_probes(&dir).map_err(ReportError::Output)?;
            let lines = CentreLines::of(&table, RE100).map_err(ReportError::Output)?;
            Ok(CavityCase { run, lines })
        })
        .collect()
}

/// Runs, grades, plots and writes the section.
pub fn run(opts: &ReportOptions) -> Result<(Section, Vec<CavityCase>), ReportError> {
    let graded = run_cases(opts)?;
    let u_png = plot_line(opts, &graded, true)?;
    let v_png = plot_line(opts, &graded, false)?;
    let mut table = Table::new(
        [
            "case",
            "max |u − u_Ghia| / U",
            "max |v − v_Ghia| / U",
            "samples averaged",
        ]
        .into_iter()
        .chain(COST_HEADERS),
    );
    for c in &graded {
        let (u, v) = c.lines.errors();
        let mut cells = vec![
            c.run.label.clone(),
            format!("{:.2} %", 100.0 * u),
            format!("{:.2} %", 100.0 * v),
            c.lines.samples.to_string(),
        ];
        cells.extend(cost_cells(&c.run));
        table.row(cells);
    }
    let mut body = String::from(
        "A unit square of fluid, the lid sliding at U = 1 m/s, ν = 0.01 m²/s (Re = 100), \
         Δx = 0.02 (2,500 fluid particles), walls and lid of three layers of particles, c0 = \
         10 U, 20 s (scene `cavity_2d.ron`; the second case has `viscous: Own`). Reference: \
         Ghia, Ghia & Shin (1982), Tables I–II. The probes sample u on x = 0.5 and v on y = \
         0.5 every 500 steps; the lines are averaged over the samples at t ≥ 16 s and \
         interpolated to Ghia's 15 interior points of each line.\n\n",
    );
    body += &table.render();
    body += &failures(graded.iter().map(|c| &c.run));
    let ((u0, v0), (u1, v1)) = (graded[0].lines.errors(), graded[1].lines.errors());
    body += &format!(
        "**Finding.** With the no-slip wall velocity both centrelines are {} {:.0} % of U of \
         Ghia's values ({:.2} % in u, {:.2} % in v); with the walls' own velocity the \
         centrelines are {} it ({:.2} % in u, {:.2} % in v).\n\n",
        within(u0.max(v0) < BOUND),
        100.0 * BOUND,
        100.0 * u0,
        100.0 * v0,
        within(u1.max(v1) < BOUND),
        100.0 * u1,
        100.0 * v1,
    );
    body += &image("u on the vertical centreline against Ghia", &u_png);
    body += &image("v on the horizontal centreline against Ghia", &v_png);
    Ok((
        Section {
            title: "Lid-driven cavity at Re = 100 (walls of particles)".into(),
            body,
        },
        graded,
    ))
}

/// u(y) on x = 0.5 (`u` true) or v(x) on y = 0.5, each run's averaged line against Ghia's
/// points.
fn plot_line(
    opts: &ReportOptions,
    graded: &[CavityCase],
    u: bool,
) -> Result<std::path::PathBuf, ReportError> {
    let (title, x, y, ghia, name) = if u {
        let pts = GHIA_U_RE100.iter().map(|&(s, v)| (v, s)).collect();
        ("Cavity: u on x = 0.5", "u / U", "y", pts, "cavity_u.png")
    } else {
        let pts = GHIA_V_RE100.to_vec();
        ("Cavity: v on y = 0.5", "x", "v / U", pts, "cavity_v.png")
    };
    let mut plot = LinePlot::new(title, x, y).with(Series::new(
        "Ghia, Ghia & Shin (1982)",
        ghia,
        SeriesStyle::Markers,
        6,
    ));
    for (k, c) in graded.iter().enumerate() {
        let line = if u { &c.lines.u } else { &c.lines.v };
        let pts = line
            .iter()
            .enumerate()
            .map(|(m, &w)| {
                let s = CentreLines::position(m, line.len());
                if u { (w, s) } else { (s, w) }
            })
            .collect();
        plot = plot.with(Series::new(c.run.label.clone(), pts, SeriesStyle::Line, k));
    }
    let png = opts.file(name);
    plot.write_png(&png)?;
    Ok(png)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both scenes' line layouts (99 points 0.01 apart, 199 points 0.005 apart) interpolate
    /// a linear profile exactly at Ghia's interior points.
    #[test]
    fn lines_of_either_layout_interpolate_at_their_positions() {
        for n in [99, 199] {
            let line: Vec<f64> = (0..n).map(|m| 2.0 * CentreLines::position(m, n)).collect();
            for &(s, _) in RE1000.u.iter().filter(|(s, _)| *s > 0.0 && *s < 1.0) {
                assert!(
                    (CentreLines::at(&line, s) - 2.0 * s).abs() < 1e-12,
                    "{n}: {s}"
                );
            }
        }
        assert_eq!(CentreLines::position(98, 99), 0.99);
        assert_eq!(CentreLines::position(0, 199), 0.005);
    }
}
