//! The paper's Case II and Case III dam breaks (§7.4 of Ren, Dai, Zhuang & Rabczuk,
//! *Dual-support Smoothed Particle Hydrodynamics*, preprint; RenDSSPH in docs/references.md)
//! in a tank whose walls are layers of particles, graded by the water front against the
//! experiment of Koshizuka & Oka (1996), *Moving-Particle Semi-Implicit Method for
//! Fragmentation of Incompressible Fluid*, Nucl. Sci. Eng. 123, 421–434.
//!
//! Case II is `scenes/dam_break_2d_walls_two_level.ron` (dual-support, Δx = 0.0125 m in the
//! lower 0.5 m of the column and 0.025 m above, walls at the fine spacing), Case III
//! `scenes/dam_break_2d_walls.ron` at a uniform Δx = 0.0125 m. The walls' pressure is
//! extrapolated from the water (Adami, Hu & Adams 2012, J. Comput. Phys. 231, 7057, Eq. 27)
//! and their velocity in the artificial viscosity is the water's next to them (free-slip);
//! the water cavitates at its vapour pressure (`TaitEos(cavitation: true, min_pressure:
//! -99000.0)`). Both run to [`END_TIME`] (the experimental front reaches the far wall at 0.70 s); the front
//! is the largest x of a water particle with another within its support, compared with the
//! experiment without a time shift by the RMS over the experimental points with t ≤ 0.70 s,
//! and Case II with Case III by the RMS of their difference every 0.01 s on (0, 0.70]
//! ([`crate::report::dam_break`]). The section runs beside them Case II with the walls' own
//! velocity in the viscous term (`viscous: Own`: the floor drags the surge, the failure the
//! bounds are meant to catch) and the paper's Cases II and III with specular walls
//! (`dam_break_2d.ron`, `dam_break_2d_uniform.ron`) to the same time, for scale.

use super::super::dam_break::{DamBreakCase, FRONT_WINDOW, front_rms_between, grade};
use super::super::{
    COST_HEADERS, CaseSpec, Recording, ReportError, ReportOptions, Section, Table, cost_cells,
    failures, image,
};
use super::within;
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use dualsph_reference::dam_break::KOSHIZUKA_OKA_FRONT;

/// The cases run to this time (s) unless the options say otherwise.
pub const END_TIME: f64 = 0.72;
/// Bound on each wall case's front RMS against the experiment (m).
pub const EXPERIMENT_RMS: f64 = 0.1;
/// Bound on the RMS between Case II's and Case III's fronts with walls of particles (m).
pub const BETWEEN_RMS: f64 = 0.04;
/// The fewest experimental points a front is compared on.
pub const MIN_POINTS: usize = 10;

/// The scene of Case III: the walls dam break at Δx = 0.0125 m.
const CASE_THREE: (&str, [(&str, &str); 2]) = (
    "dam_break_2d_walls.ron",
    [
        ("spacing: 0.025", "spacing: 0.0125"),
        (
            "domain: (min: [-0.075, -0.075], max: [4.075, 3.075])",
            "domain: (min: [-0.0375, -0.0375], max: [4.0375, 3.0375])",
        ),
    ],
);
/// The scene of Case II.
const CASE_TWO: &str = "dam_break_2d_walls_two_level.ron";

/// A spec run to [`END_TIME`] (or the options' end time).
fn to_end(opts: &ReportOptions, label: &str, scene: dualsph_scene::Scene) -> CaseSpec {
    let mut spec = CaseSpec::new(label, scene, None);
    spec.scene.end_time = opts.end_time.unwrap_or(END_TIME);
    spec
}

/// Case II and Case III with walls of particles, in that order (module docs).
pub fn cases(opts: &ReportOptions) -> Result<Vec<CaseSpec>, ReportError> {
    Ok(vec![
        to_end(opts, "Case II, walls of particles", opts.scene(CASE_TWO)?),
        to_end(
            opts,
            "Case III, walls of particles",
            opts.scene_with_edits(CASE_THREE.0, &CASE_THREE.1)?,
        ),
    ])
}

/// The runs beside them: Case II with the walls' own velocity in the viscous term, then the
/// paper's Cases II and III with specular walls.
pub fn other_cases(opts: &ReportOptions) -> Result<Vec<CaseSpec>, ReportError> {
    Ok(vec![
        to_end(
            opts,
            "Case II, walls at their own velocity",
            opts.scene_edited(CASE_TWO, "viscous: FreeSlip", "viscous: Own")?,
        ),
        to_end(
            opts,
            "Case II, specular walls",
            opts.scene("dam_break_2d.ron")?,
        ),
        to_end(
            opts,
            "Case III, specular walls",
            opts.scene("dam_break_2d_uniform.ron")?,
        ),
    ])
}

/// The recording the grading needs: the front every 20 steps.
pub fn recording() -> Recording {
    Recording {
        every: 20,
        front: true,
        ..Recording::default()
    }
}

/// Case II and Case III graded, and the RMS between their fronts.
#[derive(Clone, Debug)]
pub struct FrontPair {
    /// Case II.
    pub two: DamBreakCase,
    /// Case III.
    pub three: DamBreakCase,
    /// RMS of Case II's front minus Case III's (m).
    pub between: f64,
}

impl FrontPair {
    /// Grades the two runs.
    pub fn of(two: DamBreakCase, three: DamBreakCase) -> Self {
        let between = front_rms_between(&two.run, &three.run);
        FrontPair {
            two,
            three,
            between,
        }
    }

    /// Whether the pair is within the bounds ([`bounds_hold`]).
    pub fn within_bounds(&self) -> bool {
        bounds_hold(&self.two, &self.three, self.between)
    }

    /// One line with the figures.
    pub fn describe(&self) -> String {
        format!(
            "front RMS against the experiment: II {:.4} m, III {:.4} m ({} points); II vs III {:.4} m",
            self.two.front_rms_experiment,
            self.three.front_rms_experiment,
            self.two.front_points,
            self.between
        )
    }
}

/// Whether both fronts are within [`EXPERIMENT_RMS`] of the experiment on at least
/// [`MIN_POINTS`] points, and within [`BETWEEN_RMS`] of each other (`between`).
pub fn bounds_hold(two: &DamBreakCase, three: &DamBreakCase, between: f64) -> bool {
    let near =
        |c: &DamBreakCase| c.front_points >= MIN_POINTS && c.front_rms_experiment < EXPERIMENT_RMS;
    near(two) && near(three) && between < BETWEEN_RMS
}

/// Runs the wall cases and grades them.
pub fn run_pair(opts: &ReportOptions) -> Result<FrontPair, ReportError> {
    let mut graded = opts.run_graded(&cases(opts)?, &recording(), grade)?;
    let three = graded.pop().expect("two cases");
    let two = graded.pop().expect("two cases");
    Ok(FrontPair::of(two, three))
}

/// Runs, grades, plots and writes the section.
pub fn run(opts: &ReportOptions) -> Result<(Section, FrontPair), ReportError> {
    let pair = run_pair(opts)?;
    let others = opts.run_graded(&other_cases(opts)?, &recording(), grade)?;
    let (own, spec_two, spec_three) = (&others[0], &others[1], &others[2]);
    let all = [&pair.two, &pair.three, own, spec_two, spec_three];
    let png = plot(opts, &all)?;
    let mut table = Table::new(
        [
            "case",
            "front RMS vs experiment (t ≤ 0.70 s)",
            "front RMS vs Case III",
        ]
        .into_iter()
        .chain(COST_HEADERS),
    );
    // each case against the Case III of its own walls
    let against = [
        &pair.three,
        &pair.three,
        &pair.three,
        spec_three,
        spec_three,
    ];
    for (c, three) in all.iter().zip(against) {
        let mut cells = vec![
            c.run.label.clone(),
            format!(
                "{:.3} m ({} points)",
                c.front_rms_experiment, c.front_points
            ),
            format!("{:.3} m", front_rms_between(&c.run, &three.run)),
        ];
        cells.extend(cost_cells(&c.run));
        table.row(cells);
    }
    let t_end = pair.two.run.final_diagnostics().t;
    let mut body = format!(
        "The paper's dam break (a 1 m × 2 m water column in a 4 m tank, Tait c0 = 100 m/s, \
         artificial viscosity α = β = 1, h = 2Δx) with the tank's walls as three layers of \
         particles whose pressure is extrapolated from the water (Adami et al. 2012) and whose \
         velocity in the artificial viscosity is the water's next to them (free-slip); the \
         water starts hydrostatic and cavitates at its vapour pressure (TaitEos `cavitation` \
         at −99 kPa), CFL 0.2 of the support radius, t = {t_end:.2} s. Case II: \
         dual-support, Δx = 0.0125 m in the lower 0.5 m of the column and 0.025 m above, walls \
         at 0.0125 m (scene `dam_break_2d_walls_two_level.ron`); Case III: uniform Δx = 0.0125 \
         m (`dam_break_2d_walls.ron` at half its spacing). Beside them: Case II with the walls' \
         own velocity in the viscous term (`viscous: Own`), and the paper's Cases II and III \
         with specular walls (`dam_break_2d.ron`, `dam_break_2d_uniform.ron`) to the same time. \
         The front is the largest x of a water particle with another within its support, \
         compared with Koshizuka & Oka (1996) without a time shift; the RMS against Case III is \
         against the Case III of the same walls.\n\n"
    );
    body += &table.render();
    body += &failures(all.iter().map(|c| &c.run));
    body += &verdict(&pair, own, spec_two, spec_three);
    body += &image("water front against the experiment", &png);
    Ok((
        Section {
            title: "Dam break with walls of particles: the water front (Cases II and III)".into(),
            body,
        },
        pair,
    ))
}

/// The fronts of every case against time, with the experiment.
fn plot(opts: &ReportOptions, all: &[&DamBreakCase]) -> Result<std::path::PathBuf, ReportError> {
    let mut front = LinePlot::new(
        "Dam break with walls of particles: water front",
        "t (s)",
        "front x (m)",
    )
    .with(Series::new(
        "Koshizuka & Oka (1996)",
        KOSHIZUKA_OKA_FRONT.to_vec(),
        SeriesStyle::Markers,
        6,
    ));
    for (k, c) in all.iter().enumerate() {
        front = front.with(Series::new(
            c.run.label.clone(),
            c.run.front.clone(),
            SeriesStyle::Line,
            k,
        ));
    }
    // room above the fronts for the legend (upper right)
    front.x_range = Some((0.0, 0.8));
    front.y_range = Some((0.9, 5.4));
    let png = opts.file("walls_dam_break_front.png");
    front.write_png(&png)?;
    Ok(png)
}

fn verdict(
    pair: &FrontPair,
    own: &DamBreakCase,
    spec_two: &DamBreakCase,
    spec_three: &DamBreakCase,
) -> String {
    let own_between = front_rms_between(&own.run, &pair.three.run);
    format!(
        "**Finding.** With walls of particles the fronts are {:.3} m (Case II) and {:.3} m (Case \
         III) RMS from the experiment up to {FRONT_WINDOW:.2} s, and Case II's is {:.3} m RMS \
         from Case III's: {} the bounds of {EXPERIMENT_RMS} m against the experiment and \
         {BETWEEN_RMS} m between the cases. With specular walls the same cases are {:.3} m and \
         {:.3} m from the experiment and {:.3} m apart. With the walls' own velocity in the \
         viscous term Case II's front is {:.3} m from the experiment and {:.3} m from Case III \
         (free-slip walls): {} the bounds.\n\n",
        pair.two.front_rms_experiment,
        pair.three.front_rms_experiment,
        pair.between,
        within(pair.within_bounds()),
        spec_two.front_rms_experiment,
        spec_three.front_rms_experiment,
        front_rms_between(&spec_two.run, &spec_three.run),
        own.front_rms_experiment,
        own_between,
        within(bounds_hold(own, &pair.three, own_between)),
    )
}
