//! The optional `output` section: diagnostics cadence, when snapshots are written (every N
//! steps or every Δt of simulated time), in which formats, and with which columns.
//!
//! ```ron
//! output: (
//!     diagnostics_every: 10,
//!     snapshot_dt: 0.05,            // or snapshot_every: 200 (steps), not both
//!     formats: [Csv, Vtk],          // [] = no snapshot files
//!     vtk_encoding: Binary,         // Compressed (zlib) or Ascii
//!     columns: ["velocity", "pressure"], // position and id are always written
//! )
//! ```

use serde::Deserialize;
use serde::de::{self, Deserializer};

use crate::de::int;
use crate::error::Problem;

/// A snapshot file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize)]
pub enum OutputFormat {
    /// `particles_NNNNNN.csv`: a table with a header, one row per particle.
    Csv,
    /// `particles_NNNNNN.vtp`: VTK XML PolyData, listed in `particles.pvd` for ParaView.
    Vtk,
}

/// How the arrays of the VTK files are stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize)]
pub enum VtkEncoding {
    /// Raw little-endian binary in the file's appended section (compact and exact).
    #[default]
    Binary,
    /// Like `Binary`, zlib-compressed (`vtkZLibDataCompressor`).
    Compressed,
    /// Text (readable, larger, slower).
    Ascii,
}

/// The default snapshot cadence in steps.
pub const DEFAULT_SNAPSHOT_EVERY: u64 = 200;

/// The optional `output` section.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSettings {
    /// Steps between diagnostics lines (>= 1); default 10.
    #[serde(deserialize_with = "int::de")]
    pub diagnostics_every: u64,
    /// Steps between snapshots (0 = none); default 200. Ignored when `snapshot_dt` is given
    /// (which then requires it to be left at its default or 0).
    #[serde(deserialize_with = "int::de")]
    pub snapshot_every: u64,
    /// Simulated seconds between snapshots: a snapshot is written at the first step whose t
    /// reaches each multiple `k·snapshot_dt` (and at t = 0 and at the end). A finite number
    /// > 0, refused at its position otherwise.
    #[serde(deserialize_with = "snapshot_dt")]
    pub snapshot_dt: Option<f64>,
    /// Snapshot file formats, each at most once; default `[Csv, Vtk]`; `[]` writes no snapshot
    /// files (`diagnostics.csv` and `final.csv` are always written).
    #[serde(deserialize_with = "formats")]
    pub formats: Vec<OutputFormat>,
    /// How VTK arrays are stored; default `Binary`.
    pub vtk_encoding: VtkEncoding,
    /// The output columns written to snapshots and `final.csv`, by registered name
    /// (`dualsph plan` lists them); `None` = every output column. `position` and `id` are
    /// always written. The names are checked when the simulation is built (plugins register
    /// columns); each may be given once.
    #[serde(deserialize_with = "columns")]
    pub columns: Option<Vec<String>>,
}

impl Default for OutputSettings {
    fn default() -> Self {
        OutputSettings {
            diagnostics_every: 10,
            snapshot_every: DEFAULT_SNAPSHOT_EVERY,
            snapshot_dt: None,
            formats: vec![OutputFormat::Csv, OutputFormat::Vtk],
            vtk_encoding: VtkEncoding::Binary,
            columns: None,
        }
    }
}

impl OutputSettings {
    /// Whether snapshots are written in `format`.
    pub fn writes(&self, format: OutputFormat) -> bool {
        self.formats.contains(&format)
    }

    /// The checks between fields: `diagnostics_every >= 1`, and not both cadences.
    pub(crate) fn check(&self) -> Result<(), Problem> {
        if self.diagnostics_every == 0 {
            return Err(Problem::new(
                "output.diagnostics_every",
                "must be at least 1",
            ));
        }
        let every = self.snapshot_every;
        if let Some(dt) = self.snapshot_dt
            && every != 0
            && every != DEFAULT_SNAPSHOT_EVERY
        {
            return Err(Problem::new(
                "output.snapshot_dt",
                format!(
                    "both snapshot_dt ({dt} s) and snapshot_every ({every} steps) are given: \
                     the snapshot cadence is ambiguous; keep one of them"
                ),
            ));
        }
        Ok(())
    }
}

/// `None`, or a finite number > 0 (refused where it stands).
fn snapshot_dt<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    let dt = Option::<f64>::deserialize(d)?;
    match dt {
        Some(x) if !(x.is_finite() && x > 0.0) => Err(de::Error::custom(format!(
            "snapshot_dt must be a finite number of seconds > 0, got {x}"
        ))),
        _ => Ok(dt),
    }
}

/// A list of formats without duplicates.
fn formats<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<OutputFormat>, D::Error> {
    let list = Vec::<OutputFormat>::deserialize(d)?;
    if let Some(i) = (1..list.len()).find(|&i| list[..i].contains(&list[i])) {
        return Err(de::Error::custom(format!(
            "formats lists {:?} twice",
            list[i]
        )));
    }
    Ok(list)
}

/// `None`, or a list of distinct non-empty column names.
fn columns<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<String>>, D::Error> {
    let list = Option::<Vec<String>>::deserialize(d)?;
    if let Some(names) = &list {
        if names.iter().any(|n| n.trim().is_empty()) {
            return Err(de::Error::custom("columns holds an empty name"));
        }
        if let Some(i) = (1..names.len()).find(|&i| names[..i].contains(&names[i])) {
            return Err(de::Error::custom(format!(
                "columns lists {:?} twice",
                names[i]
            )));
        }
    }
    Ok(list)
}
