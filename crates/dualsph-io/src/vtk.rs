//! VTK XML output: one ASCII PolyData file (`.vtp`) per snapshot and a
//! ParaView collection (`.pvd`) that lists them with their times.

use std::io::{self, Write};

use crate::csv_out::{SnapshotEntry, push_real};
use crate::table::{POSITION, ParticleTable};

/// Values per line inside ASCII `DataArray`s (purely cosmetic).
const PER_LINE: usize = 9;

/// Write one `Float64` data array of `comps` components per point (`values` holds them).
fn real_array(
    w: &mut dyn Write,
    name: Option<&str>,
    comps: usize,
    values: &[f64],
) -> io::Result<()> {
    let name_attr = name.map_or(String::new(), |n| format!(" Name=\"{}\"", xml_attr(n)));
    let comp_attr = if comps > 1 {
        format!(" NumberOfComponents=\"{comps}\"")
    } else {
        String::new()
    };
    writeln!(
        w,
        "        <DataArray type=\"Float64\"{name_attr}{comp_attr} format=\"ascii\">"
    )?;
    let mut line = String::new();
    let per_line = (PER_LINE / comps).max(1) * comps;
    for (count, &x) in values.iter().enumerate() {
        line.push_str(if count % per_line == 0 {
            "          "
        } else {
            " "
        });
        push_real(&mut line, x);
        if (count + 1) % per_line == 0 {
            line.push('\n');
            w.write_all(line.as_bytes())?;
            line.clear();
        }
    }
    if !line.is_empty() {
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    writeln!(w, "        </DataArray>")
}

/// Write one `Int64` data array.
fn int_array(w: &mut dyn Write, name: &str, values: impl Iterator<Item = u64>) -> io::Result<()> {
    writeln!(
        w,
        "        <DataArray type=\"Int64\" Name=\"{name}\" format=\"ascii\">"
    )?;
    let mut line = String::new();
    for (i, v) in values.enumerate() {
        line.push_str(if i % PER_LINE == 0 { "          " } else { " " });
        line.push_str(&v.to_string());
        if (i + 1) % PER_LINE == 0 {
            line.push('\n');
            w.write_all(line.as_bytes())?;
            line.clear();
        }
    }
    if !line.is_empty() {
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    writeln!(w, "        </DataArray>")
}

/// Write an ASCII VTK XML PolyData file: one point and one vertex cell per particle, the
/// [`POSITION`] column as the points, and point data `id` (Int64) and every other column of
/// the table (as many components as it has labels).
///
/// Particle ids are written as `Int64`; ids above `i64::MAX` are not expected.
pub(crate) fn write_vtp(w: &mut dyn Write, table: &ParticleTable) -> io::Result<()> {
    let n = table.len();
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">"
    )?;
    writeln!(w, "  <PolyData>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    )?;
    let active = |name: &str, attr: &str| match table.column(name) {
        Some(_) => format!(" {attr}=\"{name}\""),
        None => String::new(),
    };
    writeln!(
        w,
        "      <PointData{}{}>",
        active("density", "Scalars"),
        active("velocity", "Vectors")
    )?;
    int_array(w, "id", table.ids.iter().copied())?;
    for c in table.columns.iter().filter(|c| c.name != POSITION) {
        real_array(w, Some(&c.name), c.width(), &c.values)?;
    }
    writeln!(w, "      </PointData>")?;
    writeln!(w, "      <Points>")?;
    match table.column(POSITION) {
        Some(c) => real_array(w, None, c.width(), &c.values)?,
        None => real_array(w, None, 3, &vec![0.0; 3 * n])?,
    }
    writeln!(w, "      </Points>")?;
    writeln!(w, "      <Verts>")?;
    int_array(w, "connectivity", 0..n as u64)?;
    int_array(w, "offsets", 1..=n as u64)?;
    writeln!(w, "      </Verts>")?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </PolyData>")?;
    writeln!(w, "</VTKFile>")
}

/// Escape the five XML special characters for use inside an attribute.
fn xml_attr(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Write a ParaView collection listing the `.vtp` of every snapshot entry
/// with `timestep` = the snapshot time.
pub(crate) fn write_pvd(w: &mut dyn Write, entries: &[SnapshotEntry]) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">"
    )?;
    writeln!(w, "  <Collection>")?;
    for e in entries {
        let mut t = String::new();
        push_real(&mut t, e.t);
        writeln!(
            w,
            "    <DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{}\"/>",
            xml_attr(&e.vtp_file())
        )?;
    }
    writeln!(w, "  </Collection>")?;
    writeln!(w, "</VTKFile>")
}

/// Crude parsers used by the tests to check written VTK files.
#[cfg(test)]
pub(crate) mod check {
    use std::path::Path;

    /// Crude XML well-formedness check: every tag is closed in order.
    pub(crate) fn check_xml_balanced(xml: &str) {
        let mut stack: Vec<String> = Vec::new();
        let mut rest = xml;
        while let Some(start) = rest.find('<') {
            let end = rest[start..].find('>').expect("unterminated tag") + start;
            let tag = &rest[start + 1..end];
            rest = &rest[end + 1..];
            if tag.starts_with('?') {
                continue;
            }
            assert_eq!(
                tag.matches('"').count() % 2,
                0,
                "unbalanced quotes in <{tag}>"
            );
            let name = tag
                .trim_start_matches('/')
                .split_whitespace()
                .next()
                .unwrap()
                .trim_end_matches('/');
            if tag.starts_with('/') {
                assert_eq!(stack.pop().as_deref(), Some(name), "mismatched </{name}>");
            } else if !tag.ends_with('/') {
                stack.push(name.to_string());
            }
        }
        assert!(stack.is_empty(), "unclosed elements {stack:?}");
        assert!(!rest.contains('>'));
    }

    fn attr<'a>(tag: &'a str, key: &str) -> Option<&'a str> {
        let pat = format!(" {key}=\"");
        let i = tag.find(&pat)? + pat.len();
        Some(&tag[i..i + tag[i..].find('"')?])
    }

    /// Parse a .vtp back crudely and check point count and array lengths.
    pub(crate) fn check_vtp(path: &Path, n: usize) {
        let xml = std::fs::read_to_string(path).unwrap();
        check_xml_balanced(&xml);
        let piece = xml.lines().find(|l| l.contains("<Piece")).unwrap();
        assert_eq!(attr(piece, "NumberOfPoints"), Some(n.to_string().as_str()));
        assert_eq!(attr(piece, "NumberOfVerts"), Some(n.to_string().as_str()));

        let mut arrays = Vec::new();
        let mut rest = xml.as_str();
        while let Some(i) = rest.find("<DataArray") {
            let open_end = rest[i..].find('>').unwrap() + i;
            let tag = &rest[i..open_end];
            let close = rest[open_end..].find("</DataArray>").unwrap() + open_end;
            let values: Vec<&str> = rest[open_end + 1..close].split_whitespace().collect();
            arrays.push((
                attr(tag, "Name").unwrap_or("Points").to_string(),
                attr(tag, "type").unwrap().to_string(),
                attr(tag, "NumberOfComponents").map_or(1, |c| c.parse().unwrap()),
                values.iter().map(|v| v.to_string()).collect::<Vec<_>>(),
            ));
            rest = &rest[close..];
        }
        let names: Vec<&str> = arrays.iter().map(|a| a.0.as_str()).collect();
        assert_eq!(
            names,
            [
                "id",
                "velocity",
                "mass",
                "density",
                "pressure",
                "internal_energy",
                "smoothing_length",
                "Points",
                "connectivity",
                "offsets"
            ]
        );
        for (name, ty, comps, values) in &arrays {
            assert_eq!(
                values.len(),
                n * comps,
                "array {name} in {}",
                path.display()
            );
            for v in values {
                if ty == "Int64" {
                    v.parse::<u64>().unwrap();
                } else {
                    v.parse::<f64>().unwrap();
                }
            }
        }
        assert_eq!(arrays[1].2, 3);
        assert_eq!(arrays[7].2, 3);
        let offsets = &arrays[9].3;
        assert!(
            offsets
                .iter()
                .enumerate()
                .all(|(i, v)| *v == (i + 1).to_string())
        );
    }
}
