//! Sampling the probes and writing `probes.csv` and `probes_points.csv`.

use crate::quantity::Source;
use crate::{Dry, PROBE_POINTS_FILE, PROBES_FILE, ProbeSamples, ProbeState, Quantity, What};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::columns::{Columns, take_vector};
use dualsph_core::sampling::SamplingCloud;
use dualsph_core::sim::StepFailure;
use dualsph_sweep::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The sampled particles' core values, in row order.
struct Sampled<V: Vector> {
    /// Whether each row (of every particle) is sampled.
    keep: Vec<bool>,
    pos: Vec<V>,
    mass: Vec<Real>,
    rho: Vec<Real>,
    h: Vec<Real>,
    /// The particles of the bodies not sampled (the walls): positions, masses, support radii.
    others: (Vec<V>, Vec<Real>, Vec<Real>),
}

impl<V: Vector> Sampled<V> {
    /// The particles of the sampled bodies.
    fn of(world: &mut World, sampled: &[bool]) -> Self {
        let mut q = world.query::<(&BodyId, &Position<V>, &Mass, &Density, &SmoothingLength)>();
        let mut s = Sampled {
            keep: Vec::new(),
            pos: Vec::new(),
            mass: Vec::new(),
            rho: Vec::new(),
            h: Vec::new(),
            others: (Vec::new(), Vec::new(), Vec::new()),
        };
        // by row (the one table's order): every sampled particle, whatever its id
        for (b, r, m, rho, h) in q.iter(world) {
            let keep = sampled[b.0 as usize];
            s.keep.push(keep);
            if keep {
                s.pos.push(r.0);
                s.mass.push(m.0);
                s.rho.push(rho.0);
                s.h.push(h.0);
            } else {
                s.others.0.push(r.0);
                s.others.1.push(m.0);
                s.others.2.push(h.0);
            }
        }
        s
    }

    /// The values of `source` of the sampled particles.
    fn values(&self, world: &mut World, source: &Source) -> Vec<Real> {
        match source {
            Source::ShepardSum => self.rho.clone(),
            Source::Speed => {
                let v = world.resource::<Columns>().of::<Velocity<V>>().cloned();
                let v = v.map_or(Vec::new(), |c| c.values_by_row(world));
                self.kept(&v, V::DIM)
                    .map(|row| take_vector::<V>(row).length())
                    .collect()
            }
            Source::Column { column, k } => {
                let all = column.values_by_row(world);
                self.kept(&all, column.width).map(|row| row[*k]).collect()
            }
        }
    }

    /// The rows of the sampled particles in `values` (`w` reals per particle).
    fn kept<'a>(&'a self, values: &'a [Real], w: usize) -> impl Iterator<Item = &'a [Real]> {
        values
            .chunks_exact(w)
            .zip(&self.keep)
            .filter_map(|(row, &k)| k.then_some(row))
    }
}

/// Samples every probe when the step is a multiple of `every` (and at step 0 and the end),
/// then puts the sample in `probes.csv` if the run has an output directory.
pub fn sample_probes<V: Vector>(world: &mut World) {
    let clock = *world.resource::<SimClock>();
    let limit = world.get_resource::<StepLimit>().map(|l| l.0);
    let at_end = clock.at_end(limit);
    let every = world.resource::<ProbeState<V>>().every;
    if !(clock.step.is_multiple_of(every) || at_end) {
        return;
    }
    world.resource_scope(|world, mut state: Mut<ProbeState<V>>| {
        let keep = world
            .resource::<ProbeSamples>()
            .rows
            .partition_point(|r| r.0 < clock.step);
        if let Some(why) = table_full(state.columns.len(), keep + 1, state.max_values) {
            world.resource_mut::<StepFailure>().fail(|| why);
            return;
        }
        let values = sample_columns(world, &state);
        let mut samples = world.resource_mut::<ProbeSamples>();
        samples.rows.truncate(keep);
        samples.rows.push((clock.step, clock.t, values));
        if let Some(dir) = world.get_resource::<RunOutputDir>() {
            let res = grow_files(&dir.0, &mut state, &world.resource::<ProbeSamples>().rows);
            state.write_error = res.err();
            if let Some(e) = &state.write_error {
                eprintln!("dualsph probes: {e}");
            }
        }
    });
}

/// Why a table of `columns` × `rows` values cannot be kept within `max` values
/// ([`crate::MAX_TABLE_VALUES`] in a run), if so.
fn table_full(columns: usize, rows: usize, max: u64) -> Option<String> {
    let values = (columns as u64).saturating_mul(rows as u64);
    (values > max).then(|| {
        format!(
            "Probes: the table would hold {values} values ({columns} columns × {rows} \
             samples), more than {max:.0e}; raise `every` or sample fewer points"
        )
    })
}

/// A sensor's clouds: the sampled particles' and, for a cut-off, the others'.
type Clouds<V> = (SamplingCloud<V>, Option<SamplingCloud<V>>);

/// The value of every probe column now.
fn sample_columns<V: Vector>(world: &mut World, state: &ProbeState<V>) -> Vec<Real> {
    let kernel = world.resource::<KernelRes>().0;
    let domain = *world.resource::<Domain<V>>();
    let s = Sampled::<V>::of(world, &state.sampled);
    let mut cache: Vec<(Quantity, Vec<Real>)> = Vec::new();
    for (q, source) in &state.sources {
        cache.push((q.clone(), s.values(world, source)));
    }
    let particles = ProbedParticles {
        pos: s.pos,
        mass: s.mass,
        rho: s.rho,
        h: s.h,
        others: s.others,
    };
    evaluate(state, kernel, &domain, &particles, &cache)
}

/// The particles a probe reads (those of its sampled bodies): positions, masses, densities
/// and support radii, in one order.
#[derive(Clone, Debug, Default)]
pub struct ProbedParticles<V: Vector> {
    /// Positions.
    pub pos: Vec<V>,
    /// Masses.
    pub mass: Vec<Real>,
    /// Densities.
    pub rho: Vec<Real>,
    /// Support radii.
    pub h: Vec<Real>,
    /// The particles of the bodies not sampled (the walls): positions, masses, support radii.
    pub others: (Vec<V>, Vec<Real>, Vec<Real>),
}

impl<V: Vector> ProbedParticles<V> {
    /// The clouds a sensor of `reach` reads: the sampled particles' with every support radius
    /// times `reach`, and, when `others` is true, the other particles' with their masses as
    /// volumes (so that its Shepard sum is `Σ_b m_b W_b`, for [`What::Mean`]'s `cut_off`).
    fn clouds(
        &self,
        kernel: Kernel,
        reach: Real,
        others: bool,
    ) -> (SamplingCloud<V>, Option<SamplingCloud<V>>) {
        let h = self.h.iter().map(|h| reach * h).collect();
        let fluid =
            SamplingCloud::from_particles(kernel, self.pos.clone(), &self.mass, &self.rho, h);
        let others = others.then(|| {
            let (pos, mass, h) = &self.others;
            let h = h.iter().map(|h| reach * h).collect();
            SamplingCloud::new(kernel, pos.clone(), mass.clone(), h)
        });
        (fluid, others)
    }
}

/// The value of every column of `state` from `particles`, with `values` holding each sampled
/// quantity's values of those particles (in their order): the live probes' reading of the
/// simulation, and `dualsph probe`'s of a snapshot. A quantity missing from `values` reads
/// NaN.
pub fn evaluate<V: Vector>(
    state: &ProbeState<V>,
    kernel: Kernel,
    domain: &Domain<V>,
    particles: &ProbedParticles<V>,
    values: &[(Quantity, Vec<Real>)],
) -> Vec<Real> {
    let s = particles;
    let cloud = SamplingCloud::from_particles(kernel, s.pos.clone(), &s.mass, &s.rho, s.h.clone());
    let array = |q: &Quantity| values.iter().find(|c| &c.0 == q).map(|c| &c.1);
    let h_min = s.h.iter().copied().fold(Real::INFINITY, Real::min);
    // the clouds of the sensors' reaches (and of the walls, for a cut-off), built once per
    // sample
    let mut wide: Vec<(Real, bool, Clouds<V>)> = Vec::new();
    for c in &state.columns {
        if let What::Mean { reach, cut_off, .. } = c.what
            && (reach != 1.0 || cut_off)
            && !wide.iter().any(|w| w.0 == reach && w.1 == cut_off)
        {
            wide.push((reach, cut_off, s.clouds(kernel, reach, cut_off)));
        }
    }
    state
        .columns
        .iter()
        .zip(&state.points)
        .map(|(c, &x)| match &c.what {
            What::Value(q) => {
                let Some(values) = array(q) else {
                    // unresolved (the simulation was not finished): no value
                    return Real::NAN;
                };
                let smp = cloud.sample(x, values);
                if q.name() == crate::quantity::SHEPARD_SUM {
                    smp.shepard_sum
                } else if smp.shepard_sum > state.min_shepard {
                    smp.shepard.unwrap_or(Real::NAN)
                } else {
                    Real::NAN
                }
            }
            What::Mean {
                quantity,
                points,
                dry,
                floor,
                clip,
                reach,
                cut_off,
            } => {
                let Some(values) = array(quantity) else {
                    return Real::NAN;
                };
                let clipped: Vec<Real>;
                let values = match clip {
                    Some(c) => {
                        clipped = values.iter().map(|v| v.max(*c)).collect();
                        &clipped
                    }
                    None => values,
                };
                let (cloud, others) = wide
                    .iter()
                    .find(|w| w.0 == *reach && w.1 == *cut_off)
                    .map_or((&cloud, None), |w| (&w.2.0, w.2.1.as_ref()));
                let read = points.iter().map(|p| {
                    let x = V::from_slice(&p[..V::DIM]).unwrap_or(x);
                    let smp = cloud.sample(x, values);
                    // Σ_f m_f W_f = Σ_f ρ_f V_f W_f against the others' Σ_b m_b W_b
                    let walled = others.is_some_and(|o| {
                        let mass = cloud.sample(x, &s.rho).value;
                        o.shepard_sum(x) > mass
                    });
                    match smp.shepard_sum > state.min_shepard && !walled {
                        true => smp.shepard.unwrap_or(Real::NAN),
                        false => Real::NAN,
                    }
                });
                sensor_mean(read, *dry, *floor)
            }
            What::Height { threshold, dy } => water_height(
                &cloud,
                &s.pos,
                x,
                domain,
                *threshold,
                dy.unwrap_or(0.25 * h_min),
            ),
        })
        .collect()
}

/// The reading of a sensor from its points' values (NaN where a point is dry): values below
/// `floor` raised to it, then the mean with a dry point counted as `dry` says.
pub fn sensor_mean(values: impl Iterator<Item = Real>, dry: Dry, floor: Option<Real>) -> Real {
    let (mut sum, mut counted) = (0.0, 0usize);
    for v in values {
        if v.is_nan() {
            match dry {
                Dry::Zero => {}
                Dry::Skip => continue,
                Dry::Nan => return Real::NAN,
            }
        } else {
            sum += floor.map_or(v, |f| v.max(f));
        }
        counted += 1;
    }
    match counted {
        0 => Real::NAN,
        n => sum / n as Real,
    }
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

/// Puts the last of `rows` in `probes.csv` in `dir`: appended as one row (rows of its step or
/// later replaced) to the file the run writes, or, at the run's first sample or after a
/// failed write, the whole table rewritten ([`write_files`]) and opened to grow. Appending
/// keeps a sample's cost independent of the samples before it (rewriting the whole table at
/// every sample is quadratic in the samples).
fn grow_files<V: Vector>(
    dir: &Path,
    state: &mut ProbeState<V>,
    rows: &[(u64, Real, Vec<Real>)],
) -> Result<(), String> {
    let res = match (&mut state.table, rows.last()) {
        (Some(table), Some((step, t, values))) => table
            .push(*step, &[row_line(*step, *t, values)])
            .map_err(|e| e.to_string()),
        _ => write_files(dir, state, rows).and_then(|()| {
            let path = dir.join(PROBES_FILE);
            let table = dualsph_io::GrowingCsv::reopen(&path, &header(state), u64::MAX)
                .map_err(|e| e.to_string())?;
            state.table = Some(table);
            Ok(())
        }),
    };
    if res.is_err() {
        // the next sample rewrites the whole table
        state.table = None;
    }
    res
}

/// The header of `probes.csv`: `t`, `step` and the columns.
fn header<V: Vector>(state: &ProbeState<V>) -> Vec<String> {
    let fixed = ["t", "step"].map(String::from);
    fixed
        .into_iter()
        .chain(state.columns.iter().map(|c| c.name.clone()))
        .collect()
}

/// One row of `probes.csv`.
fn row_line(step: u64, t: Real, values: &[Real]) -> String {
    let mut line = format!("{t},{step}");
    for v in values {
        let _ = write!(line, ",{v}");
    }
    line
}

/// Rewrites `probes_points.csv` (at the first sample, or when it is missing) and
/// `probes.csv` in `dir`, whole and atomically.
pub fn write_files<V: Vector>(
    dir: &Path,
    state: &ProbeState<V>,
    rows: &[(u64, Real, Vec<Real>)],
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let points = dir.join(PROBE_POINTS_FILE);
    if rows.len() <= 1 || !points.exists() {
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
        writeln!(w, "{}", header(state).join(","))?;
        for (step, t, values) in rows {
            writeln!(w, "{}", row_line(*step, *t, values))?;
        }
        Ok(())
    })
    .map_err(|e| e.to_string())
}
