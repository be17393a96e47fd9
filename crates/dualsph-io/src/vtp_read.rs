//! Reading back the particles of a VTK XML PolyData file (`.vtp`) this crate wrote, in any
//! of its [`crate::VtkEncoding`]s: the XML is parsed by `roxmltree`, the arrays are read as
//! text (`ascii`) or from the raw appended section (UInt64 byte count, or the zlib block
//! header and blocks); values come back bit for bit.

use crate::{OutputError, POSITION, ParticleTable, Real, TableColumn};
use flate2::read::ZlibDecoder;
use std::io::Read;
use std::path::Path;

/// The parts of the file: its XML text (up to the appended section) and the appended bytes
/// after the `_` that opens them (empty without the section).
fn split(bytes: &[u8]) -> (&[u8], &[u8]) {
    let tag = b"<AppendedData";
    match bytes.windows(tag.len()).position(|w| w == tag) {
        Some(at) => {
            let rest = &bytes[at..];
            let data = rest
                .iter()
                .position(|&b| b == b'_')
                .map_or(&[][..], |u| &rest[u + 1..]);
            (&bytes[..at], data)
        }
        None => (bytes, &[]),
    }
}

/// Reads every array of a particle file written as VTK XML PolyData by this crate as a
/// [`ParticleTable`]: the `id` point data as the ids, the points as the [`POSITION`] column
/// (labels `x, y, z`), then every other point-data array under its name, its labels
/// `name` (one component) or `name0, name1, …`.
pub fn read_particle_table_vtp(path: &Path) -> Result<ParticleTable, OutputError> {
    vtp_table(path).map(|(t, _)| t)
}

/// The file's XML text (closed after the appended section, which is cut out) and the
/// appended bytes.
fn read_parts(path: &Path) -> Result<(String, Vec<u8>), OutputError> {
    let bytes =
        crate::read_input(path, crate::INPUT_FILE_LIMIT).map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            op: "read",
            source,
        })?;
    let (head, data) = split(&bytes);
    let mut text = String::from_utf8_lossy(head).into_owned();
    if !data.is_empty() {
        text.push_str("</VTKFile>");
    }
    Ok((text, data.to_vec()))
}

/// The table of [`read_particle_table_vtp`] and the line of its `<Piece>`.
fn vtp_table(path: &Path) -> Result<(ParticleTable, u64), OutputError> {
    let (text, data) = read_parts(path)?;
    let fail = |line: u32, msg: String| OutputError::Parse {
        path: path.to_path_buf(),
        line: u64::from(line),
        msg,
    };
    let doc = roxmltree::Document::parse(&text).map_err(|e| fail(e.pos().row, e.to_string()))?;
    let line = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row;
    let root = doc.root_element();
    if root.attribute("type") != Some("PolyData") {
        return Err(fail(line(root), "not a VTK PolyData file".into()));
    }
    let file = File {
        compressed: root.attribute("compressor").is_some(),
        data: &data,
    };
    let piece = root
        .descendants()
        .find(|n| n.has_tag_name("Piece"))
        .ok_or_else(|| fail(line(root), "no <Piece>".into()))?;
    let n: usize = piece
        .attribute("NumberOfPoints")
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| fail(line(piece), "no NumberOfPoints".into()))?;
    let arrays = |parent: &'static str| {
        piece
            .descendants()
            .filter(move |p| p.has_tag_name(parent))
            .flat_map(|p| p.children().filter(|c| c.has_tag_name("DataArray")))
    };
    let values = |a: roxmltree::Node, comps: usize| {
        let name = a.attribute("Name").unwrap_or("points");
        file.values(a, n * comps)
            .map_err(|m| fail(line(a), format!("DataArray `{name}`: {m}")))
    };
    let points = arrays("Points")
        .next()
        .ok_or_else(|| fail(line(piece), "no <Points>".into()))?;
    let mut table = ParticleTable {
        ids: Vec::new(),
        columns: vec![TableColumn {
            name: POSITION.into(),
            labels: ["x", "y", "z"].map(String::from).into(),
            values: values(points, 3)?,
        }],
    };
    for a in arrays("PointData") {
        let name = a.attribute("Name").unwrap_or("");
        if name == crate::VOLUME_ARRAY {
            continue; // derived for viewers (m/ρ), not a column of the state
        }
        let comps: usize = a
            .attribute("NumberOfComponents")
            .map_or(Some(1), |c| c.parse().ok())
            .filter(|&c| c > 0)
            .ok_or_else(|| {
                fail(
                    line(a),
                    format!("DataArray `{name}`: bad NumberOfComponents"),
                )
            })?;
        let v = values(a, comps)?;
        if name == "id" {
            table.ids = v.into_iter().map(|x| x as i64 as u64).collect();
            continue;
        }
        let labels = match comps {
            1 => vec![name.to_string()],
            _ => (0..comps).map(|k| format!("{name}{k}")).collect(),
        };
        table.columns.push(TableColumn {
            name: name.into(),
            labels,
            values: v,
        });
    }
    if table.ids.len() != n {
        return Err(fail(line(piece), "no point data `id`".into()));
    }
    Ok((table, u64::from(line(piece))))
}

/// How the arrays are stored: zlib-compressed or not, and the appended bytes.
struct File<'a> {
    compressed: bool,
    data: &'a [u8],
}

impl File<'_> {
    /// The `count` values of the array `a` as reals (Int64 ids converted, bit for bit for
    /// any id up to 2^53; the engine's ids are far below).
    fn values(&self, a: roxmltree::Node, count: usize) -> Result<Vec<Real>, String> {
        let ty = a.attribute("type").unwrap_or("");
        let out: Vec<Real> = match a.attribute("format") {
            Some("ascii") => {
                let words = a.text().unwrap_or("").split_whitespace();
                match ty {
                    "Int64" => words
                        .map(|w| {
                            w.parse::<i64>()
                                .map(|v| v as Real)
                                .map_err(|e| format!("not an integer: {e}"))
                        })
                        .collect::<Result<_, _>>()?,
                    _ => words
                        .map(|w| w.parse::<Real>().map_err(|e| format!("not a number: {e}")))
                        .collect::<Result<_, _>>()?,
                }
            }
            Some("appended") => {
                let offset: usize = a
                    .attribute("offset")
                    .and_then(|s| s.parse().ok())
                    .ok_or("no offset")?;
                let bytes = self.appended(offset, 8 * count)?;
                let word = |c: &[u8]| <[u8; 8]>::try_from(c).unwrap_or([0; 8]);
                match ty {
                    "Int64" => bytes
                        .chunks_exact(8)
                        .map(|c| i64::from_le_bytes(word(c)) as Real)
                        .collect(),
                    "Float64" => bytes
                        .chunks_exact(8)
                        .map(|c| f64::from_le_bytes(word(c)))
                        .collect(),
                    other => return Err(format!("type {other} is not read")),
                }
            }
            other => return Err(format!("format {other:?} is not read")),
        };
        if out.len() != count {
            return Err(format!("expected {count} values, got {}", out.len()));
        }
        Ok(out)
    }

    /// The bytes of the appended array at `offset`: after its UInt64 byte count, or its
    /// zlib blocks inflated (no more than `want` bytes and one, so a corrupt block cannot
    /// inflate without end).
    fn appended(&self, offset: usize, want: usize) -> Result<Vec<u8>, String> {
        let short = || "the appended data end early".to_string();
        let at = |k: usize| -> Result<u64, String> {
            let s = offset.checked_add(8 * k).ok_or_else(short)?;
            let b = self.data.get(s..s + 8).ok_or_else(short)?;
            Ok(u64::from_le_bytes(
                <[u8; 8]>::try_from(b).map_err(|_| short())?,
            ))
        };
        let slice = |from: usize, len: u64| -> Result<&[u8], String> {
            let len = usize::try_from(len).map_err(|_| short())?;
            self.data
                .get(from..from.checked_add(len).ok_or_else(short)?)
                .ok_or_else(short)
        };
        if !self.compressed {
            return slice(offset + 8, at(0)?).map(<[u8]>::to_vec);
        }
        let blocks = usize::try_from(at(0)?).map_err(|_| short())?;
        let mut from = blocks
            .checked_add(3)
            .and_then(|b| b.checked_mul(8))
            .and_then(|b| b.checked_add(offset))
            .ok_or_else(short)?;
        let mut out = Vec::new();
        for k in 0..blocks {
            let size = at(3 + k)?;
            let room = (want + 1).saturating_sub(out.len()) as u64;
            let mut z = ZlibDecoder::new(slice(from, size)?).take(room);
            z.read_to_end(&mut out)
                .map_err(|e| format!("zlib block {k}: {e}"))?;
            from = from.checked_add(size as usize).ok_or_else(short)?;
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_particles::{Particle, particles_of, table_of};
    use crate::{VtkEncoding, vtk};

    fn records(n: usize) -> Vec<Particle> {
        (0..n)
            .map(|i| {
                let x = i as f64 / 7.0;
                Particle {
                    id: 3 * i as u64 + 1,
                    pos: [x, -x * 1e-300, 0.1 + x],
                    vel: [-0.0, 1.0 / (x + 1.0), libm::sin(x)],
                    mass: 1.0 / (x + 3.0),
                    rho: 1000.0 + x,
                    p: if i % 2 == 0 { f64::INFINITY } else { -x },
                    e: 5e-324,
                    h: 0.1 * x + 1e-3,
                }
            })
            .collect()
    }

    fn bits(r: &Particle) -> Vec<u64> {
        let mut v: Vec<f64> = r.pos.iter().chain(&r.vel).copied().collect();
        v.extend([r.mass, r.rho, r.p, r.e, r.h]);
        v.into_iter().map(f64::to_bits).collect()
    }

    fn written(n: usize, encoding: VtkEncoding) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.vtp");
        let mut bytes = Vec::new();
        vtk::write_vtp(&mut bytes, &table_of(&records(n)), encoding, &[]).unwrap();
        std::fs::write(&path, bytes).unwrap();
        (dir, path)
    }

    #[test]
    fn particles_read_back_bitwise_in_every_encoding() {
        for encoding in [
            VtkEncoding::Ascii,
            VtkEncoding::Binary,
            VtkEncoding::Compressed,
        ] {
            // 5000 particles: the velocity is 120 000 bytes, four zlib blocks
            for n in [1, 17, 5000] {
                let (_dir, path) = written(n, encoding);
                let back = particles_of(&crate::read_particles(&path).unwrap());
                let want = records(n);
                assert_eq!(back.len(), n);
                for (a, b) in back.iter().zip(&want) {
                    assert_eq!(a.id, b.id);
                    assert_eq!(bits(a), bits(b), "{encoding:?}, particle {}", b.id);
                }
            }
        }
    }

    /// Every column, the plugins' too, comes back by name (VTK) or label (CSV).
    #[test]
    fn tables_read_back_every_column_bitwise() {
        let mut t = table_of(&records(40));
        t.columns.push(crate::TableColumn {
            name: "stress".into(),
            labels: ["sa", "sb", "sc", "sd"].map(String::from).into(),
            values: (0..160).map(|k| k as f64 * 0.37 - 3.0).collect(),
        });
        let dir = tempfile::tempdir().unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for encoding in [
            VtkEncoding::Ascii,
            VtkEncoding::Binary,
            VtkEncoding::Compressed,
        ] {
            let path = dir.path().join("t.vtp");
            let mut bytes = Vec::new();
            vtk::write_vtp(&mut bytes, &t, encoding, &[]).unwrap();
            std::fs::write(&path, bytes).unwrap();
            let back = read_particle_table_vtp(&path).unwrap();
            assert_eq!(back.ids, t.ids);
            for c in &t.columns {
                let b = back.column(&c.name).unwrap();
                assert_eq!(b.width(), c.width(), "{}", c.name);
                assert_eq!(bits(&b.values), bits(&c.values), "{} {encoding:?}", c.name);
            }
        }
        let path = dir.path().join("t.csv");
        let mut bytes = Vec::new();
        crate::csv_out::write_particles(&mut bytes, &t).unwrap();
        std::fs::write(&path, bytes).unwrap();
        let back = crate::read_particle_table_csv(&path).unwrap();
        assert_eq!(back.ids, t.ids);
        for c in &t.columns {
            for (k, label) in c.labels.iter().enumerate() {
                let b = back.column(label).unwrap();
                let want: Vec<f64> = (0..40).map(|i| c.values[i * c.width() + k]).collect();
                assert_eq!(bits(&b.values), bits(&want), "{label}");
            }
        }
    }

    #[test]
    fn a_damaged_file_is_an_error_with_its_line() {
        let (_dir, path) = written(17, VtkEncoding::Compressed);
        let bytes = std::fs::read(&path).unwrap();
        // cut inside the appended data
        std::fs::write(&path, &bytes[..bytes.len() - 200]).unwrap();
        let e = read_particle_table_vtp(&path).unwrap_err().to_string();
        assert!(
            e.contains("the appended data end early") || e.contains("zlib"),
            "{e}"
        );
        let (_dir, path) = written(3, VtkEncoding::Ascii);
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, text.replace("Name=\"mass\"", "Name=\"weight\"")).unwrap();
        let t = read_particle_table_vtp(&path).unwrap();
        let e = t.require(&["position", "mass"]).unwrap_err();
        assert!(
            e.contains("no column `mass`") && !e.contains("weight"),
            "{e}"
        );
        std::fs::write(&path, text.replace("<PolyData>", "<PolyDat>")).unwrap();
        let e = read_particle_table_vtp(&path).unwrap_err().to_string();
        assert!(e.contains("p.vtp, line"), "{e}");
        std::fs::write(&path, "not xml at all").unwrap();
        assert!(read_particle_table_vtp(&path).is_err());
    }
}
