//! The totals of the state: mass, linear and angular momentum, kinetic / internal /
//! potential / total energy, per body and in all, and the largest density variation, summed
//! in particle-id order (deterministic).

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Bodies, BodyId};
use dualsph_core::components::*;
use dualsph_core::math::{Real, Vector};
use dualsph_core::potentials::ExternalPotentials;
use dualsph_core::sim::SimClock;
use glam::DVec3;

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
    /// max |ρ_i/ρ_i(0) − 1| over the particles, with ρ_i(0) their [`InitialDensity`]
    /// (NaN when the particles have none: a simulation without the plugin).
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
/// steps (and at t = 0); [`SimDiagnostics::diagnostics`](crate::SimDiagnostics::diagnostics) brings a stale value up to date on demand.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct DiagnosticsEvery(pub u64);

impl Default for DiagnosticsEvery {
    fn default() -> Self {
        DiagnosticsEvery(1)
    }
}

/// A particle's reference density for the density-variation diagnostic and the health
/// check's density range: its density after the initial evaluation of the rates, or at its
/// creation for a particle added during the run (a column, kept in checkpoints).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct InitialDensity(pub Real);
dualsph_core::scalar_column!(InitialDensity);

/// Sets every particle's [`InitialDensity`] to its density, at the initial evaluation only.
pub fn capture_initial_density(
    clock: Res<SimClock>,
    mut q: Query<(&Density, &mut InitialDensity)>,
) {
    if clock.initializing {
        for (rho, mut r0) in &mut q {
            r0.0 = rho.0;
        }
    }
}

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
        Option<&'static InitialDensity>,
    ),
>;

/// Computes [`Diagnostics`] at t = 0 and every [`DiagnosticsEvery`] steps.
pub fn compute_diagnostics<V: Vector>(
    every: Res<DiagnosticsEvery>,
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    bodies: Res<Bodies>,
    diag: ResMut<Diagnostics>,
    q: DiagQuery<V>,
) {
    if clock.initializing || clock.step.is_multiple_of(every.0.max(1)) {
        compute_diagnostics_now(clock, potentials, bodies, diag, q);
    }
}

/// Computes [`Diagnostics`] now.
#[inline(never)] // a frame of its own in profiles
pub fn compute_diagnostics_now<V: Vector>(
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    bodies: Res<Bodies>,
    mut diag: ResMut<Diagnostics>,
    q: DiagQuery<V>,
) {
    let mut rows: Vec<_> = q.iter().collect();
    rows.sort_unstable_by_key(|r| r.0.0);
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
    for (_, r, v, m, rho, e, body, r0) in rows {
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
        d.max_density_variation = match r0 {
            Some(r0) => d.max_density_variation.max((rho.0 / r0.0 - 1.0).abs()),
            None => Real::NAN,
        };
    }
    d.momentum = p.to_array();
    d.angular_momentum = l.to_array();
    d.e_tot = d.e_kin + d.e_int + d.e_pot;
    *diag = d;
}
