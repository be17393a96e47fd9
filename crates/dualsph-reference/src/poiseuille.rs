//! Plane Poiseuille flow started from rest: fluid of kinematic viscosity ν between two plates
//! at `y = 0` and `y = L`, at rest at `t = 0` and driven along x by a body force F. Its
//! velocity is the series solution of Morris, Fox & Zhu (1997), *Modeling low Reynolds number
//! incompressible flows using SPH*, J. Comput. Phys. 136, 214–226, Eq. 21:
//!
//! `v_x(y, t) = F y (L − y) / (2ν)
//!   − Σ_{n≥0} 4 F L² / (ν π³ (2n+1)³) sin(π y (2n+1)/L) exp(−(2n+1)² π² ν t / L²)`,
//!
//! which tends to the parabola `F y (L − y) / (2ν)` (peak `F L²/(8ν)`) as `t → ∞`.

/// The channel: plate distance `L`, kinematic viscosity `ν`, body force per mass `F`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Poiseuille {
    /// `L` (m).
    pub width: f64,
    /// `ν` (m²/s).
    pub nu: f64,
    /// `F` (m/s²).
    pub force: f64,
}

impl Poiseuille {
    /// The steady velocity `F y (L − y) / (2ν)`.
    pub fn steady(&self, y: f64) -> f64 {
        self.force * y * (self.width - y) / (2.0 * self.nu)
    }

    /// The velocity at height `y` and time `t` (module docs). The series is summed until
    /// its terms (bounded by `4 F L²/(ν π³ k³)`, k odd) fall below 1e-15 of the peak
    /// velocity, so it is exact to round-off also at `t = 0`, where it converges slowest.
    pub fn velocity(&self, y: f64, t: f64) -> f64 {
        use std::f64::consts::PI;
        let (l, nu, f) = (self.width, self.nu, self.force);
        let peak = f * l * l / (8.0 * nu);
        let mut v = self.steady(y);
        for n in 0.. {
            let k = (2 * n + 1) as f64;
            let amplitude = 4.0 * f * l * l / (nu * PI.powi(3) * k.powi(3));
            if amplitude < 1e-15 * peak {
                break;
            }
            let decay = libm::exp(-k * k * PI * PI * nu * t / (l * l));
            v -= amplitude * libm::sin(PI * y * k / l) * decay;
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MORRIS: Poiseuille = Poiseuille {
        width: 1e-3,
        nu: 1e-6,
        force: 2e-4,
    };

    /// At rest at the start: the series cancels the parabola (the sine series of
    /// `y (L − y)` on [0, L] is `8 L²/π³ Σ sin(kπy/L)/k³`, k odd).
    #[test]
    fn starts_at_rest() {
        for k in 1..10 {
            let y = k as f64 * 1e-4;
            let v = MORRIS.velocity(y, 0.0);
            assert!(v.abs() < 1e-6 * 2.5e-5, "y = {y}: {v}");
        }
    }

    /// Tends to the parabola, peak `F L²/(8ν)` = 2.5e-5 m/s at mid-channel, and the slowest
    /// mode decays as `exp(−π² ν t/L²)`.
    #[test]
    fn tends_to_the_parabola() {
        let mid = MORRIS.width / 2.0;
        assert!((MORRIS.velocity(mid, 10.0) - 2.5e-5).abs() < 1e-18);
        let gap = |t: f64| MORRIS.steady(mid) - MORRIS.velocity(mid, t);
        let rate = libm::log(gap(0.2) / gap(0.3)) / 0.1;
        let expect = std::f64::consts::PI.powi(2) * MORRIS.nu / MORRIS.width.powi(2);
        assert!((rate - expect).abs() < 1e-6 * expect, "{rate} vs {expect}");
    }
}
