//! `Probes(every: k, probes: [...])`: fixed measurement points, lines and water-height gauges
//! sampled every k steps into `probes.csv` in the run's output directory.
//!
//! ```ron
//! Probes(
//!     every: 20,
//!     probes: [
//!         Point(name: "P1", at: [4.0, 0.16], quantity: Pressure),
//!         Line(name: "rho", start: [-0.5], end: [0.5], n: 101, quantity: Density),
//!         WaterHeight(name: "H1", at: [0.3]),          // 2-D: at = [x]; 3-D: [x, y]
//!     ],
//! )
//! ```
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
//! * `probes_points.csv`: `column,probe,kind,quantity,x,y,z`, the position of every column.
//!
//! Both are rewritten whole and atomically at every sample ([`dualsph_io::write_atomic_with`],
//! like `diagnostics.csv`), so they are complete, parseable tables at any moment.
//! [`plot_probes`] turns them into PNG charts.
#![warn(missing_docs)]

mod plot;

pub use plot::{ProbeTable, plot_probes, read_probes};

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::sampling::SamplingCloud;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::PathBuf;

/// File name of the probe table.
pub const PROBES_FILE: &str = "probes.csv";
/// File name of the probe positions.
pub const PROBE_POINTS_FILE: &str = "probes_points.csv";

/// What a point or line probe measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum Quantity {
    /// Density ρ.
    Density,
    /// Pressure p (needs an equation of state).
    Pressure,
    /// Velocity component x.
    VelocityX,
    /// Velocity component y (2-D and 3-D).
    VelocityY,
    /// Velocity component z (3-D).
    VelocityZ,
    /// Speed |v|.
    Speed,
    /// Specific internal energy ε (needs the energy equation).
    InternalEnergy,
    /// The Shepard sum σ = Σ V_j W_j itself (≈ 1 in the fluid, 0 outside).
    ShepardSum,
}

/// One probe of the scene.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub enum Probe {
    /// A fixed point.
    Point {
        /// Column name.
        name: String,
        /// Position (one component per dimension).
        at: Vec<Real>,
        /// What to sample.
        quantity: Quantity,
    },
    /// `n` equally spaced points from `start` to `end` (both included).
    Line {
        /// Column prefix: the columns are `name[0]` … `name[n-1]`.
        name: String,
        /// First point.
        start: Vec<Real>,
        /// Last point.
        end: Vec<Real>,
        /// Number of points (≥ 2).
        n: usize,
        /// What to sample.
        quantity: Quantity,
    },
    /// Free-surface height on the vertical line through `at` (2-D: `[x]`, 3-D: `[x, y]`).
    WaterHeight {
        /// Column name.
        name: String,
        /// Horizontal position (dimension − 1 components).
        at: Vec<Real>,
        /// Shepard-sum level of the surface (default 0.5).
        #[serde(default)]
        threshold: Option<Real>,
        /// Vertical sampling step (default: a quarter of the smallest h).
        #[serde(default)]
        dy: Option<Real>,
    },
}

/// The plugin's settings.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Probes {
    /// Sample every this many steps (≥ 1).
    pub every: u64,
    /// Smallest Shepard sum for which a point value is reported (else NaN); default 0.
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
    /// `point`, `line` or `water_height`.
    pub kind: &'static str,
    /// Quantity name (`Density`, …, or `WaterHeight`).
    pub quantity: String,
    /// Position (x, y, z; unused components 0; for a gauge, the vertical one is the bottom).
    pub pos: [Real; 3],
    what: What,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum What {
    Value(Quantity),
    Height { threshold: Real, dy: Option<Real> },
}

/// The point `x` lies in the scene's domain; the error names the field.
fn check_inside(field: &str, x: &[Real], info: &SceneInfo) -> Result<(), String> {
    if info.in_domain(x) {
        return Ok(());
    }
    Err(format!(
        "{field}: {x:?} is outside the domain [{:?}, {:?}]",
        info.domain.0, info.domain.1
    ))
}

/// The plugin's state: columns, sampled rows, and the last write error (if any).
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
    /// `(step, t, values)` of every sample so far, in step order.
    pub rows: Vec<(u64, Real, Vec<Real>)>,
    /// The last error writing the files (the run goes on; the message says which file).
    pub write_error: Option<String>,
}

fn check_name(field: &str, name: &str) -> Result<(), String> {
    let bad = |c: char| c.is_whitespace() || ",\"[]".contains(c);
    if name.is_empty() || name.chars().any(bad) {
        return Err(format!(
            "{field}: name {name:?} must be non-empty without spaces, commas, quotes or brackets"
        ));
    }
    Ok(())
}

fn check_vec(field: &str, v: &[Real], d: usize) -> Result<(), String> {
    if v.len() != d {
        return Err(format!("{field}: expected {d} components, got {}", v.len()));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(format!("{field}: components must be finite"));
    }
    Ok(())
}

fn check_quantity(field: &str, q: Quantity, d: usize) -> Result<(), String> {
    match q {
        Quantity::VelocityY if d < 2 => Err(format!("{field}: VelocityY needs dimension >= 2")),
        Quantity::VelocityZ if d < 3 => Err(format!("{field}: VelocityZ needs dimension 3")),
        _ => Ok(()),
    }
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
                    quantity: format!("{quantity:?}"),
                    pos: xyz(at),
                    what: What::Value(*quantity),
                }),
                Probe::Line {
                    name,
                    start,
                    end,
                    n,
                    quantity,
                } => {
                    for k in 0..*n {
                        let f = k as Real / (*n as Real - 1.0);
                        let at: Vec<Real> = start
                            .iter()
                            .zip(end)
                            .map(|(a, b)| a + f * (b - a))
                            .collect();
                        out.push(Column {
                            name: format!("{name}[{k}]"),
                            probe: name.clone(),
                            kind: "line",
                            quantity: format!("{quantity:?}"),
                            pos: xyz(&at),
                            what: What::Value(*quantity),
                        });
                    }
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
                    quantity: "WaterHeight".into(),
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

impl SimPlugin for Probes {
    const NAME: &'static str = "Probes";
    const SUMMARY: &'static str =
        "point/line/water-height probes sampled every k steps into probes.csv";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        let d = info.dimension;
        if self.every == 0 {
            return Err("every: must be at least 1".into());
        }
        if !(self.min_shepard.is_finite() && (0.0..1.0).contains(&self.min_shepard)) {
            return Err(format!(
                "min_shepard: must be in [0, 1), got {}",
                self.min_shepard
            ));
        }
        if self.probes.is_empty() {
            return Err("probes: the list is empty".into());
        }
        for (k, b) in self.bodies.iter().enumerate() {
            info.check_body(&format!("bodies[{k}]"), b)?;
        }
        let mut names: Vec<&str> = Vec::new();
        for (i, p) in self.probes.iter().enumerate() {
            let f = |s: &str| format!("probes[{i}].{s}");
            let name = match p {
                Probe::Point { name, at, quantity } => {
                    check_vec(&f("at"), at, d)?;
                    check_inside(&f("at"), at, info)?;
                    check_quantity(&f("quantity"), *quantity, d)?;
                    name
                }
                Probe::Line {
                    name,
                    start,
                    end,
                    n,
                    quantity,
                } => {
                    check_vec(&f("start"), start, d)?;
                    check_vec(&f("end"), end, d)?;
                    check_inside(&f("start"), start, info)?;
                    check_inside(&f("end"), end, info)?;
                    check_quantity(&f("quantity"), *quantity, d)?;
                    if !(2..=10_000).contains(n) {
                        return Err(format!("{}: must be between 2 and 10000, got {n}", f("n")));
                    }
                    name
                }
                Probe::WaterHeight {
                    name,
                    at,
                    threshold,
                    dy,
                } => {
                    if d < 2 {
                        return Err(format!(
                            "{}: a water-height gauge needs dimension 2 or 3",
                            f("")
                        ));
                    }
                    check_vec(&f("at"), at, d - 1)?;
                    check_inside(&f("at"), at, info)?;
                    if let Some(t) = threshold
                        && !(t.is_finite() && *t > 0.0 && *t < 1.0)
                    {
                        return Err(format!("{}: must be in (0, 1), got {t}", f("threshold")));
                    }
                    if let Some(dy) = dy
                        && !(dy.is_finite() && *dy > 0.0)
                    {
                        return Err(format!("{}: must be > 0, got {dy}", f("dy")));
                    }
                    name
                }
            };
            check_name(&f("name"), name)?;
            if names.contains(&name.as_str()) {
                return Err(format!("{}: duplicate probe name {name:?}", f("name")));
            }
            names.push(name);
        }
        Ok(())
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
        let wants = |q: Quantity| columns.iter().any(|c| c.what == What::Value(q));
        if wants(Quantity::Pressure) {
            sim.require::<dualsph_fluid::EquationOfState>(
                "Probes: a Pressure probe needs an equation of state (TaitEos or IdealGas)",
            );
        }
        if wants(Quantity::InternalEnergy) {
            sim.require::<dualsph_fluid::EnergyEquation>(
                "Probes: an InternalEnergy probe needs a plugin that solves the energy equation",
            );
        }
        let bodies = &sim.world.resource::<dualsph_core::bodies::Bodies>().0;
        let sampled = bodies
            .iter()
            .map(|b| match self.bodies.is_empty() {
                true => b.is_fluid(),
                false => self.bodies.contains(&b.name),
            })
            .collect();
        sim.world.insert_resource(ProbeState::<V> {
            every: self.every,
            min_shepard: self.min_shepard,
            sampled,
            columns,
            points,
            rows: Vec::new(),
            write_error: None,
        });
        sim.add_system(StepSet::Diagnostics, "probes", sample_probes::<V>);
        Ok(())
    }
}

/// Per-particle arrays in id order.
struct Snapshot<V: Vector> {
    pos: Vec<V>,
    vel: Vec<V>,
    mass: Vec<Real>,
    rho: Vec<Real>,
    h: Vec<Real>,
    p: Vec<Real>,
    e: Vec<Real>,
}

/// Samples every probe when the step is a multiple of `every` (and at step 0 and the end),
/// then rewrites `probes.csv` if the run has an output directory.
pub fn sample_probes<V: Vector>(
    clock: Res<SimClock>,
    kernel: Res<KernelRes>,
    domain: Res<Domain<V>>,
    out: Option<Res<RunOutputDir>>,
    limit: Option<Res<StepLimit>>,
    mut state: ResMut<ProbeState<V>>,
    q: Query<(
        &BodyId,
        &Position<V>,
        &Velocity<V>,
        &Mass,
        &Density,
        &SmoothingLength,
        Option<&Pressure>,
        Option<&InternalEnergy>,
    )>,
) {
    let at_end = clock.t >= clock.t_end * (1.0 - 1e-12) || limit.is_some_and(|l| clock.step >= l.0);
    if !(clock.step.is_multiple_of(state.every) || at_end) {
        return;
    }
    let sampled = |b: &BodyId| state.sampled[b.0 as usize];
    let n = q.iter().filter(|row| sampled(row.0)).count();
    let mut s = Snapshot {
        pos: vec![V::zero(); n],
        vel: vec![V::zero(); n],
        mass: vec![0.0; n],
        rho: vec![1.0; n],
        h: vec![0.0; n],
        p: vec![0.0; n],
        e: vec![0.0; n],
    };
    // by row (the one table's order): every sampled particle, whatever its id
    let rows = q.iter().filter(|row| sampled(row.0));
    for (i, (_, r, v, m, rho, h, p, e)) in rows.enumerate() {
        s.pos[i] = r.0;
        s.vel[i] = v.0;
        s.mass[i] = m.0;
        s.rho[i] = rho.0;
        s.h[i] = h.0;
        s.p[i] = p.map_or(0.0, |p| p.0);
        s.e[i] = e.map_or(0.0, |e| e.0);
    }
    let values = sample_columns(&state, &s, kernel.0, &domain);
    let step = clock.step;
    let keep = state.rows.partition_point(|r| r.0 < step);
    state.rows.truncate(keep);
    state.rows.push((step, clock.t, values));
    if let Some(dir) = out {
        let res = write_files(&dir.0, &state);
        state.write_error = res.err();
        if let Some(e) = &state.write_error {
            eprintln!("dualsph probes: {e}");
        }
    }
}

fn sample_columns<V: Vector>(
    state: &ProbeState<V>,
    s: &Snapshot<V>,
    kernel: Kernel,
    domain: &Domain<V>,
) -> Vec<Real> {
    let cloud = SamplingCloud::from_particles(kernel, s.pos.clone(), &s.mass, &s.rho, s.h.clone());
    let mut cache: Vec<(Quantity, Vec<Real>)> = Vec::new();
    let mut array = |q: Quantity| -> Vec<Real> {
        if let Some((_, a)) = cache.iter().find(|c| c.0 == q) {
            return a.clone();
        }
        let a: Vec<Real> = match q {
            Quantity::Density | Quantity::ShepardSum => s.rho.clone(),
            Quantity::Pressure => s.p.clone(),
            Quantity::VelocityX => s.vel.iter().map(|v| v.get(0)).collect(),
            Quantity::VelocityY => s.vel.iter().map(|v| v.get(1)).collect(),
            Quantity::VelocityZ => s.vel.iter().map(|v| v.get(2)).collect(),
            Quantity::Speed => s.vel.iter().map(|v| v.length()).collect(),
            Quantity::InternalEnergy => s.e.clone(),
        };
        cache.push((q, a.clone()));
        a
    };
    let h_min = s.h.iter().copied().fold(Real::INFINITY, Real::min);
    state
        .columns
        .iter()
        .zip(&state.points)
        .map(|(c, &x)| match c.what {
            What::Value(qty) => {
                let smp = cloud.sample(x, &array(qty));
                if qty == Quantity::ShepardSum {
                    smp.shepard_sum
                } else if smp.shepard_sum > state.min_shepard {
                    smp.shepard.unwrap_or(Real::NAN)
                } else {
                    Real::NAN
                }
            }
            What::Height { threshold, dy } => water_height(
                &cloud,
                &s.pos,
                x,
                domain,
                threshold,
                dy.unwrap_or(0.25 * h_min),
            ),
        })
        .collect()
}

/// Height above `domain.min` of the highest point on the vertical through `x` with
/// `σ ≥ threshold`, interpolated between samples `dy` apart; 0 if there is none.
pub fn water_height<V: Vector>(
    cloud: &SamplingCloud<V>,
    pos: &[V],
    x: V,
    domain: &Domain<V>,
    threshold: Real,
    dy: Real,
) -> Real {
    let k = V::DIM - 1;
    let lo = domain.min.get(k);
    let top_particle = pos.iter().map(|p| p.get(k)).fold(lo, Real::max);
    let hi = domain.max.get(k).min(top_particle + cloud.h_max());
    if !(dy > 0.0 && dy.is_finite()) || hi <= lo {
        return 0.0;
    }
    let steps = ((hi - lo) / dy).ceil().min(1e6) as usize;
    let mut pts = Vec::with_capacity(steps + 1);
    for i in 0..=steps {
        let mut p = x;
        p.set(k, (lo + i as Real * dy).min(hi));
        pts.push(p);
    }
    let sigma = cloud.shepard_sums(&pts);
    match sigma.iter().rposition(|&s| s >= threshold) {
        None => 0.0,
        Some(i) if i == steps => pts[i].get(k) - lo,
        Some(i) => {
            let (s0, s1) = (sigma[i], sigma[i + 1]);
            let (y0, y1) = (pts[i].get(k), pts[i + 1].get(k));
            let f = if s0 > s1 {
                (s0 - threshold) / (s0 - s1)
            } else {
                0.0
            };
            y0 + f * (y1 - y0) - lo
        }
    }
}

fn write_files<V: Vector>(dir: &std::path::Path, state: &ProbeState<V>) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let points = dir.join(PROBE_POINTS_FILE);
    if state.rows.len() <= 1 || !points.exists() {
        let mut text = String::from("column,probe,kind,quantity,x,y,z\n");
        for c in &state.columns {
            let _ = writeln!(
                text,
                "{},{},{},{},{},{},{}",
                c.name, c.probe, c.kind, c.quantity, c.pos[0], c.pos[1], c.pos[2]
            );
        }
        dualsph_io::write_atomic(&points, text.as_bytes()).map_err(|e| e.to_string())?;
    }
    let path: PathBuf = dir.join(PROBES_FILE);
    dualsph_io::write_atomic_with(&path, |w| {
        write!(w, "t,step")?;
        for c in &state.columns {
            write!(w, ",{}", c.name)?;
        }
        writeln!(w)?;
        for (step, t, values) in &state.rows {
            write!(w, "{t},{step}")?;
            for v in values {
                write!(w, ",{v}")?;
            }
            writeln!(w)?;
        }
        Ok(())
    })
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests;
