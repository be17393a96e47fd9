//! The non-reflecting outflow (`OutflowBoundary(.., pressure: Some(p), non_reflecting:
//! Some(τ))`): the buffer's pressure follows the acoustic impedance of an open end instead of
//! holding p, so that a pressure wave leaves the domain instead of being reflected.
//!
//! In one dimension the linear acoustics about a mean state (p, ρ, Ū, sound speed c) carry
//! two characteristic amplitudes, `J± = p' ± ρc u'`, along `u ± c` (e.g. Poinsot & Lele 1992,
//! *Boundary conditions for direct simulations of compressible viscous flows*, J. Comput.
//! Phys. 101, 104, §2–3; in SPH, Lastiwka, Basa & Quinlan 2009, §3). At an outflow `J+`
//! leaves the domain and `J−` enters it; a fixed pressure `p' = 0` reflects the leaving wave
//! with `J− = −J+`. Setting the entering amplitude to zero, `J− = p' − ρc u' = 0`, gives the
//! buffer the pressure
//!
//! `p_B = p + ρ c (U − Ū)`,
//!
//! with `U` the mean normal velocity extrapolated into the buffer (over its particles, this
//! step) and `Ū` its running mean over the relaxation time τ, `dŪ/dt = (U − Ū)/τ`
//! (integrated exactly over each step, `Ū ← Ū + (1 − e^{−Δt/τ})(U − Ū)`; Ū starts at the
//! first U). A wave of period well below τ sees the impedance ρc and leaves; slower changes of
//! the flow see the prescribed p, which is the buffer's pressure in a steady state (U = Ū).
//! ρ and c are the fluid's equation of state at p. The velocity stays the extrapolated one.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::math::Real;
use serde::{Deserialize, Serialize};

/// The running means of the non-reflecting outflows, by boundary (none for the others), kept
/// in checkpoints under the key `open_boundaries_impedance`.
#[derive(Resource, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Impedance(pub Vec<Relaxed>);

/// One outflow's running mean.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Relaxed {
    /// `Ū` (m/s), none before the first extrapolation.
    pub mean: Option<Real>,
    /// `U` of the last extrapolation (m/s).
    pub current: Real,
}

impl Relaxed {
    /// The buffer's pressure for the mean normal velocity `u`, prescribed pressure `p` and
    /// impedance `z = ρc`: `p + z (u − Ū)` (module docs); records `u` as the current mean.
    pub fn pressure(&mut self, p: Real, z: Real, u: Real) -> Real {
        self.current = u;
        let mean = *self.mean.get_or_insert(u);
        p + z * (u - mean)
    }

    /// Advances `Ū` over a step `dt` towards the current `U` with relaxation time `tau`.
    pub fn relax(&mut self, dt: Real, tau: Real) {
        if let Some(mean) = &mut self.mean {
            *mean += (1.0 - libm::exp(-dt / tau)) * (self.current - *mean);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pressure_holds_p_in_a_steady_state_and_follows_the_impedance_in_a_wave() {
        let mut r = Relaxed::default();
        // the first U sets the mean: p itself
        assert_eq!(r.pressure(1.0, 3.0, 0.2), 1.0);
        // a fast change of U by 0.01 is carried at the impedance
        assert!((r.pressure(1.0, 3.0, 0.21) - 1.03).abs() < 1e-15);
        // held for 20 τ, the mean follows and the pressure returns to p (to e^{−20} of the step)
        for _ in 0..1000 {
            r.relax(0.01, 0.5);
        }
        assert!((r.pressure(1.0, 3.0, 0.21) - 1.0).abs() < 1e-10);
    }

    #[test]
    fn the_relaxation_over_a_step_is_exact_whatever_the_step() {
        let run = |steps: usize| {
            let mut r = Relaxed {
                mean: Some(0.0),
                current: 1.0,
            };
            for _ in 0..steps {
                r.relax(1.0 / steps as Real, 0.5);
            }
            r.mean.unwrap()
        };
        let exact = 1.0 - libm::exp(-2.0 as Real);
        assert!((run(1) - exact).abs() < 1e-15 && (run(1000) - exact).abs() < 1e-12);
    }
}
