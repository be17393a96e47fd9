//! What an inflow prescribes: the speed across its section ([`Profile`]) and its ramp in time
//! ([`ramp_factor`], [`ramp_integral`]).

use super::zone::Zone;
use dualsph_core::math::{Real, Vector};
use serde::{Deserialize, Serialize};

/// The inflow's speed along its direction at a point of its cross-section.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
pub enum Profile {
    /// The same speed `U` (m/s) over the whole section.
    Uniform(Real),
    /// The laminar profile of a channel whose walls are the faces of the buffer's box across
    /// the flow, with peak speed `U` (m/s): `u = U Π_k 4 s_k (1 − s_k)` over the axes k across
    /// the flow that are not periodic, `s_k = (x_k − min_k)/(max_k − min_k)`. In 2-D this is
    /// plane Poiseuille flow, `u = 4U (y/H)(1 − y/H)` (mean speed 2U/3), and so it is in 3-D
    /// between two walls with the third axis periodic; in a 3-D duct it is the product form,
    /// which is not the exact duct solution (that is a series) but vanishes on all four walls.
    Parabolic(Real),
}

impl Profile {
    /// The speed at `x` (not ramped).
    pub fn speed<V: Vector>(&self, zone: &Zone<V>, x: V) -> Real {
        match *self {
            Profile::Uniform(u) => u,
            Profile::Parabolic(peak) => {
                (0..V::DIM)
                    .filter(|&k| k != zone.axis && !zone.periodic[k])
                    .map(|k| {
                        let s = zone.fraction(x, k).clamp(0.0, 1.0);
                        4.0 * s * (1.0 - s)
                    })
                    .product::<Real>()
                    * peak
            }
        }
    }

    /// The largest speed of the profile (for the sound-speed scale and the time step).
    pub fn peak(&self) -> Real {
        match *self {
            Profile::Uniform(u) | Profile::Parabolic(u) => u.abs(),
        }
    }

    /// The message for a speed that is not a finite number, naming the field.
    pub fn check(&self) -> Result<(), String> {
        let u = match *self {
            Profile::Uniform(u) | Profile::Parabolic(u) => u,
        };
        if u.is_finite() {
            Ok(())
        } else {
            Err(format!(
                "profile: the speed must be a finite number, got {u}"
            ))
        }
    }
}

/// The ramp's factor at time t, `f(t) = ½ (1 − cos(π t/T))` for `t < T` and 1 after (a
/// smooth start from rest: `f` and `f'` are continuous at 0 and T); 1 for `T = 0`.
pub fn ramp_factor(ramp: Real, t: Real) -> Real {
    if t >= ramp {
        1.0
    } else {
        0.5 * (1.0 - libm::cos(std::f64::consts::PI * t.max(0.0) / ramp))
    }
}

/// `S(t) = ∫_0^t f(τ) dτ` of [`ramp_factor`]: `½ (t − (T/π) sin(π t/T))` for `t < T`,
/// `T/2 + (t − T)` after. A buffer particle moves by `u (S(t + Δt) − S(t))` over a step, the
/// exact travel of the ramped speed, so the lattice the inflow keeps stays one spacing apart.
pub fn ramp_integral(ramp: Real, t: Real) -> Real {
    use std::f64::consts::PI;
    if t >= ramp {
        0.5 * ramp + (t - ramp)
    } else {
        let t = t.max(0.0);
        0.5 * (t - ramp / PI * libm::sin(PI * t / ramp))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn the_parabola_vanishes_on_the_walls_and_peaks_in_the_middle() {
        let zone = Zone::new(DVec2::new(-0.1, 0.0), DVec2::new(0.0, 2.0), 0, 1.0, true);
        let p = Profile::Parabolic(3.0);
        assert_eq!(p.speed(&zone, DVec2::new(-0.05, 1.0)), 3.0);
        assert_eq!(p.speed(&zone, DVec2::new(-0.05, 0.0)), 0.0);
        assert_eq!(p.speed(&zone, DVec2::new(-0.05, 0.5)), 3.0 * 0.75);
        assert_eq!(Profile::Uniform(2.0).speed(&zone, DVec2::ZERO), 2.0);
        assert!(
            Profile::Parabolic(Real::NAN)
                .check()
                .unwrap_err()
                .starts_with("profile:")
        );
    }

    /// Between two walls with the third axis periodic the profile is plane Poiseuille flow,
    /// uniform along the period.
    #[test]
    fn the_parabola_is_uniform_along_a_periodic_axis() {
        use glam::DVec3;
        let zone = Zone::new(
            DVec3::new(-0.1, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 1.0),
            0,
            1.0,
            true,
        );
        let p = Profile::Parabolic(3.0);
        let at = |z| {
            p.speed(
                &zone.with_periodic([false, false, true]),
                DVec3::new(-0.05, 0.5, z),
            )
        };
        assert_eq!((at(0.0), at(0.3), at(1.0)), (2.25, 2.25, 2.25));
        // a duct: the product vanishes on the faces across z too
        assert_eq!(p.speed(&zone, DVec3::new(-0.05, 0.5, 0.0)), 0.0);
        assert_eq!(p.speed(&zone, DVec3::new(-0.05, 0.5, 0.5)), 2.25);
    }

    #[test]
    fn the_ramp_integral_is_the_integral_of_the_ramp() {
        let ramp = 0.7;
        assert_eq!((ramp_factor(ramp, 0.0), ramp_factor(ramp, 0.7)), (0.0, 1.0));
        assert_eq!(ramp_factor(0.0, 0.0), 1.0);
        assert_eq!(ramp_integral(0.0, 2.0), 2.0);
        // the midpoint rule over fine steps against the closed form
        let n = 20_000;
        let dt = 1.0 / n as Real;
        let sum: Real = (0..n)
            .map(|k| ramp_factor(ramp, (k as Real + 0.5) * dt) * dt)
            .sum();
        assert!((sum - ramp_integral(ramp, 1.0)).abs() < 1e-9, "{sum}");
        assert!((ramp_integral(ramp, ramp) - 0.35).abs() < 1e-15);
    }
}
