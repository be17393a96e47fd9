//! Plane Poiseuille flow started from rest between plates of wall particles
//! (`scenes/poiseuille_2d.ron`, the case of Morris, Fox & Zhu 1997, *Modeling low Reynolds
//! number incompressible flows using SPH*, J. Comput. Phys. 136, 214–226, §4.1), graded by
//! the relative L2 error of v_x over the water,
//! `‖v_x − v_exact‖ = sqrt(Σ (v_x − v_exact(y, t))² / Σ v_exact(y, t)²)`, against their
//! series solution (Eq. 21, [`dualsph_reference::poiseuille`]) at every snapshot. The walls'
//! viscous velocity is the no-slip one of Adami, Hu & Adams (2012), J. Comput. Phys. 231,
//! 7057, Eqs. 22–23; the same walls with their own (zero) velocity are run beside it.

use super::super::{
    COST_HEADERS, CaseRun, CaseSpec, Recording, ReportError, ReportOptions, Section, Table,
    cost_cells, failures, image,
};
use super::within;
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_reference::poiseuille::Poiseuille;

/// The scene's channel: L = 1 mm, ν = 1e-6 m²/s, F = 2e-4 m/s².
pub const MORRIS: Poiseuille = Poiseuille {
    width: 1e-3,
    nu: 1e-6,
    force: 2e-4,
};

/// Bound on the relative L2 error at every snapshot with no-slip walls.
pub const L2_BOUND: f64 = 0.006;

/// The scene's snapshot interval (s); the run ends at 1 s.
pub const SNAPSHOT_DT: f64 = 0.0225;

/// The relative L2 error (module docs) of the water's `(y, v_x)` at time `t`.
pub fn profile_error(water: impl IntoIterator<Item = (f64, f64)>, t: f64) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (y, vx) in water {
        let exact = MORRIS.velocity(y, t);
        num += (vx - exact).powi(2);
        den += exact * exact;
    }
    (num / den).sqrt()
}

/// The water's `(y, v_x)`: the particles between the plates (0 < y < L).
fn water(particles: &dualsph_io::ParticleTable) -> Vec<(f64, f64)> {
    particles
        .rows()
        .filter(|p| p.pos()[1] > 0.0 && p.pos()[1] < MORRIS.width)
        .map(|p| (p.pos()[1], p.vel()[0]))
        .collect()
}

/// One graded run.
#[derive(Clone, Debug)]
pub struct ChannelCase {
    /// The run.
    pub run: CaseRun,
    /// `(t, relative L2 error)` at every snapshot.
    pub errors: Vec<(f64, f64)>,
}

impl ChannelCase {
    /// The largest error over the snapshots.
    pub fn worst(&self) -> f64 {
        self.errors.iter().map(|e| e.1).fold(0.0, f64::max)
    }

    /// The error at the last snapshot.
    pub fn last(&self) -> f64 {
        self.errors.last().map_or(f64::NAN, |e| e.1)
    }
}

/// Grades a run at each of its snapshots.
pub fn grade(run: CaseRun) -> ChannelCase {
    let errors = run
        .snapshots
        .iter()
        .map(|(_, t, particles)| (*t, profile_error(water(particles), *t)))
        .collect();
    ChannelCase { run, errors }
}

/// The scene with no-slip walls, then with the walls' own velocity.
pub fn cases(opts: &ReportOptions) -> Result<Vec<CaseSpec>, ReportError> {
    super::no_slip_and_own(opts, "poiseuille_2d.ron")
}

fn recording() -> Recording {
    let n = (1.0 / SNAPSHOT_DT).floor() as usize;
    Recording {
        every: 100,
        snapshot_times: (1..=n)
            .map(|k| k as f64 * SNAPSHOT_DT)
            .chain([1.0])
            .collect(),
        ..Default::default()
    }
}

/// Runs, grades, plots and writes the section.
pub fn run(opts: &ReportOptions) -> Result<(Section, Vec<ChannelCase>), ReportError> {
    let graded = opts.run_graded(&cases(opts)?, &recording(), grade)?;
    let profiles = plot_profiles(opts, &graded)?;
    let mut errors = LinePlot::new(
        "Poiseuille flow: relative L2 error of v_x",
        "t (s)",
        "‖v_x − v_exact‖ / ‖v_exact‖",
    );
    for (k, c) in graded.iter().enumerate() {
        errors = errors.with(Series::new(
            c.run.label.clone(),
            c.errors.clone(),
            SeriesStyle::LineMarkers,
            k,
        ));
    }
    errors.log_y = true;
    let errors_png = opts.file("poiseuille_error.png");
    errors.write_png(&errors_png)?;

    let mut table = Table::new(
        [
            "case",
            "largest L2 error",
            "L2 error at the end",
            "snapshots",
        ]
        .into_iter()
        .chain(COST_HEADERS),
    );
    for c in &graded {
        let mut cells = vec![
            c.run.label.clone(),
            format!("{:.2} %", 100.0 * c.worst()),
            format!("{:.2} %", 100.0 * c.last()),
            c.errors.len().to_string(),
        ];
        cells.extend(cost_cells(&c.run));
        table.row(cells);
    }
    let mut body = String::from(
        "Water between two plates L = 1 mm apart (three layers of fixed particles each), \
         periodic along the flow, at rest at t = 0 and driven by a body force F = 2e-4 m/s² \
         (ν = 1e-6 m²/s, Re = 2.5e-2, Δx = L/40), to t = 1 s, when the slowest mode of the \
         start-up has decayed to 5e-5 of itself (scene `poiseuille_2d.ron`; the second case \
         has `viscous: Own`). Reference: the series solution of Morris, Fox & Zhu (1997, \
         Eq. 21). The error is the relative L2 norm of v_x − v_exact over the water at every \
         snapshot (every 0.0225 s).\n\n",
    );
    body += &table.render();
    body += &failures(graded.iter().map(|c| &c.run));
    let (no_slip, own) = (&graded[0], &graded[1]);
    body += &format!(
        "**Finding.** With the no-slip wall velocity the profile is {} {:.1} % of the series at \
         every snapshot (largest {:.2} %); with the walls' own velocity it ends {:.1} % off, \
         {} that bound{}.\n\n",
        within(no_slip.worst() < L2_BOUND),
        100.0 * L2_BOUND,
        100.0 * no_slip.worst(),
        100.0 * own.last(),
        within(own.last() < L2_BOUND),
        if own.last() >= L2_BOUND {
            ": the bound tells the two wall models apart"
        } else {
            ", so the bound does NOT tell the two wall models apart"
        },
    );
    body += &image("v_x across the channel against the series", &profiles);
    body += &image("relative L2 error against time", &errors_png);
    Ok((
        Section {
            title: "Plane Poiseuille flow (walls of particles)".into(),
            body,
        },
        graded,
    ))
}

/// v_x(y) of the no-slip run at four snapshots and of the other run at the end, against the
/// series.
fn plot_profiles(
    opts: &ReportOptions,
    graded: &[ChannelCase],
) -> Result<std::path::PathBuf, ReportError> {
    let mut plot = LinePlot::new(
        "Poiseuille flow: v_x across the channel",
        "y (mm)",
        "v_x (mm/s)",
    );
    let snaps = &graded[0].run.snapshots;
    let picks = [0, snaps.len() / 8, snaps.len() / 3, snaps.len() - 1];
    for (k, &i) in picks.iter().enumerate() {
        let (_, t, particles) = &snaps[i];
        let exact = (0..=100)
            .map(|j| {
                let y = MORRIS.width * j as f64 / 100.0;
                (1e3 * y, 1e3 * MORRIS.velocity(y, *t))
            })
            .collect();
        plot = plot.with(Series::new(
            format!("series, t = {t:.3} s"),
            exact,
            SeriesStyle::Line,
            k,
        ));
        let pts = water(particles)
            .iter()
            .map(|&(y, v)| (1e3 * y, 1e3 * v))
            .collect();
        plot = plot.with(Series::new(
            format!("{}, t = {t:.3} s", graded[0].run.label),
            pts,
            SeriesStyle::Markers,
            k,
        ));
    }
    if let Some((_, t, particles)) = graded[1].run.snapshots.last() {
        let pts = water(particles)
            .iter()
            .map(|&(y, v)| (1e3 * y, 1e3 * v))
            .collect();
        plot = plot.with(Series::new(
            format!("{}, t = {t:.3} s", graded[1].run.label),
            pts,
            SeriesStyle::Markers,
            5,
        ));
    }
    let png = opts.file("poiseuille_profiles.png");
    plot.write_png(&png)?;
    Ok(png)
}
