//! Conservation diagnostics: mass, linear and angular momentum, kinetic / internal /
//! potential / total energy, and the largest density variation, summed in particle-id order
//! (deterministic).

use crate::components::*;
use crate::math::{Real, Vector};
use crate::sim::{Domain, Sim, SimClock, StepSet};
use bevy_ecs::prelude::*;
use glam::DVec3;

/// Potential of a body force per unit mass at a point, registered by plugins (gravity).
#[derive(Resource, Clone, Default)]
pub struct ExternalPotentials {
    /// `φ(x)` terms; the potential energy is `Σ m_i Σ_k φ_k(x_i)`.
    pub terms: Vec<fn(&[Real; 3], &[Real; 3]) -> Real>,
    /// Parameters of each term (e.g. g).
    pub params: Vec<[Real; 3]>,
}

/// Totals of the current state.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct Diagnostics {
    /// Simulated time.
    pub t: Real,
    /// Step.
    pub step: u64,
    /// dt of the last step.
    pub dt: Real,
    /// Particle count.
    pub n: u64,
    /// Total mass.
    pub mass: Real,
    /// Linear momentum Σ m v (3-D embedding).
    pub momentum: [Real; 3],
    /// Angular momentum Σ m r × v about the origin.
    pub angular_momentum: [Real; 3],
    /// Σ ½ m v².
    pub e_kin: Real,
    /// Σ m ε.
    pub e_int: Real,
    /// Σ m φ(r).
    pub e_pot: Real,
    /// e_kin + e_int + e_pot.
    pub e_tot: Real,
    /// max |ρ_i/ρ_i(0) − 1|.
    pub max_density_variation: Real,
    /// Σ |m v| (scale for relative momentum errors).
    pub momentum_scale: Real,
}

/// Steps between diagnostics evaluations (the scene's `output.diagnostics_every`; default 1).
/// [`compute_diagnostics`] sums over all particles in id order, so it runs only on those
/// steps (and at t = 0); [`Sim::diagnostics`] brings a stale value up to date on demand.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct DiagnosticsEvery(pub u64);

impl Default for DiagnosticsEvery {
    fn default() -> Self {
        DiagnosticsEvery(1)
    }
}

/// Initial densities by id (for the density-variation diagnostic).
#[derive(Resource, Clone, Debug, Default)]
pub struct InitialDensity(pub Vec<Real>);

/// The particle data the diagnostics read.
type DiagQuery<'w, 's, V> = Query<
    'w,
    's,
    (
        &'static ParticleId,
        &'static Position<V>,
        &'static Velocity<V>,
        &'static Mass,
        &'static Density,
        Option<&'static InternalEnergy>,
    ),
>;

/// Computes [`Diagnostics`] at t = 0 and every [`DiagnosticsEvery`] steps.
pub fn compute_diagnostics<V: Vector>(
    every: Res<DiagnosticsEvery>,
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    init_rho: ResMut<InitialDensity>,
    diag: ResMut<Diagnostics>,
    q: DiagQuery<V>,
) {
    if clock.initializing || clock.step.is_multiple_of(every.0.max(1)) {
        compute_diagnostics_now(clock, potentials, init_rho, diag, q);
    }
}

/// Computes [`Diagnostics`] now.
#[inline(never)] // a frame of its own in profiles
pub fn compute_diagnostics_now<V: Vector>(
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    mut init_rho: ResMut<InitialDensity>,
    mut diag: ResMut<Diagnostics>,
    q: DiagQuery<V>,
) {
    let mut rows: Vec<_> = q.iter().collect();
    rows.sort_unstable_by_key(|r| r.0.0);
    if init_rho.0.len() != rows.len() {
        init_rho.0 = rows.iter().map(|r| r.4.0).collect();
    }
    let mut d = Diagnostics {
        t: clock.t,
        step: clock.step,
        dt: clock.dt,
        n: rows.len() as u64,
        ..Default::default()
    };
    let mut p = DVec3::ZERO;
    let mut l = DVec3::ZERO;
    for (id, r, v, m, rho, e) in rows {
        let (x, u) = (r.0.to_xyz(), v.0.to_xyz());
        let mv = DVec3::from_array(u) * m.0;
        d.mass += m.0;
        p += mv;
        d.momentum_scale += mv.length();
        l += V::cross3(r.0, v.0) * m.0;
        d.e_kin += 0.5 * m.0 * v.0.length_squared();
        if let Some(e) = e {
            d.e_int += m.0 * e.0;
        }
        for (phi, par) in potentials.terms.iter().zip(&potentials.params) {
            d.e_pot += m.0 * phi(&x, par);
        }
        let r0 = init_rho.0[id.0 as usize];
        d.max_density_variation = d.max_density_variation.max((rho.0 / r0 - 1.0).abs());
    }
    d.momentum = p.to_array();
    d.angular_momentum = l.to_array();
    d.e_tot = d.e_kin + d.e_int + d.e_pot;
    *diag = d;
}

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

/// Scans for non-finite positions/velocities, non-positive or non-finite density and h, and
/// particles farther than [`DOMAIN_TOLERANCE`] × the largest box extent outside the domain.
#[inline(never)] // a frame of its own in profiles
pub fn check_health<V: Vector>(
    mut health: ResMut<Health>,
    domain: Res<Domain<V>>,
    q: Query<(
        &ParticleId,
        &Position<V>,
        &Velocity<V>,
        &Density,
        &SmoothingLength,
        Option<&InternalEnergy>,
    )>,
) {
    let extent = (0..V::DIM)
        .map(|k| domain.max.get(k) - domain.min.get(k))
        .fold(0.0, Real::max);
    let tol = DOMAIN_TOLERANCE * extent;
    let (lo, hi) = (domain.min, domain.max);
    let mut worst: Option<(u32, &'static str, Real)> = None;
    for (id, r, v, rho, h, e) in &q {
        // fast path: one sum is finite iff every term is (or it overflowed: then look closer)
        let mut sum = rho.0 + h.0 + e.map_or(0.0, |e| e.0);
        let mut inside = true;
        for k in 0..V::DIM {
            let x = r.0.get(k);
            sum += x + v.0.get(k);
            inside &= x >= lo.get(k) - tol && x <= hi.get(k) + tol;
        }
        if sum.is_finite() && rho.0 > 0.0 && h.0 > 0.0 && inside {
            continue;
        }
        let outside = distance_outside(r.0, lo, hi);
        let bad = if !r.0.is_finite() {
            Some(("position", r.0.length()))
        } else if !v.0.is_finite() {
            Some(("velocity", v.0.length()))
        } else if !(rho.0.is_finite() && rho.0 > 0.0) {
            Some(("density", rho.0))
        } else if !(h.0.is_finite() && h.0 > 0.0) {
            Some(("smoothing length", h.0))
        } else if e.is_some_and(|e| !e.0.is_finite()) {
            Some(("internal energy", e.map_or(0.0, |e| e.0)))
        } else if outside > tol {
            Some((OUTSIDE_DOMAIN, outside))
        } else {
            None
        };
        if let Some((what, val)) = bad
            && worst.is_none_or(|w| id.0 < w.0)
        {
            worst = Some((id.0, what, val));
        }
    }
    health.problem = worst;
}

pub(crate) fn add_diagnostics_system<V: Vector>(sim: &mut Sim<V>) {
    sim.world.insert_resource(ExternalPotentials::default());
    sim.world.insert_resource(InitialDensity::default());
    sim.world.insert_resource(Health::default());
    sim.add_system(StepSet::Diagnostics, "check_health", check_health::<V>);
    sim.world.insert_resource(DiagnosticsEvery::default());
    sim.add_system(
        StepSet::Diagnostics,
        "compute_diagnostics (every diagnostics_every steps)",
        compute_diagnostics::<V>,
    );
}
