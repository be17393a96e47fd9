//! A CSV file that grows by whole rows as a run goes: `diagnostics.csv` and `bodies.csv`.
//!
//! Rows are appended, each step's rows with one `write` of complete lines, so that the cost
//! of a row does not grow with the rows before it (rewriting the whole file at every row, as
//! an atomic replacement would, is quadratic: a run of 10⁵ diagnostics rows spent most of
//! its time in it). The file is nevertheless always a whole table: a failed append is cut
//! off again, rows that a re-run step supersedes are replaced by an atomic rewrite
//! ([`write_atomic_with`]), and a reopened file drops an incomplete last line that only a
//! crash in the middle of an append can leave (the readers of the run, `read_table` and the
//! resume, never see it).

use std::fs::{File, OpenOptions};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

use crate::csv_out::{csv_error, header_mismatch, parse_field, read_header, reader};
use crate::{INPUT_FILE_LIMIT, OutputError, read_input, write_atomic_with};

/// Where the rows of one step start in the file.
#[derive(Debug, Clone, Copy)]
struct StepStart {
    step: u64,
    /// Byte offset of the step's first row.
    offset: u64,
    /// Rows before it.
    rows_before: usize,
}

/// A growing CSV table whose second column is the step, steps in increasing order.
#[derive(Debug)]
pub struct GrowingCsv {
    path: PathBuf,
    file: File,
    /// One entry per step that has rows, in file order.
    steps: Vec<StepStart>,
    /// Rows in the file.
    rows: usize,
    /// Bytes in the file.
    len: u64,
}

impl GrowingCsv {
    /// Starts the table at `path` with its `header` line only, replacing any file there.
    pub fn create(path: &Path, header: &[String]) -> Result<Self, OutputError> {
        let head = format!("{}\n", header.join(","));
        write_atomic_with(path, |w| w.write_all(head.as_bytes()))?;
        Ok(GrowingCsv {
            path: path.to_path_buf(),
            file: open_append(path)?,
            steps: Vec::new(),
            rows: 0,
            len: head.len() as u64,
        })
    }

    /// Continues the table at `path` (started anew when it is missing) from its rows with
    /// `step <= up_to_step`: the rows after them, and an incomplete last line, are cut off.
    /// Its header must be `header`; a step that is not a number is an error naming its line.
    pub fn reopen(path: &Path, header: &[String], up_to_step: u64) -> Result<Self, OutputError> {
        let bytes = match read_input(path, INPUT_FILE_LIMIT) {
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Self::create(path, header),
            r => r.map_err(|source| OutputError::Io {
                path: path.to_path_buf(),
                op: "read",
                source,
            })?,
        };
        let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let (steps, rows, cut) = scan(path, &bytes[..complete], header, up_to_step)?;
        let file = open_append(path)?;
        if cut < bytes.len() as u64 {
            file.set_len(cut)
                .and_then(|()| file.sync_data())
                .map_err(|source| OutputError::Io {
                    path: path.to_path_buf(),
                    op: "truncate",
                    source,
                })?;
        }
        Ok(GrowingCsv {
            path: path.to_path_buf(),
            file,
            steps,
            rows,
            len: cut,
        })
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.rows
    }

    /// Whether the table has no rows.
    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// Puts `lines` (complete CSV rows without line breaks, all of `step`) after the rows of
    /// the steps before `step`; rows of `step` and later are replaced. On an error the file
    /// and the table are as before.
    pub fn push(&mut self, step: u64, lines: &[String]) -> Result<(), OutputError> {
        let mut text = String::with_capacity(lines.iter().map(|l| l.len() + 1).sum());
        for line in lines {
            text.push_str(line);
            text.push('\n');
        }
        let first_superseded = self.steps.partition_point(|s| s.step < step);
        if first_superseded < self.steps.len() {
            self.supersede(first_superseded, &text)?;
        } else {
            self.append(&text)?;
        }
        if !lines.is_empty() {
            self.steps.push(StepStart {
                step,
                offset: self.len,
                rows_before: self.rows,
            });
        }
        self.len += text.len() as u64;
        self.rows += lines.len();
        Ok(())
    }

    /// Makes the rows written so far durable (`fsync`).
    pub fn sync(&self) -> Result<(), OutputError> {
        self.file.sync_data().map_err(|source| OutputError::Io {
            path: self.path.clone(),
            op: "fsync",
            source,
        })
    }

    /// Appends `text` with one write; a failed write is cut off again.
    fn append(&mut self, text: &str) -> Result<(), OutputError> {
        self.file.write_all(text.as_bytes()).map_err(|source| {
            // the file ends where it did: never a torn row
            let _ = self.file.set_len(self.len);
            OutputError::Io {
                path: self.path.clone(),
                op: "append to",
                source,
            }
        })
    }

    /// Replaces the rows from step entry `first` on by `text`, atomically.
    fn supersede(&mut self, first: usize, text: &str) -> Result<(), OutputError> {
        let start = self.steps[first];
        let mut kept = vec![0; start.offset as usize];
        File::open(&self.path)
            .and_then(|mut f| f.read_exact(&mut kept))
            .map_err(|source| OutputError::Io {
                path: self.path.clone(),
                op: "read",
                source,
            })?;
        write_atomic_with(&self.path, |w| {
            w.write_all(&kept)?;
            w.write_all(text.as_bytes())
        })?;
        // the rename put a new file at the path: append to it from now on
        self.file = open_append(&self.path)?;
        self.steps.truncate(first);
        self.rows = start.rows_before;
        self.len = start.offset;
        Ok(())
    }
}

/// The step entries, row count and byte length of the rows of `text` (complete lines) up to
/// the first of a step after `up_to_step`; the header must be `header`.
fn scan(
    path: &Path,
    text: &[u8],
    header: &[String],
    up_to_step: u64,
) -> Result<(Vec<StepStart>, usize, u64), OutputError> {
    let mut rdr = reader(text);
    let found = read_header(path, &mut rdr)?;
    if found != header {
        return Err(header_mismatch(path, &found, header));
    }
    let (mut steps, mut rows) = (Vec::<StepStart>::new(), 0);
    let mut cut = text.len() as u64;
    for rec in rdr.records() {
        let rec = rec.map_err(csv_error(path))?;
        let (line, offset) = rec.position().map_or((0, 0), |p| (p.line(), p.byte()));
        let step: u64 = parse_field(path, line, &rec, 1, "step")?;
        if step > up_to_step {
            cut = offset;
            break;
        }
        if steps.last().is_none_or(|s| s.step != step) {
            steps.push(StepStart {
                step,
                offset,
                rows_before: rows,
            });
        }
        rows += 1;
    }
    Ok((steps, rows, cut))
}

/// `path` opened to append to.
fn open_append(path: &Path) -> Result<File, OutputError> {
    OpenOptions::new()
        .append(true)
        .open(path)
        .map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            op: "open",
            source,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> Vec<String> {
        vec!["t".into(), "step".into()]
    }

    fn lines(step: u64) -> Vec<String> {
        vec![format!("0.5,{step}")]
    }

    fn text(path: &Path) -> String {
        std::fs::read_to_string(path).unwrap()
    }

    #[test]
    fn rows_append_and_a_re_run_step_replaces_the_later_rows() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("g.csv");
        let mut g = GrowingCsv::create(&path, &header()).unwrap();
        for s in 0..4 {
            g.push(s, &lines(s)).unwrap();
        }
        g.push(4, &["1,4".into(), "2,4".into()]).unwrap();
        assert_eq!(g.len(), 6);
        assert_eq!(
            text(&path),
            "t,step\n0.5,0\n0.5,1\n0.5,2\n0.5,3\n1,4\n2,4\n"
        );
        g.push(2, &lines(2)).unwrap();
        assert_eq!(g.len(), 3);
        assert_eq!(text(&path), "t,step\n0.5,0\n0.5,1\n0.5,2\n");
        g.push(3, &lines(3)).unwrap();
        assert_eq!(text(&path), "t,step\n0.5,0\n0.5,1\n0.5,2\n0.5,3\n");
        let names: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file is left");
    }

    #[test]
    fn reopen_keeps_the_rows_up_to_the_step_and_drops_a_torn_line() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("g.csv");
        std::fs::write(&path, "t,step\n0,0\n1,1\n1,1\n2,2\n3,").unwrap();
        let mut g = GrowingCsv::reopen(&path, &header(), 1).unwrap();
        assert_eq!(g.len(), 3);
        assert_eq!(text(&path), "t,step\n0,0\n1,1\n1,1\n");
        g.push(1, &lines(1)).unwrap();
        assert_eq!(text(&path), "t,step\n0,0\n0.5,1\n");
        drop(g);
        std::fs::write(&path, "t,step\n0,0\n1,1\n2,").unwrap();
        let g = GrowingCsv::reopen(&path, &header(), 10).unwrap();
        assert_eq!(g.len(), 2);
        assert_eq!(text(&path), "t,step\n0,0\n1,1\n");
    }

    #[test]
    fn reopen_refuses_another_header_and_a_bad_step_naming_the_line() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("g.csv");
        std::fs::write(&path, "t,steps\n0,0\n").unwrap();
        let err = GrowingCsv::reopen(&path, &header(), 1).unwrap_err();
        assert!(err.to_string().contains("header"), "{err}");
        std::fs::write(&path, "t,step\n0,0\n1,x\n").unwrap();
        let err = GrowingCsv::reopen(&path, &header(), 1).unwrap_err();
        assert!(err.to_string().contains("line 3"), "{err}");
        assert_eq!(
            text(&path),
            "t,step\n0,0\n1,x\n",
            "an error changes nothing"
        );
        let missing = tmp.path().join("new.csv");
        let g = GrowingCsv::reopen(&missing, &header(), 1).unwrap();
        assert_eq!((g.len(), text(&missing)), (0, "t,step\n".to_string()));
    }
}
