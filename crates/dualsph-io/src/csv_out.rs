//! CSV formatting and parsing: particle tables, the diagnostics table and the
//! snapshot index. Writing is done by hand (every field is a number or a plain
//! file name, so no quoting is ever needed); reading uses the `csv` crate.

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;
use std::str::FromStr;

use crate::{DiagnosticsRow, OutputError, ParticleTable, Real, TableColumn};

/// Fixed leading column names of `diagnostics.csv`; extra columns follow.
pub const DIAGNOSTICS_FIXED_COLUMNS: [&str; 13] = [
    "t", "step", "dt", "n", "mass", "px", "py", "pz", "lz", "e_kin", "e_int", "e_pot", "e_tot",
];

/// Column names of `snapshots.csv`.
pub const SNAPSHOT_INDEX_COLUMNS: [&str; 3] = ["step", "t", "file"];

/// Append `x` so that parsing it back with `str::parse::<f64>` gives the same
/// bits. Rust's `Display`/`LowerExp` without precision print the shortest
/// round-tripping digits; exponent form is used for very small/large
/// magnitudes to keep the text short. NaN and infinities print as `NaN`,
/// `inf`, `-inf`, which `f64::from_str` accepts.
pub(crate) fn push_real(out: &mut String, x: Real) {
    let a = x.abs();
    // `write!` into a String cannot fail.
    let _ = if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        write!(out, "{x:e}")
    } else {
        write!(out, "{x}")
    };
}

/// Format one real (see [`push_real`]).
pub(crate) fn fmt_real(x: Real) -> String {
    let mut s = String::new();
    push_real(&mut s, x);
    s
}

/// Write a particle table: the header `id` and every column's labels, then one line per
/// particle.
pub(crate) fn write_particles(w: &mut dyn Write, table: &ParticleTable) -> io::Result<()> {
    let labels = table
        .columns
        .iter()
        .flat_map(|c| c.labels.iter().map(String::as_str));
    let header: Vec<&str> = std::iter::once("id").chain(labels).collect();
    writeln!(w, "{}", header.join(","))?;
    let mut line = String::with_capacity(256);
    for (k, id) in table.ids.iter().enumerate() {
        line.clear();
        let _ = write!(line, "{id}");
        for x in table.columns.iter().flat_map(|c| c.row(k)) {
            line.push(',');
            push_real(&mut line, *x);
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// Format one diagnostics row (without trailing newline).
pub(crate) fn format_diagnostics_row(row: &DiagnosticsRow) -> String {
    let mut s = String::with_capacity(256);
    push_real(&mut s, row.t);
    let _ = write!(s, ",{}", row.step);
    s.push(',');
    push_real(&mut s, row.dt);
    let _ = write!(s, ",{}", row.n);
    let reals = [
        row.mass, row.p[0], row.p[1], row.p[2], row.lz, row.e_kin, row.e_int, row.e_pot, row.e_tot,
    ];
    for x in reals.into_iter().chain(row.extra.iter().copied()) {
        s.push(',');
        push_real(&mut s, x);
    }
    s
}

/// Full header of `diagnostics.csv` for the given extra columns.
pub(crate) fn diagnostics_header(extra: &[String]) -> Vec<String> {
    DIAGNOSTICS_FIXED_COLUMNS
        .iter()
        .map(|s| s.to_string())
        .chain(extra.iter().cloned())
        .collect()
}

/// A headered CSV reader over `input`, fields trimmed: how every table of a run is read.
pub(crate) fn reader<R: std::io::Read>(input: R) -> csv::Reader<R> {
    csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(input)
}

/// The error of a CSV record or header read from `path`.
pub(crate) fn csv_error(path: &Path) -> impl Fn(csv::Error) -> OutputError + '_ {
    move |source| OutputError::Csv {
        path: path.to_path_buf(),
        source,
    }
}

/// The header row of `rdr`, read from `path`.
pub(crate) fn read_header<R: std::io::Read>(
    path: &Path,
    rdr: &mut csv::Reader<R>,
) -> Result<Vec<String>, OutputError> {
    let header = rdr.headers().map_err(csv_error(path))?;
    Ok(header.iter().map(str::to_owned).collect())
}

/// Read the header row and all records of a CSV file as strings.
/// Each record is returned with its 1-based line number.
pub(crate) fn read_table(
    path: &Path,
) -> Result<(Vec<String>, Vec<(u64, csv::StringRecord)>), OutputError> {
    let file =
        crate::bounded_reader(path, crate::INPUT_FILE_LIMIT).map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            op: "open",
            source,
        })?;
    let mut rdr = reader(file);
    let header = read_header(path, &mut rdr)?;
    let mut rows = Vec::new();
    for rec in rdr.records() {
        let rec = rec.map_err(csv_error(path))?;
        let line = rec.position().map_or(0, |p| p.line());
        rows.push((line, rec));
    }
    Ok((header, rows))
}

/// Parse field `i` of `rec` as `T`, with an error naming path, line and column.
pub(crate) fn parse_field<T: FromStr>(
    path: &Path,
    line: u64,
    rec: &csv::StringRecord,
    i: usize,
    column: &str,
) -> Result<T, OutputError> {
    // the value is not quoted: a file that is not what it should be stays unprinted
    let raw = rec.get(i).unwrap_or("");
    raw.parse().map_err(|_| OutputError::Parse {
        path: path.to_path_buf(),
        line,
        msg: format!("column {} ({}): not a number", i + 1, printable(column)),
    })
}

/// A column label fit to print: one of the engine's own (letters, digits, `_`, `.`, up to 32
/// characters), else only its length, so a file that is not a particle file is never
/// echoed.
fn printable(label: &str) -> String {
    let own = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '.';
    if label.len() <= 32 && label.chars().all(own) {
        format!("`{label}`")
    } else {
        format!("a label of {} characters", label.chars().count())
    }
}

/// Error for a header that differs from the expected one (the header found is not quoted).
pub(crate) fn header_mismatch(path: &Path, found: &[String], expected: &[String]) -> OutputError {
    OutputError::Parse {
        path: path.to_path_buf(),
        line: 1,
        msg: format!(
            "unexpected header ({} columns), expected `{}`",
            found.len(),
            expected.join(",")
        ),
    }
}

/// Read every column of a particle CSV as a [`ParticleTable`]: the `id` column as the ids,
/// every other column as a one-component column named by its label, in file order; values
/// bit for bit as written.
pub fn read_particle_table_csv(path: &Path) -> Result<ParticleTable, OutputError> {
    let (header, rows) = read_table(path)?;
    let id = header.iter().position(|h| h == "id");
    let mut table = ParticleTable {
        ids: Vec::with_capacity(rows.len()),
        columns: header
            .iter()
            .enumerate()
            .filter(|&(k, _)| Some(k) != id)
            .map(|(_, h)| TableColumn {
                name: h.clone(),
                labels: vec![h.clone()],
                values: Vec::with_capacity(rows.len()),
            })
            .collect(),
    };
    for (line, rec) in rows {
        table.ids.push(match id {
            Some(i) => parse_field(path, line, &rec, i, "id")?,
            None => table.ids.len() as u64,
        });
        let others = (0..header.len()).filter(|&k| Some(k) != id);
        for (c, k) in table.columns.iter_mut().zip(others) {
            c.values.push(parse_field(path, line, &rec, k, &header[k])?);
        }
    }
    Ok(table)
}

/// Read a diagnostics CSV: returns the header and every row as reals
/// (integer columns such as `step` and `n` are converted to `f64`).
pub fn read_diagnostics_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<Real>>), OutputError> {
    let (header, rows) = read_table(path)?;
    let mut out = Vec::with_capacity(rows.len());
    for (line, rec) in rows {
        let vals = (0..rec.len())
            .map(|i| parse_field(path, line, &rec, i, &header[i]))
            .collect::<Result<Vec<Real>, _>>()?;
        out.push(vals);
    }
    Ok((header, out))
}

/// One entry of the snapshot index `snapshots.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct SnapshotEntry {
    /// Simulation step of the snapshot.
    pub step: u64,
    /// Simulation time of the snapshot.
    pub t: Real,
    /// File name (relative to the output directory) of the particle CSV, or of the `.vtp`
    /// when the run writes no CSV snapshots.
    pub file: String,
}

impl SnapshotEntry {
    /// File name (relative to the output directory) of the matching `.vtp`.
    pub fn vtp_file(&self) -> String {
        match self.file.strip_suffix(".csv") {
            Some(stem) => format!("{stem}.vtp"),
            None if self.file.ends_with(".vtp") => self.file.clone(),
            None => format!("{}.vtp", self.file),
        }
    }
}

/// Write the snapshot index.
pub(crate) fn write_snapshot_index(w: &mut dyn Write, entries: &[SnapshotEntry]) -> io::Result<()> {
    writeln!(w, "{}", SNAPSHOT_INDEX_COLUMNS.join(","))?;
    for e in entries {
        writeln!(w, "{},{},{}", e.step, fmt_real(e.t), e.file)?;
    }
    Ok(())
}

/// Read the snapshot index.
pub(crate) fn read_snapshot_index(path: &Path) -> Result<Vec<SnapshotEntry>, OutputError> {
    let (header, rows) = read_table(path)?;
    if header != SNAPSHOT_INDEX_COLUMNS {
        let expected: Vec<String> = SNAPSHOT_INDEX_COLUMNS
            .iter()
            .map(|s| s.to_string())
            .collect();
        return Err(header_mismatch(path, &header, &expected));
    }
    rows.into_iter()
        .map(|(line, rec)| {
            Ok(SnapshotEntry {
                step: parse_field(path, line, &rec, 0, "step")?,
                t: parse_field(path, line, &rec, 1, "t")?,
                file: rec.get(2).unwrap_or("").to_owned(),
            })
        })
        .collect()
}
