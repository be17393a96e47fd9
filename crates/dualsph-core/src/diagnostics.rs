//! Conservation diagnostics: mass, linear and angular momentum, kinetic / internal /
//! potential / total energy, and the largest density variation, summed in particle-id order
//! (deterministic).

use crate::bodies::{Bodies, BodyId};
use crate::chunks::{DENSE, MIN_LEN};
use crate::components::*;
use crate::math::{Real, Vector};
use crate::sim::{Domain, Sim, SimClock, StepSet};
use bevy_ecs::prelude::*;
use glam::DVec3;
use rayon::prelude::*;

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
    /// The totals of each body, indexed by [`BodyId`].
    pub per_body: Vec<BodyTotals>,
}

/// Mass, momentum and energies of one body's particles.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyTotals {
    /// Σ m.
    pub mass: Real,
    /// Σ m v (3-D embedding).
    pub momentum: [Real; 3],
    /// Σ ½ m v².
    pub e_kin: Real,
    /// Σ m ε.
    pub e_int: Real,
    /// Σ m φ(r).
    pub e_pot: Real,
}

impl BodyTotals {
    /// The names of [`BodyTotals::values`], in order.
    pub const NAMES: [&'static str; 7] = ["mass", "px", "py", "pz", "e_kin", "e_int", "e_pot"];

    /// The totals as a list, in the order of [`BodyTotals::NAMES`].
    pub fn values(&self) -> [Real; 7] {
        let [px, py, pz] = self.momentum;
        [self.mass, px, py, pz, self.e_kin, self.e_int, self.e_pot]
    }

    /// The totals from a list in the order of [`BodyTotals::NAMES`].
    pub fn from_values(v: &[Real; 7]) -> Self {
        BodyTotals {
            mass: v[0],
            momentum: [v[1], v[2], v[3]],
            e_kin: v[4],
            e_int: v[5],
            e_pot: v[6],
        }
    }
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
        &'static BodyId,
    ),
>;

/// Computes [`Diagnostics`] at t = 0 and every [`DiagnosticsEvery`] steps.
pub fn compute_diagnostics<V: Vector>(
    every: Res<DiagnosticsEvery>,
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    bodies: Res<Bodies>,
    init_rho: ResMut<InitialDensity>,
    diag: ResMut<Diagnostics>,
    q: DiagQuery<V>,
) {
    if clock.initializing || clock.step.is_multiple_of(every.0.max(1)) {
        compute_diagnostics_now(clock, potentials, bodies, init_rho, diag, q);
    }
}

/// Computes [`Diagnostics`] now.
#[inline(never)] // a frame of its own in profiles
pub fn compute_diagnostics_now<V: Vector>(
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    bodies: Res<Bodies>,
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
        per_body: vec![BodyTotals::default(); bodies.0.len()],
        ..Default::default()
    };
    let mut p = DVec3::ZERO;
    let mut l = DVec3::ZERO;
    for (id, r, v, m, rho, e, body) in rows {
        let (x, u) = (r.0.to_xyz(), v.0.to_xyz());
        let mv = DVec3::from_array(u) * m.0;
        let e_kin = 0.5 * m.0 * v.0.length_squared();
        let e_int = e.map_or(0.0, |e| m.0 * e.0);
        let mut e_pot = 0.0;
        for (phi, par) in potentials.terms.iter().zip(&potentials.params) {
            e_pot += m.0 * phi(&x, par);
        }
        d.mass += m.0;
        p += mv;
        d.momentum_scale += mv.length();
        l += V::cross3(r.0, v.0) * m.0;
        d.e_kin += e_kin;
        d.e_int += e_int;
        d.e_pot += e_pot;
        if let Some(b) = d.per_body.get_mut(body.0 as usize) {
            b.mass += m.0;
            for (k, x) in b.momentum.iter_mut().enumerate() {
                *x += mv[k];
            }
            b.e_kin += e_kin;
            b.e_int += e_int;
            b.e_pot += e_pot;
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
    init_rho: Res<InitialDensity>,
    domain: Res<Domain<V>>,
    q: HealthQuery<V>,
) {
    if bounds.rho_range.is_none() {
        // on a resumed run InitialDensity is restored; at initialisation the current state
        // is the initial one
        bounds.rho_range = if init_rho.0.is_empty() {
            range(q.iter().map(|r| r.3.0))
        } else {
            range(init_rho.0.iter().copied())
        };
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

pub(crate) fn add_diagnostics_system<V: Vector>(sim: &mut Sim<V>) {
    sim.world.insert_resource(ExternalPotentials::default());
    sim.world.insert_resource(InitialDensity::default());
    sim.world.insert_resource(Health::default());
    sim.world.insert_resource(HealthBounds::default());
    sim.add_system(StepSet::Diagnostics, "check_health", check_health::<V>);
    sim.world.insert_resource(DiagnosticsEvery::default());
    sim.add_system(
        StepSet::Diagnostics,
        "compute_diagnostics (every diagnostics_every steps)",
        compute_diagnostics::<V>,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::KernelKind;
    use crate::neighbours::SkinRule;
    use crate::sim::{ParticleInit, SimConfig, TimeStepping};
    use crate::sweep::Formulation;
    use glam::DVec2;

    /// Two particles at rest, densities 1000 and 1200, h 0.1 and 0.2; no forces.
    fn sim() -> Sim<DVec2> {
        let mut sim = Sim::<DVec2>::new(SimConfig {
            kernel: KernelKind::CubicSpline,
            formulation: Formulation::DualSupport,
            domain: Domain {
                min: DVec2::ZERO,
                max: DVec2::ONE,
            },
            skin: 0.1,
            skin_rule: SkinRule::Fixed,
            time_stepping: TimeStepping::Fixed(1e-3),
        });
        let p = |x: f64, density: f64, h: f64| ParticleInit {
            pos: DVec2::new(x, 0.5),
            vel: DVec2::ZERO,
            mass: 1.0,
            density,
            h,
            internal_energy: 0.0,
            body: 0,
        };
        sim.spawn_particles(&[p(0.2, 1000.0, 0.1), p(0.8, 1200.0, 0.2)]);
        sim.initialize().unwrap();
        sim
    }

    fn set(sim: &mut Sim<DVec2>, id: u32, rho: Real, h: Real) {
        let mut q = sim
            .world
            .query::<(&ParticleId, &mut Density, &mut SmoothingLength)>();
        for (pid, mut d, mut s) in q.iter_mut(&mut sim.world) {
            if pid.0 == id {
                (d.0, s.0) = (rho, h);
            }
        }
    }

    fn problem(sim: &mut Sim<DVec2>) -> Option<(u32, &'static str, Real)> {
        use bevy_ecs::system::RunSystemOnce;
        sim.world.run_system_once(check_health::<DVec2>).unwrap();
        sim.world.resource::<Health>().problem
    }

    #[test]
    fn density_and_h_are_checked_against_the_initial_ranges_widened_by_their_factors() {
        let mut s = sim();
        assert_eq!(problem(&mut s), None);
        let b = s.world.resource::<HealthBounds>().clone();
        assert_eq!(b.rho_range, Some((1000.0, 1200.0)));
        assert_eq!(b.h_range, Some((0.1, 0.2)));
        s.world.resource_mut::<HealthBounds>().density = (3.0, 3.0);
        s.world.resource_mut::<HealthBounds>().h = (3.0, 3.0);
        // factors 3: ρ ∈ [333.3, 3600], h ∈ [0.0333, 0.6]; values just inside pass
        set(&mut s, 0, 3599.0, 0.59);
        set(&mut s, 1, 334.0, 0.034);
        assert_eq!(problem(&mut s), None);
        set(&mut s, 1, 3601.0, 0.1);
        assert_eq!(problem(&mut s), Some((1, DENSITY_ABOVE, 3601.0)));
        set(&mut s, 1, 333.0, 0.1);
        assert_eq!(problem(&mut s), Some((1, DENSITY_BELOW, 333.0)));
        set(&mut s, 1, 1000.0, 0.61);
        assert_eq!(problem(&mut s), Some((1, H_ABOVE, 0.61)));
        set(&mut s, 1, 1000.0, 0.033);
        assert_eq!(problem(&mut s), Some((1, H_BELOW, 0.033)));
        // the lowest id is reported; non-positive values keep their own name
        set(&mut s, 0, -1.0, 0.1);
        assert_eq!(problem(&mut s), Some((0, "density", -1.0)));
        let (lo, hi) = s
            .world
            .resource::<HealthBounds>()
            .interval(H_BELOW)
            .unwrap();
        assert!((lo - 0.1 / 3.0).abs() < 1e-15 && (hi - 0.6).abs() < 1e-15);
    }

    #[test]
    fn the_density_range_comes_from_the_initial_densities_when_they_are_restored() {
        let mut s = sim();
        // a resumed run: fresh bounds, InitialDensity restored from the checkpoint
        s.world.insert_resource(HealthBounds {
            density: (1.5, 1.5),
            h: (2.0, 2.0),
            rho_range: None,
            h_range: Some((0.1, 0.2)),
        });
        s.world.resource_mut::<InitialDensity>().0 = vec![900.0, 1000.0];
        set(&mut s, 0, 1499.0, 0.1);
        assert_eq!(problem(&mut s), None);
        assert_eq!(
            s.world.resource::<HealthBounds>().rho_range,
            Some((900.0, 1000.0))
        );
        set(&mut s, 0, 1501.0, 0.1);
        assert_eq!(problem(&mut s), Some((0, DENSITY_ABOVE, 1501.0)));
    }
}

/// How well the pair forces of the last sweep balance, at the positions they were computed
/// at: `|Σ_i m_i a_i| / Σ_i |m_i a_i|` and `|Σ_i r_i × m_i a_i| / Σ_i |r_i × m_i a_i|`, read
/// right after the sweep (before body forces and boundaries). Round-off for the dual-support
/// sweep whatever the h field (§5); see [`track_pair_balance`].
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct PairBalance {
    /// Relative net force.
    pub force: Real,
    /// Relative net torque about the origin.
    pub torque: Real,
}

/// Computes [`PairBalance`] from the accelerations the sweep just wrote (row order).
pub fn pair_balance<V: Vector>(
    mut balance: ResMut<PairBalance>,
    q: Query<(&Position<V>, &Mass, &Acceleration<V>)>,
) {
    let (mut f, mut f_abs, mut t, mut t_abs) = (DVec3::ZERO, 0.0, DVec3::ZERO, 0.0);
    for (r, m, a) in q.contiguous_iter().expect(DENSE) {
        for ((r, m), a) in r.iter().zip(m).zip(a) {
            let fi = a.0 * m.0;
            let ti = V::cross3(r.0, fi);
            f += DVec3::from_array(fi.to_xyz());
            f_abs += fi.length();
            t += ti;
            t_abs += ti.length();
        }
    }
    *balance = PairBalance {
        force: f.length() / f_abs.max(Real::MIN_POSITIVE),
        torque: t.length() / t_abs.max(Real::MIN_POSITIVE),
    };
}

/// Adds [`pair_balance`] right after the scene's force systems (call before the first step):
/// the [`PairBalance`] resource then holds the balance of every step's sweep.
pub fn track_pair_balance<V: Vector>(sim: &mut Sim<V>) {
    sim.world.insert_resource(PairBalance::default());
    sim.add_system(
        StepSet::Forces,
        "pair_balance (diagnostic)",
        pair_balance::<V>,
    );
}
