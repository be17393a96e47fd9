//! 1-D heat conduction between two half-bars, Eq. 7.1 of Ren, Dai, Zhuang & Rabczuk,
//! *Dual-support Smoothed Particle Hydrodynamics* (preprint; RenDSSPH in docs/references.md):
//!
//! `e(x, t) = (e_r + e_l)/2 + (e_r − e_l)/2 · erf((x − x_c) / √(4 α t))`
//!
//! exact for an infinite bar with a step at `x_c` and diffusivity `α`.

/// The erf profile of Eq. 7.1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatStep {
    /// Internal energy left of the step.
    pub e_left: f64,
    /// Internal energy right of the step.
    pub e_right: f64,
    /// Position of the step.
    pub x_c: f64,
    /// Thermal diffusivity α (m²/s).
    pub alpha: f64,
}

impl HeatStep {
    /// `e(x, t)` of Eq. 7.1 (the step itself at `t = 0`).
    pub fn energy(&self, x: f64, t: f64) -> f64 {
        let mean = 0.5 * (self.e_right + self.e_left);
        let half = 0.5 * (self.e_right - self.e_left);
        if t <= 0.0 {
            return mean + half * (x - self.x_c).signum();
        }
        mean + half * libm::erf((x - self.x_c) / (4.0 * self.alpha * t).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_profile_limits_and_centre() {
        let s = HeatStep {
            e_left: 1.0,
            e_right: 2.0,
            x_c: 0.25,
            alpha: 1e-4,
        };
        assert!((s.energy(0.25, 4.0) - 1.5).abs() < 1e-15);
        assert!((s.energy(0.0, 4.0) - 1.0).abs() < 1e-12);
        assert!((s.energy(0.5, 4.0) - 2.0).abs() < 1e-12);
        // erf(1) = 0.8427007929497149: one diffusion length to the right.
        let x = 0.25 + (4.0 * 1e-4 * 4.0f64).sqrt();
        assert!((s.energy(x, 4.0) - (1.5 + 0.5 * 0.842_700_792_949_714_9)).abs() < 1e-14);
    }

    #[test]
    fn profile_solves_the_heat_equation() {
        // ∂e/∂t = α ∂²e/∂x² by central differences at a point inside the front.
        let s = HeatStep {
            e_left: 1.0,
            e_right: 2.0,
            x_c: 0.25,
            alpha: 1e-4,
        };
        let (x, t, dx, dt) = (0.27, 4.0, 1e-4, 1e-4);
        let et = (s.energy(x, t + dt) - s.energy(x, t - dt)) / (2.0 * dt);
        let exx = (s.energy(x + dx, t) - 2.0 * s.energy(x, t) + s.energy(x - dx, t)) / (dx * dx);
        assert!(
            (et - s.alpha * exx).abs() < 1e-5 * et.abs(),
            "{et} vs {}",
            s.alpha * exx
        );
    }
}
