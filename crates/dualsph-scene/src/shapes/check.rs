//! Validation of shapes, cut regions and the `Shape` generator; every problem names its field.

use super::polygon::{first_crossing, signed_area};
use super::{Fill, Region, Shape, ShapeGenerator};
use crate::checks::{Check, ordered, positive, vector};
use crate::error::Problem;

/// The dimension a shape needs, or `None` for any.
fn needs(s: &Shape) -> Option<(usize, &'static str)> {
    match s {
        Shape::Box { .. } => None,
        Shape::Polygon { .. } | Shape::PolygonFile { .. } => {
            Some((2, "in 3-D use a Box, Ball, Cylinder or Stl mesh"))
        }
        Shape::Circle { .. } => Some((2, "in 3-D use a Ball, or a Cylinder for a disk")),
        Shape::Ball { .. } => Some((3, "in 2-D use a Circle")),
        Shape::Cylinder { .. } => Some((3, "in 2-D its cross-section is a Circle")),
        Shape::Stl { .. } => Some((3, "in 2-D give the outline as a Polygon or PolygonFile")),
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
        Shape::Polygon { vertices } => polygon(&f("vertices"), vertices, &|_| String::new()),
        Shape::PolygonFile { file, outline } => match outline.vertices() {
            Some(v) => polygon(&f("file"), v, &|i| match outline.line(i) {
                Some(l) => format!(" (line {l} of `{file}`)"),
                None => String::new(),
            }),
            None => Err(not_read(&f("file"))),
        },
        Shape::Stl {
            scale,
            translate,
            mesh,
            ..
        } => {
            if mesh.get().is_none() {
                return Err(not_read(&f("file")));
            }
            positive(&f("scale"), *scale)?;
            match translate {
                Some(t) => vector(&f("translate"), t, d),
                None => Ok(()),
            }
        }
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

/// A shape whose file was not read: the scene was deserialized without
/// [`crate::Scene::parse_only`].
fn not_read(field: &str) -> Problem {
    Problem::new(
        field,
        "the file was not read: parse scenes with Scene::load, Scene::from_str or \
         Scene::parse_only",
    )
}

/// At least 3 finite 2-D vertices, a simple boundary (no two edges meet except adjacent ones
/// at their shared vertex) and a non-zero area. `at(i)` follows vertex `i` in messages (where
/// it comes from, or nothing).
fn polygon(field: &str, vertices: &[Vec<f64>], at: &dyn Fn(usize) -> String) -> Check {
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
        let (ni, nj) = ((i + 1) % n, (j + 1) % n);
        let message = if i == j {
            format!(
                "vertices {i}{} and {ni}{} coincide: the polygon has an edge of zero length",
                at(i),
                at(ni)
            )
        } else {
            format!(
                "the polygon intersects itself: edge {i} (vertices {i}{} → {ni}{}) and edge {j} \
                 (vertices {j}{} → {nj}{}) meet; the edges must only join at shared vertices",
                at(i),
                at(ni),
                at(j),
                at(nj)
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
pub(crate) fn generator(i: usize, g: &ShapeGenerator, d: usize, domain: (&[f64], &[f64])) -> Check {
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
        let (dmin, dmax) = (domain.0[k], domain.1[k]);
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
