//! A quantity's per-particle values in a [`ParticleTable`], named as the probes name them
//! ([`dualsph_probes::quantity`]): a scalar column (`density`), a component of a vector or
//! matrix column (`velocity.x`, `velocity_gradient.xy`), `speed` or `shepard_sum`.

use super::GridError;
use dualsph_io::{ParticleTable, TableColumn};
use dualsph_probes::Quantity;
use dualsph_probes::quantity::{SHEPARD_SUM, SPEED};
use dualsph_sweep::prelude::Real;

const AXES: [char; 3] = ['x', 'y', 'z'];

/// How a table column of `width` components reads in `dim` dimensions.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layout {
    Scalar,
    /// Padded to x, y, z.
    Vector,
    /// `dim × dim`, row-major.
    Matrix,
}

fn layout(c: &TableColumn, dim: usize) -> Option<Layout> {
    match c.width() {
        1 => Some(Layout::Scalar),
        3 if c.labels.last().is_some_and(|l| l.ends_with('z')) => Some(Layout::Vector),
        w if w == dim * dim => Some(Layout::Matrix),
        _ => None,
    }
}

/// The names of the table's quantities in `dim` dimensions (as in the probes' errors).
pub(crate) fn available(table: &ParticleTable, dim: usize) -> Vec<String> {
    let axes: Vec<String> = AXES[..dim].iter().map(char::to_string).collect();
    let mut out: Vec<String> = table
        .columns
        .iter()
        .filter_map(|c| match layout(c, dim)? {
            Layout::Scalar => Some(c.name.clone()),
            Layout::Vector => Some(format!("{}.{{{}}}", c.name, axes.join(","))),
            Layout::Matrix => {
                let pairs: Vec<String> = axes
                    .iter()
                    .flat_map(|a| axes.iter().map(move |b| format!("{a}{b}")))
                    .collect();
                Some(format!("{}.{{{}}}", c.name, pairs.join(",")))
            }
        })
        .collect();
    out.extend([SPEED.to_string(), SHEPARD_SUM.to_string()]);
    out
}

/// The column `name` of `table`, or an error naming what the table holds.
pub(crate) fn column<'a>(
    table: &'a ParticleTable,
    name: &str,
    dim: usize,
) -> Result<&'a TableColumn, GridError> {
    table.column(name).ok_or_else(|| {
        GridError::Invalid(format!(
            "the particles have no column `{name}`; they have: {}",
            available(table, dim).join(", ")
        ))
    })
}

/// The values of `q` of every particle of `table` (in its rows' order) in `dim` dimensions.
/// `speed` is `√(vx² + vy² + vz²)` of the `velocity` column; `shepard_sum` reads the
/// `density` (the sampler reports σ, whatever the values).
pub(crate) fn values(
    table: &ParticleTable,
    q: &Quantity,
    dim: usize,
) -> Result<Vec<Real>, GridError> {
    match q.name() {
        SPEED => {
            let v = column(table, "velocity", dim)?;
            if layout(v, dim) != Some(Layout::Vector) {
                return Err(GridError::Invalid(
                    "column `velocity` is not a vector".into(),
                ));
            }
            return Ok(v
                .values
                .chunks_exact(3)
                .map(|v| (v[0].powi(2) + v[1].powi(2) + v[2].powi(2)).sqrt())
                .collect());
        }
        SHEPARD_SUM => return Ok(column(table, "density", dim)?.values.clone()),
        _ => {}
    }
    let (base, suffix) = match q.name().rsplit_once('.') {
        Some((b, s)) => (b, s),
        None => (q.name(), ""),
    };
    let c = column(table, base, dim)?;
    let axis = |ch: char| AXES[..dim].iter().position(|&a| a == ch);
    let chars: Vec<char> = suffix.chars().collect();
    let k = match (layout(c, dim), chars.as_slice()) {
        (Some(Layout::Scalar), []) => Some(0),
        (Some(Layout::Vector), [a]) => axis(*a),
        (Some(Layout::Matrix), [a, b]) => axis(*a).zip(axis(*b)).map(|(a, b)| a * dim + b),
        _ => None,
    };
    let Some(k) = k else {
        return Err(GridError::Invalid(format!(
            "quantity `{q}`: no such component of column `{base}` ({} values per particle) in \
             {dim}-D; the particles have: {}",
            c.width(),
            available(table, dim).join(", ")
        )));
    };
    let w = c.width();
    Ok(c.values.chunks_exact(w).map(|row| row[k]).collect())
}
