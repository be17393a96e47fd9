//! [`OutputDir`]: the set of output files of one run.

use std::path::{Path, PathBuf};

use crate::csv_out::{
    DIAGNOSTICS_FIXED_COLUMNS, SnapshotEntry, diagnostics_header, format_diagnostics_row,
    read_snapshot_index, write_particles, write_snapshot_index,
};
use crate::growing::GrowingCsv;
use crate::loads::{BODIES_FILE, BodyLoadRow, LoadsTable};
use crate::vtk::{self, VtkEncoding};
use crate::{DiagnosticsRow, OutputError, ParticleTable, Real, write_atomic_with};

/// File name of the diagnostics table.
pub const DIAGNOSTICS_FILE: &str = "diagnostics.csv";
/// File name of the snapshot index.
pub const SNAPSHOT_INDEX_FILE: &str = "snapshots.csv";
/// File name of the ParaView collection of all snapshots.
pub const PVD_FILE: &str = "particles.pvd";
/// File name of the final particle table.
pub const FINAL_FILE: &str = "final.csv";

/// File stem of the snapshot of `step`: `particles_NNNNNN` with the step
/// zero-padded to 6 digits (more digits if the step needs them).
pub fn snapshot_stem(step: u64) -> String {
    format!("particles_{step:06}")
}

/// Which files a snapshot is written as: the particle CSV, the VTK PolyData (`.vtp`) in
/// `encoding`, both, or neither (then no snapshot is written or indexed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct OutputOptions {
    /// Write `particles_NNNNNN.csv`.
    pub csv: bool,
    /// Write `particles_NNNNNN.vtp` and list it in `particles.pvd`.
    pub vtk: bool,
    /// How the `.vtp` arrays are stored.
    pub encoding: VtkEncoding,
}

impl Default for OutputOptions {
    /// CSV and binary VTK.
    fn default() -> Self {
        OutputOptions {
            csv: true,
            vtk: true,
            encoding: VtkEncoding::Binary,
        }
    }
}

impl OutputOptions {
    /// True when snapshots are written in at least one format.
    pub fn any(&self) -> bool {
        self.csv || self.vtk
    }
}

/// The output directory of a run and the in-memory state of its growing
/// files (diagnostics rows and snapshot index).
///
/// `diagnostics.csv` and `bodies.csv` grow by whole rows; every other file is
/// rewritten completely and atomically when it changes, see the
/// [crate documentation](crate).
#[derive(Debug)]
pub struct OutputDir {
    dir: PathBuf,
    extra: Vec<String>,
    options: OutputOptions,
    /// `diagnostics.csv`.
    diag: GrowingCsv,
    /// Snapshot index, sorted by step.
    snapshots: Vec<SnapshotEntry>,
    /// The rows of `bodies.csv`, once [`OutputDir::enable_body_loads`] is called.
    loads: Option<LoadsTable>,
    /// The step a resumed run continues from ([`OutputDir::reopen`]).
    resumed_at: Option<u64>,
    /// The body names the `.vtp` files list ([`OutputDir::set_body_names`]).
    bodies: Vec<String>,
}

impl OutputDir {
    /// Create `dir` (and its parents) if needed and start a fresh run there.
    ///
    /// `diagnostics.csv` (header only), `snapshots.csv` (header only) and, when
    /// `options.vtk`, an empty `particles.pvd` are written immediately, replacing
    /// those of any earlier run in the same directory, and the `bodies.csv` of an
    /// earlier run is removed (see [`OutputDir::enable_body_loads`]); this also checks
    /// that the directory is writable. Old snapshot files are left alone. Extra column
    /// names must be non-empty, unique, and free of `,` `"` and line breaks.
    pub fn create(
        dir: &Path,
        extra_diag_columns: Vec<String>,
        options: OutputOptions,
    ) -> Result<Self, OutputError> {
        let out = Self::empty(dir, extra_diag_columns, options, GrowingCsv::create)?;
        out.write_snapshot_indexes()?;
        let stale = out.path(BODIES_FILE);
        match std::fs::remove_file(&stale) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(OutputError::Io {
                path: stale,
                op: "remove",
                source: e,
            }),
            _ => Ok(out),
        }
    }

    /// Resume a run in `dir`: re-read its `diagnostics.csv` and
    /// `snapshots.csv`, keep only rows with `step <= up_to_step`, and rewrite
    /// both files and (when `options.vtk`) `particles.pvd` atomically with the
    /// kept rows.
    ///
    /// Missing index files (or a missing directory) count as empty. The
    /// diagnostics header must match `extra_diag_columns`. Snapshot files of
    /// dropped steps stay on disk but are no longer listed; they are
    /// overwritten if the resumed run writes the same steps again.
    pub fn reopen(
        dir: &Path,
        extra_diag_columns: Vec<String>,
        up_to_step: u64,
        options: OutputOptions,
    ) -> Result<Self, OutputError> {
        let mut out = Self::empty(dir, extra_diag_columns, options, |path, header| {
            GrowingCsv::reopen(path, header, up_to_step)
        })?;
        let index_path = out.path(SNAPSHOT_INDEX_FILE);
        if index_path.exists() {
            out.snapshots = read_snapshot_index(&index_path)?;
            out.snapshots.retain(|e| e.step <= up_to_step);
            out.snapshots.sort_by_key(|e| e.step);
        }

        out.write_snapshot_indexes()?;
        out.resumed_at = Some(up_to_step);
        Ok(out)
    }

    /// Keep `DIR/bodies.csv`, the loads on the fixed and prescribed bodies
    /// (`t,step,body,fx,fy,fz,mx,my,mz`, one row per diagnostics step and body, see
    /// [`OutputDir::push_body_loads`]): written now with its header only, or, in a
    /// resumed run ([`OutputDir::reopen`]), re-read and rewritten with the rows up to
    /// the step resumed from (a missing file counts as empty).
    pub fn enable_body_loads(&mut self) -> Result<(), OutputError> {
        let path = self.path(BODIES_FILE);
        self.loads = Some(match self.resumed_at {
            Some(step) => LoadsTable::reopen(&path, step)?,
            None => LoadsTable::create(&path)?,
        });
        Ok(())
    }

    /// The body names, by body index, that every `.vtp` written from now on lists in its
    /// field data (`body_names`), so that a viewer can tell the `body` indices apart.
    pub fn set_body_names(&mut self, names: Vec<String>) {
        self.bodies = names;
    }

    /// Number of rows currently in `bodies.csv` (0 without it).
    pub fn body_loads_len(&self) -> usize {
        self.loads.as_ref().map_or(0, LoadsTable::len)
    }

    /// Put the rows of `step` (one per body, each of that step) in `DIR/bodies.csv`. Like diagnostics rows, they supersede the rows of `step`
    /// and later. An error when [`OutputDir::enable_body_loads`] was not called, or a
    /// row is of another step or names its body with `,` `"`, a line break or
    /// surrounding blanks (nothing is changed then).
    pub fn push_body_loads(&mut self, step: u64, rows: &[BodyLoadRow]) -> Result<(), OutputError> {
        let path = self.dir.join(BODIES_FILE);
        match &mut self.loads {
            Some(table) => table.push(step, rows),
            None => Err(OutputError::Invalid {
                path,
                msg: "body loads were not enabled for this output directory".into(),
            }),
        }
    }

    /// Validate the column names, create the directory and open `diagnostics.csv` with
    /// `open_diag(path, header)`; no other file is written.
    fn empty(
        dir: &Path,
        extra: Vec<String>,
        options: OutputOptions,
        open_diag: impl FnOnce(&Path, &[String]) -> Result<GrowingCsv, OutputError>,
    ) -> Result<Self, OutputError> {
        let diag_path = dir.join(DIAGNOSTICS_FILE);
        for (i, name) in extra.iter().enumerate() {
            let bad = name.is_empty()
                || name.contains([',', '"', '\n', '\r'])
                || name.trim() != name
                || DIAGNOSTICS_FIXED_COLUMNS.contains(&name.as_str())
                || extra[..i].contains(name);
            if bad {
                return Err(OutputError::Invalid {
                    path: diag_path,
                    msg: format!("invalid or duplicate extra column name {name:?}"),
                });
            }
        }
        std::fs::create_dir_all(dir).map_err(|source| OutputError::Io {
            path: dir.to_path_buf(),
            op: "create directory",
            source,
        })?;
        let diag = open_diag(&diag_path, &diagnostics_header(&extra))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            extra,
            options,
            diag,
            snapshots: Vec::new(),
            loads: None,
            resumed_at: None,
            bodies: Vec::new(),
        })
    }

    /// The output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The snapshot formats.
    pub fn options(&self) -> OutputOptions {
        self.options
    }

    /// Names of the extra diagnostics columns, in order.
    pub fn extra_diag_columns(&self) -> &[String] {
        &self.extra
    }

    /// The snapshot index (as in `snapshots.csv`), sorted by step.
    pub fn snapshots(&self) -> &[SnapshotEntry] {
        &self.snapshots
    }

    /// Number of rows currently in `diagnostics.csv`.
    pub fn diagnostics_len(&self) -> usize {
        self.diag.len()
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Append a row to `DIR/diagnostics.csv`.
    ///
    /// Steps are expected to increase; a row whose step is not larger than
    /// earlier rows supersedes them (rows with `step >= row.step` are dropped
    /// first, by an atomic rewrite), so re-running a step after a resume never
    /// duplicates rows. `row.extra` must have one value per extra column; on an
    /// error the file is unchanged.
    pub fn push_diagnostics(&mut self, row: DiagnosticsRow) -> Result<(), OutputError> {
        if row.extra.len() != self.extra.len() {
            return Err(OutputError::Invalid {
                path: self.path(DIAGNOSTICS_FILE),
                msg: format!(
                    "row has {} extra values but there are {} extra columns ({})",
                    row.extra.len(),
                    self.extra.len(),
                    self.extra.join(",")
                ),
            });
        }
        let line = format_diagnostics_row(&row);
        self.diag.push(row.step, &[line])
    }

    /// Make the rows of `diagnostics.csv` and `bodies.csv` written so far durable
    /// (`fsync`); done at every snapshot and by [`OutputDir::write_final`].
    pub fn sync(&self) -> Result<(), OutputError> {
        self.diag.sync()?;
        self.loads.as_ref().map_or(Ok(()), LoadsTable::sync)
    }

    /// Write the snapshot of `step` in the chosen formats, `DIR/particles_NNNNNN.csv` and/or
    /// `DIR/particles_NNNNNN.vtp` (`NNNNNN` = step zero-padded to 6 digits, more digits if
    /// needed), then rewrite `DIR/snapshots.csv` (`step,t,file`, file = the CSV name, or the
    /// `.vtp` name when no CSV is written) and `DIR/particles.pvd` (every `.vtp` with
    /// `timestep` = t) atomically. Without any format nothing is written or indexed.
    ///
    /// The CSV holds `id` and every column of the table; the VTK file one
    /// point and one vertex per particle with point data `id` (Int64) and
    /// every column but `position` (the points). Writing a step that is
    /// already indexed replaces its entry.
    pub fn write_snapshot(
        &mut self,
        step: u64,
        t: Real,
        particles: &ParticleTable,
    ) -> Result<(), OutputError> {
        self.sync()?;
        if !self.options.any() {
            return Ok(());
        }
        let stem = snapshot_stem(step);
        self.write_formats(&stem, particles, self.options.csv)?;
        let ext = if self.options.csv { "csv" } else { "vtp" };
        let entry = SnapshotEntry {
            step,
            t,
            file: format!("{stem}.{ext}"),
        };
        let old = self.snapshots.clone();
        match self.snapshots.binary_search_by_key(&step, |e| e.step) {
            Ok(i) => self.snapshots[i] = entry,
            Err(i) => self.snapshots.insert(i, entry),
        }
        let res = self.write_snapshot_indexes();
        if res.is_err() {
            self.snapshots = old;
        }
        res
    }

    /// Write `DIR/<stem>.csv` and, when VTK is among the formats, `DIR/<stem>.vtp`
    /// atomically, without indexing them (e.g. the last good state of a run that blew up).
    pub fn write_particles_as(
        &self,
        stem: &str,
        particles: &ParticleTable,
    ) -> Result<(), OutputError> {
        self.write_formats(stem, particles, true)
    }

    /// Writes `DIR/<stem>.csv` when `csv` and `DIR/<stem>.vtp` when VTK is chosen.
    fn write_formats(
        &self,
        stem: &str,
        particles: &ParticleTable,
        csv: bool,
    ) -> Result<(), OutputError> {
        let csv_path = self.path(&format!("{stem}.csv"));
        valid(&csv_path, particles)?;
        if csv {
            write_atomic_with(&csv_path, |w| write_particles(w, particles))?;
        }
        if self.options.vtk {
            write_atomic_with(&self.path(&format!("{stem}.vtp")), |w| {
                vtk::write_vtp(w, particles, self.options.encoding, &self.bodies)
            })?;
        }
        Ok(())
    }

    /// Write `DIR/final.csv` with the same columns as the snapshot CSVs.
    pub fn write_final(&self, particles: &ParticleTable) -> Result<(), OutputError> {
        self.sync()?;
        valid(&self.path(FINAL_FILE), particles)?;
        write_atomic_with(&self.path(FINAL_FILE), |w| write_particles(w, particles))
    }

    fn write_snapshot_indexes(&self) -> Result<(), OutputError> {
        write_atomic_with(&self.path(SNAPSHOT_INDEX_FILE), |w| {
            write_snapshot_index(w, &self.snapshots)
        })?;
        if !self.options.vtk {
            return Ok(());
        }
        write_atomic_with(&self.path(PVD_FILE), |w| vtk::write_pvd(w, &self.snapshots))
    }
}

/// The table's columns fit its rows, or an [`OutputError::Invalid`] for `path`.
fn valid(path: &Path, table: &ParticleTable) -> Result<(), OutputError> {
    table.check().map_err(|msg| OutputError::Invalid {
        path: path.to_path_buf(),
        msg,
    })
}
