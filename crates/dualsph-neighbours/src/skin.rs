//! The Verlet skin chosen by a cost model (the `Tuned` [`SkinRule`]).
//!
//! A list built with skin `s` holds about `k (1 + s)^d` candidates per particle (`k` pairs
//! per particle, `d` the dimension). Each step the sweep pays for every candidate (the
//! compaction that keeps those inside `h_i`, the zeroed reaction slot that pass 2 reads); each
//! build pays for every candidate it finds. With `c` the cost of one candidate in one step and
//! `β c` its cost in one build, and the lists lasting `L(s) = s / u` steps when the fastest
//! particle moves `u h_min / 2` per step (the rebuild rule fires once `2 max|Δr| > s h_min`),
//! the cost per particle-step is
//!
//! ```text
//! g(s) = c k (1 + s)^d (β u / s + 1).
//! ```
//!
//! `d/ds ln g = 0` gives `d s² + (d − 1) β u s − β u = 0` (with `β` in units of `c`), whose
//! positive root [`optimal_skin`] is the skin of the next build, kept inside
//! [[`MIN_SKIN`], [`MAX_SKIN`]]. `u` is measured, not guessed: the largest displacement since the
//! last build divided by the steps it took (both exact, so the choice is the same on any number
//! of threads; and the state never depends on the skin anyway, see the module docs of
//! [`super`]).
//!
//! `β` was measured with callgrind on the dam-break column (`validation/validation/examples/perf.rs`): a build costs
//! ~173 instructions per candidate in 2-D and ~210 in 3-D, a step ~45 (compaction 33, pass 2
//! ~12); [`BUILD_OVER_STEP`] rounds the ratio to 4.
//!
//! A list built with a skin much larger than the flow needs (the first build, from the scene's
//! skin, or after the flow slowed down) would be kept for hundreds of steps; [`retune_now`]
//! rebuilds it early once the measured `u` says that the optimal skin, builds included, costs
//! less per step than the candidates of the current list alone.

use dualsph_math::Real;

/// How the skin of each build is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkinRule {
    /// Always the configured skin.
    Fixed,
    /// The configured skin for the first build, then [`optimal_skin`] of the measured motion.
    Tuned,
}

/// The cost of one candidate in a build over its cost in one step (the module docs' `β`).
pub const BUILD_OVER_STEP: Real = 4.0;
/// The smallest skin the tuner chooses.
pub const MIN_SKIN: Real = 0.02;
/// The largest skin the tuner chooses.
pub const MAX_SKIN: Real = 0.5;
/// Steps a list lives before [`retune_now`] trusts the measured motion.
pub const PROBE_STEPS: u64 = 8;
/// The relative saving per step an early rebuild must promise.
const EARLY_MARGIN: Real = 0.1;

/// `u`: twice the largest displacement since the last build, in units of `h_min`, per step
/// (the rate at which `2 max|Δr| / h_min` approaches the skin).
pub fn motion_rate(max_displacement: Real, h_min: Real, steps: u64) -> Real {
    2.0 * max_displacement / (h_min * steps.max(1) as Real)
}

/// The module docs' cost per particle-step, in units of `c k`: `(1 + s)^d (β u / s + 1)`.
pub fn cost_per_step(s: Real, u: Real, dim: usize) -> Real {
    (1.0 + s).powi(dim as i32) * (BUILD_OVER_STEP * u / s + 1.0)
}

/// The skin that minimises `cost_per_step` for motion rate `u` in `dim` dimensions: the
/// positive root of `d s² + (d − 1) β u s − β u = 0`, written `2βu / (b + √(b² + 4dβu))`
/// with `b = (d − 1)βu` (no cancellation for large `u`, where it tends to `1/(d − 1)`),
/// clamped to [`MIN_SKIN`, `MAX_SKIN`].
pub fn optimal_skin(u: Real, dim: usize) -> Real {
    let d = dim as Real;
    let bu = BUILD_OVER_STEP * u;
    if bu <= 0.0 {
        return MIN_SKIN;
    }
    let b = (d - 1.0) * bu;
    let s = 2.0 * bu / (b + (b * b + 4.0 * d * bu).sqrt());
    if s.is_finite() {
        s.clamp(MIN_SKIN, MAX_SKIN)
    } else {
        MAX_SKIN
    }
}

/// True when a list built with `skin`, alive for `steps` steps during which the fastest
/// particle moved `u` (see [`motion_rate`]), should be rebuilt now with [`optimal_skin`]: the
/// optimum, its builds included, must cost at least [`EARLY_MARGIN`] less per step than the
/// current list's candidates alone (its build is already paid).
pub fn retune_now(skin: Real, u: Real, steps: u64, dim: usize) -> bool {
    if steps < PROBE_STEPS {
        return false;
    }
    let best = optimal_skin(u, dim);
    let keep = (1.0 + skin).powi(dim as i32);
    cost_per_step(best, u, dim) < (1.0 - EARLY_MARGIN) * keep
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cost model's minimum by brute force over a fine grid of skins.
    fn grid_minimum(u: Real, dim: usize) -> Real {
        (0..=100_000)
            .map(|k| MIN_SKIN + (MAX_SKIN - MIN_SKIN) * k as Real / 100_000.0)
            .min_by(|a, b| cost_per_step(*a, u, dim).total_cmp(&cost_per_step(*b, u, dim)))
            .unwrap()
    }

    #[test]
    fn optimal_skin_is_the_minimum_of_the_cost_model() {
        for dim in [1, 2, 3] {
            for u in [1e-4, 1e-3, 3e-3, 1e-2, 3e-2] {
                let (s, grid) = (optimal_skin(u, dim), grid_minimum(u, dim));
                assert!(
                    (s - grid).abs() < 1e-4,
                    "dim {dim} u {u}: {s} vs grid {grid}"
                );
            }
        }
    }

    #[test]
    fn optimal_skin_grows_with_the_motion_and_stays_in_range() {
        let mut last = 0.0;
        for k in 0..40 {
            let u = 1e-7 * 2.0_f64.powi(k);
            let s = optimal_skin(u, 2);
            assert!((MIN_SKIN..=MAX_SKIN).contains(&s));
            assert!(s >= last);
            last = s;
        }
        assert_eq!(optimal_skin(0.0, 3), MIN_SKIN);
        // very fast motion: the root tends to 1/(d − 1)
        assert!((optimal_skin(1e6, 3) - 0.5).abs() < 1e-6);
        assert_eq!(optimal_skin(1e6, 2), MAX_SKIN);
        assert_eq!(optimal_skin(Real::INFINITY, 2), MAX_SKIN);
        assert_eq!(optimal_skin(Real::NAN, 2), MAX_SKIN);
    }

    #[test]
    fn a_list_is_retuned_only_when_the_optimum_is_clearly_cheaper() {
        // slow flow: the optimum is near MIN_SKIN, far cheaper than 0.15's candidates
        assert!(retune_now(0.15, 1e-4, PROBE_STEPS, 2));
        // not before the motion has been watched for PROBE_STEPS steps
        assert!(!retune_now(0.15, 1e-4, PROBE_STEPS - 1, 2));
        // a list already at the optimum is kept
        let u = 1e-3;
        assert!(!retune_now(optimal_skin(u, 2), u, 50, 2));
        // a list thinner than the optimum is kept (its rebuild rule fires soon enough)
        assert!(!retune_now(MIN_SKIN, 1e-2, 50, 3));
    }
}
