//! h from the particle distribution: enlarge `h_i` until its support is populated in every
//! direction (`SmoothingLengthUpdate(isotropy: (min: I, max_growth: G))`).
//!
//! Eq. 6.1 sizes h from the density alone, `h_i = n (m_i/ρ_i)^{1/d}`, i.e. from the *mean*
//! spacing. Under a strong affine deformation (the stretched drop: x-spacing 0.4Δx, y-spacing
//! 2.5Δx at b ≈ 2.4) the mean spacing is fine but the support holds hardly a neighbour in the
//! stretched direction, so the kernel-correction matrix of Eq. 2.10 turns ill-conditioned
//! there and `L_i` amplifies noise. The measure used here is the isotropy of the
//! kernel-weighted second moment of i's support,
//!
//! `S_i(h) = Σ_{j: r_ij < h} V_j W(r_ij, h) r_ij ⊗ r_ij`,  `I_i(h) = det S_i / (tr S_i / d)^d`,
//!
//! which is 1 for a support populated alike in every direction (a disk, a square lattice; in
//! the continuum also a half-disk, but on a lattice the outermost row of a free surface lowers
//! it to 0.95 at h = 2.6Δx, and a 90° corner has `S_xy ≠ 0`, 0.92) and tends to 0 when the
//! support degenerates to a line (in 2-D, `I = 4r/(1+r)²` with r the ratio of
//! the smallest to the largest eigenvalue). `h_i` is raised in steps of 5 % from its Eq. 6.1
//! value until `I_i(h) ≥ I_min`, at most to `G` times that value. DS-SPH conserves linear and
//! angular momentum exactly for any h field (§5, the dual-support sweep applies each pair
//! force and its reaction; §5.2 with the correction `L_i`), so this costs no conservation.
use dualsph_core::math::{Matrix, Real, Vector};
use dualsph_core::neighbours::{
    NeighbourIndex, Period, periodic_radius_csr, radius_csr, separation,
};
use dualsph_core::prelude::Kernel;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Settings of the isotropy enlargement (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Isotropy {
    /// Smallest admissible `I_i = det S_i / (tr S_i / d)^d` (dimensionless), in (0, 1).
    pub min: Real,
    /// Largest factor by which `h_i` may exceed its Eq. 6.1 value (dimensionless, ≥ 1).
    pub max_growth: Real,
}

/// Growth factor of one search step.
const STEP: Real = 1.05;

impl Isotropy {
    /// Refuses values outside their ranges (a message naming the field).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.min.is_finite() && self.min > 0.0 && self.min < 1.0) {
            return Err(format!(
                "isotropy.min: must lie strictly between 0 and 1, got {}",
                self.min
            ));
        }
        if !(self.max_growth.is_finite() && self.max_growth >= 1.0) {
            return Err(format!(
                "isotropy.max_growth: must be at least 1, got {}",
                self.max_growth
            ));
        }
        Ok(())
    }

    /// The enlarged h of every particle: for each i the smallest `h = h_i · 1.05^k ≤ G h_i`
    /// with `I_i(h) ≥ min` (or `G h_i` when none is), from positions `pos`, volumes
    /// `vol = m/ρ` and the Eq. 6.1 values `h`. Each particle's search reads only the inputs,
    /// so the result does not depend on the order of the particles or the thread count. On a
    /// periodic domain (`period`) the neighbours are found, and separated, across the period.
    pub fn enlarge<V: Vector>(
        &self,
        kernel: &Kernel,
        h: &[Real],
        (pos, period): (&[V], Option<&Period<V>>),
        vol: &[Real],
    ) -> Vec<Real> {
        let radii: Vec<Real> = h.iter().map(|&hi| hi * self.max_growth).collect();
        let (cand, _) = match period {
            Some(p) => periodic_radius_csr(pos, &radii, NeighbourIndex::Auto, p),
            None => radius_csr(pos, &radii, NeighbourIndex::Auto),
        };
        (0..h.len())
            .into_par_iter()
            .map(|i| {
                let row = cand.row(i);
                let h_cap = radii[i];
                let mut hi = h[i];
                loop {
                    if hi >= h_cap
                        || isotropy(kernel, hi, pos[i], row, (pos, period), vol) >= self.min
                    {
                        return hi.min(h_cap);
                    }
                    hi *= STEP;
                }
            })
            .collect()
    }
}

/// `I = det S / (tr S / d)^d` of `S = Σ_j V_j W(r_ij, h) r_ij ⊗ r_ij` over the `j` in `row`
/// with `r_ij < h` (the minimum image across a `period`); 0 for an empty support.
pub fn isotropy<V: Vector>(
    kernel: &Kernel,
    h: Real,
    xi: V,
    row: &[u32],
    (pos, period): (&[V], Option<&Period<V>>),
    vol: &[Real],
) -> Real {
    let mut s = V::Mat::zero();
    for &j in row {
        let j = j as usize;
        let rij = separation(period, xi, pos[j]);
        let r = rij.length();
        if r < h {
            s += V::outer(rij, rij) * (vol[j] * kernel.w(r, h));
        }
    }
    let mean = s.trace() / V::DIM as Real;
    if mean <= 0.0 {
        return 0.0;
    }
    s.determinant() / mean.powi(V::DIM as i32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::glam::DVec2;
    use dualsph_core::prelude::KernelKind;

    fn lattice(sx: Real, sy: Real, n: i32) -> Vec<DVec2> {
        let mut p = Vec::new();
        for a in -n..=n {
            for b in -n..=n {
                p.push(DVec2::new(a as Real * sx, b as Real * sy));
            }
        }
        p
    }

    #[test]
    fn square_lattice_is_isotropic_and_a_sheared_one_is_not() {
        let k = Kernel::new(KernelKind::CubicSpline, 2);
        let sq = lattice(0.1, 0.1, 8);
        let all: Vec<u32> = (0..sq.len() as u32).collect();
        let vol = vec![0.01; sq.len()];
        let c = sq.len() / 2; // the centre (0, 0)
        let i_sq = isotropy(&k, 0.26, sq[c], &all, (&sq, None), &vol);
        assert!((i_sq - 1.0).abs() < 1e-12, "{i_sq}");
        // a half-plane support (free surface): isotropic in the continuum, but the lattice's
        // outermost row adds to S_xx only: I = 0.9522 at h = 2.6Δx (an independent
        // evaluation of the same sum, in Python); a 90° corner has S_xy ≠ 0, I = 0.9243
        let upper: Vec<u32> = all
            .iter()
            .copied()
            .filter(|&j| sq[j as usize].y >= 0.0)
            .collect();
        let i_half = isotropy(&k, 0.26, sq[c], &upper, (&sq, None), &vol);
        assert!((i_half - 0.9522).abs() < 1e-4, "{i_half}");
        let corner: Vec<u32> = upper
            .iter()
            .copied()
            .filter(|&j| sq[j as usize].x >= 0.0)
            .collect();
        let i_corner = isotropy(&k, 0.26, sq[c], &corner, (&sq, None), &vol);
        assert!((i_corner - 0.9243).abs() < 1e-4, "{i_corner}");
        // spacing 0.04 × 0.25 at h = 0.26: rows at ±0.25 carry W(0.96 h) ≈ 0
        let sh = lattice(0.04, 0.25, 12);
        let all: Vec<u32> = (0..sh.len() as u32).collect();
        let vol = vec![0.01; sh.len()];
        let i_sh = isotropy(&k, 0.26, sh[sh.len() / 2], &all, (&sh, None), &vol);
        assert!(i_sh < 0.05, "{i_sh}");
    }

    #[test]
    fn enlargement_leaves_a_square_lattice_and_raises_a_sheared_one_just_to_the_bound() {
        let k = Kernel::new(KernelKind::CubicSpline, 2);
        let iso = Isotropy {
            min: 0.8,
            max_growth: 4.0,
        };
        let sq = lattice(0.1, 0.1, 6);
        let h = vec![0.26; sq.len()];
        let vol = vec![0.01; sq.len()];
        let c = sq.len() / 2;
        assert_eq!(iso.enlarge(&k, &h, (&sq, None), &vol)[c], 0.26);
        let sh = lattice(0.04, 0.25, 14);
        let h = vec![0.26; sh.len()];
        let vol = vec![0.01; sh.len()];
        let out = iso.enlarge(&k, &h, (&sh, None), &vol);
        let c = sh.len() / 2;
        // the result satisfies the bound, one step less does not, and stays within the cap
        assert!(out[c] > 0.26 && out[c] <= 0.26 * 4.0, "{}", out[c]);
        let all: Vec<u32> = (0..sh.len() as u32).filter(|&j| j as usize != c).collect();
        assert!(isotropy(&k, out[c], sh[c], &all, (&sh, None), &vol) >= 0.8);
        assert!(isotropy(&k, out[c] / STEP, sh[c], &all, (&sh, None), &vol) < 0.8);
    }

    #[test]
    fn bad_settings_are_refused_with_the_field_named() {
        let bad = |min, max_growth| Isotropy { min, max_growth }.validate().unwrap_err();
        assert!(bad(0.0, 2.0).contains("isotropy.min"));
        assert!(bad(1.0, 2.0).contains("isotropy.min"));
        assert!(bad(Real::NAN, 2.0).contains("isotropy.min"));
        assert!(bad(0.5, 0.9).contains("isotropy.max_growth"));
        assert!(bad(0.5, Real::INFINITY).contains("isotropy.max_growth"));
        assert!(
            Isotropy {
                min: 0.5,
                max_growth: 1.0
            }
            .validate()
            .is_ok()
        );
    }
}
