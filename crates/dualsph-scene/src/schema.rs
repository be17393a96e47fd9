//! The parts of a scene file. Every struct rejects unknown fields; vectors are RON lists whose
//! length must equal the scene dimension (checked by validation, not by the parser).

use crate::particles_file::FileParticles;
use crate::shapes::{Region, ShapeGenerator};
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Which SPH formulation the engine runs (mapped onto the core's sweep by the engine).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize, Serialize)]
pub enum Formulation {
    /// Dual-support SPH: every pair interacts through the support of one particle and the
    /// dual-support of the other, so momentum and energy are conserved exactly (§5 of Ren, Dai,
    /// Zhuang & Rabczuk, *Dual-support Smoothed Particle Hydrodynamics*, preprint; RenDSSPH in
    /// docs/references.md).
    DualSupport,
    /// Variable-h SPH that uses only each particle's own support (not exactly conservative).
    SingleSupport,
    /// Classical SPH with one common smoothing length.
    ConstantH,
    /// Variable-h SPH symmetrised by averaging the two kernels of a pair.
    AveragedKernel,
    /// Grad-h SPH (Springel & Hernquist 2002; Price 2012): h tied to the summation density at
    /// every step, `h_i = n (m_i/ρ_i)^{1/d}` with `ρ_i = Σ_j m_j W(r_ij, h_i)` solved together
    /// (n from the scene's `SmoothingLengthUpdate`), and the Ω terms in the pressure and
    /// viscous forces. Needs `SummationDensity()` and `SmoothingLengthUpdate(...)`.
    GradH,
}

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

/// An axis-aligned box used by `clip` and `cut`; a point is inside when
/// `min_k <= x_k <= max_k` on every axis.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxRegion {
    /// Lower corner.
    pub min: Vec<f64>,
    /// Upper corner.
    pub max: Vec<f64>,
}

impl BoxRegion {
    /// Whether `p` lies in the box (bounds included) on the first `d` axes.
    pub fn contains(&self, p: &[f64; 3], d: usize) -> bool {
        (0..d).all(|k| {
            let lo = self.min.get(k).copied().unwrap_or(f64::NAN);
            let hi = self.max.get(k).copied().unwrap_or(f64::NAN);
            lo <= p[k] && p[k] <= hi
        })
    }
}

/// How lattice points fill a generator's box.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize, Serialize)]
pub enum Lattice {
    /// Cell-centred square/cubic lattice: `min + (i + 0.5)·Δx` on every axis.
    Square,
    /// Like `Square`, but alternate rows (index along axis 1; in 3-D alternate layers along
    /// axis 2, shifting axes 0 and 1) use offsets `0.25Δx` (even) and `0.75Δx` (odd) instead
    /// of `0.5Δx`. In 1-D it equals `Square`.
    Staggered,
}

/// The initial velocity of a generator's particles.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
pub enum Velocity {
    /// The same velocity for every particle.
    Uniform(Vec<f64>),
    /// `v = G·x` with `G` given by its rows (a d×d matrix) and `x` the absolute position.
    Linear(Vec<Vec<f64>>),
    /// The 2-D Taylor–Green vortex of wavelength `L` and peak speed `U`, with `k = 2π/L` and
    /// `x` the absolute position: `u = U sin(kx) cos(ky)`, `v = −U cos(kx) sin(ky)`
    /// (Taylor & Green 1937, *Proc. R. Soc. Lond. A* 158, 499). Divergence-free; with
    /// kinematic viscosity ν it is an exact Navier–Stokes solution decaying as `e^{−2νk²t}`.
    TaylorGreen {
        /// `U`.
        speed: f64,
        /// `L`.
        wavelength: f64,
    },
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
    /// Lattice kind.
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
    /// Lattice kind.
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

/// What moves a body's particles.
#[derive(Clone, Debug, PartialEq, Default, Deserialize, Serialize)]
pub enum BodyKind {
    /// Integrated in time by the forces on them (the default).
    #[default]
    Fluid,
    /// Held at their initial positions with zero velocity: a wall or a fixed obstacle.
    Fixed,
    /// Moved by a law of time whatever the forces (a piston, a flap, a lid):
    /// `Prescribed(Translate(velocity: [1.0, 0.0]))`.
    Prescribed(MotionSettings),
}

/// A prescribed body's law of motion (time from the start of the run; vectors with the
/// scene's dimension).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub enum MotionSettings {
    /// `x = x_0 + velocity·t`.
    Translate {
        /// Velocity (m/s).
        velocity: Vec<f64>,
    },
    /// A surface moving along itself (a belt, a cavity's lid): the particles stay at `x_0`
    /// and carry `velocity` (m/s) into the fluid's equations.
    Slide {
        /// Velocity (m/s).
        velocity: Vec<f64>,
    },
    /// `x = x_0 + amplitude (sin(2π frequency t + phase) − sin(phase))`.
    Oscillate {
        /// Amplitude vector (m).
        amplitude: Vec<f64>,
        /// Frequency (Hz).
        frequency: f64,
        /// Phase (rad, default 0).
        #[serde(default)]
        phase: f64,
    },
    /// A rotation at `omega` (rad/s, counter-clockwise) about `center`, about the z axis in
    /// 2-D and about `axis` in 3-D.
    Rotate {
        /// The point on the axis.
        center: Vec<f64>,
        /// The axis direction (3-D only).
        #[serde(default)]
        axis: Option<Vec<f64>>,
        /// Angular velocity (rad/s).
        omega: f64,
    },
}

/// A named body: `Body(name: "water")`, `Body(name: "tank", kind: Fixed)`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename = "Body")]
pub struct BodySettings {
    /// The name generators and plugins refer to it by.
    pub name: String,
    /// What moves it (default `Fluid`).
    #[serde(default)]
    pub kind: BodyKind,
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

/// Deserializes an identifier (a struct field or enum variant name) as an owned string.
pub(crate) struct Ident;

impl<'de> DeserializeSeed<'de> for Ident {
    type Value = String;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<String, D::Error> {
        d.deserialize_identifier(IdentVisitor)
    }
}

struct IdentVisitor;

impl Visitor<'_> for IdentVisitor {
    type Value = String;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an identifier")
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<String, E> {
        Ok(v.to_owned())
    }
}

/// `clip` accepts `Some((min: .., max: ..))`, `Some(min: .., max: ..)`, `(min: .., max: ..)`
/// and `None`. (With ron's `UNWRAP_VARIANT_NEWTYPES` a derived struct inside `Some(..)`
/// would reject the double parentheses, hence this hand-written visitor that takes the box
/// from whatever map ron offers.)
pub(crate) fn deserialize_clip<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<BoxRegion>, D::Error> {
    Ok(Option::<AnyBox>::deserialize(d)?.map(|b| b.0))
}

struct AnyBox(BoxRegion);

impl<'de> Deserialize<'de> for AnyBox {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(AnyBoxVisitor)
    }
}

struct AnyBoxVisitor;

impl<'de> Visitor<'de> for AnyBoxVisitor {
    type Value = AnyBox;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a clip box `(min: [..], max: [..])`")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<AnyBox, A::Error> {
        let (mut min, mut max) = (None, None);
        while let Some(key) = map.next_key_seed(Ident)? {
            let slot = match key.as_str() {
                "min" => &mut min,
                "max" => &mut max,
                other => {
                    return Err(de::Error::custom(format!(
                        "unknown field `{other}` in clip box, expected `min` or `max`"
                    )));
                }
            };
            if slot.is_some() {
                return Err(de::Error::custom(format!(
                    "duplicate field `{key}` in clip box"
                )));
            }
            *slot = Some(map.next_value::<Vec<f64>>()?);
        }
        let missing = |f: &str| de::Error::custom(format!("clip box is missing field `{f}`"));
        let min = min.ok_or_else(|| missing("min"))?;
        let max = max.ok_or_else(|| missing("max"))?;
        Ok(AnyBox(BoxRegion { min, max }))
    }
}

/// Integer fields read through `deserialize_any`, so a float or a string is reported as "expected
/// a non-negative integer" at its own position (ron's typed integer parser would stop at the
/// `.` of `2.5` and complain about a missing comma instead).
pub(crate) mod int {
    use serde::de::{self, Deserializer, Unexpected, Visitor};
    use std::fmt;
    use std::marker::PhantomData;

    struct Int;

    impl Visitor<'_> for Int {
        type Value = u64;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a non-negative integer")
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<u64, E> {
            Ok(v)
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<u64, E> {
            u64::try_from(v).map_err(|_| E::invalid_value(Unexpected::Signed(v), &self))
        }
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<u64, E> {
            Err(E::invalid_type(Unexpected::Float(v), &self))
        }
    }

    /// A non-negative integer that fits `T`.
    pub(crate) fn de<'de, D: Deserializer<'de>, T: TryFrom<u64>>(d: D) -> Result<T, D::Error> {
        let v = d.deserialize_any(Int)?;
        T::try_from(v).map_err(|_| de::Error::custom(format!("integer {v} is out of range")))
    }

    struct OptInt<T>(PhantomData<T>);

    impl<'de, T: TryFrom<u64>> Visitor<'de> for OptInt<T> {
        type Value = Option<T>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("`None` or a non-negative integer")
        }
        fn visit_none<E: de::Error>(self) -> Result<Option<T>, E> {
            Ok(None)
        }
        fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Option<T>, D::Error> {
            de(d).map(Some)
        }
    }

    /// `None`, `Some(n)` or (implicitly) `n`.
    pub(crate) fn de_opt<'de, D: Deserializer<'de>, T: TryFrom<u64>>(
        d: D,
    ) -> Result<Option<T>, D::Error> {
        d.deserialize_option(OptInt(PhantomData))
    }
}
