//! The health check of the state: the first non-finite or unphysical value, a density or h
//! outside its sane range, or a particle far outside the domain (a blow-up). The sane ranges
//! are set by the scene's `health` section ([`settings`]).

pub mod settings;

use crate::totals::InitialDensity;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::chunks::{DENSE, MIN_LEN};
use dualsph_core::components::*;
use dualsph_core::math::{Real, Vector};
use dualsph_core::sim::{Domain, SimClock, StepFailure};
use dualsph_fluid::components::*;
use rayon::prelude::*;

/// The first unphysical value found in the state (lowest particle id), if any.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct Health {
    /// `(particle id, quantity, value)` of the first problem.
    pub problem: Option<(u32, &'static str, Real)>,
}

/// How far a particle may stray outside the domain box before the run counts as blown up,
/// as a fraction of the box's largest extent. Walls keep particles inside to round-off and a
/// free surface (a drop, a gas expanding at a free end) moves far less than this within the
/// scenes' end times (a scene whose free ends expand into vacuum, like the Sod tube, declares a
/// domain that holds them), so a particle this far out has been thrown out by an instability.
pub const DOMAIN_TOLERANCE: Real = 0.1;

/// Quantity named by [`Health`] for a particle outside the domain; the value is the distance
/// to the box.
pub const OUTSIDE_DOMAIN: &str = "distance outside the domain";

/// The distance from `x` to the box `[min, max]` (0 inside).
fn distance_outside<V: Vector>(x: V, min: V, max: V) -> Real {
    let mut d2 = 0.0;
    for k in 0..V::DIM {
        let (a, lo, hi) = (x.get(k), min.get(k), max.get(k));
        let d = if a < lo {
            lo - a
        } else if a > hi {
            a - hi
        } else {
            0.0
        };
        d2 += d * d;
    }
    d2.sqrt()
}

/// Sane bounds on density and h, relative to their ranges at initialisation: a run stops when
/// a density leaves `[ρ_min0 / density_below, ρ_max0 · density_above]` or an h leaves
/// `[h_min0 / h_below, h_max0 · h_above]`. The ranges are over all particles (a scene with
/// two resolutions or two densities keeps both), taken from the spawned h (build time, so a
/// resumed run has them) and from [`InitialDensity`] (the densities after
/// `Sim::initialize`, restored with a checkpoint).
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct HealthBounds {
    /// Factors (> 1) beyond the initial density range: `(below, above)`.
    pub density: (Real, Real),
    /// Factors (> 1) beyond the initial h range: `(below, above)`.
    pub h: (Real, Real),
    /// `(ρ_min0, ρ_max0)`, filled on first use.
    pub rho_range: Option<(Real, Real)>,
    /// `(h_min0, h_max0)`, filled at build or on first use.
    pub h_range: Option<(Real, Real)>,
}

/// Default factors `(below, above)` on the initial density range. Expansion is the loose
/// side: a gas expanding into vacuum at a free end thins without limit (the uniform Sod tube's
/// end particles reach 1/59 of the initial minimum by t = 0.2 s), so 300 (5 × that); on
/// compression a shock multiplies the density by at most (γ+1)/(γ−1) = 4 (γ = 5/3) and a
/// liquid moves by per cents (the largest in the scenes: 1.21, the two-resolution drop near
/// its end), so 10. Measured with `examples/health_extremes.rs`
/// (docs/validation/hard_cases.md).
pub const DEFAULT_DENSITY_FACTORS: (Real, Real) = (300.0, 10.0);
/// Default factors `(below, above)` on the initial h range; h ∝ (m/ρ)^{1/d} mirrors the
/// density (the uniform Sod tube's free ends reach 77 × the initial h; the largest fall is
/// 1/2.15, in the same tube), so 10 below, 300 above.
pub const DEFAULT_H_FACTORS: (Real, Real) = (10.0, 300.0);

impl HealthBounds {
    /// Widens the initial h range by `ratio` (> 1) both ways: a plugin that changes particle
    /// sizes during a run (splits and merges) makes h that far from the initial range
    /// without anything having gone wrong. Nothing to do before the range is known.
    pub fn widen_h_range(&mut self, ratio: Real) {
        if let Some((lo, hi)) = self.h_range {
            self.h_range = Some((lo / ratio, hi * ratio));
        }
    }
}

impl Default for HealthBounds {
    fn default() -> Self {
        HealthBounds {
            density: DEFAULT_DENSITY_FACTORS,
            h: DEFAULT_H_FACTORS,
            rho_range: None,
            h_range: None,
        }
    }
}

/// Quantity named by [`Health`] for a density above its sane range.
pub const DENSITY_ABOVE: &str = "density above its sane range";
/// Quantity named by [`Health`] for a density below its sane range.
pub const DENSITY_BELOW: &str = "density below its sane range";
/// Quantity named by [`Health`] for an h above its sane range.
pub const H_ABOVE: &str = "smoothing length above its sane range";
/// Quantity named by [`Health`] for an h below its sane range.
pub const H_BELOW: &str = "smoothing length below its sane range";

/// `(min, max)` of `values` (None when empty).
fn range(values: impl Iterator<Item = Real>) -> Option<(Real, Real)> {
    values.fold(None, |r, x| match r {
        None => Some((x, x)),
        Some((lo, hi)) => Some((lo.min(x), hi.max(x))),
    })
}

/// `[lo / below, hi · above]` for a range and its factors.
fn widened((lo, hi): (Real, Real), (below, above): (Real, Real)) -> (Real, Real) {
    (lo / below, hi * above)
}

/// The particle data the health check reads.
type HealthQuery<'w, 's, V> = Query<
    'w,
    's,
    (
        &'static ParticleId,
        &'static Position<V>,
        &'static Velocity<V>,
        &'static Density,
        &'static SmoothingLength,
        Option<&'static InternalEnergy>,
    ),
>;

/// Scans for non-finite positions/velocities, non-positive or non-finite density and h, density
/// and h outside their sane ranges ([`HealthBounds`]), and particles farther than
/// [`DOMAIN_TOLERANCE`] × the largest box extent outside the domain.
#[inline(never)] // a frame of its own in profiles
pub fn check_health<V: Vector>(
    mut health: ResMut<Health>,
    mut bounds: ResMut<HealthBounds>,
    domain: Res<Domain<V>>,
    q: HealthQuery<V>,
    init_rho: Query<&InitialDensity>,
    (clock, mut failure): (Res<SimClock>, ResMut<StepFailure>),
) {
    if bounds.rho_range.is_none() {
        // captured at the initial evaluation, restored with a checkpoint
        bounds.rho_range = range(init_rho.iter().map(|r| r.0));
    }
    if bounds.h_range.is_none() {
        bounds.h_range = range(q.iter().map(|r| r.4.0));
    }
    let (rho_lo, rho_hi) = bounds
        .rho_range
        .map_or((0.0, Real::INFINITY), |r| widened(r, bounds.density));
    let (h_lo, h_hi) = bounds
        .h_range
        .map_or((0.0, Real::INFINITY), |r| widened(r, bounds.h));
    let extent = (0..V::DIM)
        .map(|k| domain.max.get(k) - domain.min.get(k))
        .fold(0.0, Real::max);
    let tol = DOMAIN_TOLERANCE * extent;
    let (lo, hi) = (domain.min, domain.max);
    let limits = Limits {
        rho: (rho_lo, rho_hi),
        h: (h_lo, h_hi),
        lo,
        hi,
        tol,
    };
    let mut worst: Option<(u32, &'static str, Real)> = None;
    for (ids, r, v, rho, h, e) in q.contiguous_iter().expect(DENSE) {
        // the common case in parallel: every particle passes the fast test
        let fine = |r: &Position<V>, v: &Velocity<V>, rho: &Density, h: &SmoothingLength, e| {
            limits.fine(r.0, v.0, rho.0, h.0, e)
        };
        let all_fine = match e {
            Some(e) => (r, v, rho, h, e)
                .into_par_iter()
                .with_min_len(MIN_LEN)
                .all(|(r, v, rho, h, e)| fine(r, v, rho, h, e.0)),
            None => (r, v, rho, h)
                .into_par_iter()
                .with_min_len(MIN_LEN)
                .all(|(r, v, rho, h)| fine(r, v, rho, h, 0.0)),
        };
        if all_fine {
            continue;
        }
        // else the smallest id with a problem, in order
        for (k, id) in ids.iter().enumerate() {
            let e = e.map(|e| e[k].0);
            if let Some((what, val)) = limits.problem(r[k].0, v[k].0, rho[k].0, h[k].0, e)
                && worst.is_none_or(|w| id.0 < w.0)
            {
                worst = Some((id.0, what, val));
            }
        }
    }
    health.problem = worst;
    if let Some((id, what, value)) = worst {
        failure.fail(|| problem_message(id, what, value, &bounds, clock.dt));
    }
}

/// What the step's failure says of an unphysical `value` of `what` at particle `id`: the
/// sane interval it left, the time step, and the usual cause ([`likely_cause`]).
fn problem_message(id: u32, what: &str, value: Real, bounds: &HealthBounds, dt: Real) -> String {
    let sane = bounds
        .interval(what)
        .map(|(lo, hi)| format!(", outside [{lo:.4e}, {hi:.4e}]"))
        .unwrap_or_default();
    format!(
        "particle {id} has {what} = {value:e}{sane} (dt = {dt:.3e}; likely cause: {})",
        likely_cause(what)
    )
}

/// The usual cause of an unphysical `quantity` (as named by [`Health`]).
pub fn likely_cause(quantity: &str) -> &'static str {
    match quantity {
        OUTSIDE_DOMAIN => {
            "a particle thrown out of the domain: a dt above the CFL limit, or a missing wall (SpecularWalls)"
        }
        DENSITY_ABOVE => {
            "density far above its initial range: likely dt too large or c0 too small for the flow speed (a compression the equation of state does not resist)"
        }
        DENSITY_BELOW => {
            "density far below its initial range: likely the tensile instability (particles under tension pairing up) or particles left with too few neighbours"
        }
        H_ABOVE => {
            "smoothing length far above its initial range: particles spreading apart (a splash or a free end with too few neighbours), or the density collapsing"
        }
        H_BELOW => {
            "smoothing length far below its initial range: particles clumping (the tensile instability) or a runaway compression (dt too large or c0 too small)"
        }
        "density" | "smoothing length" => {
            "a dt above the CFL limit, or particles left with too few neighbours"
        }
        _ => "a dt above the CFL limit or too few neighbours",
    }
}

/// The sane ranges of one health check.
struct Limits<V: Vector> {
    rho: (Real, Real),
    h: (Real, Real),
    lo: V,
    hi: V,
    tol: Real,
}

impl<V: Vector> Limits<V> {
    /// The fast test of one particle (position, velocity, ρ, h, ε or 0): true when it is
    /// certainly fine. One sum is finite iff every term is (or it overflowed: then
    /// [`Self::problem`] looks closer).
    #[inline(always)]
    fn fine(&self, r: V, v: V, rho: Real, h: Real, e: Real) -> bool {
        let (lo, hi, tol) = (self.lo, self.hi, self.tol);
        let ((rho_lo, rho_hi), (h_lo, h_hi)) = (self.rho, self.h);
        let mut sum = rho + h + e;
        let mut inside = true;
        for k in 0..V::DIM {
            let x = r.get(k);
            sum += x + v.get(k);
            inside &= x >= lo.get(k) - tol && x <= hi.get(k) + tol;
        }
        let sane = rho >= rho_lo && rho <= rho_hi && h >= h_lo && h <= h_hi;
        sum.is_finite() && rho > 0.0 && h > 0.0 && inside && sane
    }

    /// What is wrong with one particle (position, velocity, ρ, h, ε), if anything: the
    /// quantity and its value.
    fn problem(
        &self,
        r: V,
        v: V,
        rho: Real,
        h: Real,
        e: Option<Real>,
    ) -> Option<(&'static str, Real)> {
        if self.fine(r, v, rho, h, e.unwrap_or(0.0)) {
            return None;
        }
        let (lo, hi, tol) = (self.lo, self.hi, self.tol);
        let ((rho_lo, rho_hi), (h_lo, h_hi)) = (self.rho, self.h);
        let outside = distance_outside(r, lo, hi);
        if !r.is_finite() {
            Some(("position", r.length()))
        } else if !v.is_finite() {
            Some(("velocity", v.length()))
        } else if !(rho.is_finite() && rho > 0.0) {
            Some(("density", rho))
        } else if !(h.is_finite() && h > 0.0) {
            Some(("smoothing length", h))
        } else if e.is_some_and(|e| !e.is_finite()) {
            Some(("internal energy", e.unwrap_or(0.0)))
        } else if outside > tol {
            Some((OUTSIDE_DOMAIN, outside))
        } else if rho > rho_hi {
            Some((DENSITY_ABOVE, rho))
        } else if rho < rho_lo {
            Some((DENSITY_BELOW, rho))
        } else if h > h_hi {
            Some((H_ABOVE, h))
        } else if h < h_lo {
            Some((H_BELOW, h))
        } else {
            None
        }
    }
}

impl HealthBounds {
    /// The sane interval of `quantity` (one of [`DENSITY_ABOVE`], [`DENSITY_BELOW`],
    /// [`H_ABOVE`], [`H_BELOW`]), for messages.
    pub fn interval(&self, quantity: &str) -> Option<(Real, Real)> {
        match quantity {
            DENSITY_ABOVE | DENSITY_BELOW => self.rho_range.map(|r| widened(r, self.density)),
            H_ABOVE | H_BELOW => self.h_range.map(|r| widened(r, self.h)),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests;
