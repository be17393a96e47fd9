//! The time-step rule, installed by every scheme of this crate: dt fixed or chosen from each
//! particle's own h, and a fixed dt checked against the acoustic limit.
//!
//! It lives with the schemes because a stable dt is a property of the scheme: the limits
//! below are those of the explicit second-order leapfrog family (both schemes here), where
//! the sound-wave mode grows above a Courant number of order one. A scheme with another
//! stability region installs its own rule instead. The rule's settings (the scene's
//! `integrator` section, [`IntegratorSettings`](crate::IntegratorSettings)) are the core's
//! [`TimeStepping`] resource, and the largest viscosity the
//! viscous limit needs is the core's [`MaxViscosity`], which viscosity plugins raise.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::chunks::{DENSE, MIN_LEN};
use dualsph_core::sim::{MaxViscosity, StepFailure};
use dualsph_fluid::prelude::*;
use rayon::prelude::*;

/// The limit of one particle, `min(C_cfl h/(c + |v|), C_f √(h/|a|), C_v ρ h²/μ)`: the
/// acoustic (CFL), force and viscous criteria with the particle's own support radius h,
/// speed |v|, acceleration |a|, density ρ and sound speed c (a criterion whose denominator is
/// 0 gives no limit).
#[inline(always)]
fn limit(coefficients: (Real, Real, Real), visc: Real, s: (Real, Real, Real, Real, Real)) -> Real {
    let (courant, force, viscous) = coefficients;
    let (speed, acc, h, rho, c) = s;
    let mut dt = Real::INFINITY;
    let signal = c + speed;
    if signal > 0.0 {
        dt = dt.min(courant * h / signal);
    }
    if acc > 0.0 {
        dt = dt.min(force * (h / acc).sqrt());
    }
    if visc > 0.0 {
        dt = dt.min(viscous * rho * h * h / visc);
    }
    dt
}

/// Chooses dt for this step: fixed, or the smallest over the particles of
/// `min(C_cfl h/(c + |v|), C_f √(h/|a|), C_v ρ h²/μ)` (the acoustic, force and viscous
/// criteria, each with the particle's own support radius h) capped by `max_dt`; shortened to
/// land on the end time.
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
            let (k, visc) = ((courant, force, viscous), visc.0);
            let one = |v: V, a: V, h: Real, rho: Real, c: Real| {
                limit(k, visc, (v.length(), a.length(), h, rho, c))
            };
            let mut dt = max_dt;
            // a minimum: exact and independent of the order, so of the thread count
            for (v, a, h, rho, c) in q.contiguous_iter().expect(DENSE) {
                let inf = || Real::INFINITY;
                let chunk = match c {
                    Some(c) => (v, a, h, rho, c)
                        .into_par_iter()
                        .with_min_len(MIN_LEN)
                        .map(|(v, a, h, rho, c)| one(v.0, a.0, h.0, rho.0, c.0))
                        .reduce(inf, Real::min),
                    None => (v, a, h, rho)
                        .into_par_iter()
                        .with_min_len(MIN_LEN)
                        .map(|(v, a, h, rho)| one(v.0, a.0, h.0, rho.0, 0.0))
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
    mut failure: ResMut<StepFailure>,
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
        failure.fail(|| {
            format!(
                "the fixed dt = {dt:.3e} is above the CFL limit {limit:.3e} = {CFL_LIMIT} h/(c + |v|) \
                 of particle {id} (likely cause: dt above the CFL limit; lower dt or use Adaptive)"
            )
        });
    }
}

/// Adds [`choose_dt`] (first in the step) and [`check_time_step`] (with the diagnostics).
pub fn add_time_step_systems<V: Vector>(sim: &mut Sim<V>) {
    sim.add_system(StepSet::TimeStep, "choose_dt", choose_dt::<V>);
    sim.world.insert_resource(TimeStepCheck::default());
    sim.add_system(
        StepSet::Diagnostics,
        "check_time_step (fixed dt vs CFL)",
        check_time_step::<V>,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_limit_is_the_smallest_criterion_and_infinite_without_any() {
        let k = (0.1, 0.25, 0.125);
        // CFL: 0.1 · 0.02 / (10 + 0) = 2e-4
        assert_eq!(
            limit(k, 0.0, (0.0, 0.0, 0.02, 1000.0, 10.0)),
            0.1 * 0.02 / 10.0
        );
        // force: 0.25 √(0.02 / 100) = 3.54e-3 > CFL with c = 1 (2e-3)? no: 2e-3 < 3.54e-3
        let with_force = limit(k, 0.0, (0.0, 100.0, 0.02, 1000.0, 1.0));
        assert_eq!(with_force, 0.1 * 0.02 / 1.0);
        let force_only = limit(k, 0.0, (0.0, 100.0, 0.02, 1000.0, 0.0));
        assert_eq!(force_only, 0.25 * (0.02f64 / 100.0).sqrt());
        // viscous: 0.125 · 1000 · 0.02² / 1e3 = 5e-5
        let viscous = limit(k, 1e3, (0.0, 100.0, 0.02, 1000.0, 0.0));
        assert_eq!(viscous, 0.125 * 1000.0 * 0.02 * 0.02 / 1e3);
        assert_eq!(limit(k, 0.0, (0.0, 0.0, 0.02, 1000.0, 0.0)), Real::INFINITY);
    }

    #[test]
    fn the_cfl_limit_is_set_by_the_slowest_particle_lowest_id_on_ties() {
        use glam::DVec2;
        let p = |id, v: f64, h, c| (id, DVec2::new(v, 0.0), h, c);
        let found = cfl_limit(
            [
                p(3, 1.0, 0.1, 9.0),
                p(1, 0.0, 0.05, 5.0),
                p(0, 0.0, 0.05, 5.0),
            ]
            .into_iter(),
        );
        assert_eq!(found, Some((0, CFL_LIMIT * 0.05 / 5.0)));
        assert_eq!(cfl_limit([p(0, 0.0, 0.1, 0.0)].into_iter()), None);
    }
}
