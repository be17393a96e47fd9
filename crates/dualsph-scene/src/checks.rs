//! The value checks every part of a scene uses: a vector of the scene's dimension, a positive
//! number, an ordered box; each problem names the field.

use crate::error::Problem;
use std::cmp::Ordering;

/// The outcome of a check: the first problem found.
pub(crate) type Check = Result<(), Problem>;

/// A vector with exactly `d` finite components.
pub(crate) fn vector(field: &str, v: &[f64], d: usize) -> Check {
    if v.len() != d {
        return Err(Problem::new(
            field,
            format!("expected {d} components for dimension {d}, got {}", v.len()),
        ));
    }
    match v.iter().position(|x| !x.is_finite()) {
        Some(k) => Err(Problem::new(
            field,
            format!("component {k} is not finite ({})", v[k]),
        )),
        None => Ok(()),
    }
}

/// A finite number `> 0`.
pub(crate) fn positive(field: &str, x: f64) -> Check {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(Problem::new(
            field,
            format!("must be a finite number > 0, got {x}"),
        ))
    }
}

/// `max > min` on every axis (both already checked to have `d` components).
pub(crate) fn ordered(field: &str, min: &[f64], max: &[f64]) -> Check {
    match (0..min.len()).find(|&k| max[k].partial_cmp(&min[k]) != Some(Ordering::Greater)) {
        Some(k) => Err(Problem::new(
            field,
            format!(
                "max must exceed min on every axis; on axis {k} max is {} and min is {}",
                max[k], min[k]
            ),
        )),
        None => Ok(()),
    }
}
