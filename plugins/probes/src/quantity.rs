//! What a point or line probe measures, named like the snapshot columns.
//!
//! A quantity is one of
//! * a registered **scalar column** by its snapshot (VTK) name: `density`, `pressure`,
//!   `internal_energy`, `smoothing_length`, `mass`, or a plugin's own column;
//! * one **component of a vector column**: the column's name, a dot and the axis, `velocity.x`,
//!   `velocity.y`, `velocity.z` (up to the scene's dimension);
//! * one **entry of a matrix column**: the name, a dot and two axes, `velocity_gradient.xy`
//!   (row, then column);
//! * a **derived** value: `speed` (|v|) or `shepard_sum` (σ = Σ V_j W_j itself, ≈ 1 in the
//!   fluid, 0 outside; not normalised).
//!
//! In a scene the name is a string, `quantity: "velocity.x"`; a name that is a plain word
//! may also be written bare, `quantity: density`. The spellings `Density`, `Pressure`,
//! `VelocityX`, `VelocityY`, `VelocityZ`, `Speed`, `InternalEnergy` and `ShepardSum` name
//! the same quantities. The names are checked when the simulation is built, against the
//! columns its plugins registered: an unknown name is a build error that lists the names
//! available.

use dualsph_core::columns::{Column, Columns, Shape};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The derived quantity |v|.
pub const SPEED: &str = "speed";
/// The derived quantity σ = Σ V_j W_j.
pub const SHEPARD_SUM: &str = "shepard_sum";

const AXES: [char; 3] = ['x', 'y', 'z'];

/// What a point or line probe measures: a column name, a component of one, `speed` or
/// `shepard_sum` (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(try_from = "Spelling", into = "String")]
pub struct Quantity(String);

/// A quantity as written in a scene: a string, or a bare word, which RON hands to an untagged
/// enum by its name.
#[derive(Deserialize, schemars::JsonSchema)]
#[serde(
    untagged,
    expecting = "a quantity: a column name in quotes (\"density\", \"velocity.x\") or a bare word (density, Pressure)"
)]
enum Spelling {
    Name(String),
}

impl TryFrom<Spelling> for Quantity {
    type Error = String;
    fn try_from(s: Spelling) -> Result<Self, String> {
        let Spelling::Name(name) = s;
        Quantity::parse(&name)
    }
}

impl From<Quantity> for String {
    fn from(q: Quantity) -> String {
        q.0
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl Quantity {
    /// The quantity named `text` (the older spellings `Density`, `VelocityX`, … are taken for
    /// `density`, `velocity.x`, …); the error says what a name looks like. Whether a column
    /// of that name exists is checked when the simulation is built.
    pub fn parse(text: &str) -> Result<Self, String> {
        let name = match text {
            "Density" => "density",
            "Pressure" => "pressure",
            "VelocityX" => "velocity.x",
            "VelocityY" => "velocity.y",
            "VelocityZ" => "velocity.z",
            "Speed" => SPEED,
            "InternalEnergy" => "internal_energy",
            "ShepardSum" => SHEPARD_SUM,
            other => other,
        };
        let bad = |c: char| c.is_whitespace() || ",\"[]".contains(c);
        if name.is_empty() || name.chars().any(bad) {
            return Err(format!(
                "quantity {text:?}: expected a column name such as \"density\" or \
                 \"velocity.x\", without spaces, commas, quotes or brackets"
            ));
        }
        Ok(Quantity(name.to_string()))
    }

    /// The density column, `density`.
    pub fn density() -> Self {
        Quantity("density".to_string())
    }

    /// The name, as written in `probes_points.csv`.
    pub fn name(&self) -> &str {
        &self.0
    }
}

/// Where a quantity's per-particle values come from once the columns are known.
#[derive(Clone, Debug)]
pub enum Source {
    /// Component `k` (0 for a scalar) of a registered column.
    Column {
        /// The column.
        column: Column,
        /// The component.
        k: usize,
    },
    /// |v|.
    Speed,
    /// σ itself.
    ShepardSum,
}

/// The component named by `suffix` (`x`, `y`, `xy`, …) of a column of `shape` in dimension
/// `d`, or `None`.
fn component(shape: Shape, suffix: Option<&str>, d: usize) -> Option<usize> {
    let axis = |c: char| AXES[..d].iter().position(|&a| a == c);
    let chars: Vec<char> = suffix.map_or(Vec::new(), |s| s.chars().collect());
    match (shape, chars.as_slice()) {
        (Shape::Scalar, []) => Some(0),
        (Shape::Vector, [a]) => axis(*a),
        (Shape::Matrix, [a, b]) => Some(axis(*a)? * d + axis(*b)?),
        _ => None,
    }
}

/// The names a probe can measure in a `d`-dimensional scene with `columns`: every scalar
/// column, the components of every vector and matrix column (written `name.{x,y}`), `speed`
/// and `shepard_sum`.
pub fn available(columns: &Columns, d: usize) -> Vec<String> {
    let axes: Vec<String> = AXES[..d].iter().map(char::to_string).collect();
    let mut out: Vec<String> = columns
        .iter()
        .filter_map(|c| match c.shape {
            Shape::Scalar => Some(c.spec.name.to_string()),
            Shape::Vector => Some(format!("{}.{{{}}}", c.spec.name, axes.join(","))),
            Shape::Matrix => {
                let pairs: Vec<String> = axes
                    .iter()
                    .flat_map(|a| axes.iter().map(move |b| format!("{a}{b}")))
                    .collect();
                Some(format!("{}.{{{}}}", c.spec.name, pairs.join(",")))
            }
            Shape::Record => None,
        })
        .collect();
    out.extend([SPEED.to_string(), SHEPARD_SUM.to_string()]);
    out
}

/// Which plugin writes a column that scenes often probe.
fn hint(name: &str) -> &'static str {
    match name {
        "pressure" => " (an equation of state writes it: TaitEos or IdealGas)",
        "internal_energy" => " (a plugin that solves the energy equation writes it)",
        _ => "",
    }
}

/// The source of `q` among `columns` in a `d`-dimensional scene; the error says what is
/// missing and lists the names available.
pub fn resolve(q: &Quantity, columns: &Columns, d: usize) -> Result<Source, String> {
    match q.name() {
        SPEED => return Ok(Source::Speed),
        SHEPARD_SUM => return Ok(Source::ShepardSum),
        _ => {}
    }
    let (base, suffix) = match q.name().rsplit_once('.') {
        Some((b, s)) => (b, Some(s)),
        None => (q.name(), None),
    };
    let list = || available(columns, d).join(", ");
    let Some(column) = columns.iter().find(|c| c.spec.name == base) else {
        return Err(format!(
            "quantity `{q}`: the scene has no column `{base}`{}; the quantities it can probe \
             are: {}",
            hint(base),
            list()
        ));
    };
    match component(column.shape, suffix, d) {
        Some(k) => Ok(Source::Column {
            column: column.clone(),
            k,
        }),
        None => Err(format!(
            "quantity `{q}`: column `{base}` is a {} in {d}-D; the quantities the scene can \
             probe are: {}",
            match column.shape {
                Shape::Scalar => "scalar (name it without a component)",
                Shape::Vector => "vector (name one component: `.x`, `.y`, …)",
                Shape::Matrix => "matrix (name one entry: `.xx`, `.xy`, …)",
                Shape::Record => "record, which cannot be probed",
            },
            list()
        )),
    }
}
