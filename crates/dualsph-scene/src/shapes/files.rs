//! The shapes read from files: an STL mesh and a polygon's outline. They are read when the
//! scene is parsed, each path relative to the scene file's directory, and every problem
//! names the shape's `file` field (`particles[2].shape.file`, `particles[0].cut[1].file`).

use super::Shape;
use super::mesh::{Mesh, check_closed, read_stl};
use crate::error::Problem;
use std::path::Path;
use std::sync::Arc;

/// The mesh of an `Stl` shape once its file is read (none before). Two are equal when they
/// hold the same triangles.
#[derive(Clone, Default)]
pub struct StlMesh(Option<Arc<Mesh>>);

impl StlMesh {
    pub(crate) fn get(&self) -> Option<&Mesh> {
        self.0.as_deref()
    }
}

impl std::fmt::Debug for StlMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0 {
            Some(m) => write!(f, "StlMesh({} triangles)", m.triangles.len()),
            None => f.write_str("StlMesh(not read)"),
        }
    }
}

impl PartialEq for StlMesh {
    fn eq(&self, other: &Self) -> bool {
        self.0.as_deref() == other.0.as_deref()
    }
}

/// The vertices of a `PolygonFile` shape once its file is read (none before), with the
/// line of the file each came from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outline(Option<Arc<(Vec<Vec<f64>>, Vec<usize>)>>);

impl Outline {
    pub(crate) fn vertices(&self) -> Option<&[Vec<f64>]> {
        self.0.as_deref().map(|(v, _)| v.as_slice())
    }
    /// The 1-based line of vertex `i`.
    pub(crate) fn line(&self, i: usize) -> Option<usize> {
        self.0.as_deref().and_then(|(_, l)| l.get(i).copied())
    }
}

/// Reads the file of `shape` (an `Stl` shape in 3-D, a `PolygonFile` in 2-D; other shapes
/// have none) relative to `dir`; a problem names `{field}.file`.
pub(crate) fn load_shape(
    field: &str,
    shape: &mut Shape,
    dir: &Path,
    d: usize,
) -> Result<(), Problem> {
    let at = format!("{field}.file");
    match shape {
        Shape::Stl { file, mesh, .. } if d == 3 => {
            let path = dir.join(&*file);
            let m = read_stl(&path).map_err(|e| Problem::new(&at, e))?;
            check_closed(&m)
                .map_err(|e| Problem::new(&at, format!("`{}`: {e}", path.display())))?;
            *mesh = StlMesh(Some(Arc::new(m)));
        }
        Shape::PolygonFile { file, outline } if d == 2 => {
            let path = dir.join(&*file);
            let text =
                dualsph_io::read_input_text(&path, dualsph_io::INPUT_FILE_LIMIT).map_err(|e| {
                    Problem::new(
                        &at,
                        format!("cannot read polygon file `{}`: {e}", path.display()),
                    )
                })?;
            let rows = read_rows(&text)
                .map_err(|e| Problem::new(&at, format!("`{}`:{e}", path.display())))?;
            *outline = Outline(Some(Arc::new(rows)));
        }
        _ => {}
    }
    Ok(())
}

/// The rows `x, y` of a polygon file and their 1-based lines. Blank lines and lines starting
/// with `#` are skipped, and so is a first row that is not two numbers but has a letter (a
/// header such as `x,y`). A row is two numbers separated by a comma, a semicolon or blanks.
/// The error is `LINE: what was wrong`.
pub(crate) fn read_rows(text: &str) -> Result<(Vec<Vec<f64>>, Vec<usize>), String> {
    let (mut rows, mut lines) = (Vec::new(), Vec::new());
    let mut first = true;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim().trim_start_matches('\u{feff}');
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| f.parse().ok()).collect();
        let header = first && line.chars().any(|c| c.is_alphabetic());
        first = false;
        match numbers.as_slice() {
            [Some(x), Some(y)] if x.is_finite() && y.is_finite() => {
                rows.push(vec![*x, *y]);
                lines.push(n + 1);
            }
            _ if header && numbers.iter().any(Option::is_none) => {}
            // the row is not quoted: a file that is not an outline stays unprinted
            _ => {
                return Err(format!(
                    "{}: expected a row of two finite numbers `x, y`, got {} field{}{}",
                    n + 1,
                    fields.len(),
                    if fields.len() == 1 { "" } else { "s" },
                    if fields.len() == 2 {
                        " that are not both finite numbers"
                    } else {
                        ""
                    }
                ));
            }
        }
    }
    Ok((rows, lines))
}
