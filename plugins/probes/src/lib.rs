//! `Probes(every: k, probes: [...])`: fixed measurement points, lines and water-height gauges
//! sampled every k steps into `probes.csv` in the run's output directory.
//!
//! ```ron
//! Probes(
//!     every: 20,
//!     probes: [
//!         Point(name: "P1", at: [4.0, 0.16], quantity: "pressure"),
//!         Line(name: "u", start: [0.0, 0.1], end: [1.0, 0.1], n: 101, quantity: "velocity.x"),
//!         WaterHeight(name: "H1", at: [0.3]),          // 2-D: at = [x]; 3-D: [x, y]
//!         Sensor(name: "P1", start: [3.2125, 0.07], end: [3.2125, 0.16], n: 10, floor: 0.0),
//!     ],
//! )
//! ```
//!
//! A point or line measures a `quantity` named like the snapshot columns: any registered
//! scalar column (`"density"`, `"pressure"`, a plugin's own), one component of a vector or
//! matrix column (`"velocity.x"`, `"velocity_gradient.xy"`), or the derived `"speed"` and
//! `"shepard_sum"` (see [`quantity`] for the spellings). The names are checked when the
//! simulation is built: an unknown one is an error that lists those the scene has.
//!
//! The probes sample the particles of the fluid bodies (or of the bodies named in `bodies`),
//! so that a sensor next to a wall of particles reads the fluid.
//!
//! Values are the **Shepard-normalised** SPH interpolant at the point,
//! `A(x) = Σ_j A_j V_j W_j / Σ_j V_j W_j` with each particle's own kernel and support radius
//! (FLUISIM Def. 3.1 normalised; see [`dualsph_core::sampling`]). The normalisation removes
//! the kernel-truncation deficit at a wall or free surface, so a sensor on a wall face reads
//! the fluid next to it. Where no particle reaches the point (`Σ V_j W_j` below `min_shepard`,
//! default 0: none at all) the value is `NaN` (a dry sensor).
//!
//! A sensor reports the mean over its extent, as experiments and peers report a pressure
//! sensor (a transducer face, not a point): the interpolant at `n` equally spaced points from
//! `start` to `end`, a dry point counted as zero (`dry: Zero`, the default), left out
//! (`Skip`) or making the reading NaN (`Nan`), and with `floor: x` every value below x read as
//! x (`floor: 0.0` reads suction as zero, as the published sensor curves do). With `clip: x`
//! each particle's value below x is read as x before the interpolation instead, and with
//! `reach: r` the sensor interpolates with every support radius times r,
//! `A(x) = Σ_j A_j V_j W(x − x_j, r h_j) / Σ_j V_j W(x − x_j, r h_j)`: TrixiParticles.jl's
//! dam-break validation (`validation/dam_break_2d`) reads its sensors with
//! `clip_negative_pressure = true`, twice the fluid's smoothing length and `cut_off_bnd`
//! (a point where the walls' kernel-weighted mass `Σ_b m_b W_b` exceeds the fluid's is
//! dry), i.e. `clip: 0.0, reach: 2.0, cut_off: true`.
//!
//! A water-height gauge reports the height (above the domain's bottom) of the highest point of
//! the vertical line through `at` where the Shepard sum `σ = Σ V_j W_j` is at least
//! `threshold` (default 0.5 — σ is ≈ 1 in the bulk and ½ at a flat free surface), linearly
//! interpolated between samples `dy` apart (default: a quarter of the smallest h). An isolated
//! droplet has σ ≈ 0.1 and does not count; a connected splash does. 0 when the line is dry.
//!
//! ## Files
//! * `probes.csv`: `t,step,<one column per probe value>`; a point or gauge is one column named
//!   after it, a line of n points is n columns `name[0]` … `name[n-1]`. One row per sample
//!   (steps that are multiples of `every`, step 0, and the last step: `t_end` or the
//!   runner's [`StepLimit`]).
//! * `probes_points.csv`: `column,probe,kind,quantity,x,y,z`, the position of every column
//!   (`quantity`: the quantity's name, `water_height` for a gauge).
//!
//! The samples so far ([`ProbeSamples`]) are kept in checkpoints, so a resumed run rewrites
//! the whole table at its first sample. Both files are written whole and atomically at a
//! run's first sample ([`dualsph_io::write_atomic_with`]); after it each sample appends its
//! row to `probes.csv` ([`dualsph_io::GrowingCsv`], like `diagnostics.csv`), so both are
//! complete, parseable tables at any moment.
//! [`plot_probes`] turns them into PNG charts.
#![warn(missing_docs)]

mod plot;
pub mod quantity;
mod sample;
mod validate;
pub mod vorticity;

pub use plot::{ProbeTable, plot_probes, read_probes};
pub use quantity::Quantity;
pub use sample::{
    ProbedParticles, evaluate, sample_probes, sensor_mean, water_height, write_files,
};
pub use vorticity::Vorticity;

use dualsph_core::bevy_ecs::prelude::*;

use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// File name of the probe table.
pub const PROBES_FILE: &str = "probes.csv";
/// File name of the probe positions.
pub const PROBE_POINTS_FILE: &str = "probes_points.csv";

/// One probe of the scene.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub enum Probe {
    /// A fixed point.
    Point {
        /// Column name.
        name: String,
        /// Position (m; one component per dimension).
        at: Vec<Real>,
        /// What to sample.
        quantity: Quantity,
    },
    /// `n` equally spaced points from `start` to `end` (both included).
    Line {
        /// Column prefix: the columns are `name[0]` … `name[n-1]`.
        name: String,
        /// First point (m).
        start: Vec<Real>,
        /// Last point (m).
        end: Vec<Real>,
        /// Number of points (≥ 2).
        n: usize,
        /// What to sample.
        quantity: Quantity,
    },
    /// A pressure sensor as the literature reports one: the mean of `n` equally spaced
    /// points from `start` to `end` (both included) over the sensor's extent, a dry point
    /// counted as `dry` says and values below `floor` raised to it.
    Sensor {
        /// Column name.
        name: String,
        /// One end of the sensor's extent (m).
        start: Vec<Real>,
        /// The other end (m).
        end: Vec<Real>,
        /// Number of points (≥ 2).
        n: usize,
        /// What to sample (default `"pressure"`).
        #[serde(default = "pressure")]
        quantity: Quantity,
        /// What a dry point (no particle within reach) counts as (default `Zero`).
        #[serde(default)]
        dry: Dry,
        /// Values below it (in the quantity's unit) are read as it (`floor: 0.0` reads suction as zero); default none.
        #[serde(default)]
        floor: Option<Real>,
        /// Each particle's value below it (in the quantity's unit) is read as it *before* the
        /// interpolation; default none. `clip: 0.0` is TrixiParticles.jl's `clip_negative_pressure = true`, which a
        /// `floor` on the interpolated value is not: a point between a compressed and a
        /// suction particle reads the compressed one's share.
        #[serde(default)]
        clip: Option<Real>,
        /// Factor (dimensionless) on every particle's support radius for this sensor's
        /// interpolation (default 1: the particles' own): the points read `Σ_j A_j V_j W(x − x_j, r h_j) /
        /// Σ_j V_j W(x − x_j, r h_j)`. TrixiParticles.jl's dam-break validation interpolates
        /// its sensors with twice the fluid's smoothing length (`reach: 2.0`).
        #[serde(default)]
        reach: Option<Real>,
        /// A point where the particles the probes do not sample (the walls) put more
        /// kernel-weighted mass than the sampled fluid, `Σ_b m_b W_b > Σ_f m_f W_f` (with the
        /// same `reach`), is dry (default false): TrixiParticles.jl's `cut_off_bnd`, which
        /// keeps a point next to a wall from reading a film of fluid a particle thick as a
        /// full value.
        #[serde(default)]
        cut_off: bool,
    },
    /// Free-surface height on the vertical line through `at` (2-D: `[x]`, 3-D: `[x, y]`).
    WaterHeight {
        /// Column name.
        name: String,
        /// Horizontal position (m; dimension − 1 components).
        at: Vec<Real>,
        /// Shepard-sum level of the surface (dimensionless; default 0.5).
        #[serde(default)]
        threshold: Option<Real>,
        /// Vertical sampling step (m; default: a quarter of the smallest h).
        #[serde(default)]
        dy: Option<Real>,
    },
}

/// What a [`Probe::Sensor`]'s dry point counts as.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
pub enum Dry {
    /// Zero (a dry sensor reads no pressure).
    #[default]
    Zero,
    /// Left out of the mean (the mean of the wet points; NaN when all are dry).
    Skip,
    /// NaN: the sensor reads NaN while any of its points is dry.
    Nan,
}

/// The default quantity of a sensor.
fn pressure() -> Quantity {
    Quantity::parse("pressure").expect("a column name")
}

/// The plugin's settings.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Probes {
    /// Sample every this many steps (≥ 1).
    pub every: u64,
    /// Smallest Shepard sum (dimensionless) for which a point value is reported (else NaN); default 0.
    #[serde(default)]
    pub min_shepard: Real,
    /// The bodies whose particles the probes sample, by name; empty (the default) means
    /// every fluid body, so that a probe next to a wall of particles reads the fluid, not
    /// the wall.
    #[serde(default)]
    pub bodies: Vec<String>,
    /// The probes.
    pub probes: Vec<Probe>,
}

/// One output column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Column name in `probes.csv`.
    pub name: String,
    /// Name of the probe it belongs to.
    pub probe: String,
    /// `point`, `line`, `sensor` or `water_height`.
    pub kind: &'static str,
    /// Quantity name (`density`, `velocity.x`, …, or `water_height`).
    pub quantity: String,
    /// Position (x, y, z; unused components 0; for a gauge, the vertical one is the bottom;
    /// for a sensor, the middle of its extent).
    pub pos: [Real; 3],
    what: What,
}

#[derive(Clone, Debug, PartialEq)]
enum What {
    Value(Quantity),
    Mean {
        quantity: Quantity,
        /// The points averaged over (3-D embedding).
        points: Vec<[Real; 3]>,
        dry: Dry,
        floor: Option<Real>,
        /// Per-particle clip before the interpolation.
        clip: Option<Real>,
        /// Factor on the support radii.
        reach: Real,
        /// Dry where the other bodies' mass outweighs the fluid's.
        cut_off: bool,
    },
    Height {
        threshold: Real,
        dy: Option<Real>,
    },
}

/// The largest factor a sensor may put on the support radii ([`Probe::Sensor`]'s `reach`).
pub const MAX_SENSOR_REACH: Real = 10.0;

/// The most samples a water-height gauge takes along the domain's height per reading.
pub const MAX_GAUGE_SAMPLES: Real = 1e6;

/// The most values the probe table may hold, columns × samples (0.8 GB in memory, about
/// 2 GB of CSV): a scene whose `max_steps` implies more is refused, and a run reaching it
/// stops with the cause.
pub const MAX_TABLE_VALUES: u64 = 100_000_000;

/// The plugin's settings once built: columns, where their values come from, and the last
/// write error (if any). The samples are [`ProbeSamples`].
#[derive(Resource, Debug)]
pub struct ProbeState<V: Vector> {
    /// Sample cadence.
    pub every: u64,
    /// Smallest Shepard sum for a reported value.
    pub min_shepard: Real,
    /// Whether the particles of each body (by [`BodyId`]) are sampled.
    pub sampled: Vec<bool>,
    /// Output columns in file order.
    pub columns: Vec<Column>,
    points: Vec<V>,
    /// Every quantity sampled and the values it reads (set when the simulation is finished).
    sources: Vec<(Quantity, quantity::Source)>,
    /// The last error writing the files (the run goes on; the message says which file).
    pub write_error: Option<String>,
    /// The most values the table may hold ([`MAX_TABLE_VALUES`]).
    pub max_values: u64,
    /// `probes.csv` as the run writes it, once its first sample is written.
    table: Option<dualsph_io::GrowingCsv>,
}

impl<V: Vector> ProbeState<V> {
    /// Every quantity the probes sample, each once (resolved when the simulation is
    /// finished: empty before).
    pub fn quantities(&self) -> impl Iterator<Item = &Quantity> {
        self.sources.iter().map(|(q, _)| q)
    }
}

/// The probes' samples so far: `(step, t, values)` in step order, one value per column of
/// [`ProbeState`]. Kept in checkpoints (key `probes`), so a resumed run goes on with them.
#[derive(Resource, Debug, Default, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProbeSamples {
    /// The samples.
    pub rows: Vec<(u64, Real, Vec<Real>)>,
}

/// Resolves the probes' quantity names against the registered columns (a finish hook: every
/// plugin has registered its columns by then); the error names the probe and lists the
/// quantities the scene has.
fn resolve_quantities<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    let Some(state) = sim.world.get_resource::<ProbeState<V>>() else {
        return Ok(());
    };
    let columns = sim.world.resource::<dualsph_core::columns::Columns>();
    let mut sources: Vec<(Quantity, quantity::Source)> = Vec::new();
    for c in &state.columns {
        let q = match &c.what {
            What::Value(q) | What::Mean { quantity: q, .. } => q,
            What::Height { .. } => continue,
        };
        if sources.iter().any(|s| &s.0 == q) {
            continue;
        }
        let source = quantity::resolve(q, columns, V::DIM)
            .map_err(|e| SimError::Build(format!("Probes: probe `{}`: {e}", c.probe)))?;
        sources.push((q.clone(), source));
    }
    sim.world.resource_mut::<ProbeState<V>>().sources = sources;
    Ok(())
}

/// `n ≥ 2` equally spaced points from `start` to `end`, both included.
fn spaced(start: &[Real], end: &[Real], n: usize) -> Vec<Vec<Real>> {
    (0..n)
        .map(|k| {
            let f = k as Real / (n as Real - 1.0);
            start
                .iter()
                .zip(end)
                .map(|(a, b)| a + f * (b - a))
                .collect()
        })
        .collect()
}

impl Probes {
    fn columns(&self) -> Vec<Column> {
        let mut out = Vec::new();
        let xyz = |v: &[Real]| {
            let mut p = [0.0; 3];
            p[..v.len().min(3)].copy_from_slice(&v[..v.len().min(3)]);
            p
        };
        for p in &self.probes {
            match p {
                Probe::Point { name, at, quantity } => out.push(Column {
                    name: name.clone(),
                    probe: name.clone(),
                    kind: "point",
                    quantity: quantity.to_string(),
                    pos: xyz(at),
                    what: What::Value(quantity.clone()),
                }),
                Probe::Line {
                    name,
                    start,
                    end,
                    n,
                    quantity,
                } => {
                    for (k, at) in spaced(start, end, *n).into_iter().enumerate() {
                        out.push(Column {
                            name: format!("{name}[{k}]"),
                            probe: name.clone(),
                            kind: "line",
                            quantity: quantity.to_string(),
                            pos: xyz(&at),
                            what: What::Value(quantity.clone()),
                        });
                    }
                }
                Probe::Sensor {
                    name,
                    start,
                    end,
                    n,
                    quantity,
                    dry,
                    floor,
                    clip,
                    reach,
                    cut_off,
                } => {
                    let mid: Vec<Real> =
                        start.iter().zip(end).map(|(a, b)| 0.5 * (a + b)).collect();
                    out.push(Column {
                        name: name.clone(),
                        probe: name.clone(),
                        kind: "sensor",
                        quantity: quantity.to_string(),
                        pos: xyz(&mid),
                        what: What::Mean {
                            quantity: quantity.clone(),
                            points: spaced(start, end, *n).iter().map(|p| xyz(p)).collect(),
                            dry: *dry,
                            floor: *floor,
                            clip: *clip,
                            reach: reach.unwrap_or(1.0),
                            cut_off: *cut_off,
                        },
                    });
                }
                Probe::WaterHeight {
                    name,
                    at,
                    threshold,
                    dy,
                } => out.push(Column {
                    name: name.clone(),
                    probe: name.clone(),
                    kind: "water_height",
                    quantity: "water_height".into(),
                    pos: xyz(at),
                    what: What::Height {
                        threshold: threshold.unwrap_or(0.5),
                        dy: *dy,
                    },
                }),
            }
        }
        out
    }
}

impl Probes {
    /// The columns of the probe table: n for a line, one for any other probe.
    pub fn column_count(&self) -> u64 {
        self.probes
            .iter()
            .map(|p| match p {
                Probe::Line { n, .. } => *n as u64,
                _ => 1,
            })
            .sum()
    }
}

/// By body index, whether the body's particles are sampled: those named in `names`, or every
/// fluid body when it is empty (the probes' and the vorticity's `bodies`).
pub(crate) fn sampled_bodies(bodies: &dualsph_core::bodies::Bodies, names: &[String]) -> Vec<bool> {
    (bodies.0.iter())
        .map(|b| match names.is_empty() {
            true => b.is_fluid(),
            false => names.contains(&b.name),
        })
        .collect()
}

impl SimPlugin for Probes {
    const NAME: &'static str = "Probes";
    const SUMMARY: &'static str =
        "point/line/water-height probes sampled every k steps into probes.csv";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        validate::probes(self, info)
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if sim.has::<ProbeState<V>>() {
            return Err(SimError::Build(
                "Probes appears twice: list every probe in one Probes(...) entry".into(),
            ));
        }
        let columns = self.columns();
        let points = columns
            .iter()
            .map(|c| V::from_slice(&c.pos[..V::DIM]).unwrap_or_else(V::zero))
            .collect();
        let sampled = sampled_bodies(sim.world.resource(), &self.bodies);
        sim.world.insert_resource(ProbeState::<V> {
            every: self.every,
            min_shepard: self.min_shepard,
            sampled,
            columns,
            points,
            sources: Vec::new(),
            write_error: None,
            max_values: MAX_TABLE_VALUES,
            table: None,
        });
        sim.world.insert_resource(ProbeSamples::default());
        sim.keep_resource::<ProbeSamples>("probes");
        sim.add_finish_hook("probes", resolve_quantities::<V>);
        sim.add_system(StepSet::Diagnostics, "probes", sample_probes::<V>);
        Ok(())
    }
}

#[cfg(test)]
mod tests;
