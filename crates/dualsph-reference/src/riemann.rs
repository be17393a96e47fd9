//! The exact solution of the Riemann problem for the 1-D Euler equations of an ideal gas
//! (`p = (γ − 1) ρ e`), after Toro, *Riemann Solvers and Numerical Methods for Fluid
//! Dynamics*, ch. 4: the star pressure from Newton's method on
//!
//! `f(p) = f_L(p) + f_R(p) + (u_R − u_L) = 0`,
//!
//! with `f_K` the shock (Rankine–Hugoniot) branch for `p > p_K` and the rarefaction
//! (isentropic) branch otherwise; `u* = ½(u_L + u_R) + ½(f_R(p*) − f_L(p*))`. The solution
//! is self-similar in `ξ = (x − x₀)/t` and is sampled wave by wave.

/// A constant gas state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GasState {
    /// Density.
    pub rho: f64,
    /// Velocity.
    pub u: f64,
    /// Pressure.
    pub p: f64,
}

/// A sampled point of the solution, with the specific internal energy `e = p/((γ−1)ρ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Density.
    pub rho: f64,
    /// Velocity.
    pub u: f64,
    /// Pressure.
    pub p: f64,
    /// Specific internal energy.
    pub e: f64,
}

/// Why a Riemann problem has no solution of this kind.
#[derive(Clone, Debug, PartialEq)]
pub enum RiemannError {
    /// A state has non-positive density or pressure, or γ ≤ 1.
    BadState,
    /// The pressure-positivity condition fails: the two rarefactions would create vacuum.
    Vacuum,
}

/// The exact Riemann solution between a left and a right state.
#[derive(Clone, Copy, Debug)]
pub struct Riemann {
    left: GasState,
    right: GasState,
    gamma: f64,
    /// Pressure in the star region.
    pub p_star: f64,
    /// Velocity in the star region (the contact speed).
    pub u_star: f64,
}

impl Riemann {
    /// Sod's shock tube: ρ = 1, p = 1 on the left and ρ = 0.125, p = 0.1 on the right, at rest.
    pub fn sod(gamma: f64) -> Self {
        let left = GasState {
            rho: 1.0,
            u: 0.0,
            p: 1.0,
        };
        let right = GasState {
            rho: 0.125,
            u: 0.0,
            p: 0.1,
        };
        Riemann::new(left, right, gamma).expect("Sod's states are valid for γ > 1")
    }

    /// Solves for the star state.
    pub fn new(left: GasState, right: GasState, gamma: f64) -> Result<Self, RiemannError> {
        let ok = |s: &GasState| s.rho > 0.0 && s.p > 0.0 && s.rho.is_finite() && s.p.is_finite();
        if !(ok(&left) && ok(&right) && gamma > 1.0) {
            return Err(RiemannError::BadState);
        }
        let (cl, cr) = (sound(&left, gamma), sound(&right, gamma));
        if 2.0 / (gamma - 1.0) * (cl + cr) <= right.u - left.u {
            return Err(RiemannError::Vacuum);
        }
        let du = right.u - left.u;
        // Start from the two-rarefaction approximation (Toro 4.46), always positive.
        let z = (gamma - 1.0) / (2.0 * gamma);
        let mut p = libm::pow(
            (cl + cr - 0.5 * (gamma - 1.0) * du)
                / (cl / libm::pow(left.p, z) + cr / libm::pow(right.p, z)),
            1.0 / z,
        )
        .max(1e-12 * left.p.min(right.p));
        for _ in 0..100 {
            let (fl, dfl) = wave_function(p, &left, gamma);
            let (fr, dfr) = wave_function(p, &right, gamma);
            let next = (p - (fl + fr + du) / (dfl + dfr)).max(1e-14 * p);
            let change = 2.0 * (next - p).abs() / (next + p);
            p = next;
            if change < 1e-15 {
                break;
            }
        }
        let u = 0.5 * (left.u + right.u)
            + 0.5 * (wave_function(p, &right, gamma).0 - wave_function(p, &left, gamma).0);
        Ok(Riemann {
            left,
            right,
            gamma,
            p_star: p,
            u_star: u,
        })
    }

    /// The solution at `ξ = (x − x₀)/t`.
    pub fn sample(&self, xi: f64) -> Sample {
        let g = self.gamma;
        let (ps, us) = (self.p_star, self.u_star);
        let gm = (g - 1.0) / (g + 1.0);
        let state = if xi <= us {
            let w = self.left;
            let c = sound(&w, g);
            if ps > w.p {
                let s = w.u - c * ((g + 1.0) / (2.0 * g) * ps / w.p + (g - 1.0) / (2.0 * g)).sqrt();
                if xi <= s {
                    w
                } else {
                    GasState {
                        rho: w.rho * (ps / w.p + gm) / (gm * ps / w.p + 1.0),
                        u: us,
                        p: ps,
                    }
                }
            } else {
                let c_star = c * libm::pow(ps / w.p, (g - 1.0) / (2.0 * g));
                if xi <= w.u - c {
                    w
                } else if xi > us - c_star {
                    GasState {
                        rho: w.rho * libm::pow(ps / w.p, 1.0 / g),
                        u: us,
                        p: ps,
                    }
                } else {
                    let u = 2.0 / (g + 1.0) * (c + 0.5 * (g - 1.0) * w.u + xi);
                    let cf = 2.0 / (g + 1.0) * (c + 0.5 * (g - 1.0) * (w.u - xi));
                    fan(&w, c, u, cf, g)
                }
            }
        } else {
            let w = self.right;
            let c = sound(&w, g);
            if ps > w.p {
                let s = w.u + c * ((g + 1.0) / (2.0 * g) * ps / w.p + (g - 1.0) / (2.0 * g)).sqrt();
                if xi >= s {
                    w
                } else {
                    GasState {
                        rho: w.rho * (ps / w.p + gm) / (gm * ps / w.p + 1.0),
                        u: us,
                        p: ps,
                    }
                }
            } else {
                let c_star = c * libm::pow(ps / w.p, (g - 1.0) / (2.0 * g));
                if xi >= w.u + c {
                    w
                } else if xi <= us + c_star {
                    GasState {
                        rho: w.rho * libm::pow(ps / w.p, 1.0 / g),
                        u: us,
                        p: ps,
                    }
                } else {
                    let u = 2.0 / (g + 1.0) * (-c + 0.5 * (g - 1.0) * w.u + xi);
                    let cf = 2.0 / (g + 1.0) * (c - 0.5 * (g - 1.0) * (w.u - xi));
                    fan(&w, c, u, cf, g)
                }
            }
        };
        Sample {
            rho: state.rho,
            u: state.u,
            p: state.p,
            e: state.p / ((g - 1.0) * state.rho),
        }
    }

    /// The solution at position `x` and time `t > 0` for a membrane initially at `x0`.
    pub fn at(&self, x: f64, t: f64, x0: f64) -> Sample {
        self.sample((x - x0) / t)
    }
}

fn sound(s: &GasState, gamma: f64) -> f64 {
    (gamma * s.p / s.rho).sqrt()
}

/// The state inside a rarefaction fan with local velocity `u` and sound speed `cf`.
fn fan(w: &GasState, c: f64, u: f64, cf: f64, g: f64) -> GasState {
    GasState {
        rho: w.rho * libm::pow(cf / c, 2.0 / (g - 1.0)),
        u,
        p: w.p * libm::pow(cf / c, 2.0 * g / (g - 1.0)),
    }
}

/// `f_K(p)` and its derivative (Toro 4.6–4.7, 4.37).
fn wave_function(p: f64, s: &GasState, g: f64) -> (f64, f64) {
    if p > s.p {
        let a = 2.0 / ((g + 1.0) * s.rho);
        let b = (g - 1.0) / (g + 1.0) * s.p;
        let q = (a / (p + b)).sqrt();
        ((p - s.p) * q, q * (1.0 - 0.5 * (p - s.p) / (b + p)))
    } else {
        let c = sound(s, g);
        let r = p / s.p;
        (
            2.0 * c / (g - 1.0) * (libm::pow(r, (g - 1.0) / (2.0 * g)) - 1.0),
            1.0 / (s.rho * c) * libm::pow(r, -(g + 1.0) / (2.0 * g)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sod_star_state_gamma_five_thirds() {
        // The star state given for the paper's tube (DESIGN.md): p* = 0.293945, u* = 0.841195.
        let r = Riemann::sod(5.0 / 3.0);
        assert!((r.p_star - 0.293945).abs() < 1e-6, "{}", r.p_star);
        assert!((r.u_star - 0.841195).abs() < 1e-6, "{}", r.u_star);
    }

    #[test]
    fn sod_star_state_gamma_seven_fifths() {
        // Toro, Table 4.3 (test 1 is Sod with γ = 1.4): p* = 0.30313, u* = 0.92745.
        let r = Riemann::sod(1.4);
        assert!((r.p_star - 0.30313).abs() < 1e-5, "{}", r.p_star);
        assert!((r.u_star - 0.92745).abs() < 1e-5, "{}", r.u_star);
    }

    #[test]
    fn jump_conditions_hold_across_the_shock() {
        // Rankine–Hugoniot: mass and momentum fluxes are continuous in the shock frame.
        let g = 5.0 / 3.0;
        let r = Riemann::sod(g);
        let right = GasState {
            rho: 0.125,
            u: 0.0,
            p: 0.1,
        };
        let c = sound(&right, g);
        let s = c * ((g + 1.0) / (2.0 * g) * r.p_star / right.p + (g - 1.0) / (2.0 * g)).sqrt();
        let behind = r.sample(s - 1e-9);
        let ahead = r.sample(s + 1e-9);
        let mass = |w: &Sample| w.rho * (w.u - s);
        let mom = |w: &Sample| w.rho * (w.u - s) * (w.u - s) + w.p;
        assert!((mass(&behind) - mass(&ahead)).abs() < 1e-9);
        assert!((mom(&behind) - mom(&ahead)).abs() < 1e-9);
        assert_eq!(ahead.rho, 0.125);
    }

    #[test]
    fn rarefaction_is_isentropic_and_continuous() {
        let g = 5.0 / 3.0;
        let r = Riemann::sod(g);
        let c = (g * 1.0f64 / 1.0).sqrt();
        // p/ρ^γ is constant through the fan, and the head matches the left state.
        for k in 1..10 {
            let xi = -c + k as f64 * 0.1 * (r.u_star - c * 0.3 + c);
            let w = r.sample(xi.min(r.u_star - 1e-9));
            assert!((w.p / libm::pow(w.rho, g) - 1.0).abs() < 1e-12);
        }
        let head = r.sample(-c + 1e-12);
        assert!((head.rho - 1.0).abs() < 1e-9 && head.u.abs() < 1e-9);
        assert_eq!(r.sample(-10.0).p, 1.0);
        assert_eq!(r.sample(10.0).p, 0.1);
        // Pressure and velocity are continuous across the contact.
        let (a, b) = (r.sample(r.u_star - 1e-12), r.sample(r.u_star + 1e-12));
        assert!((a.p - b.p).abs() < 1e-12 && (a.u - b.u).abs() < 1e-12 && a.rho > b.rho);
    }

    #[test]
    fn bad_states_are_refused() {
        let good = GasState {
            rho: 1.0,
            u: 0.0,
            p: 1.0,
        };
        let bad = GasState {
            rho: 0.0,
            u: 0.0,
            p: 1.0,
        };
        assert_eq!(
            Riemann::new(good, bad, 1.4).unwrap_err(),
            RiemannError::BadState
        );
        let left = GasState {
            rho: 1.0,
            u: -20.0,
            p: 1.0,
        };
        let right = GasState {
            rho: 1.0,
            u: 20.0,
            p: 1.0,
        };
        assert_eq!(
            Riemann::new(left, right, 1.4).unwrap_err(),
            RiemannError::Vacuum
        );
    }
}
