//! `bodies.csv`: the load on every fixed or prescribed body, one row per (diagnostics step,
//! body), growing by whole rows like `diagnostics.csv`.

use std::path::Path;

use crate::csv_out::{header_mismatch, parse_field, push_real, read_table};
use crate::growing::GrowingCsv;
use crate::{OutputError, Real};

/// File name of the table of body loads.
pub const BODIES_FILE: &str = "bodies.csv";

/// Column names of `bodies.csv`: time, step, the body's name, the force on it and its moment
/// (3-D components whatever the dimension: `fz, mx, my` are 0 in 2-D).
pub const BODIES_COLUMNS: [&str; 9] = ["t", "step", "body", "fx", "fy", "fz", "mx", "my", "mz"];

/// One row of `bodies.csv`: the load on one body at one diagnostics step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BodyLoadRow {
    /// Simulation time.
    pub t: Real,
    /// Step number.
    pub step: u64,
    /// The body's name (no `,`, `"`, line breaks or surrounding blanks).
    pub body: String,
    /// The force on the body (`fx,fy,fz`).
    pub force: [Real; 3],
    /// Its moment about the body's reference point (`mx,my,mz`).
    pub moment: [Real; 3],
}

/// `bodies.csv` as it grows, once started ([`LoadsTable::create`]) or reopened.
#[derive(Debug)]
pub(crate) struct LoadsTable(GrowingCsv);

impl LoadsTable {
    /// Starts `bodies.csv` at `path`, its header only.
    pub(crate) fn create(path: &Path) -> Result<Self, OutputError> {
        GrowingCsv::create(path, &header()).map(LoadsTable)
    }

    /// Continues the file at `path` from its rows with `step <= up_to_step` (started anew
    /// when it is missing); its header must be [`BODIES_COLUMNS`].
    pub(crate) fn reopen(path: &Path, up_to_step: u64) -> Result<Self, OutputError> {
        GrowingCsv::reopen(path, &header(), up_to_step).map(LoadsTable)
    }

    /// The number of rows.
    pub(crate) fn len(&self) -> usize {
        self.0.len()
    }

    /// Makes the rows written so far durable.
    pub(crate) fn sync(&self) -> Result<(), OutputError> {
        self.0.sync()
    }

    /// Replaces the rows of `step` and later by `rows` (all of step `step`); on an error the
    /// table and the file are unchanged.
    pub(crate) fn push(&mut self, step: u64, rows: &[BodyLoadRow]) -> Result<(), OutputError> {
        let invalid = |msg: String| OutputError::Invalid {
            path: self.0.path().to_path_buf(),
            msg,
        };
        let mut lines = Vec::with_capacity(rows.len());
        for r in rows {
            if r.step != step {
                return Err(invalid(format!(
                    "a row of step {} among step {step}",
                    r.step
                )));
            }
            let b = &r.body;
            if b.is_empty() || b.contains([',', '"', '\n', '\r']) || b.trim() != b {
                return Err(invalid(format!("invalid body name {b:?}")));
            }
            lines.push(format_row(r));
        }
        self.0.push(step, &lines)
    }
}

/// [`BODIES_COLUMNS`] as strings.
fn header() -> Vec<String> {
    BODIES_COLUMNS.iter().map(|s| s.to_string()).collect()
}

/// The records of the `bodies.csv` at `path` with their line numbers; its header must be
/// [`BODIES_COLUMNS`].
fn read_rows(path: &Path) -> Result<Vec<(u64, csv::StringRecord)>, OutputError> {
    let (found, rows) = read_table(path)?;
    let expected = header();
    if found != expected {
        return Err(header_mismatch(path, &found, &expected));
    }
    Ok(rows)
}

/// The rows of the `bodies.csv` at `path` of the body named `body`, in file order; an error
/// names the file and line of a field that is not a number, or the header when the columns
/// are not [`BODIES_COLUMNS`].
pub fn read_body_loads(path: &Path, body: &str) -> Result<Vec<BodyLoadRow>, OutputError> {
    let mut out = Vec::new();
    for (line, rec) in read_rows(path)? {
        if rec.get(2) != Some(body) {
            continue;
        }
        let real = |i: usize| parse_field::<Real>(path, line, &rec, i, BODIES_COLUMNS[i]);
        out.push(BodyLoadRow {
            t: real(0)?,
            step: parse_field(path, line, &rec, 1, "step")?,
            body: body.to_string(),
            force: [real(3)?, real(4)?, real(5)?],
            moment: [real(6)?, real(7)?, real(8)?],
        });
    }
    Ok(out)
}

/// One row as a CSV line (without line break), reals round-tripping.
fn format_row(r: &BodyLoadRow) -> String {
    let mut s = String::with_capacity(160);
    push_real(&mut s, r.t);
    s.push_str(&format!(",{},{}", r.step, r.body));
    for x in r.force.iter().chain(&r.moment) {
        s.push(',');
        push_real(&mut s, *x);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(step: u64, body: &str, fx: Real) -> BodyLoadRow {
        BodyLoadRow {
            t: 0.5 * step as Real,
            step,
            body: body.into(),
            force: [fx, -1.0 / 3.0, 0.0],
            moment: [0.0, 0.0, 2.5e-17],
        }
    }

    /// Rows round-trip bit for bit, a repeated step supersedes the rows from it on, and a
    /// re-read keeps the rows up to the given step.
    #[test]
    fn rows_round_trip_supersede_and_truncate() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(BODIES_FILE);
        let mut t = LoadsTable::create(&path).unwrap();
        t.push(0, &[row(0, "tank", 1.0), row(0, "flap", 2.0)])
            .unwrap();
        t.push(1, &[row(1, "tank", 0.1), row(1, "flap", 0.2)])
            .unwrap();
        t.push(1, &[row(1, "tank", 0.3), row(1, "flap", 0.4)])
            .unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 5, "{text}");
        assert_eq!(lines[0], "t,step,body,fx,fy,fz,mx,my,mz");
        assert_eq!(lines[3], "0.5,1,tank,0.3,-0.3333333333333333,0,0,0,2.5e-17");
        drop(t);
        let again = LoadsTable::reopen(&path, 0).unwrap();
        assert_eq!(again.len(), 2);
        let kept = std::fs::read_to_string(&path).unwrap();
        assert_eq!(kept.lines().collect::<Vec<_>>(), lines[..3]);
        assert_eq!(
            LoadsTable::reopen(&dir.path().join("none.csv"), 9)
                .unwrap()
                .len(),
            0
        );
    }

    #[test]
    fn a_bad_body_name_or_step_is_refused_and_changes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(BODIES_FILE);
        let mut t = LoadsTable::create(&path).unwrap();
        t.push(0, &[row(0, "tank", 1.0)]).unwrap();
        let before = std::fs::read(&path).unwrap();
        for bad in [vec![row(1, "a,b", 1.0)], vec![row(2, "tank", 1.0)]] {
            assert!(t.push(1, &bad).is_err());
        }
        assert_eq!(std::fs::read(&path).unwrap(), before);
        assert_eq!(t.len(), 1);
    }

    #[test]
    fn the_rows_of_one_body_are_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(BODIES_FILE);
        let mut t = LoadsTable::create(&path).unwrap();
        t.push(0, &[row(0, "tank", 1.0), row(0, "flap", 2.0)])
            .unwrap();
        t.push(1, &[row(1, "tank", 0.1), row(1, "flap", 0.2)])
            .unwrap();
        let flap = read_body_loads(&path, "flap").unwrap();
        assert_eq!(flap, vec![row(0, "flap", 2.0), row(1, "flap", 0.2)]);
        assert!(read_body_loads(&path, "none").unwrap().is_empty());
    }

    #[test]
    fn a_file_of_other_columns_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(BODIES_FILE);
        std::fs::write(&path, "t,step,body,fx\n0,0,tank,1\n").unwrap();
        let e = LoadsTable::reopen(&path, 5).unwrap_err().to_string();
        assert!(e.contains("unexpected header"), "{e}");
    }
}
