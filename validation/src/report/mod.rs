//! `dualsph-validation report`: the paper's benchmarks (§7 of Ren, Dai, Zhuang & Rabczuk,
//! *Dual-support Smoothed Particle Hydrodynamics*, preprint; RenDSSPH in docs/references.md)
//! run case by case, graded against their references ([`dualsph_reference`]) and written up
//! as `report.md` with PNG plots; likewise the flows bounded by walls of particles and the
//! viscous flows ([`walls`]).
//!
//! Each benchmark module builds its cases from the scene files, runs them ([`case`]),
//! computes the error metrics, draws the plots and returns a markdown [`Section`] together
//! with a typed result that the end-to-end tests assert on.

pub mod budget;
pub mod case;
pub mod dam_break;
pub mod drop;
pub mod heat;
mod markdown;
pub mod sedov;
pub mod sod;
pub mod speed_error;
pub mod three_d;
pub mod walls;

pub use case::{CaseRun, CaseSpec, Recording, coarsen, run_case};
pub use markdown::Table;

use dualsph_scene::Scene;
use std::path::{Path, PathBuf};

/// Where the scenes are, where the report goes, and at which resolution.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// Folder holding the scene files (`scenes/`).
    pub scenes: PathBuf,
    /// Folder receiving `report.md` and the PNG plots.
    pub out: PathBuf,
    /// Spacing multiplier: 1 is the scenes' resolution (the paper's, for its benchmarks), 2
    /// halves it in every direction.
    pub coarsen: f64,
    /// Replaces the end time of the long cases (the dam break) when set.
    pub end_time: Option<f64>,
    /// Log each case as it starts and ends (stderr).
    pub log: bool,
}

impl ReportOptions {
    /// Loads a scene of the set, applying the resolution option.
    pub fn scene(&self, file: &str) -> Result<Scene, ReportError> {
        let path = self.scenes.join(file);
        let mut scene = Scene::load(&path, &dualsph::default_registry())
            .map_err(|e| ReportError::Scene(e.to_string()))?;
        if self.coarsen != 1.0 {
            coarsen(&mut scene, self.coarsen);
        }
        Ok(scene)
    }

    /// Loads a scene of the set with `from` replaced by `to` in its text first (a plugin
    /// left out or one of its options changed), applying the resolution option. Fails when
    /// the text does not contain `from`.
    pub fn scene_edited(&self, file: &str, from: &str, to: &str) -> Result<Scene, ReportError> {
        self.scene_with_edits(file, &[(from, to)])
    }

    /// Loads a scene of the set with each `(from, to)` of `edits` applied to its text in
    /// turn (every occurrence of `from` replaced by `to`), applying the resolution option.
    /// Fails when the text does not contain a `from`.
    pub fn scene_with_edits<A: AsRef<str>, B: AsRef<str>>(
        &self,
        file: &str,
        edits: &[(A, B)],
    ) -> Result<Scene, ReportError> {
        let path = self.scenes.join(file);
        let mut text = std::fs::read_to_string(&path)
            .map_err(|e| ReportError::Scene(format!("{}: {e}", path.display())))?;
        for (from, to) in edits {
            let from = from.as_ref();
            if !text.contains(from) {
                return Err(ReportError::Scene(format!(
                    "{}: no `{from}` to replace",
                    path.display()
                )));
            }
            text = text.replace(from, to.as_ref());
        }
        let mut scene = Scene::from_str(&text, &path, &dualsph::default_registry())
            .map_err(|e| ReportError::Scene(e.to_string()))?;
        if self.coarsen != 1.0 {
            coarsen(&mut scene, self.coarsen);
        }
        Ok(scene)
    }

    /// Runs a case, logging it when asked.
    pub fn run(&self, spec: &CaseSpec, rec: &Recording) -> Result<CaseRun, ReportError> {
        if self.log {
            eprintln!("report: {} ({}) …", spec.label, spec.scene.name);
        }
        let run =
            run_case(spec, rec).map_err(|e| ReportError::Run(format!("{}: {e}", spec.label)))?;
        if let (true, Some(why)) = (self.log, &run.failure) {
            eprintln!("report: {} STOPPED EARLY: {why}", run.label);
        }
        if self.log {
            eprintln!(
                "report: {}: {} particles, {} steps, {:.1} s CPU ({:.2e} particle-steps/CPU-s)",
                run.label,
                run.particles,
                run.steps,
                run.cpu_seconds,
                run.particle_steps_per_cpu_second()
            );
        }
        Ok(run)
    }

    /// Runs every case with the same recording and grades each run.
    pub fn run_graded<T>(
        &self,
        specs: &[CaseSpec],
        rec: &Recording,
        grade: impl Fn(CaseRun) -> T,
    ) -> Result<Vec<T>, ReportError> {
        specs.iter().map(|c| self.run(c, rec).map(&grade)).collect()
    }

    /// Diagnostics every 10 steps, nothing else: what the heat, Sod and drop grading needs.
    pub fn every_ten_steps() -> Recording {
        Recording {
            every: 10,
            ..Default::default()
        }
    }

    /// A scene run twice: as written (DualSupport) and with SingleSupport, in that order.
    pub fn dual_and_single(
        &self,
        file: &str,
        dual: &str,
        single: &str,
    ) -> Result<Vec<CaseSpec>, ReportError> {
        Ok(vec![
            CaseSpec::new(dual, self.scene(file)?, None),
            CaseSpec::new(
                single,
                self.scene(file)?,
                Some(dualsph_scene::Formulation::SingleSupport),
            ),
        ])
    }

    /// Path of an output file.
    pub fn file(&self, name: &str) -> PathBuf {
        self.out.join(name)
    }
}

/// Why a report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A scene failed to load or validate.
    #[error("{0}")]
    Scene(String),
    /// A case failed to build or blew up.
    #[error("{0}")]
    Run(String),
    /// A plot or the report could not be written.
    #[error("{0}")]
    Output(String),
}

impl From<dualsph_plot::PlotError> for ReportError {
    fn from(e: dualsph_plot::PlotError) -> Self {
        ReportError::Output(e.to_string())
    }
}

/// A part of the report: a heading and its markdown body.
#[derive(Clone, Debug)]
pub struct Section {
    /// Heading.
    pub title: String,
    /// Markdown below the heading.
    pub body: String,
}

/// The benchmarks: the paper's, then the walls of particles and the viscous flows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Benchmark {
    /// 1-D heat conduction (§7.1).
    Heat,
    /// Sod shock tube (§7.2).
    Sod,
    /// Elliptical drop (§7.3).
    Drop,
    /// Dam break over a dry bed (§7.4).
    DamBreak,
    /// Sod, drop, dam break and the walls dam break (adaptive among them) at three resolutions: error against CPU seconds.
    SpeedError,
    /// The 3-D drop and dam break (dimension genericity).
    ThreeD,
    /// The Sedov–Taylor blast wave in 2-D and 3-D: DualSupport, grad-h and SingleSupport.
    Sedov,
    /// Water at rest in a tank with walls of particles: the hydrostatic pressure.
    Hydrostatic,
    /// Plane Poiseuille flow between walls of particles against the series solution.
    Poiseuille,
    /// The lid-driven cavity at Re = 100 against Ghia, Ghia & Shin (1982).
    Cavity,
    /// The periodic Taylor–Green vortex: the decay of its mode.
    TaylorGreen,
    /// The pressure of a dam break on the far wall against Buchner (2002).
    WallPressure,
    /// The paper's Case II and Case III dam breaks with walls of particles: the water front
    /// against Koshizuka & Oka (1996), beside specular walls.
    WallsDamBreak,
    /// The 3-D tank with an STL obstacle: the load on the submerged obstacle against its
    /// buoyancy.
    StlTank,
    /// A 2-D dam break onto a step and a cylinder: the obstacles' load history, the
    /// cylinder's at rest against its buoyancy.
    DamBreakObstacle,
    /// The walls dam break at Δx/2 and Δx/4 and Buchner's at H/40, H/80 and H/160, to their end.
    Refinement,
}

impl Benchmark {
    /// The paper's four, in its order, and the Sedov blast (the speed-against-error study
    /// and the 3-D cases are asked for by name).
    pub const ALL: [Benchmark; 5] = [
        Benchmark::Heat,
        Benchmark::Sod,
        Benchmark::Drop,
        Benchmark::DamBreak,
        Benchmark::Sedov,
    ];

    /// Runs the benchmark and returns its section.
    pub fn section(self, opts: &ReportOptions) -> Result<Section, ReportError> {
        Ok(match self {
            Benchmark::Heat => heat::run(opts)?.0,
            Benchmark::Sod => sod::run(opts)?.0,
            Benchmark::Drop => drop::run(opts)?.0,
            Benchmark::DamBreak => dam_break::run(opts)?.0,
            Benchmark::SpeedError => speed_error::run(opts)?.0,
            Benchmark::ThreeD => three_d::run(opts)?.0,
            Benchmark::Sedov => sedov::run(opts)?.0,
            Benchmark::Hydrostatic => walls::hydrostatic::run(opts)?.0,
            Benchmark::Poiseuille => walls::poiseuille::run(opts)?.0,
            Benchmark::Cavity => walls::cavity::run(opts)?.0,
            Benchmark::TaylorGreen => walls::taylor_green::run(opts)?.0,
            Benchmark::WallPressure => walls::wall_pressure::run(opts)?.0,
            Benchmark::WallsDamBreak => walls::dam_break_fronts::run(opts)?.0,
            Benchmark::StlTank => walls::stl_tank::run(opts)?.0,
            Benchmark::DamBreakObstacle => walls::dam_break_obstacle::run(opts)?.0,
            Benchmark::Refinement => walls::refinement::run(opts)?.0,
        })
    }
}

/// Runs the benchmarks and writes `report.md` (atomically, after each benchmark) with their
/// plots beside it.
pub fn write_report(
    benchmarks: &[Benchmark],
    opts: &ReportOptions,
    command: &str,
) -> Result<PathBuf, ReportError> {
    std::fs::create_dir_all(&opts.out)
        .map_err(|e| ReportError::Output(format!("{}: {e}", opts.out.display())))?;
    let mut md = format!("# dualsph validation report: {}\n\n", title(benchmarks));
    md += &format!(
        "Regenerate with `{command}`. Resolution: {}. Threads: {} (rayon). Wall and CPU seconds \
         are of the stepping loop; CPU seconds add all threads. \"h\" is the support radius \
         (W = 0 for r ≥ h), as in the paper.\n\n",
        if opts.coarsen == 1.0 {
            "the scenes' (the paper's, for its benchmarks)".to_string()
        } else {
            format!("particle spacing × {}", opts.coarsen)
        },
        rayon::current_num_threads()
    );
    // Rewritten after every benchmark, so a long report shows its finished parts early.
    let path = opts.out.join("report.md");
    for b in benchmarks {
        let s = b.section(opts)?;
        md += &format!("## {}\n\n{}\n", s.title, s.body);
        dualsph_io::write_atomic(&path, md.as_bytes())
            .map_err(|e| ReportError::Output(e.to_string()))?;
    }
    Ok(path)
}

/// What a report of these benchmarks is: the paper's when every one is of the paper (its
/// §7, the speed-against-error study of three of them, its 3-D cases and the Sedov blast),
/// the viscous and wall flows when every one is of those, else both.
fn title(benchmarks: &[Benchmark]) -> &'static str {
    let walls = |b: &Benchmark| {
        matches!(
            b,
            Benchmark::Hydrostatic
                | Benchmark::Poiseuille
                | Benchmark::Cavity
                | Benchmark::TaylorGreen
                | Benchmark::WallPressure
                | Benchmark::WallsDamBreak
                | Benchmark::StlTank
                | Benchmark::DamBreakObstacle
                | Benchmark::Refinement
        )
    };
    if benchmarks.iter().all(|b| !walls(b)) {
        "the paper's benchmarks"
    } else if benchmarks.iter().all(walls) {
        "walls of particles and viscous flows"
    } else {
        "the paper's benchmarks, walls of particles and viscous flows"
    }
}

/// The common columns of every case table: the time reached (marked when the run blew up),
/// particles, steps, wall and CPU seconds, and particle-steps per CPU second.
pub(crate) fn cost_cells(run: &CaseRun) -> Vec<String> {
    let t = run.final_diagnostics().t;
    vec![
        if run.failure.is_some() {
            format!("**{t:.4} (blew up)**")
        } else {
            format!("{t:.4}")
        },
        run.particles.to_string(),
        run.steps.to_string(),
        format!("{:.1}", run.wall_seconds),
        format!("{:.1}", run.cpu_seconds),
        // /proc/self/stat counts in 0.01 s ticks: a rate from a few ticks means nothing.
        if run.cpu_seconds < 0.1 {
            "— (< 0.1 CPU s)".into()
        } else {
            format!("{:.2e}", run.particle_steps_per_cpu_second())
        },
    ]
}

/// Headers matching [`cost_cells`].
pub(crate) const COST_HEADERS: [&str; 6] = [
    "t reached (s)",
    "particles",
    "steps",
    "wall s",
    "CPU s",
    "particle-steps / CPU-s",
];

/// A paragraph naming every run that stopped early and why (empty when none did).
pub(crate) fn failures<'a>(runs: impl IntoIterator<Item = &'a CaseRun>) -> String {
    let mut md = String::new();
    for run in runs {
        if let Some(why) = &run.failure {
            md += &format!(
                "**{} stopped early** at t = {:.4} s: {why}. Its figures cover the run up to the last good step.\n\n",
                run.label,
                run.final_diagnostics().t
            );
        }
    }
    md
}

/// One marker series per run: the final particles kept by `keep`, as points `at(p)`, in the
/// palette colour of the run's index.
pub(crate) fn final_particles<'a>(
    runs: impl IntoIterator<Item = &'a CaseRun>,
    keep: impl Fn(&dualsph_io::ParticleRow<'_>) -> bool,
    at: impl Fn(&dualsph_io::ParticleRow<'_>) -> (f64, f64),
) -> Vec<dualsph_plot::Series> {
    runs.into_iter()
        .enumerate()
        .map(|(k, run)| {
            let pts = run
                .last
                .rows()
                .filter(|p| keep(p))
                .map(|p| at(&p))
                .collect();
            dualsph_plot::Series::new(
                run.label.clone(),
                pts,
                dualsph_plot::SeriesStyle::Markers,
                k,
            )
        })
        .collect()
}

/// A markdown image link to a file in (or below) the report folder `base`.
pub(crate) fn image_in(alt: &str, path: &Path, base: &Path) -> String {
    let rel = path.strip_prefix(base).unwrap_or(path);
    format!("![{alt}]({})\n\n", rel.to_string_lossy())
}

/// A markdown image link to a file in the report folder.
pub(crate) fn image(alt: &str, path: &Path) -> String {
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    format!("![{alt}]({name})\n\n")
}
