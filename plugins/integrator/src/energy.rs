//! The work-consistent internal-energy update: total energy kept in time, not only by the pair
//! sums.
//!
//! The pair terms conserve energy at each evaluation: for every pair the power credited to i
//! and j adds up to minus the work rate of their pair force at the velocities it was evaluated
//! with, `Σ_i m_i ε̇_i + Σ_i F_i·v_i^ev = 0`, with `F_i` the pair forces on i and `v^ev` the
//! velocities of that evaluation. A step, though, changes i's kinetic energy by exactly
//! `½m_i(v_i^{n+1}² − v_i^n²) = Δt Σ_k w_k F_i^k·v̄_i`, `v̄_i = ½(v_i^n + v_i^{n+1})`, where
//! `w_k` are the scheme's weights of its evaluations in the velocity update (the leapfrog
//! predictor–corrector: ½ and ½ for the evaluations at the start and the end of the step;
//! the position Verlet: 1 for the one at the middle). Integrating `ε̇` as it comes gives the
//! internal energy `Δt Σ_k w_k m_i ε̇_i^k` instead, and the difference, `Δt Σ_k w_k
//! F_i^k·(v_i^ev,k − v̄_i)` per particle, is the energy the step loses (7·10⁻³ of the
//! elliptical drop's energy over its run).
//!
//! So after the scheme's own update of `ε`, each particle's internal energy is corrected by
//! that difference:
//!
//! `m_i ε_i^{n+1} ← m_i ε_i^{n+1} − Δt Σ_k w_k F_i^k·(v̄_i − v_i^ev,k)`,
//!
//! which makes the step's change of `Σ ½m v² + Σ m ε` exactly `Δt Σ_k w_k Σ_i (m_i ε̇_i^k +
//! F_i^k·v_i^ev,k) = 0` (to round-off), whatever Δt. The correction is the work of i's own pair
//! force over the difference between the velocity it was evaluated at and the velocity the
//! step moved i with; both differ from `v̄` by O(Δt) with opposite signs across the two
//! evaluations of the predictor–corrector (and by O(Δt²) in the Verlet), so the correction is
//! O(Δt³) per step and the schemes keep their second order. It is Galilean invariant (a
//! difference of velocities) and local (no pair is visited again). This is the idea of the
//! compatible energy discretisation of Owen (J. M. Owen, *A compatibly differenced total
//! energy conserving form of SPH*, Int. J. Numer. Meth. Fluids 75 (2014) 749–774; Owen2014 in
//! `docs/references.md`) — the internal energy built from the same force and the same mean
//! velocity as the kinetic energy — applied per particle to the net pair force instead of per
//! pair, which needs no pair forces kept from one evaluation to the next.
//!
//! Body forces (gravity, in `BodyForces`) are not pair forces: their work goes to the
//! potential energy, so the record below is taken from the acceleration the force stage
//! leaves, before them.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bevy_ecs::system::ScheduleSystem;
use dualsph_core::bodies::DriveBodies;
use dualsph_core::chunks::{DENSE, MIN_LEN};
use dualsph_core::columns::{ColumnValue, Shape, put_vector, take_vector};
use dualsph_fluid::prelude::*;
use dualsph_integrate::Updates;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// How a scheme advances the internal energy (`energy:` of `LeapfrogPC(...)` and
/// `PositionVerlet(...)`).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
pub enum EnergyUpdate {
    /// The rates, then the work-consistent correction (see the module docs): total energy
    /// kept to round-off by the time integration (the default).
    #[default]
    Consistent,
    /// The rates only, like any other integrated scalar: the total energy drifts by the
    /// scheme's error.
    Rates,
}

/// The pair acceleration `a = F_i/m_i` and its power per unit mass `w = a·v^ev` at the
/// velocity of the evaluation, for the last two force evaluations: what the correction needs
/// of them. Kept in checkpoints (the next step reads the last evaluation's record before it
/// writes its own).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct Evaluations<V: Vector> {
    /// Pair acceleration of the evaluation before the last.
    pub a_prev: V,
    /// Pair acceleration of the last evaluation.
    pub a: V,
    /// `a·v^ev` of the evaluation before the last.
    pub w_prev: Real,
    /// `a·v^ev` of the last evaluation.
    pub w: Real,
}

impl<V: Vector> ColumnValue<V> for Evaluations<V> {
    const SHAPE: Shape = Shape::Record;
    fn width() -> usize {
        2 * V::DIM + 2
    }
    fn put(&self, out: &mut Vec<Real>) {
        put_vector(self.a_prev, out);
        put_vector(self.a, out);
        out.extend([self.w_prev, self.w]);
    }
    fn take(&mut self, values: &[Real]) {
        let d = V::DIM;
        self.a_prev = take_vector(values);
        self.a = take_vector(&values[d..]);
        (self.w_prev, self.w) = (values[2 * d], values[2 * d + 1]);
    }
}

/// Keeps the evaluation that the force stage has just made: the last record becomes the one
/// before, and `(a, a·v)` the last.
#[inline(never)] // a frame of its own in profiles
pub fn record_evaluation<V: Vector>(
    mut q: Query<(&Acceleration<V>, &Velocity<V>, &mut Evaluations<V>)>,
) {
    for (a, v, mut e) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (a, v, e.bypass_change_detection())
            .into_par_iter()
            .with_min_len(MIN_LEN);
        rows.for_each(|(a, v, e)| {
            (e.a_prev, e.w_prev) = (e.a, e.w);
            (e.a, e.w) = (a.0, a.0.dot(v.0));
        });
    }
}

/// The correction of one particle's specific internal energy for the evaluations
/// `(w_k Δt, a_k, a_k·v_k^ev)` and the step's mean velocity `v̄`:
/// `−Σ_k w_k Δt (a_k·v̄ − a_k·v_k^ev)`.
#[inline(always)]
pub fn correction<V: Vector, const K: usize>(terms: [(Real, V, Real); K], vbar: V) -> Real {
    let mut de = 0.0;
    for (wdt, a, w) in terms {
        de -= wdt * (a.dot(vbar) - w);
    }
    de
}

/// Adds the record of the evaluations and the system that keeps it (right after the force
/// sweep), and the scheme's correction `system` in `Correct`: after the scheme's velocity
/// update ([`crate::Kinematics`]), its update of ε and the driving of the bodies.
pub(crate) fn install<V: Vector, M: 'static>(
    sim: &mut Sim<V>,
    system: impl IntoScheduleConfigs<ScheduleSystem, M> + Send + Sync + 'static,
) -> Result<(), SimError> {
    sim.add_column(ColumnSpec::restart_only("pair_work_evaluations"), |_| {
        Evaluations::<V>::default()
    })?;
    sim.add_system(
        StepSet::Forces,
        "record_evaluation (work-consistent energy)",
        record_evaluation::<V>,
    )
    .after::<dualsph_sweep::ForceSweep>();
    sim.add_system(StepSet::Correct, CORRECT_LABEL, system)
        .after::<crate::Kinematics>()
        .after::<Updates<InternalEnergy>>()
        .after::<DriveBodies>();
    Ok(())
}

/// The label of a scheme's correction system.
const CORRECT_LABEL: &str = "correct_energy_work (work-consistent energy)";

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// Two particles under a pair force (`f_k` on i, `−f_k` on j at the evaluations t^n and
    /// t^{n+1}) through one predictor–corrector step: the rates' internal energy, the pair's
    /// power `−f_k·v_ij^ev,k` weighted ½ each, leaves `ΔK + ΔU` at O(Δt³); with the
    /// correction it is zero to round-off.
    #[test]
    fn a_pair_step_keeps_kinetic_plus_internal_energy() {
        let (m, dt) = (2.0, 0.01);
        let f = [DVec2::new(3.0, -1.0), DVec2::new(2.5, 0.5)];
        let v0 = [DVec2::new(1.0, 2.0), DVec2::new(-0.5, 0.25)];
        let sign = [1.0, -1.0];
        let a = |k: usize, p: usize| f[k] * (sign[p] / m);
        // velocities of the two evaluations: v^n, then the predicted v^n + Δt a^n
        let vev = |k: usize, p: usize| v0[p] + a(0, p) * (k as f64 * dt);
        let (mut d_kin, mut d_corr, mut kin) = (0.0, 0.0, 0.0);
        for p in 0..2 {
            let v1 = v0[p] + (a(0, p) + a(1, p)) * (0.5 * dt);
            d_kin += 0.5 * m * (v1.length_squared() - v0[p].length_squared());
            kin += 0.5 * m * v0[p].length_squared();
            let vbar = (v0[p] + v1) * 0.5;
            let term = |k: usize| (0.5 * dt, a(k, p), a(k, p).dot(vev(k, p)));
            let terms = [term(0), term(1)];
            d_corr += m * correction(terms, vbar);
        }
        let d_rates: f64 = (0..2)
            .map(|k| -0.5 * dt * f[k].dot(vev(k, 0) - vev(k, 1)))
            .sum();
        // round-off of the kinetic energies themselves: a few ulps of K
        let (without, with) = ((d_kin + d_rates).abs(), (d_kin + d_rates + d_corr).abs());
        assert!(
            with < 4.0 * f64::EPSILON * kin,
            "ΔK {d_kin} ΔU {} → {with}",
            d_rates + d_corr
        );
        assert!(
            without > 1e-9 * kin,
            "the rates alone lose {without} of K = {kin}"
        );
    }
}
