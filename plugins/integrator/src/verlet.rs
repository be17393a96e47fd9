//! `PositionVerlet()`: the Störmer–Verlet scheme in its position ("drift–kick–drift") form,
//! one force evaluation per step, at the middle of the step.
//!
//! With `a^{n−½}` and `ẋ^{n−½}` the rates of the previous evaluation (at t = 0 those of the
//! initial state):
//!
//! * (V1) `r^{n+½} = r^n + Δt/2 v^n` — drift, in `Predict`;
//! * (V2) `ṽ^{n+½} = v^n + Δt/2 a^{n−½}`, `x̃^{n+½} = x^n + Δt/2 ẋ^{n−½}` — the predicted
//!   mid-step velocity and scalars (density, energy), in `Predict`, at which the
//!   velocity-dependent forces (viscosity) and the scalars' rates are evaluated;
//! * (V3) `a^{n+½} = a(r^{n+½}, ṽ^{n+½}, x̃^{n+½})`, `ẋ^{n+½}` likewise — the step's
//!   evaluation;
//! * (V4) `v^{n+1} = v^n + Δt a^{n+½}`, `x^{n+1} = x^n + Δt ẋ^{n+½}` — kick, in `Correct`;
//! * (V5) `r^{n+1} = r^{n+½} + Δt/2 v^{n+1}` — drift, in `Correct`.
//!
//! For forces that depend on position only, (V1), (V4), (V5) are the Störmer–Verlet method in
//! its position form (Hairer, Lubich & Wanner, *Geometric numerical integration illustrated
//! by the Störmer–Verlet method*, Acta Numerica 12 (2003) 399–450; Hairer2003 in
//! `docs/references.md`): symplectic, time-reversible and of second order, and (V2) changes
//! nothing. With velocity-dependent forces and integrated scalars the rates at the middle of
//! the step come from the state predicted by (V2) with the rates of the last evaluation, half
//! a step old: its error is O(Δt²), so the kick, a midpoint rule, keeps second order (without
//! (V2) the order falls to one, `tests/schemes.rs`). This is the "Symplectic" time stepping of
//! DualSPHysics (Domínguez et al., *DualSPHysics: from fluid dynamics to multiphysics
//! problems*, Comput. Part. Mech. 9 (2022) 867–895; Domínguez2022), here with the plain
//! midpoint rule for the density.
//!
//! Compared with [`crate::LeapfrogPC`], which evaluates the forces at the end of the step
//! (`r^{n+1}`; for position-only forces it is the velocity form of Störmer–Verlet), the forces
//! here are evaluated at `r^{n+½}`: the two agree to second order and differ in their errors
//! (`tests/schemes.rs` measures both). The start-of-step values `v^n`
//! and `x^n` are the scheme's own columns, written in `Predict` before `Correct` reads them,
//! so they are not kept in checkpoints.

use crate::energy::{EnergyUpdate, Evaluations};
use crate::time_step::add_time_step_systems;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::DriveBodies;
use dualsph_core::chunks::{DENSE, MIN_LEN};
use dualsph_fluid::INTERNAL_ENERGY;
use dualsph_fluid::prelude::*;
use dualsph_integrate::{ScalarEquation, ScalarRows, Scheme};
use rayon::prelude::*;
use std::sync::Arc;

/// The start-of-step velocity `v^n` kept by the position Verlet.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct VerletStart<V: Vector>(pub V);

dualsph_core::vector_column!(VerletStart);

/// (V1) and (V2) for positions and velocities.
#[inline(never)] // a frame of its own in profiles
pub fn drift_and_predict<V: Vector>(
    clock: Res<SimClock>,
    mut q: Query<(
        &mut Position<V>,
        &mut Velocity<V>,
        &Acceleration<V>,
        &mut VerletStart<V>,
    )>,
) {
    let half = 0.5 * clock.dt;
    for (mut r, mut v, a, mut k) in q.contiguous_iter_mut().expect(DENSE) {
        let (r, v) = (r.bypass_change_detection(), v.bypass_change_detection());
        let rows = (r, v, a, k.bypass_change_detection()).into_par_iter();
        rows.with_min_len(MIN_LEN).for_each(|(r, v, a, k)| {
            k.0 = v.0;
            r.0 += v.0 * half;
            v.0 += a.0 * half;
        });
    }
}

/// (V4) and (V5) for velocities and positions.
#[inline(never)] // a frame of its own in profiles
pub fn kick_and_drift<V: Vector>(
    clock: Res<SimClock>,
    mut q: Query<(
        &mut Position<V>,
        &mut Velocity<V>,
        &Acceleration<V>,
        &VerletStart<V>,
    )>,
) {
    let (dt, half) = (clock.dt, 0.5 * clock.dt);
    for (mut r, mut v, a, k) in q.contiguous_iter_mut().expect(DENSE) {
        let (r, v) = (r.bypass_change_detection(), v.bypass_change_detection());
        let rows = (r, v, a, k).into_par_iter();
        rows.with_min_len(MIN_LEN).for_each(|(r, v, a, k)| {
            v.0 = k.0 + a.0 * dt;
            r.0 += v.0 * half;
        });
    }
}

/// (V2) for a scalar: keeps `x^n`, then `x += Δt/2 ẋ`.
pub fn predict_scalar(clock: &SimClock, rows: ScalarRows<'_>) {
    let half = 0.5 * clock.dt;
    let ScalarRows {
        value,
        rate,
        registers,
    } = rows;
    for ((x, r), k) in value.iter_mut().zip(rate).zip(registers) {
        k[0] = *x;
        *x += half * r;
    }
}

/// (V4) for a scalar: `x = x^n + Δt ẋ^{n+½}`.
pub fn kick_scalar(clock: &SimClock, rows: ScalarRows<'_>) {
    let dt = clock.dt;
    let ScalarRows {
        value,
        rate,
        registers,
    } = rows;
    for ((x, r), k) in value.iter_mut().zip(rate).zip(registers.iter()) {
        *x = k[0] + dt * r;
    }
}

/// The work-consistent correction of the internal energy (see [`crate::energy`]) for the
/// position Verlet: `ε −= Δt a^{n+½}·(v̄ − ṽ^{n+½})` with `v̄ = ½(v^n + v^{n+1})`, `a` the
/// pair acceleration of the step's one evaluation and `ṽ` its velocity.
#[inline(never)] // a frame of its own in profiles
pub fn correct_energy_work<V: Vector>(
    clock: Res<SimClock>,
    mut q: Query<(
        &mut InternalEnergy,
        &Velocity<V>,
        &VerletStart<V>,
        &Evaluations<V>,
    )>,
) {
    let dt = clock.dt;
    for (mut e, v, k, ev) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (e.bypass_change_detection(), v, k, ev)
            .into_par_iter()
            .with_min_len(MIN_LEN);
        rows.for_each(|(e, v, k, ev)| {
            let vbar = (k.0 + v.0) * 0.5;
            e.0 += crate::energy::correction([(dt, ev.a, ev.w)], vbar);
        });
    }
}

/// The scheme's systems.
pub(crate) struct Verlet(pub(crate) EnergyUpdate);

impl<V: Vector> Scheme<V> for Verlet {
    fn name(&self) -> &'static str {
        crate::POSITION_VERLET
    }

    fn integrate_scalar(
        &self,
        sim: &mut Sim<V>,
        equation: &dyn ScalarEquation<V>,
    ) -> Result<(), SimError> {
        crate::two_updates(
            sim,
            equation,
            ("predict", Arc::new(predict_scalar)),
            ("kick", Arc::new(kick_scalar)),
        )?;
        if equation.name() == INTERNAL_ENERGY && self.0 == EnergyUpdate::Consistent {
            let system = correct_energy_work::<V>;
            crate::energy::install(sim, system)?;
        }
        Ok(())
    }
}

/// Installs the scheme: its kinematics systems, its start-of-step column and the time-step
/// rule; the declared scalars follow through [`Scheme::integrate_scalar`].
pub(crate) fn install<V: Vector>(sim: &mut Sim<V>, energy: EnergyUpdate) -> Result<(), SimError> {
    sim.add_column(ColumnSpec::scratch("verlet_start_of_step"), |_| {
        VerletStart(V::zero())
    })?;
    add_time_step_systems(sim);
    sim.add_system(
        StepSet::Predict,
        "drift_and_predict (position Verlet, first half)",
        drift_and_predict::<V>,
    )
    .in_group::<crate::Kinematics>()
    .before::<DriveBodies>();
    sim.add_system(
        StepSet::Correct,
        "kick_and_drift (position Verlet, second half)",
        kick_and_drift::<V>,
    )
    .in_group::<crate::Kinematics>()
    .before::<DriveBodies>();
    sim.set_integrator(Verlet(energy))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scalar_half_drift_and_kick_are_v2_and_v4() {
        let clock = SimClock {
            t: 0.0,
            step: 0,
            dt: 0.1,
            initializing: false,
            t_end: Real::INFINITY,
        };
        let (x0, r_old, r_mid) = (2.0, -3.0, 5.0);
        let (mut x, mut k) = ([x0], [[0.0; 2]]);
        predict_scalar(
            &clock,
            ScalarRows {
                value: &mut x,
                rate: &[r_old],
                registers: &mut k,
            },
        );
        assert_eq!((x[0], k[0][0]), (x0 + 0.5 * 0.1 * r_old, x0));
        kick_scalar(
            &clock,
            ScalarRows {
                value: &mut x,
                rate: &[r_mid],
                registers: &mut k,
            },
        );
        assert_eq!(x[0], x0 + 0.1 * r_mid);
    }
}
