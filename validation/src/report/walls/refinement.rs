//! Stability under refinement: the validated free-surface flows against walls of particles,
//! run to their end at two and four times their resolution. A scene that is validated at one
//! spacing must not blow up when it is refined — refinement thins jets and splashes and
//! multiplies the particles that leave the water, which is where tension and wall suction
//! throw particles into walls. The cases:
//!
//! * the walls dam break (`dam_break_2d_walls.ron`, Δx = 0.025 m) at Δx/2 and Δx/4, to 1.5 s
//!   (the run-up on the far wall reaches the ceiling and falls back);
//! * Buchner's dam break (`dam_break_buchner_2d.ron`, H/Δx = 40) at H/40 and H/80, to
//!   t* = t √(g/H) = 8 (the second impact and the wave running back).
//!
//! Each run reports the time it reached (a blow-up stops it with the particle and the
//! quantity), the largest density variation `max |ρ/ρ0 − 1|` over the diagnostics rows and the
//! largest total-energy variation.

use super::super::markdown::Table;
use super::super::{
    COST_HEADERS, CaseRun, CaseSpec, ReportError, ReportOptions, Section, coarsen, cost_cells,
    failures,
};
use dualsph_core::math::Real;

/// Buchner's column height H (m) and gravity (m/s²): t* = t √(g/H).
const H: Real = 0.6;
const G: Real = 9.81;
/// The end of the Buchner runs (s): t* = 8.
pub fn buchner_end_time() -> Real {
    BUCHNER_END_STAR / (G / H).sqrt()
}
/// The end of the Buchner runs, in t*.
pub const BUCHNER_END_STAR: Real = 8.0;
/// The end of the walls dam-break runs (s).
pub const WALLS_END: Real = 1.5;

/// One refined run: the scene, its refinement (the spacing divided by it) and its end time.
#[derive(Clone, Copy, Debug)]
pub struct Refined {
    /// Scene file in `scenes/`.
    pub file: &'static str,
    /// What the report calls it.
    pub name: &'static str,
    /// The shipped spacing is divided by this.
    pub refine: Real,
    /// Its spacing after refinement (and any setting changed), for the label.
    pub spacing_label: &'static str,
    /// End time (s).
    pub end_time: Real,
    /// Edits to the scene's text (`from`, `to`), beside the refinement.
    pub edits: &'static [(&'static str, &'static str)],
}

/// The walls dam break with its water stretching without bound: the shipped scene without
/// TaitEos' `cavitation` (its water cavitates at the vapour pressure).
const STRETCHING: &[(&str, &str)] = &[(
    "c0: 100.0, cavitation: true, min_pressure: -99000.0)",
    "c0: 100.0)",
)];

/// The cases, coarsest first; `finest` adds Δx/4 (as shipped, and with the water stretching
/// without bound), H/80 and H/160 (about 13, 3, 7 and 50 CPU-minutes, too long for the CI's
/// second tier) and Buchner's at its shipped H/40 (the second tier's wall-pressure test runs
/// that scene to the same t* and checks it the same way).
pub fn refined(finest: bool) -> Vec<Refined> {
    let t_buchner = buchner_end_time();
    let walls = |refine, spacing_label, edits| Refined {
        file: "dam_break_2d_walls.ron",
        name: "walls dam break",
        refine,
        spacing_label,
        end_time: WALLS_END,
        edits,
    };
    let buchner = |refine, spacing_label| Refined {
        file: "dam_break_buchner_2d.ron",
        name: "Buchner dam break",
        refine,
        spacing_label,
        end_time: t_buchner,
        edits: &[],
    };
    let mut cases = vec![walls(2.0, "Δx/2 = 0.0125 m", &[])];
    if finest {
        cases.push(buchner(1.0, "H/40 = 0.015 m"));
        cases.push(walls(4.0, "Δx/4 = 0.00625 m", &[]));
        cases.push(walls(
            4.0,
            "Δx/4 = 0.00625 m, without cavitation",
            STRETCHING,
        ));
        cases.push(buchner(2.0, "H/80 = 0.0075 m"));
        cases.push(buchner(4.0, "H/160 = 0.00375 m"));
    }
    cases
}

/// The case's scene: refined, to its end time, without probes (their files are not read
/// here) and without snapshots.
pub fn spec(opts: &ReportOptions, r: &Refined) -> Result<CaseSpec, ReportError> {
    let mut scene = opts.scene_with_edits(r.file, r.edits)?;
    coarsen(&mut scene, 1.0 / r.refine);
    scene.end_time = r.end_time;
    scene.plugins.retain(|p| p.name() != "Probes");
    let label = format!("{}, {}", r.name, r.spacing_label);
    Ok(CaseSpec::new(label, scene, None))
}

/// Runs a case with diagnostics every 100 steps.
pub fn run_one(opts: &ReportOptions, r: &Refined) -> Result<CaseRun, ReportError> {
    let rec = super::super::Recording {
        every: 100,
        ..Default::default()
    };
    opts.run(&spec(opts, r)?, &rec)
}

/// The run reached its end time without a blow-up.
pub fn reached_end(run: &CaseRun, r: &Refined) -> bool {
    run.failure.is_none() && run.final_diagnostics().t >= r.end_time * (1.0 - 1e-9)
}

/// Runs every case (the finest too) and writes the section.
pub fn run(opts: &ReportOptions) -> Result<(Section, Vec<CaseRun>), ReportError> {
    let cases = refined(true);
    let runs = cases
        .iter()
        .map(|r| run_one(opts, r))
        .collect::<Result<Vec<_>, _>>()?;
    let mut table = Table::new(
        ["case", "end time (s)", "max |ρ/ρ0 − 1|", "max |ΔE/E|"]
            .into_iter()
            .chain(COST_HEADERS),
    );
    for (r, run) in cases.iter().zip(&runs) {
        let mut cells = vec![
            run.label.clone(),
            format!("{:.3}", r.end_time),
            format!("{:.3}", run.max_density_variation()),
            format!("{:.1e}", run.max_energy_variation()),
        ];
        cells.extend(cost_cells(run));
        table.row(cells);
    }
    let stopped = |shipped: bool| -> Vec<String> {
        cases
            .iter()
            .zip(&runs)
            .filter(|(r, run)| r.edits.is_empty() == shipped && !reached_end(run, r))
            .map(|(_, run)| format!("{} (at t = {:.3} s)", run.label, run.final_diagnostics().t))
            .collect()
    };
    let (ended, controls) = (stopped(true), stopped(false));
    let mut body = String::from(
        "The validated free-surface flows against walls of particles, refined: the walls dam \
         break (`dam_break_2d_walls.ron`, Δx = 0.025 m as shipped, its water cavitating at \
         the vapour pressure: TaitEos `cavitation` with `min_pressure` −99 kPa) at Δx/2 and \
         Δx/4 to 1.5 s, the finest also with the water stretching without bound (no \
         `cavitation`), and Buchner's dam break (`dam_break_buchner_2d.ron`, H/40 as shipped) \
         at H/40, H/80 and H/160 to t* = 8. Every other setting is the shipped scene's \
         (h = h_factor Δx follows the spacing); the probes are left out. The density \
         variation is the largest over the diagnostics rows (every 100 steps). The CI's \
         second tier runs the Δx/2 case (`validation/tests/validation/refinement.rs`) and \
         the H/40 one (`validation/tests/validation/dam_break_pressure.rs`, with its \
         probes); the finer ones run here only.\n\n",
    );
    body += &table.render();
    body += &failures(&runs);
    body += &if ended.is_empty() {
        "**Finding.** Every case with the shipped settings runs to its end time without a \
         blow-up"
            .to_string()
    } else {
        format!(
            "**Finding.** NOT every case with the shipped settings runs to its end: {} stopped \
             early",
            ended.join(", ")
        )
    };
    body += &if controls.is_empty() {
        "; the water stretching without bound runs to its end too.\n\n".to_string()
    } else {
        format!(
            "; with the water stretching without bound, {} stopped early (the table's \
             failures say where and why).\n\n",
            controls.join(", ")
        )
    };
    Ok((
        Section {
            title: "Stability under refinement (walls of particles)".into(),
            body,
        },
        runs,
    ))
}
