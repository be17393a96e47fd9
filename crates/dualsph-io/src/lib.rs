//! Crash-safe output files of a dualsph simulation run.
//!
//! Every file is written **atomically** ([`write_atomic`]): the content goes to
//! a temporary file in the destination directory, which is flushed, fsync'ed
//! and then renamed onto the final name. After a crash a file name therefore
//! holds either the old or the new complete content, never a torn file.
//!
//! The two tables that grow by a row (or a row per body) at every diagnostics
//! step, `diagnostics.csv` and `bodies.csv`, are appended to instead, since
//! rewriting them whole at every row costs time quadratic in the rows: each
//! step's rows go in one write of complete lines, a failed write is cut off
//! again, rows that a re-run step supersedes are replaced by an atomic rewrite,
//! and the rows are made durable (fsync) at every snapshot and at the end. A
//! crash in the middle of an append can leave an incomplete last line, which a
//! resumed run cuts off. The snapshot index (`snapshots.csv`, `particles.pvd`),
//! a line per snapshot, is rewritten atomically whenever it changes.
//!
//! Layout of an output directory `DIR`:
//!
//! | file | content |
//! |------|---------|
//! | `diagnostics.csv` | `t,step,dt,n,mass,px,py,pz,lz,e_kin,e_int,e_pot,e_tot` + extra columns |
//! | `particles_NNNNNN.csv` | particle table at step `NNNNNN`: `id` and the labels of every column of the [`ParticleTable`] (the scene's chosen output columns: `x,y,z,vx,vy,vz,m,rho,h`, then the plugins') |
//! | `particles_NNNNNN.vtp` | the same particles as VTK XML PolyData (`position` as the points, every other column as point data), in the [`VtkEncoding`] of the [`OutputOptions`] |
//! | `snapshots.csv` | snapshot index `step,t,file` (file: the CSV, or the `.vtp` without CSV snapshots) |
//! | `particles.pvd` | ParaView collection of all `.vtp` files with their times (only with VTK snapshots) |
//! | `final.csv` | particle table at the end of the run |
//! | `bodies.csv` | the load on each fixed or prescribed body: `t,step,body,fx,fy,fz,mx,my,mz`, one row per diagnostics step and body (only when [`OutputDir::enable_body_loads`] is called) |
//!
//! Which snapshot files are written is set by [`OutputOptions`]; `diagnostics.csv`,
//! `snapshots.csv` and `final.csv` are always written. The VTK writer ([`write_vti`] for
//! grids) is described in its module: ASCII, raw appended binary, or zlib-compressed
//! appended binary.
//!
//! Reals are written with the shortest decimal text that parses back to the
//! identical `f64`, so CSV round trips are bit-exact.
#![warn(missing_docs)]

mod atomic;
mod csv_out;
mod growing;
mod input;
mod loads;
mod output_dir;
mod table;
mod vtk;
mod vtp_read;

#[cfg(test)]
mod test_particles;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod vtk_tests;

use std::io;
use std::path::{Path, PathBuf};

pub use atomic::{write_atomic, write_atomic_with};
pub use csv_out::{
    DIAGNOSTICS_FIXED_COLUMNS, SNAPSHOT_INDEX_COLUMNS, SnapshotEntry, read_diagnostics_csv,
    read_particle_table_csv,
};
pub use growing::GrowingCsv;
pub use input::{
    INPUT_FILE_LIMIT, SCENE_FILE_LIMIT, bounded_reader, open_input, read_input, read_input_text,
};
pub use loads::{BODIES_COLUMNS, BODIES_FILE, BodyLoadRow, read_body_loads};
pub use output_dir::{
    DIAGNOSTICS_FILE, FINAL_FILE, OutputDir, OutputOptions, PVD_FILE, SNAPSHOT_INDEX_FILE,
    snapshot_stem,
};
pub use table::{
    DENSITY, INTERNAL_ENERGY, MASS, POSITION, PRESSURE, ParticleRow, ParticleTable,
    SMOOTHING_LENGTH, STANDARD_COLUMNS, TableColumn, VELOCITY,
};
pub use vtk::{
    ArrayValues, BODY_NAMES_ARRAY, ImageGrid, VOLUME_ARRAY, VtkArray, VtkEncoding, ZLIB_BLOCK,
    write_vti,
};
pub use vtp_read::read_particle_table_vtp;

/// Floating-point type of all written quantities.
pub type Real = f64;

/// One diagnostics row: fixed columns
/// `t,step,dt,n,mass,px,py,pz,lz,e_kin,e_int,e_pot,e_tot`, then `extra` values
/// in the order of the extra column names given to [`OutputDir`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DiagnosticsRow {
    /// Simulation time.
    pub t: Real,
    /// Step number.
    pub step: u64,
    /// Time step used for the step.
    pub dt: Real,
    /// Number of particles.
    pub n: u64,
    /// Total mass.
    pub mass: Real,
    /// Total linear momentum (`px,py,pz`).
    pub p: [Real; 3],
    /// Total angular momentum about the z axis.
    pub lz: Real,
    /// Total kinetic energy.
    pub e_kin: Real,
    /// Total internal energy.
    pub e_int: Real,
    /// Total potential energy.
    pub e_pot: Real,
    /// Total energy.
    pub e_tot: Real,
    /// Values of the extra columns, same order and count as the column names.
    pub extra: Vec<Real>,
}

/// Reads a particle file this crate wrote: a `.vtp` snapshot (its arrays by name, the points
/// as [`POSITION`]) or a particle CSV (snapshot or `final.csv`), whose labels of the
/// [`STANDARD_COLUMNS`] are grouped into those columns (`vx, vy, vz` → `velocity`) and every
/// other label kept as a one-component column of that name. Values come back bit for bit.
pub fn read_particles(path: &Path) -> Result<ParticleTable, OutputError> {
    let vtp = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("vtp"));
    if vtp {
        return read_particle_table_vtp(path);
    }
    let groups: Vec<(String, Vec<String>)> = STANDARD_COLUMNS
        .iter()
        .map(|(n, l)| (n.to_string(), l.iter().map(|l| l.to_string()).collect()))
        .collect();
    Ok(read_particle_table_csv(path)?.grouped(&groups))
}

/// Error of an output operation; every variant names the file or directory
/// concerned.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// An I/O operation failed.
    #[error("cannot {op} {}: {source}", path.display())]
    Io {
        /// File or directory concerned.
        path: PathBuf,
        /// What was attempted (e.g. `"write"`, `"create directory"`).
        op: &'static str,
        /// Underlying error.
        #[source]
        source: io::Error,
    },
    /// A CSV file could not be read as a table.
    #[error("malformed CSV file {}: {source}", path.display())]
    Csv {
        /// File concerned.
        path: PathBuf,
        /// Underlying error.
        #[source]
        source: csv::Error,
    },
    /// A CSV file has an unexpected header or an unparsable value.
    #[error("{}, line {line}: {msg}", path.display())]
    Parse {
        /// File concerned.
        path: PathBuf,
        /// 1-based line number.
        line: u64,
        /// What is wrong.
        msg: String,
    },
    /// The data handed to the writer do not fit the file (e.g. wrong number
    /// of extra diagnostics values, invalid column name).
    #[error("invalid data for {}: {msg}", path.display())]
    Invalid {
        /// File concerned.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
}

impl OutputError {
    /// The file or directory the error is about.
    pub fn path(&self) -> &Path {
        match self {
            OutputError::Io { path, .. }
            | OutputError::Csv { path, .. }
            | OutputError::Parse { path, .. }
            | OutputError::Invalid { path, .. } => path,
        }
    }
}
