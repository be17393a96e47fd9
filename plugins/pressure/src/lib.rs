//! `PressureForce()`: the dual-support pressure force, Eq. 4.19 (pressure part).
//!
//! For `j ∈ H_i`, evaluated once with i's kernel: `f_ij = −m_i m_j (p_i/ρ_i²) ∇_iW_ij` acts on
//! i and `−f_ij` on j (the `H'_j` term of Eq. 4.19). The pair's work `−f_ij·v_ij` goes into i's
//! internal energy: `m_i ε̇_i += m_i m_j (p_i/ρ_i²) v_ij·∇_iW_ij`, the `σ_i`-term of Eq. 4.15,
//! so that `Σ(m v·a + m ε̇) = 0` exactly and `dε_i = (p_i/ρ_i²) dρ_i` with the continuity
//! equation (4.9). (Eq. 4.20 splits this work ½/½ instead; that also balances but is not
//! consistent with `dε = p/ρ² dρ`.) With the kernel correction active, `1/ρ_i²` becomes
//! `1/(ρ_iρ_j)` and `∇_iW_ij` becomes `L_i ∇_iW_ij` (§5.2), which keeps angular momentum exact.

use dualsph_core::integrator::ensure_energy_equation;
use dualsph_core::prelude::*;
use serde::Deserialize;

/// Pressure force.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureForce {}

/// The pair term.
#[derive(Debug, Clone, Copy)]
pub struct PressureTerm;

impl PressureTerm {
    /// The owner's factor of the pair coefficient: `m_i p_i/ρ_i²`, or `m_i p_i/ρ_i` with the
    /// kernel correction (then the neighbour's factor is `m_j/ρ_j`, otherwise `m_j`).
    #[inline(always)]
    fn owner<V: Vector>(f: &Fields<V>, i: usize) -> Real {
        if f.correction.is_empty() {
            f.mass[i] * f.pressure[i] / (f.rho[i] * f.rho[i])
        } else {
            f.mass[i] * f.pressure[i] / f.rho[i]
        }
    }

    /// The neighbour's factor (see [`PressureTerm::owner`]).
    #[inline(always)]
    fn other<V: Vector>(f: &Fields<V>, j: usize) -> Real {
        if f.correction.is_empty() {
            f.mass[j]
        } else {
            f.mass[j] / f.rho[j]
        }
    }

    /// `f_ij = −c ∇̃_iW_ij` on i and `c v_ij·∇̃_iW_ij` to `m_i ε̇_i`, `c = owner · other`.
    #[inline(always)]
    fn add<V: Vector>(coef: Real, vij: V, grad: V, out: &mut PairOut<V>) {
        out.force += grad * (-coef);
        out.power_i += coef * vij.dot(grad);
    }
}

impl<V: Vector> PairTerm<V> for PressureTerm {
    fn name(&self) -> &str {
        "pressure (Eq. 4.19)"
    }

    #[inline(always)]
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        let f = p.fields;
        let coef = Self::owner(f, p.i) * Self::other(f, p.j);
        Self::add(coef, p.vij(), p.grad, out);
    }

    /// The same arithmetic as [`PairTerm::interact`] with the owner's values loaded once.
    fn interact_row(&self, row: &Row<'_, V>, out: &mut [PairOut<V>]) {
        let f = row.fields;
        let (owner, vi) = (Self::owner(f, row.i), f.vel[row.i]);
        let (mass, vel) = (&f.mass[..], &f.vel[..]);
        if f.correction.is_empty() {
            for ((o, &j), &g) in out.iter_mut().zip(row.j).zip(row.grad) {
                let j = j as usize;
                Self::add(owner * mass[j], vi - vel[j], g, o);
            }
        } else {
            for ((o, &j), &g) in out.iter_mut().zip(row.j).zip(row.grad) {
                let j = j as usize;
                Self::add(owner * Self::other(f, j), vi - vel[j], g, o);
            }
        }
    }
}

impl SimPlugin for PressureForce {
    const NAME: &'static str = "PressureForce";
    const SUMMARY: &'static str =
        "dual-support pressure force (Eq. 4.19) with consistent energy (Eq. 4.15)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require_feature(
            "eos",
            "PressureForce needs an equation of state (TaitEos or IdealGas)",
        );
        ensure_energy_equation(sim);
        sim.add_pair_term(PressureTerm);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::glam::DVec2;
    use dualsph_core::neighbours::Neighbours;
    use dualsph_core::sweep::check_row_matches_interact;

    /// A jittered lattice with varying h, velocities, densities and pressures (a small LCG).
    fn state() -> (Fields<DVec2>, Neighbours<DVec2>) {
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as Real / (1u64 << 53) as Real
        };
        let mut f = Fields::<DVec2>::default();
        let n = 20 * 20;
        f.resize(n);
        f.pressure = vec![0.0; n];
        f.sound = vec![0.0; n];
        for i in 0..n {
            f.pos[i] =
                DVec2::new((i % 20) as Real, (i / 20) as Real) + DVec2::new(rnd(), rnd()) * 0.4;
            f.vel[i] = DVec2::new(rnd() - 0.5, rnd() - 0.5);
            f.mass[i] = 0.8 + 0.4 * rnd();
            f.rho[i] = 950.0 + 100.0 * rnd();
            f.h[i] = 1.2 + 1.5 * rnd();
            f.pressure[i] = rnd() * 1e3 - 200.0;
            f.sound[i] = 10.0 + rnd();
        }
        let mut nb = Neighbours::new(0.1);
        nb.rebuild(&f.pos, &f.h);
        (f, nb)
    }

    #[test]
    fn interact_row_matches_interact_bitwise() {
        let (mut f, nb) = state();
        let kernel = Kernel::new(KernelKind::CubicSpline, 2);
        for corrected in [false, true] {
            if corrected {
                let n = f.len();
                f.correction = (0..n)
                    .map(|i| {
                        let a = 1.0 + 0.01 * (i % 7) as Real;
                        dualsph_core::glam::DMat2::from_cols_array(&[a, 0.02, -0.01, 1.0 / a])
                    })
                    .collect();
            }
            let ctx = SweepCtx {
                fields: &f,
                neighbours: &nb,
                kernel: &kernel,
                formulation: Formulation::DualSupport,
            };
            for term in TERMS {
                check_row_matches_interact::<DVec2>(term, &ctx).unwrap();
            }
        }
    }

    const TERMS: [&dyn PairTerm<DVec2>; 1] = [&PressureTerm];
}
