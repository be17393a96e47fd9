//! The Sedov–Taylor blast wave (2-D, and 3-D at a CI size): a point explosion in a uniform,
//! cold ideal gas, graded against the exact self-similar solution
//! ([`dualsph_reference::sedov`]; Sedov 1959, Kamm & Timmes 2007) by the L1 error of the
//! density over the shocked region and a margin beyond it, by the shock radius (where the
//! radially binned density peaks) and by the total energy, for DualSupport (h from Eq. 6.1
//! every step), grad-h SPH (h solved with the density) and SingleSupport.

use super::{
    COST_HEADERS, CaseRun, CaseSpec, ReportError, ReportOptions, Section, Table, cost_cells, image,
};
use super::{failures, final_particles};
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_reference::norms::l1_error;
use dualsph_reference::sedov::{Geometry, Sedov};

/// γ of the scenes.
pub const GAMMA: f64 = 1.4;
/// Ambient density of the scenes.
pub const RHO0: f64 = 1.0;
/// The graded region: `r ≤ WINDOW · R(t)`.
pub const WINDOW: f64 = 1.25;

/// One graded case.
#[derive(Clone, Debug)]
pub struct SedovCase {
    /// The run.
    pub run: CaseRun,
    /// Volume-weighted L1 error of ρ over `r ≤ WINDOW · R(t)`, relative to ρ0.
    pub l1_rho: f64,
    /// The exact shock radius at the end time.
    pub r_exact: f64,
    /// Where the radially binned density peaks.
    pub r_peak: f64,
    /// The peak of the binned density over the exact post-shock density `(γ+1)/(γ−1) ρ0`.
    pub peak_ratio: f64,
    /// max_t |E(t) − E(0)| / E(0).
    pub energy_drift: f64,
}

/// The exact solution for a run of `dimension` 2 or 3.
pub fn exact(dimension: usize) -> Sedov {
    let g = if dimension == 3 {
        Geometry::Spherical
    } else {
        Geometry::Cylindrical
    };
    Sedov::new(GAMMA, g).expect("γ = 1.4 is a valid Sedov problem")
}

/// DualSupport (the scene), grad-h and SingleSupport, in this order.
pub fn cases(opts: &ReportOptions, file: &str) -> Result<Vec<CaseSpec>, ReportError> {
    let mut cases = opts.dual_and_single(file, "DualSupport", "SingleSupport")?;
    let grad_h = CaseSpec::new(
        "grad-h",
        opts.scene(file)?,
        Some(dualsph_scene::Formulation::GradH),
    );
    cases.insert(1, grad_h);
    Ok(cases)
}

/// The distance of a particle from the origin.
fn radius(p: &dualsph_io::ParticleRow<'_>) -> f64 {
    (p.pos()[0] * p.pos()[0] + p.pos()[1] * p.pos()[1] + p.pos()[2] * p.pos()[2]).sqrt()
}

/// `(r of the peak, peak)` of the density averaged in radial bins of width `dr` (by volume).
fn binned_peak(particles: &dualsph_io::ParticleTable, dr: f64, r_max: f64) -> (f64, f64) {
    let n = (r_max / dr).ceil() as usize + 1;
    let (mut mass, mut vol) = (vec![0.0; n], vec![0.0; n]);
    for p in particles.rows() {
        let k = (radius(&p) / dr) as usize;
        if k < n {
            mass[k] += p.mass();
            vol[k] += p.mass() / p.rho();
        }
    }
    (0..n)
        .filter(|&k| vol[k] > 0.0)
        .map(|k| ((k as f64 + 0.5) * dr, mass[k] / vol[k]))
        .fold((0.0, 0.0), |best, x| if x.1 > best.1 { x } else { best })
}

/// Grades a run of `dimension` at its end time; the explosion energy is the run's initial
/// total energy (the ambient gas's 1e-5 included) and the bins are `dr` wide.
pub fn grade(run: CaseRun, dimension: usize, dr: f64) -> SedovCase {
    let sedov = exact(dimension);
    let d0 = run.diagnostics[0].clone();
    let (e, t) = (d0.e_tot, run.final_diagnostics().t);
    let r_exact = sedov.shock_radius(e, RHO0, t);
    let inside: Vec<_> = run
        .last
        .rows()
        .filter(|p| radius(p) <= WINDOW * r_exact)
        .collect();
    let sim: Vec<f64> = inside.iter().map(|p| p.rho()).collect();
    let reference: Vec<f64> = inside
        .iter()
        .map(|p| sedov.sample(e, RHO0, t, radius(p)).rho)
        .collect();
    let volumes: Vec<f64> = inside.iter().map(|p| p.mass() / p.rho()).collect();
    let (r_peak, peak) = binned_peak(&run.last, dr, WINDOW * r_exact);
    let energy_drift = run
        .diagnostics
        .iter()
        .map(|d| (d.e_tot - d0.e_tot).abs() / d0.e_tot.abs())
        .fold(0.0, f64::max);
    SedovCase {
        l1_rho: l1_error(&sim, &reference, &volumes) / RHO0,
        r_exact,
        r_peak,
        peak_ratio: peak / ((GAMMA + 1.0) / (GAMMA - 1.0) * RHO0),
        energy_drift,
        run,
    }
}

/// The lattice spacing of a scene's first generator (the bin width of the grading).
fn spacing(spec: &CaseSpec) -> f64 {
    let first = spec.scene.particles.first();
    first.map_or(f64::NAN, dualsph_scene::Generator::spacing)
}

/// Runs and grades the cases of `file` (of `dimension`).
pub fn run_cases(
    opts: &ReportOptions,
    file: &str,
    dimension: usize,
) -> Result<Vec<SedovCase>, ReportError> {
    let specs = cases(opts, file)?;
    let dr = spacing(&specs[0]);
    opts.run_graded(&specs, &ReportOptions::every_ten_steps(), |run| {
        grade(run, dimension, dr)
    })
}

/// The finding, every comparison computed from the cases (DualSupport, grad-h,
/// SingleSupport).
fn finding(c: &[SedovCase]) -> String {
    let best = c
        .iter()
        .min_by(|a, b| a.l1_rho.total_cmp(&b.l1_rho))
        .map_or("none", |x| x.run.label.as_str());
    let conserving: Vec<&str> = c
        .iter()
        .filter(|x| x.energy_drift <= 1e-12)
        .map(|x| x.run.label.as_str())
        .collect();
    let cost = |x: &SedovCase| x.run.cpu_seconds;
    format!(
        "**Finding.** Density L1: DualSupport {:.4}, grad-h {:.4}, SingleSupport {:.4} — {best} is the \
         lowest. Shock radius from the density peak over the exact R = {:.4}: {:.3}, {:.3}, {:.3}; peak density over the exact jump 6ρ0: {:.2}, {:.2}, \
         {:.2}. Total energy is kept to round-off (≤ 1e-12) by {}; the largest drifts are {:.1e}, {:.1e}, \
         {:.1e}. CPU seconds {:.2}, {:.2}, {:.2}.\n\n",
        c[0].l1_rho,
        c[1].l1_rho,
        c[2].l1_rho,
        c[0].r_exact,
        c[0].r_peak / c[0].r_exact,
        c[1].r_peak / c[1].r_exact,
        c[2].r_peak / c[2].r_exact,
        c[0].peak_ratio,
        c[1].peak_ratio,
        c[2].peak_ratio,
        if conserving.is_empty() {
            "none of them".to_string()
        } else {
            conserving.join(" and ")
        },
        c[0].energy_drift,
        c[1].energy_drift,
        c[2].energy_drift,
        cost(&c[0]),
        cost(&c[1]),
        cost(&c[2]),
    )
}

/// The density against radius of every case with the exact profile, as a PNG in the report.
fn density_plot(
    opts: &ReportOptions,
    c: &[SedovCase],
    dimension: usize,
) -> Result<String, ReportError> {
    let sedov = exact(dimension);
    let (e, t) = (
        c[0].run.diagnostics[0].e_tot,
        c[0].run.final_diagnostics().t,
    );
    let r_max = WINDOW * c[0].r_exact;
    let line = (0..=600).map(|k| {
        let r = r_max * k as f64 / 600.0;
        (r, sedov.sample(e, RHO0, t, r).rho)
    });
    let mut plot = LinePlot::new(
        format!("Sedov–Taylor blast ({dimension}-D): density at t = {t:.3}"),
        "r",
        "ρ",
    )
    .with(Series::new(
        "exact (Sedov)",
        line.collect(),
        SeriesStyle::Line,
        6,
    ));
    plot.series.extend(final_particles(
        c.iter().map(|x| &x.run),
        |p| radius(p) <= r_max,
        |p| (radius(p), p.rho()),
    ));
    let png = opts.file(&format!("sedov_{dimension}d_density.png"));
    plot.write_png(&png)?;
    Ok(image(&format!("Sedov {dimension}-D density"), &png))
}

/// Runs, grades, plots and writes the section (2-D at the scene's resolution, 3-D at its CI
/// size).
pub fn run(opts: &ReportOptions) -> Result<(Section, Vec<SedovCase>), ReportError> {
    let mut body = String::from(
        "Energy E = 1 released at the origin into a uniform gas (ρ0 = 1, γ = 1.4, nearly cold: e0 = 1e-5) as \
         internal energy of the particles next to it (scenes `sedov_2d.ron`, `sedov_3d.ron`). Exact solution: \
         the self-similar Sedov–Taylor blast (Sedov 1959; Kamm & Timmes 2007), computed by `dualsph_reference::sedov` \
         with E the run's initial total energy. L1 = Σ V_i |ρ_i − ρ(r_i)| / Σ V_i over r ≤ 1.25 R(t); the peak is \
         the largest density averaged in radial bins one spacing wide. DualSupport updates h by Eq. 6.1 every \
         step; grad-h solves h with the summation density every step and adds the Ω terms; SingleSupport uses \
         the same h as DualSupport without the reactions.\n\n",
    );
    let mut all = Vec::new();
    for (file, dimension) in [("sedov_2d.ron", 2), ("sedov_3d.ron", 3)] {
        let graded = run_cases(opts, file, dimension)?;
        let mut table = Table::new(
            [
                "case",
                "L1 ρ",
                "R_peak / R",
                "peak / 6ρ0",
                "max energy drift",
            ]
            .into_iter()
            .chain(COST_HEADERS),
        );
        for c in &graded {
            let mut cells = vec![
                c.run.label.clone(),
                format!("{:.4}", c.l1_rho),
                format!("{:.3}", c.r_peak / c.r_exact),
                format!("{:.2}", c.peak_ratio),
                format!("{:.1e}", c.energy_drift),
            ];
            cells.extend(cost_cells(&c.run));
            table.row(cells);
        }
        body += &format!("### {dimension}-D\n\n");
        body += &table.render();
        body += &failures(graded.iter().map(|c| &c.run));
        body += &finding(&graded);
        body += &density_plot(opts, &graded, dimension)?;
        all.extend(graded);
    }
    Ok((
        Section {
            title: "Sedov–Taylor blast wave".into(),
            body,
        },
        all,
    ))
}
