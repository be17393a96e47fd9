//! Sod shock tube (§7.2 of Ren, Dai, Zhuang & Rabczuk, *Dual-support Smoothed Particle
//! Hydrodynamics*, preprint; RenDSSPH in docs/references.md), graded against the exact Riemann
//! solution by the L1 error of density, velocity, pressure and internal energy over
//! x ∈ [−0.5, 0.5].

use super::{
    COST_HEADERS, CaseRun, CaseSpec, ReportError, ReportOptions, Section, Table, cost_cells, image,
};
use super::{failures, final_particles};
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_reference::norms::l1_error;
use dualsph_reference::riemann::{Riemann, Sample};

/// γ of the benchmark.
pub const GAMMA: f64 = 5.0 / 3.0;
/// Half-width of the graded window about the membrane.
pub const WINDOW: f64 = 0.5;

/// The exact solution of the benchmark's Riemann problem.
pub fn exact() -> Riemann {
    Riemann::sod(GAMMA)
}

/// The coarsest size of `scenes/sod_1d_adaptive.ron` (m).
pub const ADAPTIVE_COARSEST: f64 = 0.005;

/// A particle's level in the adaptive tube, `log2(coarsest/Δx_n)` with `Δx_n = m/ρ_n` its
/// size at its nominal density (`Refinement(ladder: Nominal)`; in 1-D): 0 the coarsest, 2
/// the finest. The refinement's own `level` column is a snapshot column, which the tables
/// of a report run do not carry.
pub fn adaptive_level(p: &dualsph_io::ParticleRow<'_>) -> f64 {
    let nominal = p
        .get("nominal_density")
        .expect("the adaptive tube's particles carry a nominal density")[0];
    libm::log2(ADAPTIVE_COARSEST / (p.mass() / nominal))
}

/// One graded case: L1 errors over the window.
#[derive(Clone, Debug)]
pub struct SodCase {
    /// The run.
    pub run: CaseRun,
    /// L1 errors of (ρ, u, p, e).
    pub l1: [f64; 4],
    /// Particles in the window.
    pub samples: usize,
    /// Width-equivalent density error δ (m) of the rarefaction, contact and shock: see
    /// [`wave_errors`].
    pub waves: [f64; 3],
    /// Share of `∫|ρ − ρ_exact| dx` over the graded window that lies in the contact and shock
    /// windows.
    pub contact_shock_share: f64,
}

/// Half-width of the window about each wave (the rarefaction: beyond its head and its tail).
pub const WAVE_WINDOW: f64 = 0.05;
/// A wave counts as resolved when its δ is below this (m): a jump smeared linearly across its
/// whole window gives δ = WAVE_WINDOW / 2, a missing wave δ = WAVE_WINDOW.
pub const RESOLVED_DELTA: f64 = 0.5 * WAVE_WINDOW;
/// The waves' names, in the order of [`SodCase::waves`].
pub const WAVE_NAMES: [&str; 3] = ["rarefaction", "contact", "shock"];

/// The windows `[x_from, x_to]` at time `t` about the rarefaction (head to tail), the contact
/// and the shock of `r`, and the density change across each, for a left rarefaction and a
/// right shock (Sod's structure). The wave edges are found by bisection on `ξ = x/t`: outside
/// a wave the exact solution returns the constant state unchanged.
pub fn wave_windows(r: &Riemann, t: f64) -> [(f64, f64, f64); 3] {
    let rho = |xi: f64| r.sample(xi).rho;
    let (us, far) = (r.u_star, 1e3);
    let (rho_l, rho_r) = (rho(-far), rho(far));
    let (star_l, star_r) = (rho(us - 1e-9), rho(us + 1e-9));
    // the last ξ in [a, b] at which `inside(ξ)` holds, `inside` true at a and false at b
    let edge = |inside: &dyn Fn(f64) -> bool, (mut a, mut b): (f64, f64)| {
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if inside(m) { a = m } else { b = m }
        }
        a
    };
    let head = edge(&|xi| rho(xi) == rho_l, (-far, us));
    let tail = edge(&|xi| rho(xi) != star_l, (head, us - 1e-9));
    let shock = edge(&|xi| rho(xi) != rho_r, (us + 1e-9, far));
    let w = WAVE_WINDOW;
    [
        (head * t - w, tail * t + w, rho_l - star_l),
        (us * t - w, us * t + w, star_l - star_r),
        (shock * t - w, shock * t + w, star_r - rho_r),
    ]
}

/// Per wave, `δ = ∫_window |ρ − ρ_exact| dx / |Δρ|` (m, integrated with the particle volumes
/// m/ρ): the width by which the wave is smeared or displaced; and the share of the graded
/// window's `∫|ρ − ρ_exact| dx` in the contact and shock windows.
pub fn wave_errors(
    particles: &[dualsph_io::ParticleRow<'_>],
    r: &Riemann,
    t: f64,
) -> ([f64; 3], f64) {
    let windows = wave_windows(r, t);
    let err = |p: &dualsph_io::ParticleRow<'_>| {
        p.mass() / p.rho() * (p.rho() - r.at(p.pos()[0], t, 0.0).rho).abs()
    };
    let within = |k: usize| {
        let (a, b, _) = windows[k];
        particles
            .iter()
            .filter(|p| (a..=b).contains(&p.pos()[0]))
            .map(&err)
            .sum::<f64>()
    };
    let total: f64 = particles.iter().map(err).sum();
    let deltas = [0, 1, 2].map(|k| within(k) / windows[k].2.abs());
    (deltas, (within(1) + within(2)) / total)
}

/// DualSupport (the scene) and SingleSupport, both with h from Eq. 6.1, and grad-h SPH (h
/// solved with the summation density at every step, with the Ω terms), in this order.
pub fn cases(opts: &ReportOptions) -> Result<Vec<CaseSpec>, ReportError> {
    let mut cases = opts.dual_and_single(
        "sod_1d.ron",
        "DualSupport, variable h",
        "SingleSupport, variable h",
    )?;
    cases.push(CaseSpec::new(
        "grad-h, variable h",
        opts.scene("sod_1d.ron")?,
        Some(dualsph_scene::Formulation::GradH),
    ));
    Ok(cases)
}

/// Grades a run at its end time against the exact solution.
pub fn grade(run: CaseRun) -> SodCase {
    grade_against(run, &exact())
}

/// Grades a run at its end time against the exact solution `r` of its Riemann problem
/// (membrane at x = 0), by volume-weighted L1 errors over [−WINDOW, WINDOW].
pub fn grade_against(run: CaseRun, r: &Riemann) -> SodCase {
    let t = run.final_diagnostics().t;
    let inside: Vec<_> = run
        .last
        .rows()
        .filter(|p| p.pos()[0].abs() <= WINDOW)
        .collect();
    let reference: Vec<Sample> = inside.iter().map(|p| r.at(p.pos()[0], t, 0.0)).collect();
    let col = |f: &dyn Fn(&Sample) -> f64| reference.iter().map(f).collect::<Vec<_>>();
    let sim =
        |f: &dyn Fn(&dualsph_io::ParticleRow<'_>) -> f64| inside.iter().map(f).collect::<Vec<_>>();
    let volumes = sim(&|p| p.mass() / p.rho());
    let l1 = [
        l1_error(&sim(&|p| p.rho()), &col(&|s| s.rho), &volumes),
        l1_error(&sim(&|p| p.vel()[0]), &col(&|s| s.u), &volumes),
        l1_error(&sim(&|p| p.p()), &col(&|s| s.p), &volumes),
        l1_error(&sim(&|p| p.e()), &col(&|s| s.e), &volumes),
    ];
    let (waves, contact_shock_share) = wave_errors(&inside, r, t);
    SodCase {
        samples: inside.len(),
        run,
        l1,
        waves,
        contact_shock_share,
    }
}

/// Runs, grades, plots and writes the section.
pub fn run(opts: &ReportOptions) -> Result<(Section, Vec<SodCase>), ReportError> {
    let graded = opts.run_graded(&cases(opts)?, &ReportOptions::every_ten_steps(), grade)?;
    let t = graded[0].run.final_diagnostics().t;
    let r = exact();
    let quantities: [(
        &str,
        &str,
        fn(&Sample) -> f64,
        fn(&dualsph_io::ParticleRow<'_>) -> f64,
    ); 4] = [
        ("density", "ρ", |s| s.rho, |p| p.rho()),
        ("velocity", "u", |s| s.u, |p| p.vel()[0]),
        ("pressure", "p", |s| s.p, |p| p.p()),
        ("energy", "e", |s| s.e, |p| p.e()),
    ];
    let mut images = String::new();
    for (name, sym, exact_of, sim_of) in quantities {
        let line = (0..=1000).map(|k| {
            let x = -WINDOW + 2.0 * WINDOW * k as f64 / 1000.0;
            (x, exact_of(&r.at(x, t, 0.0)))
        });
        let mut plot = LinePlot::new(format!("Sod shock tube: {name} at t = {t:.3}"), "x", sym)
            .with(Series::new(
                "exact Riemann solution",
                line.collect(),
                SeriesStyle::Line,
                6,
            ));
        let runs = graded.iter().map(|c| &c.run);
        plot.series.extend(final_particles(
            runs,
            |p| p.pos()[0].abs() <= WINDOW,
            |p| (p.pos()[0], sim_of(p)),
        ));
        let png = opts.file(&format!("sod_{name}.png"));
        plot.write_png(&png)?;
        images += &image(&format!("Sod {name}"), &png);
    }
    let mut table = Table::new(
        ["case", "L1 ρ", "L1 u", "L1 p", "L1 e", "samples"]
            .into_iter()
            .chain(COST_HEADERS),
    );
    for c in &graded {
        let mut cells = vec![c.run.label.clone()];
        cells.extend(c.l1.iter().map(|v| format!("{v:.4}")));
        cells.push(c.samples.to_string());
        cells.extend(cost_cells(&c.run));
        table.row(cells);
    }
    let mut body = format!(
        "γ = 5/3; left ρ = 1, p = 1, Δx = 0.00125; right ρ = 0.125, p = 0.1, Δx = 0.01 (equal masses); \
         summation density, ideal gas, artificial viscosity α = 1, β = 2, h = 2Δx at start and updated by Eq. 6.1 \
         every step; tube [−1, 1] so the ends stay outside the graded window (scene `sod_1d.ron`). Exact solution \
         from the project's Riemann solver (p* = {:.6}, u* = {:.6}). L1 = ∫|error| dx / ∫dx over \
         [−{WINDOW}, {WINDOW}] at t = {t:.3}, integrated with the particle volumes m/ρ (so the coarse right half \
         counts by its length, not its particle count).\n\n",
        r.p_star, r.u_star
    );
    body += &table.render();
    body += &failures(graded.iter().map(|c| &c.run));
    body += &finding(&graded);
    body += &images;
    Ok((
        Section {
            title: "Sod shock tube (§7.2)".into(),
            body,
        },
        graded,
    ))
}

/// The finding: density L1 of both cases, and which waves each resolves by [`RESOLVED_DELTA`].
fn finding(g: &[SodCase]) -> String {
    let deltas = |c: &SodCase| {
        c.waves
            .iter()
            .map(|d| format!("{d:.4}"))
            .collect::<Vec<_>>()
            .join(" / ")
    };
    let resolved = |c: &SodCase| {
        let names: Vec<&str> = (0..3)
            .filter(|&k| c.waves[k] < RESOLVED_DELTA)
            .map(|k| WAVE_NAMES[k])
            .collect();
        match names.len() {
            3 => "all three waves".to_string(),
            0 => "none of the waves".to_string(),
            _ => format!("only the {}", names.join(" and the ")),
        }
    };
    let (ds, ss) = (&g[0], &g[1]);
    format!(
        "**Finding.** The paper shows the profiles only (its Figs. 3–4). DualSupport's density L1 is {:.4}; \
         SingleSupport with the same variable h gives {:.4}. About each wave (±{WAVE_WINDOW} beyond it; the \
         rarefaction from its head to its tail) δ = ∫|ρ − ρ_exact| dx / |Δρ| measures by how much it is smeared \
         or displaced: rarefaction / contact / shock δ = {} m (DualSupport) and {} m (SingleSupport). Counting a \
         wave as resolved when δ < {RESOLVED_DELTA} m (a jump smeared linearly across its whole window gives \
         {RESOLVED_DELTA} m, a missing one {WAVE_WINDOW} m), DualSupport resolves {} and SingleSupport {}. The \
         contact and shock windows hold {:.0} % (DualSupport) and {:.0} % (SingleSupport) of the density error \
         over the graded window.\n\n",
        ds.l1[0],
        ss.l1[0],
        deltas(ds),
        deltas(ss),
        resolved(ds),
        resolved(ss),
        100.0 * ds.contact_shock_share,
        100.0 * ss.contact_shock_share,
    )
}
