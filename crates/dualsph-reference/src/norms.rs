//! Error norms and interpolation shared by the benchmark reports.

/// Linear interpolation in a table sorted by its first component; `None` outside it.
pub fn interpolate(table: &[(f64, f64)], x: f64) -> Option<f64> {
    let k = table.partition_point(|p| p.0 < x);
    if k == 0 {
        return (table.first()?.0 == x).then(|| table[0].1);
    }
    let (x1, y1) = *table.get(k)?;
    let (x0, y0) = table[k - 1];
    if x1 == x0 {
        return Some(y1);
    }
    Some(y0 + (y1 - y0) * (x - x0) / (x1 - x0))
}

/// Root-mean-square of `model(t) − reference` over the reference points whose time lies in
/// `[t_min, t_max]` and inside the model's table. Returns `(rms, points used)`.
pub fn rms_against(model: &[(f64, f64)], reference: &[(f64, f64)], t_max: f64) -> (f64, usize) {
    let diffs: Vec<f64> = reference
        .iter()
        .filter(|p| p.0 <= t_max)
        .filter_map(|&(t, r)| interpolate(model, t).map(|m| m - r))
        .collect();
    if diffs.is_empty() {
        return (f64::NAN, 0);
    }
    let ms = diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64;
    (ms.sqrt(), diffs.len())
}

/// The discrete relative L2 error of Eq. 7.2, `‖u − u_ref‖ / ‖u_ref‖` with
/// `‖u‖² = Σ_i u_i² V_i` (the integral `∫ u² dx` by the particles' volumes `V_i`).
pub fn relative_l2(values: &[f64], reference: &[f64], volumes: &[f64]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for ((u, r), v) in values.iter().zip(reference).zip(volumes) {
        num += (u - r) * (u - r) * v;
        den += r * r * v;
    }
    (num / den).sqrt()
}

/// The L1 error over a region, `∫|u − u_ref| dx / ∫dx ≈ Σ_i |u_i − u_ref(x_i)| V_i / Σ_i V_i`
/// with the particles' volumes `V_i`, so that finely and coarsely resolved parts of the region
/// count by their length, not by their particle count.
pub fn l1_error(values: &[f64], reference: &[f64], volumes: &[f64]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for ((u, r), v) in values.iter().zip(reference).zip(volumes) {
        num += (u - r).abs() * v;
        den += v;
    }
    if den > 0.0 { num / den } else { f64::NAN }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_and_rms() {
        let model = [(0.0, 0.0), (1.0, 2.0), (2.0, 2.0)];
        assert_eq!(interpolate(&model, 0.5), Some(1.0));
        assert_eq!(interpolate(&model, 0.0), Some(0.0));
        assert_eq!(interpolate(&model, 2.5), None);
        assert_eq!(interpolate(&model, -0.1), None);
        let reference = [(0.5, 1.5), (1.5, 1.0), (1.9, 2.0)];
        let (rms, n) = rms_against(&model, &reference, 1.6);
        assert_eq!(n, 2);
        assert!((rms - ((0.25 + 1.0) / 2.0f64).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn l2_and_l1() {
        assert!(
            (relative_l2(&[1.1, 2.0], &[1.0, 2.0], &[1.0, 1.0]) - (0.01f64 / 5.0).sqrt()).abs()
                < 1e-15
        );
        assert!((l1_error(&[1.0, 3.0], &[2.0, 2.0], &[1.0, 1.0]) - 1.0).abs() < 1e-15);
        // A coarse particle counts by its length: 3 × the weight of a fine one.
        assert!((l1_error(&[1.0, 2.0], &[1.0, 1.0], &[1.0, 3.0]) - 0.75).abs() < 1e-15);
        assert!(l1_error(&[], &[], &[]).is_nan());
    }
}
