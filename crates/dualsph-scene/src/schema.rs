//! The parts of a scene file. Every struct rejects unknown fields; vectors are RON lists whose
//! length must equal the scene dimension (checked by validation, not by the parser).

use crate::body_kinds;
use crate::lattice::{BoxRegion, Lattice, Velocity, deserialize_clip};
use crate::particles_file::FileParticles;
use crate::shapes::{Region, ShapeGenerator};
use dualsph_core::bodies::BodyKindConfig;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The simulation box `[min, max]` (one component per axis).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// Lower corner.
    pub min: Vec<f64>,
    /// Upper corner.
    pub max: Vec<f64>,
    /// Which axes are periodic (one flag per axis; none when absent): a particle leaving
    /// through one face enters through the opposite one, and pairs interact across the
    /// period by their nearest image.
    #[serde(default)]
    pub periodic: Vec<bool>,
}

impl Domain {
    /// The periodic flags of the three axes (false where none is given).
    pub fn periodic_axes(&self) -> [bool; 3] {
        std::array::from_fn(|k| self.periodic.get(k).copied().unwrap_or(false))
    }
}

/// A rectangular block of particles.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Block {
    /// Lower corner.
    pub min: Vec<f64>,
    /// Upper corner.
    pub max: Vec<f64>,
    /// Lattice spacing Δx.
    pub spacing: f64,
    /// Lattice kind (default `Square`).
    #[serde(default)]
    pub lattice: Lattice,
    /// Moves every lattice point by up to `jitter · Δx` along each axis (0 by default, at most
    /// 0.25 so that a point stays in its cell): a fixed pseudo-random pattern of the point's
    /// lattice index (SplitMix64), the same on every run. A perfect lattice is
    /// an equilibrium of the particle regularisers (`TransportVelocity`, `ParticleShifting`:
    /// every kernel sum of a symmetric neighbourhood vanishes), which a flow then strains
    /// into an anisotropic one they cannot see; the jitter breaks that symmetry
    /// (TrixiParticles.jl perturbs its Taylor–Green lattice by 0.2Δx the same way).
    #[serde(default)]
    pub jitter: f64,
    /// Initial density; particle mass is `density · Δx^d`.
    pub density: f64,
    /// Support radius in units of Δx: `h = h_factor · Δx`.
    pub h_factor: f64,
    /// Keep only the points inside this box.
    #[serde(default, deserialize_with = "deserialize_clip")]
    pub clip: Option<BoxRegion>,
    /// Drop the points inside any of these regions (boxes `(min: .., max: ..)` or shapes).
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

/// A disk (2-D), ball (3-D) or segment (1-D): the points of the lattice of the bounding box
/// `[center − radius, center + radius]` with `|x − center| <= radius`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Disk {
    /// Centre.
    pub center: Vec<f64>,
    /// Radius.
    pub radius: f64,
    /// Lattice spacing Δx.
    pub spacing: f64,
    /// Lattice kind (default `Square`).
    #[serde(default)]
    pub lattice: Lattice,
    /// Initial density; particle mass is `density · Δx^d`.
    pub density: f64,
    /// Support radius in units of Δx: `h = h_factor · Δx`.
    pub h_factor: f64,
    /// Keep only the points inside this box.
    #[serde(default, deserialize_with = "deserialize_clip")]
    pub clip: Option<BoxRegion>,
    /// Drop the points inside any of these regions (boxes `(min: .., max: ..)` or shapes).
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

/// A named body: `Body(name: "water")`, `Body(name: "tank", kind: Fixed)`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename = "Body")]
pub struct BodySettings {
    /// The name generators and plugins refer to it by.
    pub name: String,
    /// What moves it: a kind the registry holds (`Fluid`, the default; `Fixed`;
    /// `Prescribed(..)` in the default registry), parsed by its registered settings type.
    #[serde(
        default = "body_kinds::fluid",
        deserialize_with = "body_kinds::deserialize",
        serialize_with = "body_kinds::serialize"
    )]
    pub kind: Arc<dyn BodyKindConfig>,
    /// The point the moment of the load on a fixed or prescribed body is taken about, one
    /// component per dimension (default: the origin). Not for a fluid body, which has no load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moment_about: Option<Vec<f64>>,
}

/// One entry of the scene's `particles` list.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
pub enum Generator {
    /// `Block(min: [..], max: [..], spacing: .., ...)`.
    Block(Block),
    /// `Disk(center: [..], radius: .., spacing: .., ...)`.
    Disk(Disk),
    /// `Shape(shape: Circle(..), fill: Layers(n: 3, side: Inside), spacing: .., ...)`.
    Shape(ShapeGenerator),
    /// `File(path: "final.csv", body: "water")`: particles read from a particle CSV.
    File(FileParticles),
}

/// The settings the generators share, borrowed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Common<'a> {
    pub spacing: f64,
    pub lattice: Lattice,
    pub density: f64,
    pub h_factor: f64,
    pub clip: Option<&'a BoxRegion>,
    pub cut: &'a [Region],
    pub velocity: Option<&'a Velocity>,
    pub internal_energy: f64,
    pub body: Option<&'a str>,
}

impl Generator {
    /// `"Block"`, `"Disk"`, `"File"` or `"Shape(Box)"`, `"Shape(Circle)"`, ... (the shape's
    /// name).
    pub fn kind(&self) -> &'static str {
        use crate::shapes::Shape as S;
        match self {
            Generator::Block(_) => "Block",
            Generator::Disk(_) => "Disk",
            Generator::File(_) => "File",
            Generator::Shape(g) => match g.shape {
                S::Box { .. } => "Shape(Box)",
                S::Polygon { .. } => "Shape(Polygon)",
                S::Circle { .. } => "Shape(Circle)",
                S::Ball { .. } => "Shape(Ball)",
                S::Cylinder { .. } => "Shape(Cylinder)",
                S::PolygonFile { .. } => "Shape(PolygonFile)",
                S::Stl { .. } => "Shape(Stl)",
            },
        }
    }

    /// The generator's `cut` regions, to read the files of the shapes among them.
    pub(crate) fn cut_mut(&mut self) -> &mut [Region] {
        match self {
            Generator::Block(b) => &mut b.cut,
            Generator::Disk(c) => &mut c.cut,
            Generator::Shape(g) => &mut g.cut,
            Generator::File(_) => &mut [],
        }
    }

    /// Lattice spacing Δx.
    pub fn spacing(&self) -> f64 {
        self.common().spacing
    }

    /// The ratio of the support radius to the spacing, `h = h_factor·Δx`.
    pub fn h_factor(&self) -> f64 {
        self.common().h_factor
    }

    pub(crate) fn common(&self) -> Common<'_> {
        match self {
            Generator::Block(b) => Common {
                spacing: b.spacing,
                lattice: b.lattice,
                density: b.density,
                h_factor: b.h_factor,
                clip: b.clip.as_ref(),
                cut: &b.cut,
                velocity: b.velocity.as_ref(),
                internal_energy: b.internal_energy,
                body: b.body.as_deref(),
            },
            Generator::Disk(c) => Common {
                spacing: c.spacing,
                lattice: c.lattice,
                density: c.density,
                h_factor: c.h_factor,
                clip: c.clip.as_ref(),
                cut: &c.cut,
                velocity: c.velocity.as_ref(),
                internal_energy: c.internal_energy,
                body: c.body.as_deref(),
            },
            Generator::Shape(g) => Common {
                spacing: g.spacing,
                lattice: g.lattice,
                density: g.density,
                h_factor: g.h_factor,
                clip: g.clip.as_ref(),
                cut: &g.cut,
                velocity: g.velocity.as_ref(),
                internal_energy: g.internal_energy,
                body: g.body.as_deref(),
            },
            // the particles carry their own values; spacing and h factor stand for them in
            // the checks (`FileParticles::spacing`), the density is never used
            Generator::File(f) => Common {
                spacing: f.spacing(),
                lattice: Lattice::Square,
                density: f64::NAN,
                h_factor: f.h_factor(),
                clip: None,
                cut: &[],
                velocity: None,
                internal_energy: 0.0,
                body: f.body.as_deref(),
            },
        }
    }
}

/// Optional neighbour-search settings.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct NeighbourSettings {
    /// Verlet skin added to the search radius, as a fraction of h (>= 0); default 0.15.
    /// With `tune_skin` it is the skin of the first build only.
    pub skin: f64,
    /// When true (the default), every build after the first chooses its skin from the
    /// measured motion by a cost model (`dualsph_core::neighbours::SkinRule::Tuned`); the
    /// results are bitwise the same for any skin, only the cost changes.
    pub tune_skin: bool,
}

impl Default for NeighbourSettings {
    fn default() -> Self {
        NeighbourSettings {
            skin: 0.15,
            tune_skin: true,
        }
    }
}
