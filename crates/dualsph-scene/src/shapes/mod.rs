//! Shapes for particle generators and cuts: a box, a polygon (2-D, inline or from a file), a
//! circle (2-D), a ball (3-D), a cylinder (3-D) and a closed triangle mesh from an STL file
//! (3-D), each with an exact signed distance and one inside test.
//!
//! Every shape implements [`Geometry`]: its signed distance `s(p)` (negative inside, positive
//! outside, `|s|` the Euclidean distance to the surface), its closed inside test (the one test
//! that serves a solid fill, both sides of a layered fill and a cut), the distance used to
//! count wall layers, and its bounding box. A new shape only has to implement the trait to be
//! fillable, layerable and usable as a cut.
//!
//! The shapes read from files (`Stl`, `PolygonFile`) are read when the scene is parsed
//! ([`files`]), relative to the scene file's directory, and keep the content in the shape.

mod check;
mod files;
mod fill;
mod mesh;
mod mesh_geom;
mod polygon;

pub(crate) use check::{
    generator as check_generator, region as check_region, shape as check_shape,
};
pub(crate) use files::load_shape;
pub use files::{Outline, StlMesh};
pub use fill::{Fill, ShapeGenerator, Side};
pub(crate) use fill::{estimate_count, for_each_position};

use crate::lattice::BoxRegion;
use mesh_geom::MeshGeom;
use polygon::PolygonGeom;
use serde::{Deserialize, Serialize};

/// A geometric shape in scene coordinates (vectors with the scene's dimension).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub enum Shape {
    /// The axis-aligned box `[min, max]` (any dimension): `Box(min: [..], max: [..])`.
    Box {
        /// Lower corner.
        min: Vec<f64>,
        /// Upper corner.
        max: Vec<f64>,
    },
    /// A simple polygon (2-D), its vertices in order (either orientation), the last joined to
    /// the first: `Polygon(vertices: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])`.
    Polygon {
        /// At least 3 vertices `[x, y]`; the edges must not cross.
        vertices: Vec<Vec<f64>>,
    },
    /// A circle (2-D; in 3-D use [`Shape::Cylinder`]): `Circle(center: [..], radius: r)`.
    Circle {
        /// Centre.
        center: Vec<f64>,
        /// Radius (> 0).
        radius: f64,
    },
    /// A ball (3-D): `Ball(center: [..], radius: r)`.
    Ball {
        /// Centre.
        center: Vec<f64>,
        /// Radius (> 0).
        radius: f64,
    },
    /// A finite circular cylinder (3-D) about any axis:
    /// `Cylinder(center: [..], axis: [0.0, 0.0, 1.0], radius: r, length: l)`.
    Cylinder {
        /// The midpoint of its axis.
        center: Vec<f64>,
        /// The axis direction (any non-zero length).
        axis: Vec<f64>,
        /// Radius (> 0).
        radius: f64,
        /// Length along the axis (> 0), `length/2` on each side of `center`.
        length: f64,
    },
    /// A simple polygon (2-D) whose vertices are the rows `x, y` of a text file (commas or
    /// blanks between the two numbers; blank lines, `#` comments and a first line of column
    /// names are skipped): `PolygonFile(file: "outline.csv")`. The path is relative to the
    /// scene file's directory.
    PolygonFile {
        /// The file.
        file: String,
        /// The vertices once the scene is loaded.
        #[serde(skip)]
        outline: Outline,
    },
    /// A closed triangle mesh (3-D) read from an STL file, binary or ASCII, placed at
    /// `x = scale · x_file + translate`:
    /// `Stl(file: "obstacle.stl", scale: 0.001, translate: [0.5, 0.0, 0.2])`. The path is
    /// relative to the scene file's directory; the mesh must be closed (every edge shared by
    /// two triangles), consistently oriented (either way round) and free of degenerate
    /// triangles.
    Stl {
        /// The file.
        file: String,
        /// The factor on the file's coordinates (default 1, > 0).
        #[serde(default = "one")]
        scale: f64,
        /// The shift after scaling (default none).
        #[serde(default)]
        translate: Option<Vec<f64>>,
        /// The mesh once the scene is loaded.
        #[serde(skip)]
        mesh: StlMesh,
    },
}

fn one() -> f64 {
    1.0
}

impl Shape {
    /// `"Box"`, `"Polygon"`, `"Circle"`, `"Ball"` or `"Cylinder"`.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Box { .. } => "Box",
            Shape::Polygon { .. } => "Polygon",
            Shape::Circle { .. } => "Circle",
            Shape::Ball { .. } => "Ball",
            Shape::Cylinder { .. } => "Cylinder",
            Shape::PolygonFile { .. } => "PolygonFile",
            Shape::Stl { .. } => "Stl",
        }
    }

    /// The shape's geometry in `d` dimensions. Missing components are NaN, so a malformed
    /// shape never panics and contains nothing.
    pub fn geometry(&self, d: usize) -> std::boxed::Box<dyn Geometry + Send + Sync> {
        let v3 = |v: &[f64]| -> [f64; 3] {
            std::array::from_fn(|k| if k < d { comp(v, k) } else { 0.0 })
        };
        match self {
            Shape::Box { min, max } => std::boxed::Box::new(BoxGeom {
                lo: v3(min),
                hi: v3(max),
                d,
            }),
            Shape::Polygon { vertices } => std::boxed::Box::new(PolygonGeom::new(vertices)),
            Shape::Circle { center, radius } | Shape::Ball { center, radius } => {
                std::boxed::Box::new(RoundGeom {
                    c: v3(center),
                    r: *radius,
                    d,
                })
            }
            Shape::Cylinder {
                center,
                axis,
                radius,
                length,
            } => std::boxed::Box::new(CylinderGeom::new(v3(center), v3(axis), *radius, *length)),
            Shape::PolygonFile { outline, .. } => match outline.vertices() {
                Some(v) => std::boxed::Box::new(PolygonGeom::new(v)),
                None => std::boxed::Box::new(Nothing),
            },
            Shape::Stl {
                scale,
                translate,
                mesh,
                ..
            } => {
                let shift = translate.as_deref().map_or([0.0; 3], v3);
                match mesh.get().and_then(|m| MeshGeom::new(m, *scale, shift)) {
                    Some(g) => std::boxed::Box::new(g),
                    None => std::boxed::Box::new(Nothing),
                }
            }
        }
    }
}

/// Component `k` of `v`, NaN when missing.
pub(crate) fn comp(v: &[f64], k: usize) -> f64 {
    v.get(k).copied().unwrap_or(f64::NAN)
}

/// What a generator needs of a shape. Points are `[f64; 3]` with the components beyond the
/// scene dimension 0.
pub trait Geometry {
    /// The signed distance `s(p)` to the surface: negative inside, positive outside, `|s|`
    /// the Euclidean distance to the nearest surface point.
    fn signed_distance(&self, p: &[f64; 3]) -> f64;
    /// Whether `p` is inside or on the surface (closed; a relative tolerance of `1e-12` on
    /// the surface). The one inside test of every fill and cut.
    fn contains(&self, p: &[f64; 3]) -> bool;
    /// The distance that counts wall layers: `k`-th layer points satisfy
    /// `(k − 1)Δx < |layer_distance| ≤ kΔx`. The signed distance, except where a mitred
    /// (sharp-cornered) offset keeps a wall's corners full (box, cylinder rim).
    fn layer_distance(&self, p: &[f64; 3]) -> f64 {
        self.signed_distance(p)
    }
    /// The axis-aligned bounding box `(lo, hi)`.
    fn bounds(&self) -> ([f64; 3], [f64; 3]);
    /// The surface measure (perimeter in 2-D, area in 3-D; 2 in 1-D), for count estimates.
    fn surface(&self) -> f64;
}

/// The geometry of a shape whose file was not read (or does not place): it contains
/// nothing and its bounds are not numbers, so a generator over it yields nothing.
struct Nothing;

impl Geometry for Nothing {
    fn signed_distance(&self, _: &[f64; 3]) -> f64 {
        f64::INFINITY
    }
    fn contains(&self, _: &[f64; 3]) -> bool {
        false
    }
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        ([f64::NAN; 3], [f64::NAN; 3])
    }
    fn surface(&self) -> f64 {
        f64::NAN
    }
}

/// `|v|` over the first 3 components.
fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The box `[lo, hi]` on the first `d` axes. With `q_k = |p_k − c_k| − a_k` (`c` the centre,
/// `a` the half-widths), `s(p) = |max(q, 0)| + min(max_k q_k, 0)`; its layers use the mitred
/// distance `max_k q_k`, which equals `s` inside and makes the outside layers full at the
/// corners (a tank of `Layers(n: 3, side: Outside)` has `3Δx × 3Δx` corner blocks).
pub(crate) struct BoxGeom {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    pub d: usize,
}

impl BoxGeom {
    fn q(&self, p: &[f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| {
            if k < self.d {
                (p[k] - 0.5 * (self.lo[k] + self.hi[k])).abs() - 0.5 * (self.hi[k] - self.lo[k])
            } else {
                f64::NEG_INFINITY
            }
        })
    }
}

impl Geometry for BoxGeom {
    fn signed_distance(&self, p: &[f64; 3]) -> f64 {
        let q = self.q(p);
        let out = norm(&q.map(|x| x.max(0.0)));
        out + q[0].max(q[1]).max(q[2]).min(0.0)
    }
    fn contains(&self, p: &[f64; 3]) -> bool {
        (0..self.d).all(|k| self.lo[k] <= p[k] && p[k] <= self.hi[k])
    }
    fn layer_distance(&self, p: &[f64; 3]) -> f64 {
        let q = self.q(p);
        q[0].max(q[1]).max(q[2])
    }
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        (self.lo, self.hi)
    }
    fn surface(&self) -> f64 {
        let w: Vec<f64> = (0..self.d).map(|k| self.hi[k] - self.lo[k]).collect();
        match self.d {
            1 => 2.0,
            2 => 2.0 * (w[0] + w[1]),
            _ => 2.0 * (w[0] * w[1] + w[1] * w[2] + w[0] * w[2]),
        }
    }
}

/// A circle (`d = 2`) or ball (`d = 3`) of centre `c` and radius `r`: `s(p) = |p − c| − r`;
/// inside when `|p − c|² ≤ r²(1 + 10⁻¹²)`.
pub(crate) struct RoundGeom {
    pub c: [f64; 3],
    pub r: f64,
    pub d: usize,
}

impl RoundGeom {
    fn dist2(&self, p: &[f64; 3]) -> f64 {
        (0..self.d).map(|k| (p[k] - self.c[k]).powi(2)).sum()
    }
}

impl Geometry for RoundGeom {
    fn signed_distance(&self, p: &[f64; 3]) -> f64 {
        self.dist2(p).sqrt() - self.r
    }
    fn contains(&self, p: &[f64; 3]) -> bool {
        self.dist2(p) <= self.r * self.r * (1.0 + 1e-12)
    }
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let lo = std::array::from_fn(|k| if k < self.d { self.c[k] - self.r } else { 0.0 });
        let hi = std::array::from_fn(|k| if k < self.d { self.c[k] + self.r } else { 0.0 });
        (lo, hi)
    }
    fn surface(&self) -> f64 {
        use std::f64::consts::PI;
        match self.d {
            2 => 2.0 * PI * self.r,
            _ => 4.0 * PI * self.r * self.r,
        }
    }
}

/// A cylinder of axis midpoint `c`, unit axis `a`, radius `r` and half-length `l`. With the
/// axial coordinate `u = (p − c)·a` and the radial distance `w = |p − c − u a|`, the side and
/// cap distances are `q = (w − r, |u| − l)` and `s(p) = |max(q, 0)| + min(max(q₀, q₁), 0)`;
/// layers use the mitred `max(q₀, q₁)` (full rims).
pub(crate) struct CylinderGeom {
    c: [f64; 3],
    a: [f64; 3],
    r: f64,
    l: f64,
}

impl CylinderGeom {
    fn new(c: [f64; 3], axis: [f64; 3], r: f64, length: f64) -> Self {
        let n = norm(&axis);
        CylinderGeom {
            c,
            a: axis.map(|x| x / n),
            r,
            l: 0.5 * length,
        }
    }

    /// `(w, |u|)`: radial distance from the axis and axial distance from the midpoint.
    fn radial_axial(&self, p: &[f64; 3]) -> (f64, f64) {
        let rel: [f64; 3] = std::array::from_fn(|k| p[k] - self.c[k]);
        let u = rel[0] * self.a[0] + rel[1] * self.a[1] + rel[2] * self.a[2];
        let perp: [f64; 3] = std::array::from_fn(|k| rel[k] - u * self.a[k]);
        (norm(&perp), u.abs())
    }
}

impl Geometry for CylinderGeom {
    fn signed_distance(&self, p: &[f64; 3]) -> f64 {
        let (w, u) = self.radial_axial(p);
        let q = [w - self.r, u - self.l];
        libm::hypot(q[0].max(0.0), q[1].max(0.0)) + q[0].max(q[1]).min(0.0)
    }
    fn contains(&self, p: &[f64; 3]) -> bool {
        let (w, u) = self.radial_axial(p);
        w <= self.r * (1.0 + 1e-12) && u <= self.l * (1.0 + 1e-12)
    }
    fn layer_distance(&self, p: &[f64; 3]) -> f64 {
        let (w, u) = self.radial_axial(p);
        (w - self.r).max(u - self.l)
    }
    /// Per axis `k`: `c_k ± (l |a_k| + r √(1 − a_k²))`.
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let e: [f64; 3] = std::array::from_fn(|k| {
            self.l * self.a[k].abs() + self.r * (1.0 - self.a[k] * self.a[k]).max(0.0).sqrt()
        });
        (
            std::array::from_fn(|k| self.c[k] - e[k]),
            std::array::from_fn(|k| self.c[k] + e[k]),
        )
    }
    fn surface(&self) -> f64 {
        use std::f64::consts::PI;
        2.0 * PI * self.r * (2.0 * self.l) + 2.0 * PI * self.r * self.r
    }
}

/// One entry of a generator's `cut`: a plain box `(min: [..], max: [..])` (bounds included)
/// or any [`Shape`] (`Circle(..)`, `Polygon(..)`, ...); the generator drops its points that
/// the region contains (the shape's closed inside test).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(
    untagged,
    expecting = "a cut region: a box `(min: [..], max: [..])` or a shape `Box(..)`, \
                 `Polygon(..)`, `PolygonFile(..)`, `Circle(..)`, `Ball(..)`, `Cylinder(..)` \
                 or `Stl(..)`"
)]
pub enum Region {
    /// A shape.
    Shape(Shape),
    /// A box without a name, `(min: [..], max: [..])`.
    Box(BoxRegion),
}

impl Region {
    /// The region's geometry in `d` dimensions.
    pub fn geometry(&self, d: usize) -> std::boxed::Box<dyn Geometry + Send + Sync> {
        match self {
            Region::Shape(s) => s.geometry(d),
            Region::Box(b) => Shape::Box {
                min: b.min.clone(),
                max: b.max.clone(),
            }
            .geometry(d),
        }
    }
}

impl From<BoxRegion> for Region {
    fn from(b: BoxRegion) -> Self {
        Region::Box(b)
    }
}
