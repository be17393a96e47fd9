//! The scene's `Refinement(..)`: its fields, their checks, and what `build` installs.

use crate::apply::{RefinementStats, refine};
pub use crate::ladder::{LadderSize, NominalDensity};
pub use crate::target::Indicator;
use crate::target::{Resolved, ResolvedRegion};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::Bodies;
use dualsph_core::output::{DerivedColumns, DiagnosticColumns};
use dualsph_core::plugin::positive;
use dualsph_diagnostics::HealthBounds;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// Adaptive resolution: particles split where the regions ask for a smaller size and merge
/// where they no longer do (`docs/refinement.md`).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Refinement {
    /// The fluid bodies whose particles split and merge (none given: every fluid body).
    #[serde(default)]
    pub bodies: Vec<String>,
    /// The smallest particle size a split may make (m).
    pub finest: Real,
    /// The largest particle size a merge may make (m), and the target where no region asks
    /// for less (a particle larger than it splits only where a region asks for less).
    pub coarsest: Real,
    /// Where the particles are to be smaller.
    #[serde(default)]
    pub regions: Vec<Region>,
    /// How fast a region's size grows with the distance from it, in metres per metre
    /// (dimensionless; default 0.25: a factor of two over four sizes).
    #[serde(default = "default_grading")]
    pub grading: Real,
    /// Steps between two decisions (default 10).
    #[serde(default = "default_every")]
    pub every: u64,
    /// How far outside a region a particle must be before it merges (m; default twice
    /// `coarsest`): the hysteresis that keeps a particle at a region's edge from splitting
    /// and merging back and forth as the region moves.
    #[serde(default)]
    pub buffer: Option<Real>,
    /// The children's offset from the parent along each axis, in parent sizes
    /// (dimensionless; default 0.25: the children sit on the lattice of half the spacing,
    /// so a region split whole is that lattice; see `docs/refinement.md` for the density
    /// errors of other offsets and what they do to a flow).
    #[serde(default = "default_offset")]
    pub offset: Real,
    /// The children's support radius over the parent's (dimensionless; default 0.5, what
    /// Eq. 6.1 gives a particle of half the size).
    #[serde(default = "default_child_h")]
    pub child_h: Real,
    /// The density at which a particle's size is read against the ladder (default
    /// `Current`: liquids; `Nominal` for gases, see [`LadderSize`]).
    #[serde(default)]
    pub ladder: LadderSize,
}

fn default_grading() -> Real {
    0.25
}
fn default_every() -> u64 {
    10
}
fn default_offset() -> Real {
    DEFAULT_OFFSET
}

/// The default [`Refinement::offset`].
pub const DEFAULT_OFFSET: Real = 0.25;
fn default_child_h() -> Real {
    0.5
}

/// A part of space where the particles are to be smaller.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub enum Region {
    /// The box `[min, max]` (m), moved by `velocity · t` (m/s; none: fixed).
    Box {
        /// Lower corner (m).
        min: Vec<Real>,
        /// Upper corner (m).
        max: Vec<Real>,
        /// The particle size inside (m).
        spacing: Real,
        /// The box's velocity (m/s; none: at rest).
        #[serde(default)]
        velocity: Option<Vec<Real>>,
    },
    /// Within `distance` of any particle of `body` (m): around a wall, an obstacle, a moving
    /// body.
    Around {
        /// The body's name.
        body: String,
        /// The distance from its particles (m).
        distance: Real,
        /// The particle size there (m).
        spacing: Real,
    },
    /// Within `distance` of the free surface (m), detected where the divergence of position
    /// `∇·r_i` (d in the bulk, about d/2 at a free surface; Lind et al. 2012, as
    /// `ParticleShifting` detects it) is below `threshold` (dimensionless; default 0.6 d,
    /// [`SURFACE_THRESHOLD`]: 1.2 in 2-D). The default is below Lind et al.'s 0.75 d: next to a
    /// jump in particle size the divergence of position dips below that in the bulk, and
    /// every particle so flagged would refine its neighbourhood, and with it move the jump.
    FreeSurface {
        /// The distance from the surface particles (m).
        distance: Real,
        /// The particle size there (m).
        spacing: Real,
        /// The detection threshold on `∇·r` (dimensionless).
        #[serde(default)]
        threshold: Option<Real>,
    },
    /// Where the indicator of `quantity` is above `above` (see [`Indicator`]; units of the
    /// indicator).
    Gradient {
        /// The quantity.
        quantity: Indicator,
        /// The threshold (dimensionless; in 1/s for Velocity).
        above: Real,
        /// The particle size there (m).
        spacing: Real,
    },
}

impl Region {
    /// Multiplies the size the region asks for, and a distance that is a band of such
    /// sizes, by `factor` (see [`SimPlugin::scale_spacing`]).
    fn scale_spacing(&mut self, factor: Real) {
        match self {
            Region::Box { spacing, .. } | Region::Gradient { spacing, .. } => *spacing *= factor,
            Region::Around {
                distance, spacing, ..
            }
            | Region::FreeSurface {
                distance, spacing, ..
            } => {
                *distance *= factor;
                *spacing *= factor;
            }
        }
    }

    /// The particle size the region asks for.
    pub fn spacing(&self) -> Real {
        match self {
            Region::Box { spacing, .. }
            | Region::Around { spacing, .. }
            | Region::FreeSurface { spacing, .. }
            | Region::Gradient { spacing, .. } => *spacing,
        }
    }

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        let d = info.dimension;
        match self {
            Region::Box {
                min, max, velocity, ..
            } => {
                let finite = |v: &[Real]| v.len() == d && v.iter().all(|x| x.is_finite());
                if !(finite(min) && finite(max)) {
                    return Err(format!("Box: min and max need {d} finite components"));
                }
                if min.iter().zip(max).any(|(a, b)| a > b) {
                    return Err(format!("Box: min {min:?} is above max {max:?}"));
                }
                if velocity.as_ref().is_some_and(|v| !finite(v)) {
                    return Err(format!("Box: velocity needs {d} finite components"));
                }
            }
            Region::Around { body, distance, .. } => {
                if !info.bodies.contains(body) {
                    return Err(format!(
                        "Around: no body named `{body}` (the scene's: {})",
                        info.bodies.join(", ")
                    ));
                }
                non_negative("Around.distance", *distance)?;
            }
            Region::FreeSurface {
                distance,
                threshold,
                ..
            } => {
                non_negative("FreeSurface.distance", *distance)?;
                if let Some(t) = threshold {
                    positive("FreeSurface.threshold", *t)?;
                }
            }
            Region::Gradient { above, .. } => positive("Gradient.above", *above)?,
        }
        positive("spacing", self.spacing())
    }
}

fn non_negative(field: &str, x: Real) -> Result<(), String> {
    if x.is_finite() && x >= 0.0 {
        Ok(())
    } else {
        Err(format!("{field}: must be finite and ≥ 0, got {x}"))
    }
}

/// The default [`Region::FreeSurface`] threshold on `∇·r`, per dimension.
pub const SURFACE_THRESHOLD: Real = 0.6;

/// The most halvings of the size between `coarsest` and `finest`.
const MAX_LEVELS: Real = 10.0;

impl Refinement {
    fn check_sizes(&self) -> Result<(), String> {
        positive("finest", self.finest)?;
        positive("coarsest", self.coarsest)?;
        let levels = libm::log2(self.coarsest / self.finest);
        if !(0.0..=MAX_LEVELS).contains(&levels) || (levels - levels.round()).abs() > 1e-6 {
            return Err(format!(
                "coarsest: must be finest ({}) times a power of two up to 2^{MAX_LEVELS} (the \
                 sizes a split halves), got {}",
                self.finest, self.coarsest
            ));
        }
        for (k, r) in self.regions.iter().enumerate() {
            let s = r.spacing();
            if !(s >= self.finest && s <= self.coarsest) {
                return Err(format!(
                    "regions[{k}].spacing: {s} is outside [finest, coarsest] = [{}, {}]",
                    self.finest, self.coarsest
                ));
            }
        }
        Ok(())
    }

    fn check_pattern(&self) -> Result<(), String> {
        if self.every == 0 {
            return Err("every: must be at least 1".into());
        }
        non_negative("grading", self.grading)?;
        if let Some(b) = self.buffer {
            non_negative("buffer", b)?;
        }
        if !(self.offset > 0.0 && self.offset < 0.5) {
            return Err(format!("offset: must be in (0, 0.5), got {}", self.offset));
        }
        if !(self.child_h > 0.0 && self.child_h <= 1.0) {
            return Err(format!("child_h: must be in (0, 1], got {}", self.child_h));
        }
        Ok(())
    }
}

impl SimPlugin for Refinement {
    const NAME: &'static str = "Refinement";
    const SUMMARY: &'static str =
        "adaptive resolution: particles split and merge where the regions ask, conservatively";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        for b in &self.bodies {
            if !info.bodies.contains(b) {
                return Err(format!(
                    "bodies: no body named `{b}` (the scene's: {})",
                    info.bodies.join(", ")
                ));
            }
        }
        self.check_sizes()?;
        self.check_pattern()?;
        for (k, r) in self.regions.iter().enumerate() {
            r.validate(info).map_err(|e| format!("regions[{k}]: {e}"))?;
        }
        Ok(())
    }

    /// Refused with formulation `ConstantH`: a split gives its children `child_h` of the
    /// parent's support and a merge doubles it, so the particles would hold several smoothing
    /// lengths in a scheme that assumes one (and sums with it as if they had).
    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        if *sim.world.resource::<Formulation>() == Formulation::ConstantH {
            return Err(SimError::Build(
                "Refinement cannot be used with formulation ConstantH: a split halves the \
                 children's smoothing length (child_h) and a merge doubles it, so the \
                 particles would have several smoothing lengths where ConstantH assumes one; \
                 use the default DualSupport"
                    .into(),
            ));
        }
        let resolved = self.resolve::<V>(sim.world.resource::<Bodies>())?;
        let levels = resolved.levels;
        sim.world.insert_resource(resolved);
        // a split halves h per level, a merge doubles it: the blow-up check's sane range of h
        // is widened by the ladder's whole ratio
        if let Some(mut bounds) = sim.world.get_resource_mut::<HealthBounds>() {
            bounds.widen_h_range(self.coarsest / self.finest);
        }
        sim.world.init_resource::<RefinementStats>();
        sim.keep_resource::<RefinementStats>("refinement");
        sim.enable_population();
        if self.ladder == LadderSize::Nominal {
            let spec = ColumnSpec::restart_only("nominal_density");
            sim.add_column(spec, |seed| NominalDensity(seed.init.density))?;
        }
        add_diagnostics::<V>(&mut sim.world.resource_mut::<DiagnosticColumns>(), levels)
            .map_err(SimError::Build)?;
        add_snapshot_columns::<V>(&mut sim.world.resource_mut::<DerivedColumns>())
            .map_err(SimError::Build)?;
        sim.add_system(StepSet::Population, "refine (split and merge)", refine::<V>);
        Ok(())
    }

    /// The sizes, the buffer and the regions' sizes and distances scale; a `Box`'s corners
    /// (geometry) and the indicators' thresholds stay.
    fn scale_spacing(&mut self, factor: Real) {
        self.finest *= factor;
        self.coarsest *= factor;
        if let Some(b) = &mut self.buffer {
            *b *= factor;
        }
        for r in &mut self.regions {
            r.scale_spacing(factor);
        }
    }
}

impl Refinement {
    /// The settings with bodies as indices and vectors of the scene's dimension.
    fn resolve<V: Vector>(&self, bodies: &Bodies) -> Result<Resolved<V>, SimError> {
        let err = |m: String| SimError::Build(format!("Refinement: {m}"));
        let index = |name: &str| {
            bodies
                .index(name)
                .ok_or_else(|| err(format!("no body `{name}`")))
        };
        let refined: Vec<bool> = if self.bodies.is_empty() {
            bodies.0.iter().map(|b| b.is_fluid()).collect()
        } else {
            let mut r = vec![false; bodies.0.len()];
            for name in &self.bodies {
                let b = index(name)?;
                if !bodies.0[b].is_fluid() {
                    return Err(err(format!("bodies: `{name}` is not a fluid body")));
                }
                r[b] = true;
            }
            r
        };
        let vector = |v: &[Real]| {
            V::from_slice(v).ok_or_else(|| err("a vector of the wrong dimension".into()))
        };
        let mut regions = Vec::with_capacity(self.regions.len());
        for r in &self.regions {
            regions.push(match r {
                Region::Box {
                    min, max, velocity, ..
                } => ResolvedRegion::Box {
                    min: vector(min)?,
                    max: vector(max)?,
                    velocity: velocity
                        .as_deref()
                        .map(vector)
                        .transpose()?
                        .unwrap_or(V::zero()),
                },
                Region::Around { body, distance, .. } => ResolvedRegion::Around {
                    body: index(body)? as u16,
                    distance: *distance,
                },
                Region::FreeSurface {
                    distance,
                    threshold,
                    ..
                } => ResolvedRegion::FreeSurface {
                    distance: *distance,
                    threshold: threshold.unwrap_or(SURFACE_THRESHOLD * V::DIM as Real),
                },
                Region::Gradient {
                    quantity, above, ..
                } => ResolvedRegion::Gradient {
                    quantity: *quantity,
                    above: *above,
                },
            });
        }
        let d = V::DIM as Real;
        Ok(Resolved {
            refined,
            regions,
            spacings: self.regions.iter().map(Region::spacing).collect(),
            finest: self.finest,
            coarsest: self.coarsest,
            grading: self.grading,
            every: self.every,
            buffer: self.buffer.unwrap_or(2.0 * self.coarsest),
            offset: self.offset,
            child_h: self.child_h,
            nominal: self.ladder == LadderSize::Nominal,
            levels: (d * libm::log2(self.coarsest / self.finest)).round() as usize,
        })
    }
}

/// The columns of `diagnostics.csv` the plugin adds: the cumulative counts of splits and
/// merges, the kinetic energy and angular momentum the merges removed, and the particles of
/// the refined bodies at each size level ([`crate::apply::level_counts`]).
fn add_diagnostics<V: Vector>(cols: &mut DiagnosticColumns, levels: usize) -> Result<(), String> {
    cols.add("splits", |w| w.resource::<RefinementStats>().splits as Real)?;
    cols.add("merges", |w| w.resource::<RefinementStats>().merges as Real)?;
    cols.add("merge_e_kin", |w| w.resource::<RefinementStats>().e_kin)?;
    let axes: &[(usize, &str)] = match V::DIM {
        2 => &[(2, "merge_lz")],
        3 => &[(0, "merge_lx"), (1, "merge_ly"), (2, "merge_lz")],
        _ => &[],
    };
    for &(k, name) in axes {
        cols.add(name, move |w| w.resource::<RefinementStats>().l[k])?;
    }
    let names = (0..=levels).map(|k| format!("n_level{k}")).collect();
    cols.add_group(names, move |w| {
        let counts = crate::apply::level_counts::<V>(w, levels);
        counts.into_iter().map(|n| n as Real).collect()
    })?;
    Ok(())
}

/// The columns the plugin adds to the snapshots and `final.csv`: every particle's `size`
/// `(m/ρ)^{1/d}` (m) and, for the particles of refined bodies, its `level` (0 the coarsest,
/// as `n_level*` in `diagnostics.csv`; NaN for other bodies).
fn add_snapshot_columns<V: Vector>(cols: &mut DerivedColumns) -> Result<(), String> {
    use crate::apply::sizes_and_levels;
    cols.add("size", |w| {
        sizes_and_levels::<V>(w).into_iter().map(|s| s.0).collect()
    })?;
    cols.add("level", |w| {
        (sizes_and_levels::<V>(w).into_iter())
            .map(|(_, level, refined)| if refined { level as Real } else { Real::NAN })
            .collect()
    })
}
