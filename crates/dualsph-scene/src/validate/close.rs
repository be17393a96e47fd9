//! Particles too close where [`super::overlap`] does not look: across a periodic face (a
//! particle near one face and one near the opposite face are neighbours through it), and
//! within one particle file (two particles at the same place, e.g. a file given twice).
//!
//! Across a periodic face the rule is the overlap rule, closer than half the smaller spacing:
//! a lattice whose spacing does not divide the period puts its first and last rows closer
//! than that through the face. Within a file the particles are where a run left them (an
//! impact can bring two well within half a spacing), so only coincident ones are refused:
//! closer than [`COINCIDENT`] of the file's smallest spacing.

use super::Check;
use super::overlap::fmt_point;
use crate::Scene;
use crate::error::Problem;
use crate::generate;
use crate::schema::Generator;
use std::collections::HashMap;

/// Particles of one file closer than this fraction of its smallest spacing are coincident.
pub(super) const COINCIDENT: f64 = 1e-3;

/// Points indexed by cells of one size, for "is any point within r" queries (r ≤ cell).
struct Cells {
    cell: f64,
    map: HashMap<[i64; 3], Vec<usize>>,
}

impl Cells {
    fn new(points: &[[f64; 3]], cell: f64) -> Self {
        let mut map: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (i, p) in points.iter().enumerate() {
            map.entry(Self::key(p, cell)).or_default().push(i);
        }
        Cells { cell, map }
    }

    fn key(p: &[f64; 3], cell: f64) -> [i64; 3] {
        p.map(|x| (x / cell).floor() as i64)
    }

    /// Indices of the points in the cells around `p` (its own and the adjacent ones).
    fn around<'a>(&'a self, p: &[f64; 3], d: usize) -> impl Iterator<Item = usize> + 'a {
        let c = Self::key(p, self.cell);
        let span = |k: usize| if k < d { -1..=1 } else { 0..=0 };
        let keys: Vec<[i64; 3]> = span(0)
            .flat_map(|a| span(1).flat_map(move |b| span(2).map(move |e| [a, b, e])))
            .map(|o| [c[0] + o[0], c[1] + o[1], c[2] + o[2]])
            .collect();
        keys.into_iter()
            .filter_map(|k| self.map.get(&k))
            .flatten()
            .copied()
    }
}

fn dist(p: &[f64; 3], q: &[f64; 3], d: usize) -> f64 {
    (0..d).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt()
}

/// Two particles closer than half the smaller spacing through a periodic face (or an edge or
/// corner where two or three periodic faces meet).
pub(super) fn across_periodic_faces(s: &Scene) -> Check {
    let d = s.dimension;
    let periodic = s.domain.periodic_axes();
    let axes: Vec<usize> = (0..d).filter(|&k| periodic[k]).collect();
    if axes.is_empty() {
        return Ok(());
    }
    let spacing: Vec<f64> = s.particles.iter().map(Generator::spacing).collect();
    let reach = 0.5 * spacing.iter().copied().fold(0.0, f64::max);
    let (lo, hi) = (&s.domain.min, &s.domain.max);
    // the particles within `reach` of a periodic face, with their generator
    let mut near: Vec<([f64; 3], usize)> = Vec::new();
    for (i, g) in s.particles.iter().enumerate() {
        generate::for_each_position(g, d, |p| {
            if axes
                .iter()
                .any(|&k| p[k] - lo[k] < reach || hi[k] - p[k] < reach)
            {
                near.push((p, i));
            }
        });
    }
    let points: Vec<[f64; 3]> = near.iter().map(|(p, _)| *p).collect();
    let cells = Cells::new(&points, reach.max(f64::MIN_POSITIVE));
    for &(p, ga) in &near {
        for image in images(&p, &axes, lo, hi, reach) {
            for b in cells.around(&image, d) {
                let (q, gb) = near[b];
                let r = 0.5 * spacing[ga].min(spacing[gb]);
                let gap = dist(&image, &q, d);
                if gap < r {
                    let (first, second) = if ga <= gb { (ga, gb) } else { (gb, ga) };
                    return Err(Problem::new(
                        format!("particles[{second}]"),
                        format!(
                            "particles[{second}] comes too close to particles[{first}] through \
                             a periodic face: the particles at {} and {} are {gap:.6} apart \
                             across it, closer than half the smaller spacing ({r}) (a lattice \
                             fills a periodic axis evenly when its spacing divides the period \
                             and its first point sits half a spacing inside the face)",
                            fmt_point(&p, d),
                            fmt_point(&q, d),
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The periodic images of `p` that can fall near another particle: moved by ±the period on
/// every non-empty set of the axes where `p` is within `reach` of a face.
fn images(p: &[f64; 3], axes: &[usize], lo: &[f64], hi: &[f64], reach: f64) -> Vec<[f64; 3]> {
    let mut out = vec![*p];
    for &k in axes {
        let shift = if p[k] - lo[k] < reach {
            hi[k] - lo[k]
        } else if hi[k] - p[k] < reach {
            lo[k] - hi[k]
        } else {
            continue;
        };
        let moved: Vec<[f64; 3]> = out
            .iter()
            .map(|q| {
                let mut q = *q;
                q[k] += shift;
                q
            })
            .collect();
        out.extend(moved);
    }
    out.remove(0); // `p` itself
    out
}

/// Two particles of one particle file at the same place (closer than [`COINCIDENT`] of the
/// file's smallest spacing).
pub(super) fn coincident_in_files(s: &Scene) -> Check {
    let d = s.dimension;
    for (i, g) in s.particles.iter().enumerate() {
        let Generator::File(f) = g else { continue };
        let r = COINCIDENT * g.spacing();
        let mut points = Vec::new();
        generate::for_each_position(g, d, |p| points.push(p));
        let cells = Cells::new(&points, r.max(f64::MIN_POSITIVE));
        for (a, p) in points.iter().enumerate() {
            if let Some(b) = cells
                .around(p, d)
                .find(|&b| b != a && dist(p, &points[b], d) < r)
            {
                return Err(Problem::new(
                    format!("particles[{i}].path"),
                    format!(
                        "`{}`: particles {} and {} of the file (in its order) are at the same \
                         place {} (closer than {COINCIDENT} of its smallest spacing, {r:e}): \
                         was a file given twice?",
                        f.path,
                        a.min(b) + 1,
                        a.max(b) + 1,
                        fmt_point(p, d)
                    ),
                ));
            }
        }
    }
    Ok(())
}
