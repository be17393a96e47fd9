//! The leapfrog predictor–corrector of paper 001 §6, one force evaluation per step, and the
//! core systems every simulation has (dt, gather, neighbours, clock).
//!
//! Predictor:  `r^{t+Δt} = r^t + Δt v^t + Δt²/2 a^t`,  `v^p = v^t + Δt a^t`,
//!             `ρ^p = ρ^t + Δt ρ̇^t`,  `ε^p = ε^t + Δt ε̇^t`.
//! Then all rates are evaluated at `(r^{t+Δt}, v^p, ρ^p, ε^p)`.
//! Corrector:  `v^{t+Δt} = v^t + Δt/2 (a^t + a^{t+Δt})`, and likewise for ρ and ε.
//!
//! The per-particle updates run over bevy's contiguous table slices, in rayon pieces (see
//! [`crate::chunks`]): each particle is updated from its own data, so the result does not
//! depend on the number of threads.

use crate::chunks::{DENSE, MIN_LEN};
use crate::columns::ColumnSpec;
use crate::components::*;
use crate::math::{Real, Vector};
use crate::neighbours::Neighbours;
use crate::sim::{
    InitialInternalEnergy, MaxViscosity, Sim, SimClock, SimError, StepSet, TimeStepping,
};
use crate::store::single_table;
use bevy_ecs::prelude::*;
use rayon::prelude::*;

/// Chooses dt for this step (fixed, or the CFL / force / viscous criteria with each
/// particle's own h).
#[inline(never)] // a frame of its own in profiles
pub fn choose_dt<V: Vector>(
    mut clock: ResMut<SimClock>,
    rule: Res<TimeStepping>,
    visc: Res<MaxViscosity>,
    q: Query<(
        &Velocity<V>,
        &Acceleration<V>,
        &SmoothingLength,
        &Density,
        Option<&SoundSpeed>,
    )>,
) {
    clock.dt = match *rule {
        TimeStepping::Fixed(dt) => dt,
        TimeStepping::Adaptive {
            courant,
            force,
            viscous,
            max_dt,
        } => {
            let visc = visc.0;
            let limit = |v: V, a: V, h: Real, rho: Real, c: Real| {
                let mut dt = Real::INFINITY;
                let speed = c + v.length();
                if speed > 0.0 {
                    dt = dt.min(courant * h / speed);
                }
                let acc = a.length();
                if acc > 0.0 {
                    dt = dt.min(force * (h / acc).sqrt());
                }
                if visc > 0.0 {
                    dt = dt.min(viscous * rho * h * h / visc);
                }
                dt
            };
            let mut dt = max_dt;
            // a minimum: exact and independent of the order, so of the thread count
            for (v, a, h, rho, c) in q.contiguous_iter().expect(DENSE) {
                let inf = || Real::INFINITY;
                let chunk = match c {
                    Some(c) => (v, a, h, rho, c)
                        .into_par_iter()
                        .with_min_len(MIN_LEN)
                        .map(|(v, a, h, rho, c)| limit(v.0, a.0, h.0, rho.0, c.0))
                        .reduce(inf, Real::min),
                    None => (v, a, h, rho)
                        .into_par_iter()
                        .with_min_len(MIN_LEN)
                        .map(|(v, a, h, rho)| limit(v.0, a.0, h.0, rho.0, 0.0))
                        .reduce(inf, Real::min),
                };
                dt = dt.min(chunk);
            }
            dt
        }
    };
    let remaining = clock.t_end - clock.t;
    if remaining > 0.0 && clock.dt > remaining {
        clock.dt = remaining;
    }
}

/// Courant number on the support radius above which a fixed dt is refused:
/// `dt ≤ C_max h_i/(c_i + |v_i|)` with `C_max = 0.25`, i.e. 0.5 on the classical smoothing
/// length h_i/2 of the two-h kernels — above every acoustic Courant number in common SPH
/// use (0.2–0.4 on the classical length), where the leapfrog's sound-wave mode grows.
pub const CFL_LIMIT: Real = 0.25;

/// A fixed dt found above the CFL limit: `(particle id, dt, limit)` of the particle with the
/// smallest limit.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeStepCheck {
    /// The violation, if any, found after the last step (or at initialisation).
    pub violation: Option<(u32, Real, Real)>,
}

/// The acoustic limit `CFL_LIMIT · min_i h_i/(c_i + |v_i|)` and the particle that sets it.
pub fn cfl_limit<'a, V: Vector>(
    particles: impl Iterator<Item = (u32, V, Real, Real)> + 'a,
) -> Option<(u32, Real)> {
    let mut best: Option<(u32, Real)> = None;
    for (id, v, h, c) in particles {
        let speed = c + v.length();
        if speed > 0.0 {
            let dt = CFL_LIMIT * h / speed;
            if best.is_none_or(|(bid, b)| dt < b || (dt == b && id < bid)) {
                best = Some((id, dt));
            }
        }
    }
    best
}

/// With a fixed dt, checks after every step (and at initialisation, so a scene is refused
/// before it starts) that dt is within [`CFL_LIMIT`] with each particle's own h, sound
/// speed and velocity. An adaptive dt is within it by construction (its Courant number is
/// validated ≤ `CFL_LIMIT`).
pub fn check_time_step<V: Vector>(
    rule: Res<TimeStepping>,
    mut check: ResMut<TimeStepCheck>,
    q: Query<(
        &ParticleId,
        &Velocity<V>,
        &SmoothingLength,
        Option<&SoundSpeed>,
    )>,
) {
    check.violation = None;
    if let TimeStepping::Fixed(dt) = *rule
        && let Some((id, limit)) = cfl_limit(
            q.iter()
                .map(|(id, v, h, c)| (id.0, v.0, h.0, c.map_or(0.0, |c| c.0))),
        )
        && dt > limit
    {
        check.violation = Some((id, dt, limit));
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
        &mut Kinematics<V>,
    )>,
) {
    let dt = clock.dt;
    for (mut r, mut v, a, mut k) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (&mut *r, &mut *v, a, &mut *k).into_par_iter();
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
    mut q: Query<(&mut Velocity<V>, &Acceleration<V>, &Kinematics<V>)>,
) {
    let half = 0.5 * clock.dt;
    for (mut v, a, k) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (&mut *v, a, k).into_par_iter().with_min_len(MIN_LEN);
        rows.for_each(|(v, a, k)| v.0 = k.v0 + (k.a0 + a.0) * half);
    }
}

/// Predictor for internal energy.
#[inline(never)] // a frame of its own in profiles
pub fn predict_energy(clock: Res<SimClock>, mut q: Query<(&mut InternalEnergy, &mut EnergyRate)>) {
    let dt = clock.dt;
    for (mut e, mut r) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (&mut *e, &mut *r).into_par_iter().with_min_len(MIN_LEN);
        rows.for_each(|(e, r)| {
            r.e0 = e.0;
            r.rate0 = r.rate;
            e.0 += dt * r.rate;
        });
    }
}

/// Corrector for internal energy.
#[inline(never)] // a frame of its own in profiles
pub fn correct_energy(clock: Res<SimClock>, mut q: Query<(&mut InternalEnergy, &EnergyRate)>) {
    let half = 0.5 * clock.dt;
    for (mut e, r) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (&mut *e, r).into_par_iter().with_min_len(MIN_LEN);
        rows.for_each(|(e, r)| e.0 = r.e0 + half * (r.rate0 + r.rate));
    }
}

/// Predictor for density (continuity equation).
#[inline(never)] // a frame of its own in profiles
pub fn predict_density(clock: Res<SimClock>, mut q: Query<(&mut Density, &mut DensityRate)>) {
    let dt = clock.dt;
    for (mut rho, mut r) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (&mut *rho, &mut *r).into_par_iter().with_min_len(MIN_LEN);
        rows.for_each(|(rho, r)| {
            r.rho0 = rho.0;
            r.rate0 = r.rate;
            rho.0 += dt * r.rate;
        });
    }
}

/// Corrector for density (continuity equation).
#[inline(never)] // a frame of its own in profiles
pub fn correct_density(clock: Res<SimClock>, mut q: Query<(&mut Density, &DensityRate)>) {
    let half = 0.5 * clock.dt;
    for (mut rho, r) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (&mut *rho, r).into_par_iter().with_min_len(MIN_LEN);
        rows.for_each(|(rho, r)| rho.0 = r.rho0 + half * (r.rate0 + r.rate));
    }
}

/// Rebuilds the neighbour lists when the skin rule requires it.
#[inline(never)] // a frame of its own in profiles
pub fn update_neighbours<V: Vector>(
    mut nb: ResMut<Neighbours<V>>,
    q: Query<(&Position<V>, &SmoothingLength)>,
) {
    let (pos, h) = single_table(q.contiguous_iter().expect(DENSE)).unwrap_or((&[], &[]));
    nb.update_with(
        pos.len(),
        |i| pos[i].0,
        |p, r| {
            p.extend(pos.iter().map(|x| x.0));
            r.extend(h.iter().map(|x| x.0));
        },
    );
}

/// Advances the clock after a completed step.
pub fn advance_clock(mut clock: ResMut<SimClock>) {
    clock.t += clock.dt;
    clock.step += 1;
}

pub(crate) fn add_core_systems<V: Vector>(sim: &mut Sim<V>) {
    sim.add_system(StepSet::TimeStep, "choose_dt", choose_dt::<V>);
    sim.add_system(
        StepSet::Predict,
        "predict_kinematics",
        predict_kinematics::<V>,
    );
    sim.add_system(
        StepSet::Neighbours,
        "update_neighbours (Verlet skin)",
        update_neighbours::<V>,
    );
    sim.add_system(
        StepSet::Correct,
        "correct_kinematics",
        correct_kinematics::<V>,
    );
    sim.add_system(StepSet::Advance, "advance_clock", advance_clock);
    crate::diagnostics::add_diagnostics_system(sim);
    sim.world.insert_resource(TimeStepCheck::default());
    sim.add_system(
        StepSet::Diagnostics,
        "check_time_step (fixed dt vs CFL)",
        check_time_step::<V>,
    );
}

/// Adds the internal-energy equation once: `InternalEnergy` and `EnergyRate` components on
/// every particle (initial ε from the scene) and their predictor/corrector.
pub fn ensure_energy_equation<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if !sim.enable_feature("energy_equation") {
        return Ok(());
    }
    let eps = sim.world.resource::<InitialInternalEnergy>().0.clone();
    let spec = ColumnSpec::state("internal_energy", "e");
    sim.add_column(spec, move |id| InternalEnergy(eps[id as usize]))?;
    let rate = EnergyRate {
        rate: 0.0,
        e0: 0.0,
        rate0: 0.0,
    };
    sim.add_column(ColumnSpec::restart_only("energy_rate"), move |_| rate)?;
    sim.add_system(StepSet::Predict, "predict_internal_energy", predict_energy);
    sim.add_system(StepSet::Correct, "correct_internal_energy", correct_energy);
    Ok(())
}

/// Adds the integrated density (continuity) once: `DensityRate` and its predictor/corrector.
pub fn ensure_density_integration<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if !sim.enable_feature("density_integration") {
        return Ok(());
    }
    let rate = DensityRate {
        rate: 0.0,
        rho0: 0.0,
        rate0: 0.0,
    };
    sim.add_column(ColumnSpec::restart_only("density_rate"), move |_| rate)?;
    sim.add_system(StepSet::Predict, "predict_density", predict_density);
    sim.add_system(StepSet::Correct, "correct_density", correct_density);
    Ok(())
}
