//! The rigid laws of time a prescribed body follows, in the 3-D embedding of the scene's
//! vectors (a 2-D scene's particles have `z = 0`).

use crate::Prescribed;
use dualsph_core::bodies::BodyMotion;
use dualsph_core::math::Real;

/// A rigid motion given as a function of time `t` (from the start of the run), for a particle
/// that starts at `x_0`: its position `x(t)` and velocity `v(t) = dx/dt`. Vectors have the
/// scene's dimension in their first components (the rest is ignored).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// `x(t) = x_0 + u t`, `v = u`.
    Translate {
        /// `u`.
        velocity: [Real; 3],
    },
    /// `x(t) = x_0 + A (sin(ωt + φ) − sin φ)`, `v(t) = A ω cos(ωt + φ)`, with `ω = 2π f`.
    Oscillate {
        /// `A`.
        amplitude: [Real; 3],
        /// `f` (Hz).
        frequency: Real,
        /// `φ` (rad).
        phase: Real,
    },
    /// A surface that moves along itself at `u` (a belt, the lid of a cavity): `x(t) = x_0`,
    /// `v = u`. The particles stay where they are and carry the velocity into the fluid's
    /// equations; it stands for a wall that the motion maps onto itself (a plane wall moved
    /// along its plane), longer than the run would carry it.
    Slide {
        /// `u`.
        velocity: [Real; 3],
    },
    /// A rotation at the constant rate `Ω` about the axis through `c` along the unit vector
    /// `n` (the z axis in 2-D): `x(t) = c + R(Ωt)(x_0 − c)` with Rodrigues' rotation
    /// `R(θ)y = y cos θ + (n × y) sin θ + n (n·y)(1 − cos θ)`, and `v = Ω n × (x − c)`.
    Rotate {
        /// `c`.
        center: [Real; 3],
        /// `n`, a unit vector (`[0, 0, 1]` in 2-D).
        axis: [Real; 3],
        /// `Ω` (rad/s, counter-clockwise about `n`).
        omega: Real,
    },
}

/// `a + b`, componentwise.
fn add(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    std::array::from_fn(|k| a[k] + b[k])
}

/// `a s`.
fn scale(a: [Real; 3], s: Real) -> [Real; 3] {
    a.map(|x| x * s)
}

/// `a × b`.
fn cross(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl BodyMotion for Law {
    fn at(&self, x0: [Real; 3], t: Real) -> ([Real; 3], [Real; 3]) {
        match *self {
            Law::Translate { velocity } => (add(x0, scale(velocity, t)), velocity),
            Law::Slide { velocity } => (x0, velocity),
            Law::Oscillate {
                amplitude,
                frequency,
                phase,
            } => {
                let w = 2.0 * std::f64::consts::PI * frequency;
                let arg = w * t + phase;
                let x = add(x0, scale(amplitude, libm::sin(arg) - libm::sin(phase)));
                (x, scale(amplitude, w * libm::cos(arg)))
            }
            Law::Rotate {
                center: c,
                axis: n,
                omega,
            } => {
                let (y, th) = (std::array::from_fn(|k| x0[k] - c[k]), omega * t);
                let ny = n[0] * y[0] + n[1] * y[1] + n[2] * y[2];
                let nxy = cross(n, y);
                let (s, co) = libm::sincos(th);
                let r: [Real; 3] =
                    std::array::from_fn(|k| y[k] * co + nxy[k] * s + n[k] * ny * (1.0 - co));
                (add(c, r), scale(cross(n, r), omega))
            }
        }
    }

    /// Zero for a translation or a slide, `−A ω² sin(ωt + φ)` for an oscillation, `Ω n × v`
    /// (centripetal) for a rotation.
    fn acceleration(&self, x0: [Real; 3], t: Real) -> [Real; 3] {
        match *self {
            Law::Translate { .. } | Law::Slide { .. } => [0.0; 3],
            Law::Oscillate {
                amplitude,
                frequency,
                phase,
            } => {
                let w = 2.0 * std::f64::consts::PI * frequency;
                scale(amplitude, -w * w * libm::sin(w * t + phase))
            }
            Law::Rotate { axis, omega, .. } => scale(cross(axis, self.at(x0, t).1), omega),
        }
    }
}

/// Pads a vector of the scene to 3 components with zeros.
fn padded(v: &[f64]) -> [Real; 3] {
    std::array::from_fn(|k| v.get(k).copied().unwrap_or(0.0))
}

impl From<&Prescribed> for Law {
    /// The law of checked settings ([`Prescribed`]'s `validate`): vectors padded to 3
    /// components, a 2-D rotation about the z axis, a 3-D rotation's axis normalised.
    fn from(p: &Prescribed) -> Law {
        match p {
            Prescribed::Translate { velocity } => Law::Translate {
                velocity: padded(velocity),
            },
            Prescribed::Slide { velocity } => Law::Slide {
                velocity: padded(velocity),
            },
            Prescribed::Oscillate {
                amplitude,
                frequency,
                phase,
            } => Law::Oscillate {
                amplitude: padded(amplitude),
                frequency: *frequency,
                phase: *phase,
            },
            Prescribed::Rotate {
                center,
                axis,
                omega,
            } => {
                let n = axis.as_deref().map_or([0.0, 0.0, 1.0], padded);
                let len = n.iter().map(|x| x * x).sum::<Real>().sqrt();
                Law::Rotate {
                    center: padded(center),
                    axis: if len > 0.0 { n.map(|x| x / len) } else { n },
                    omega: *omega,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::bodies::{motion_acceleration, motion_at};
    use glam::{DVec2, DVec3};
    use std::f64::consts::PI;

    fn close(a: Real, b: Real) -> bool {
        (a - b).abs() <= 1e-14 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn a_translation_moves_at_its_velocity() {
        let m = Law::Translate {
            velocity: [0.5, -2.0, 0.0],
        };
        let (x, v) = motion_at(&m, DVec2::new(1.0, 1.0), 0.4);
        assert!(close(x.x, 1.2) && close(x.y, 0.2), "{x}");
        assert_eq!(v, DVec2::new(0.5, -2.0));
    }

    /// Starts at x0 with v(0) = Aω cos φ, and v is dx/dt (central difference, step 1e-6 s).
    #[test]
    fn an_oscillation_starts_at_its_anchor_with_the_derivative_as_velocity() {
        let m = Law::Oscillate {
            amplitude: [0.1, 0.0, 0.0],
            frequency: 2.0,
            phase: 0.3,
        };
        let x0 = DVec2::new(1.0, 0.5);
        let (x, v) = motion_at(&m, x0, 0.0);
        assert_eq!(x, x0);
        assert!(close(v.x, 0.1 * 4.0 * PI * libm::cos(0.3f64)));
        let (t, e) = (0.37, 1e-6);
        let dx = (motion_at(&m, x0, t + e).0 - motion_at(&m, x0, t - e).0) / (2.0 * e);
        let v = motion_at(&m, x0, t).1;
        assert!((dx.x - v.x).abs() < 1e-8 * v.x.abs(), "{dx} vs {v}");
        assert_eq!(dx.y, 0.0);
    }

    /// A quarter turn about c takes c + (1, 0) to c + (0, 1) with speed Ω|x − c| along −x.
    #[test]
    fn a_rotation_in_2d_turns_about_its_center() {
        let m = Law::Rotate {
            center: [2.0, 1.0, 0.0],
            axis: [0.0, 0.0, 1.0],
            omega: 3.0,
        };
        let (x, v) = motion_at(&m, DVec2::new(3.0, 1.0), PI / 6.0);
        assert!(close(x.x, 2.0) && close(x.y, 2.0), "{x}");
        assert!(
            v.x.abs() > 0.0 && close(v.x, -3.0) && v.y.abs() < 1e-14,
            "{v}"
        );
    }

    /// About the x axis: y → z after a quarter turn, x unchanged.
    #[test]
    fn a_rotation_in_3d_turns_about_its_axis() {
        let m = Law::Rotate {
            center: [0.0; 3],
            axis: [1.0, 0.0, 0.0],
            omega: 1.0,
        };
        let (x, _) = motion_at(&m, DVec3::new(0.7, 1.0, 0.0), PI / 2.0);
        assert!(
            close(x.x, 0.7) && x.y.abs() < 1e-15 && close(x.z, 1.0),
            "{x}"
        );
    }

    /// The acceleration is dv/dt (central difference, step 1e-6 s) for each law.
    #[test]
    fn the_acceleration_is_the_derivative_of_the_velocity() {
        let laws = [
            Law::Translate {
                velocity: [0.5, -2.0, 0.0],
            },
            Law::Oscillate {
                amplitude: [0.1, -0.2, 0.0],
                frequency: 2.0,
                phase: 0.3,
            },
            Law::Rotate {
                center: [2.0, 1.0, 0.0],
                axis: [0.0, 0.0, 1.0],
                omega: 3.0,
            },
        ];
        let (x0, t, e) = (DVec2::new(3.0, 1.5), 0.37, 1e-6);
        for m in laws {
            let dv = (motion_at(&m, x0, t + e).1 - motion_at(&m, x0, t - e).1) / (2.0 * e);
            let a = motion_acceleration(&m, x0, t);
            assert!(
                (dv - a).length() < 1e-7 * (1.0 + a.length()),
                "{m:?}: {dv} vs {a}"
            );
        }
    }
}
