//! `LeapfrogPC()`: the leapfrog predictor–corrector of Ren, Dai, Zhuang & Rabczuk,
//! *Dual-support Smoothed Particle Hydrodynamics* (preprint; RenDSSPH in
//! `docs/references.md`), §6 steps 1–3, one force evaluation per step (the default scheme).
//!
//! Predictor (in `Predict`):
//! `r^{t+Δt} = r^t + Δt v^t + Δt²/2 a^t`, `v^p = v^t + Δt a^t`, `x^p = x^t + Δt ẋ^t` for every
//! declared scalar x (ρ with the continuity equation, ε with the energy equation).
//! Then all rates are evaluated at `(r^{t+Δt}, v^p, x^p)`.
//! Corrector (in `Correct`): `v^{t+Δt} = v^t + Δt/2 (a^t + a^{t+Δt})`, and likewise
//! `x^{t+Δt} = x^t + Δt/2 (ẋ^t + ẋ^{t+Δt})`.
//!
//! The start-of-step values `v^t, a^t` ([`StartOfStep`]) and `x^t, ẋ^t` (the scalar's
//! [`Registers`](dualsph_integrate::Registers)) are the scheme's own columns. The
//! predictor writes them before the corrector reads them, so they are not kept in checkpoints
//! (a resumed run is bitwise the same without them).
//!
//! The per-particle updates run over bevy's contiguous table slices, in rayon pieces (see
//! [`dualsph_core::chunks`]): each particle is updated from its own data, so the result does
//! not depend on the number of threads.

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

/// Start-of-step velocity and acceleration kept by the leapfrog predictor–corrector.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct StartOfStep<V: Vector> {
    /// `v^t`.
    pub v0: V,
    /// `f^t / m`.
    pub a0: V,
}

impl<V: Vector> ColumnValue<V> for StartOfStep<V> {
    const SHAPE: Shape = Shape::Record;
    fn width() -> usize {
        2 * V::DIM
    }
    fn put(&self, out: &mut Vec<Real>) {
        dualsph_core::columns::put_vector(self.v0, out);
        dualsph_core::columns::put_vector(self.a0, out);
    }
    fn take(&mut self, values: &[Real]) {
        self.v0 = dualsph_core::columns::take_vector(values);
        self.a0 = dualsph_core::columns::take_vector(&values[V::DIM..]);
    }
}

/// Predictor for positions and velocities.
#[inline(never)] // a frame of its own in profiles
pub fn predict_kinematics<V: Vector>(
    clock: Res<SimClock>,
    mut q: Query<(
        &mut Position<V>,
        &mut Velocity<V>,
        &Acceleration<V>,
        &mut StartOfStep<V>,
    )>,
) {
    let dt = clock.dt;
    for (mut r, mut v, a, mut k) in q.contiguous_iter_mut().expect(DENSE) {
        let (r, v) = (r.bypass_change_detection(), v.bypass_change_detection());
        let rows = (r, v, a, k.bypass_change_detection()).into_par_iter();
        rows.with_min_len(MIN_LEN).for_each(|(r, v, a, k)| {
            k.v0 = v.0;
            k.a0 = a.0;
            r.0 += v.0 * dt + a.0 * (0.5 * dt * dt);
            v.0 += a.0 * dt;
        });
    }
}

/// Corrector for velocities.
#[inline(never)] // a frame of its own in profiles
pub fn correct_kinematics<V: Vector>(
    clock: Res<SimClock>,
    mut q: Query<(&mut Velocity<V>, &Acceleration<V>, &StartOfStep<V>)>,
) {
    let half = 0.5 * clock.dt;
    for (mut v, a, k) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (v.bypass_change_detection(), a, k)
            .into_par_iter()
            .with_min_len(MIN_LEN);
        rows.for_each(|(v, a, k)| v.0 = k.v0 + (k.a0 + a.0) * half);
    }
}

/// Predictor for a scalar: keeps `[x^t, ẋ^t]`, then `x += Δt ẋ`.
pub fn predict_scalar(clock: &SimClock, rows: ScalarRows<'_>) {
    let dt = clock.dt;
    let ScalarRows {
        value,
        rate,
        registers,
    } = rows;
    for ((x, r), k) in value.iter_mut().zip(rate).zip(registers) {
        *k = [*x, *r];
        *x += dt * r;
    }
}

/// Corrector for a scalar: `x = x^t + Δt/2 (ẋ^t + ẋ)`.
pub fn correct_scalar(clock: &SimClock, rows: ScalarRows<'_>) {
    let half = 0.5 * clock.dt;
    let ScalarRows {
        value,
        rate,
        registers,
    } = rows;
    for ((x, r), k) in value.iter_mut().zip(rate).zip(registers.iter()) {
        *x = k[0] + half * (k[1] + r);
    }
}

/// The work-consistent correction of the internal energy (see [`crate::energy`]) for the
/// predictor–corrector: `ε −= Δt/2 [a^n·(v̄ − v^ev,n) + a^{n+1}·(v̄ − v^ev,n+1)]` with
/// `v̄ = ½(v^n + v^{n+1})` and `a` the pair accelerations of the two evaluations.
#[inline(never)] // a frame of its own in profiles
pub fn correct_energy_work<V: Vector>(
    clock: Res<SimClock>,
    mut q: Query<(
        &mut InternalEnergy,
        &Velocity<V>,
        &StartOfStep<V>,
        &Evaluations<V>,
    )>,
) {
    let half = 0.5 * clock.dt;
    for (mut e, v, k, ev) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (e.bypass_change_detection(), v, k, ev)
            .into_par_iter()
            .with_min_len(MIN_LEN);
        rows.for_each(|(e, v, k, ev)| {
            let vbar = (k.v0 + v.0) * 0.5;
            let terms = [(half, ev.a_prev, ev.w_prev), (half, ev.a, ev.w)];
            e.0 += crate::energy::correction(terms, vbar);
        });
    }
}

/// The scheme's systems.
pub(crate) struct Leapfrog(pub(crate) EnergyUpdate);

impl<V: Vector> Scheme<V> for Leapfrog {
    fn name(&self) -> &'static str {
        crate::LEAPFROG_PC
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
            ("correct", Arc::new(correct_scalar)),
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
    sim.add_column(ColumnSpec::scratch("leapfrog_start_of_step"), |_| {
        StartOfStep::<V>::default()
    })?;
    add_time_step_systems(sim);
    sim.add_system(
        StepSet::Predict,
        "predict_kinematics",
        predict_kinematics::<V>,
    )
    .in_group::<crate::Kinematics>()
    .before::<DriveBodies>();
    sim.add_system(
        StepSet::Correct,
        "correct_kinematics",
        correct_kinematics::<V>,
    )
    .in_group::<crate::Kinematics>()
    .before::<DriveBodies>();
    sim.set_integrator(Leapfrog(energy))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clock(dt: Real) -> SimClock {
        SimClock {
            t: 0.0,
            step: 0,
            dt,
            initializing: false,
            t_end: Real::INFINITY,
        }
    }

    #[test]
    fn the_scalar_predictor_and_corrector_are_the_formulas_of_section_6() {
        let (dt, x0, r0, r1) = (0.1, 2.0, -3.0, 5.0);
        let (mut x, mut k) = ([x0], [[0.0; 2]]);
        predict_scalar(
            &clock(dt),
            ScalarRows {
                value: &mut x,
                rate: &[r0],
                registers: &mut k,
            },
        );
        assert_eq!((x[0], k[0]), (x0 + dt * r0, [x0, r0]));
        correct_scalar(
            &clock(dt),
            ScalarRows {
                value: &mut x,
                rate: &[r1],
                registers: &mut k,
            },
        );
        assert_eq!(x[0], x0 + 0.5 * dt * (r0 + r1));
    }
}
