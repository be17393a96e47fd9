//! Validation of shapes, cut regions and the `Shape` generator; every problem names its field.

use super::polygon::{first_crossing, signed_area};
use super::{Fill, Region, Shape, ShapeGenerator};
use crate::error::Problem;
use crate::schema::Domain;
use crate::validate::{Check, ordered, positive, vector};

/// The dimension a shape needs, or `None` for any.
fn needs(s: &Shape) -> Option<(usize, &'static str)> {
    match s {
        Shape::Box { .. } => None,
        Shape::Polygon { .. } => Some((2, "in 3-D use a Box, Ball or Cylinder")),
        Shape::Circle { .. } => Some((2, "in 3-D use a Ball, or a Cylinder for a disk")),
        Shape::Ball { .. } => Some((3, "in 2-D use a Circle")),
        Shape::Cylinder { .. } => Some((3, "in 2-D its cross-section is a Circle")),
    }
}

/// A shape at `field` (e.g. `particles[2].shape`) in a `d`-dimensional scene.
pub(crate) fn shape(field: &str, s: &Shape, d: usize) -> Check {
    let f = |name: &str| format!("{field}.{name}");
    if let Some((want, hint)) = needs(s)
        && d != want
    {
        return Err(Problem::new(
            field,
            format!(
                "a {} is {want}-D and the scene has dimension {d}: {hint}",
                s.name()
            ),
        ));
    }
    match s {
        Shape::Box { min, max } => {
            vector(&f("min"), min, d)?;
            vector(&f("max"), max, d)?;
            ordered(&f("max"), min, max)
        }
        Shape::Polygon { vertices } => polygon(&f("vertices"), vertices),
        Shape::Circle { center, radius } | Shape::Ball { center, radius } => {
            vector(&f("center"), center, d)?;
            positive(&f("radius"), *radius)
        }
        Shape::Cylinder {
            center,
            axis,
            radius,
            length,
        } => {
            vector(&f("center"), center, d)?;
            vector(&f("axis"), axis, d)?;
            if axis.iter().all(|&x| x == 0.0) {
                return Err(Problem::new(f("axis"), "must not be zero"));
            }
            positive(&f("radius"), *radius)?;
            positive(&f("length"), *length)
        }
    }
}

/// At least 3 finite 2-D vertices, a simple boundary (no two edges meet except adjacent ones
/// at their shared vertex) and a non-zero area.
fn polygon(field: &str, vertices: &[Vec<f64>]) -> Check {
    if vertices.len() < 3 {
        return Err(Problem::new(
            field,
            format!(
                "a polygon needs at least 3 vertices, got {}",
                vertices.len()
            ),
        ));
    }
    for (i, v) in vertices.iter().enumerate() {
        vector(&format!("{field}[{i}]"), v, 2)?;
    }
    let v: Vec<[f64; 2]> = vertices.iter().map(|p| [p[0], p[1]]).collect();
    let n = v.len();
    if let Some((i, j)) = first_crossing(&v) {
        let message = if i == j {
            format!(
                "vertices {i} and {} coincide: the polygon has an edge of zero length",
                (i + 1) % n
            )
        } else {
            format!(
                "the polygon intersects itself: edge {i} (vertices {i} → {}) and edge {j} \
                 (vertices {j} → {}) meet; the edges must only join at shared vertices",
                (i + 1) % n,
                (j + 1) % n
            )
        };
        return Err(Problem::new(field, message));
    }
    if signed_area(&v) == 0.0 {
        return Err(Problem::new(field, "the polygon has zero area"));
    }
    Ok(())
}

/// A cut region at `field`: a plain box needs `d` components in each corner (as a box cut
/// always has), a shape is checked as a shape.
pub(crate) fn region(field: &str, r: &Region, d: usize) -> Check {
    match r {
        Region::Box(b) => {
            vector(&format!("{field}.min"), &b.min, d)?;
            vector(&format!("{field}.max"), &b.max, d)
        }
        Region::Shape(s) => shape(field, s, d),
    }
}

/// The `Shape` generator number `i` (its shape already checked): its fill, and its extent (the shape's
/// bounding box widened by outside layers, narrowed to the clip box) inside the domain.
/// Called after the common settings (spacing, clip, cut) are checked.
pub(crate) fn generator(i: usize, g: &ShapeGenerator, d: usize, domain: &Domain) -> Check {
    let at = format!("particles[{i}]");
    if let Fill::Layers { n: 0, .. } = g.fill {
        return Err(Problem::new(
            format!("{at}.fill"),
            "Layers needs n >= 1 layers",
        ));
    }
    let (mut lo, mut hi) = g.shape.geometry(d).bounds();
    let reach = g.reach();
    for k in 0..d {
        lo[k] -= reach;
        hi[k] += reach;
        if let Some(clip) = &g.clip {
            lo[k] = lo[k].max(clip.min[k]);
            hi[k] = hi[k].min(clip.max[k]);
        }
        let (dmin, dmax) = (domain.min[k], domain.max[k]);
        let slack = 1e-9 * (dmax - dmin);
        if lo[k] < dmin - slack || hi[k] > dmax + slack {
            let layers = if reach > 0.0 {
                format!(" with its outside layers ({reach} beyond its surface)")
            } else {
                String::new()
            };
            return Err(Problem::new(
                format!("{at}.shape"),
                format!(
                    "the {}{layers} spans [{}, {}] on axis {k}, leaving the domain [{dmin}, \
                     {dmax}]: widen the domain, move the shape or clip it",
                    g.shape.name(),
                    lo[k],
                    hi[k]
                ),
            ));
        }
    }
    Ok(())
}
