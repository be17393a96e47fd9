//! The `Shape` generator: a shape filled solid with a lattice, or wall layers along its
//! surface, on either side.

use super::{Geometry, Region, Shape};
use crate::lattice::{BoxRegion, Lattice, Velocity};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How a [`ShapeGenerator`] fills its shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub enum Fill {
    /// The lattice points the shape contains (the default).
    #[default]
    Solid,
    /// `n` layers of particles along the surface on one side: `Layers(n: 3, side: Outside)`.
    /// Lattice points whose layer distance `s` to the surface satisfies `0 < |s| ≤ nΔx` on
    /// that side; the lattice starts at the shape's bounding box, so along a box face (or an
    /// axis-aligned polygon edge on the bounding box) the layers sit at `Δx/2, 3Δx/2, …` from
    /// the surface and mesh with a fluid lattice on the other side. For a `Circle`, `n`
    /// concentric rings instead.
    Layers {
        /// The number of layers (>= 1).
        #[serde(deserialize_with = "crate::de::int::de")]
        n: usize,
        /// Which side of the surface.
        side: Side,
    },
}

/// The side of a surface wall layers are put on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
pub enum Side {
    /// Inside the shape (an obstacle's skin).
    Inside,
    /// Outside the shape (a tank around its fluid).
    Outside,
}

fn square() -> Lattice {
    Lattice::Square
}

/// Particles in a [`Shape`]: `Shape(shape: Circle(center: [..], radius: r), fill: Solid,
/// spacing: .., density: .., h_factor: .., body: "..")`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeGenerator {
    /// The shape.
    pub shape: Shape,
    /// Solid (the default) or wall layers.
    #[serde(default)]
    pub fill: Fill,
    /// Lattice spacing Δx.
    pub spacing: f64,
    /// Lattice kind (default `Square`), aligned to the shape's bounding box.
    #[serde(default = "square")]
    pub lattice: Lattice,
    /// Initial density; particle mass is `density · Δx^d` (rings too: one particle per
    /// `Δx^d`).
    pub density: f64,
    /// Support radius in units of Δx: `h = h_factor · Δx`.
    pub h_factor: f64,
    /// Keep only the points inside this box.
    #[serde(default, deserialize_with = "crate::lattice::deserialize_clip")]
    pub clip: Option<BoxRegion>,
    /// Drop the points inside any of these regions (boxes or shapes).
    #[serde(default)]
    pub cut: Vec<Region>,
    /// Initial velocity (zero when absent).
    #[serde(default)]
    pub velocity: Option<Velocity>,
    /// Initial specific internal energy.
    #[serde(default)]
    pub internal_energy: f64,
    /// The body the particles belong to (a name from the scene's `bodies`); may be left out
    /// when the scene has one body.
    #[serde(default)]
    pub body: Option<String>,
}

impl ShapeGenerator {
    /// How far the particles reach beyond the shape's bounding box: `nΔx` for outside
    /// layers, 0 otherwise.
    pub fn reach(&self) -> f64 {
        match self.fill {
            Fill::Layers {
                n,
                side: Side::Outside,
            } => n as f64 * self.spacing,
            _ => 0.0,
        }
    }

    fn rings(&self, d: usize) -> bool {
        d == 2 && matches!(self.shape, Shape::Circle { .. }) && self.fill != Fill::Solid
    }
}

/// The lattice a generator walks: origin, spacing and per-axis index ranges `[a, b)` (unused
/// axes `[0, 1)`), narrowed to the clip box.
struct Walk {
    origin: [f64; 3],
    ranges: [(i64, i64); 3],
}

fn walk(g: &ShapeGenerator, geom: &dyn Geometry, d: usize) -> Option<Walk> {
    let dx = g.spacing;
    let (lo, hi) = geom.bounds();
    // one spare index beyond the bounds, plus the outside layers
    let m = 1.0 + (g.reach() / dx).ceil();
    let mut ranges = [(0, 1); 3];
    for k in 0..d {
        let n = ((hi[k] - lo[k]) / dx).round();
        let (mut a, mut b) = (-m, n + m);
        if let Some(clip) = &g.clip {
            let (cmin, cmax) = (super::comp(&clip.min, k), super::comp(&clip.max, k));
            a = a.max(((cmin - lo[k]) / dx - 0.75).floor());
            b = b.min(((cmax - lo[k]) / dx - 0.25).floor() + 1.0);
        }
        if !(a.is_finite() && b.is_finite() && a.abs() < 1e15 && b.abs() < 1e15) {
            return None;
        }
        ranges[k] = (a as i64, (b as i64).max(a as i64));
    }
    Some(Walk { origin: lo, ranges })
}

/// Lattice offset (in units of Δx) of axis `k` for the point with index `idx` (negative
/// indices allowed): the same rule as the `Block` lattice.
fn offset(lattice: Lattice, d: usize, k: usize, idx: [i64; 3]) -> f64 {
    let stagger = |i: i64| if i.rem_euclid(2) == 0 { 0.25 } else { 0.75 };
    match (lattice, d) {
        (Lattice::Staggered, 2) if k == 0 => stagger(idx[1]),
        (Lattice::Staggered, 3) if k < 2 => stagger(idx[2]),
        _ => 0.5,
    }
}

/// An estimate (from above, up to a margin) of how many particles `g` generates; infinite
/// when the spacing or geometry is not usable.
pub(crate) fn estimate_count(g: &ShapeGenerator, d: usize) -> f64 {
    let dx = g.spacing;
    let geom = g.shape.geometry(d);
    let Some(w) = walk(g, geom.as_ref(), d) else {
        return f64::INFINITY;
    };
    let full: f64 = w.ranges.iter().map(|(a, b)| (b - a) as f64).product();
    let est = match g.fill {
        Fill::Solid => match g.shape {
            Shape::Circle { .. } | Shape::Ball { .. } if d >= 2 => {
                let share = [1.0, PI / 4.0, PI / 6.0][d - 1];
                (full * share * 1.1).min(full)
            }
            _ => full,
        },
        Fill::Layers { n, .. } => {
            // the surface measure of the shape and of its bounding box widened by the
            // layers, times (n + 1) layers, doubled
            let (lo, hi) = geom.bounds();
            let grow = (n as f64 + 1.0) * dx;
            let outer = super::BoxGeom {
                lo: lo.map(|x| x - grow),
                hi: hi.map(|x| x + grow),
                d,
            };
            let s = geom.surface() + outer.surface();
            (2.0 * (n as f64 + 1.0) * s / dx.powi(d as i32 - 1) + 8.0).min(full)
        }
    };
    if est.is_nan() { f64::INFINITY } else { est }
}

/// Calls `f` with every position `g` generates: lattice points in lexicographic index order
/// (axis 0 slowest), or a circle's rings from the surface outwards (inwards), each
/// counter-clockwise from angle 0 (odd rings shifted half a step). Points outside the clip
/// box or inside a cut region are dropped.
pub(crate) fn for_each_position(g: &ShapeGenerator, d: usize, mut f: impl FnMut([f64; 3])) {
    let geom = g.shape.geometry(d);
    let cuts: Vec<_> = g.cut.iter().map(|r| r.geometry(d)).collect();
    let mut keep = |p: [f64; 3]| {
        let clipped = g.clip.as_ref().is_some_and(|b| !b.contains(&p, d));
        if !clipped && !cuts.iter().any(|c| c.contains(&p)) {
            f(p);
        }
    };
    if g.rings(d) {
        rings(g, &mut keep);
    } else {
        lattice(g, geom.as_ref(), d, &mut keep);
    }
}

/// The lattice points of the fill: contained (solid), or contained (outside: not contained)
/// with `|layer distance| ≤ nΔx`.
fn lattice(g: &ShapeGenerator, geom: &dyn Geometry, d: usize, f: &mut impl FnMut([f64; 3])) {
    let Some(w) = walk(g, geom, d) else { return };
    let dx = g.spacing;
    let slack = 1e-9 * dx;
    let wanted = |p: &[f64; 3]| match g.fill {
        Fill::Solid => geom.contains(p),
        Fill::Layers { n, side } => {
            let reach = n as f64 * dx + slack;
            match side {
                Side::Inside => geom.contains(p) && geom.layer_distance(p) >= -reach,
                Side::Outside => !geom.contains(p) && geom.layer_distance(p) <= reach,
            }
        }
    };
    let r = w.ranges;
    for i0 in r[0].0..r[0].1 {
        for i1 in r[1].0..r[1].1 {
            for i2 in r[2].0..r[2].1 {
                let idx = [i0, i1, i2];
                let mut p = [0.0; 3];
                for k in 0..d {
                    p[k] = w.origin[k] + (idx[k] as f64 + offset(g.lattice, d, k, idx)) * dx;
                }
                if wanted(&p) {
                    f(p);
                }
            }
        }
    }
}

/// A circle's wall layers: ring `k = 0 … n−1` at radius `r_k = R ± (k + ½)Δx` holds
/// `N_k = round(2π r_k / Δx)` points at angles `2π (j + ½ [k odd]) / N_k`, so neighbours on a
/// ring are `2π r_k / N_k ≈ Δx` apart and rings are `Δx` apart. Inside, a ring too small for
/// 3 points is replaced by the centre and ends the layers.
fn rings(g: &ShapeGenerator, f: &mut impl FnMut([f64; 3])) {
    let Shape::Circle { center, radius } = &g.shape else {
        return;
    };
    let Fill::Layers { n, side } = g.fill else {
        return;
    };
    let dx = g.spacing;
    let c = [super::comp(center, 0), super::comp(center, 1)];
    for k in 0..n {
        let step = (k as f64 + 0.5) * dx;
        let r = match side {
            Side::Inside => radius - step,
            Side::Outside => radius + step,
        };
        let count = (2.0 * PI * r / dx).round();
        if count.is_nan() || count < 3.0 {
            if r > -0.5 * dx {
                f([c[0], c[1], 0.0]);
            }
            return;
        }
        let shift = if k % 2 == 1 { 0.5 } else { 0.0 };
        for j in 0..count as usize {
            let (s, co) = libm::sincos(2.0 * PI * (j as f64 + shift) / count);
            f([c[0] + r * co, c[1] + r * s, 0.0]);
        }
    }
}
