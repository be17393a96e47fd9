//! The pressure on the far wall in a dam break, H = 0.6 m, column 2H wide, tank 5.366H long:
//! sensor P1 of Buchner (2002), *Green water on ship-type offshore structures*, PhD thesis,
//! Delft University of Technology, and the δ-SPH results of Marrone, Antuono, Colagrossi,
//! Colicchio, Le Touzé & Graziani (2011), *δ-SPH model for simulating violent impact flows*,
//! Comput. Methods Appl. Mech. Engrg. 200, 1526–1542, on the same sensor. The data and where
//! they come from: `data/dam_break_pressure/README.md`. Times and pressures are
//! dimensionless, `t* = t √(g/H)`, `p* = p/(ρ g H)`.
//!
//! A simulated sensor is compared by the mean absolute difference `Σ|p*_sim − p*_ref|/n` over
//! the reference points in a window of t*, the simulated signal first averaged over a box of
//! width `w` centred on each point ([`box_mean`]): a sensor has a finite response time, and the
//! simulated signal carries the acoustic noise of a weakly compressible fluid.

const BUCHNER_P1: &str =
    include_str!("../data/dam_break_pressure/buchner2002_H600_P1_exp_via_trixiparticles.csv");
const MARRONE_P1: &str =
    include_str!("../data/dam_break_pressure/marrone2011_H600_P1_sph_via_trixiparticles.csv");

/// The rows of a CSV of numbers after its header.
fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|v| v.trim().parse().expect("the stored data are numbers"))
                .collect()
        })
        .collect()
}

/// Buchner's P1, `(t*, p*)`, t* from 2.03 to 7.30 (98 digitised points).
pub fn buchner_p1() -> Vec<(f64, f64)> {
    rows(BUCHNER_P1).iter().map(|r| (r[0], r[1])).collect()
}

/// Marrone et al.'s δ-SPH P1, t* from 2.00 to 7.32 (525 points): `(t*, p*)` at H/Δx = 40, 80
/// and 320, and the experiment resampled on the same times.
#[derive(Clone, Debug, PartialEq)]
pub struct MarroneP1 {
    /// The experiment (Buchner's P1) at the times below.
    pub experiment: Vec<(f64, f64)>,
    /// H/Δx = 40.
    pub sph_40: Vec<(f64, f64)>,
    /// H/Δx = 80.
    pub sph_80: Vec<(f64, f64)>,
    /// H/Δx = 320.
    pub sph_320: Vec<(f64, f64)>,
}

/// Marrone et al.'s curves (the file's columns: t*, experiment, 40, 320, 80).
pub fn marrone_p1() -> MarroneP1 {
    let r = rows(MARRONE_P1);
    let col = |k: usize| r.iter().map(|row| (row[0], row[k])).collect();
    MarroneP1 {
        experiment: col(1),
        sph_40: col(2),
        sph_320: col(3),
        sph_80: col(4),
    }
}

/// The mean of a sampled signal `(t, p)` over `[t − w/2, t + w/2]`; `None` when no sample
/// falls in it.
pub fn box_mean(signal: &[(f64, f64)], t: f64, w: f64) -> Option<f64> {
    let inside: Vec<f64> = signal
        .iter()
        .filter(|s| (s.0 - t).abs() <= 0.5 * w)
        .map(|s| s.1)
        .collect();
    (!inside.is_empty()).then(|| inside.iter().sum::<f64>() / inside.len() as f64)
}

/// `Σ|model − reference|/n` over the reference points with `t0 ≤ t ≤ t1`, the model taken by
/// `model(t)`; `(mean, n)`, with the points where the model has no value left out.
pub fn mean_abs_difference(
    model: impl Fn(f64) -> Option<f64>,
    reference: &[(f64, f64)],
    (t0, t1): (f64, f64),
) -> (f64, usize) {
    let d: Vec<f64> = reference
        .iter()
        .filter(|p| p.0 >= t0 && p.0 <= t1)
        .filter_map(|&(t, r)| Some((model(t)? - r).abs()))
        .collect();
    (d.iter().sum::<f64>() / d.len() as f64, d.len())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::norms::interpolate;

    /// The tables read whole, with the peaks the data's README states.
    #[test]
    fn the_tables_read_whole() {
        let b = buchner_p1();
        assert_eq!(b.len(), 98);
        let peak = b
            .iter()
            .copied()
            .fold((0.0, 0.0), |m, p| if p.1 > m.1 { p } else { m });
        assert_eq!(peak, (5.83288, 0.87672));
        let m = marrone_p1();
        assert_eq!(m.sph_80.len(), 525);
        // the largest p* over the first impact (t* ≤ 3.03) and over the second (t* ≥ 5.5)
        let max = |s: &[(f64, f64)], (t0, t1): (f64, f64)| {
            s.iter()
                .filter(|p| p.0 >= t0 && p.0 <= t1)
                .fold((0.0, f64::MIN), |m, p| if p.1 > m.1 { *p } else { m })
        };
        let first = (2.0, 3.03);
        assert!((max(&m.sph_40, first).1 - 0.670).abs() < 5e-4);
        assert!((max(&m.sph_320, first).1 - 0.700).abs() < 5e-4);
        let second = (5.5, 7.4);
        assert_eq!(max(&m.sph_40, second), (6.31337, 0.95861));
        assert_eq!(max(&m.sph_320, second), (6.42328, 0.90047));
    }

    /// Marrone et al.'s δ-SPH against the experiment on the first impact, t* in [2.6, 3.03]:
    /// the mean absolute difference falls with resolution (0.094, 0.053, 0.043 at H/Δx = 40,
    /// 80, 320), the figures the wall-pressure comparisons quote.
    #[test]
    fn marrone_converges_to_the_experiment() {
        let m = marrone_p1();
        let err = |s: &[(f64, f64)]| {
            mean_abs_difference(|t| interpolate(s, t), &m.experiment, (2.6, 3.03)).0
        };
        let (e40, e80, e320) = (err(&m.sph_40), err(&m.sph_80), err(&m.sph_320));
        println!("{e40} {e80} {e320}");
        assert!(
            (e40 - 0.094).abs() < 5e-4 && (e80 - 0.053).abs() < 5e-4,
            "{e40} {e80}"
        );
        assert!(e320 < e80 && e80 < e40, "{e40} {e80} {e320}");
    }

    /// Marrone et al.'s δ-SPH by TrixiParticles.jl's measure (their curves averaged over a box
    /// of 0.05 in t*, against the experiment over t* 2–6.5): 0.125, 0.121 and 0.111 at
    /// H/Δx = 40, 80 and 320, the second impact (t* ≥ 5.5) alone 0.092, 0.098 and 0.088 of it.
    #[test]
    fn marrone_by_the_whole_record() {
        let (m, exp) = (marrone_p1(), buchner_p1());
        let score = |s: &[(f64, f64)], t0: f64| {
            let all = mean_abs_difference(|t| box_mean(s, t, 0.05), &exp, (2.0, 6.5));
            let late = mean_abs_difference(|t| box_mean(s, t, 0.05), &exp, (t0, 6.5));
            (all.0, late.0 * late.1 as f64 / all.1 as f64)
        };
        for (s, whole, second) in [
            (&m.sph_40, 0.125, 0.092),
            (&m.sph_80, 0.121, 0.098),
            (&m.sph_320, 0.111, 0.088),
        ] {
            let (a, b) = score(s, 5.5);
            assert!(
                (a - whole).abs() < 5e-4 && (b - second).abs() < 5e-4,
                "{a} {b}"
            );
        }
    }
}
