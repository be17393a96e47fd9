//! Tests of the VTK writer: a small reader decodes what was written, in each encoding, and
//! compares every array bitwise to the input.

use std::io::Read;

use crate::test_particles::{Particle, table_of};
use crate::vtk::{self, ArrayValues, ImageGrid, VtkArray, VtkEncoding, ZLIB_BLOCK};
use crate::{ParticleTable, TableColumn};

/// One decoded `<DataArray>`: name (`Points` when unnamed), type, components and its values
/// as little-endian bytes.
#[derive(Debug)]
pub(crate) struct Decoded {
    pub name: String,
    pub ty: String,
    pub comps: usize,
    pub bytes: Vec<u8>,
}

impl Decoded {
    pub fn f64s(&self) -> Vec<u64> {
        assert_eq!(self.ty, "Float64", "{}", self.name);
        self.bytes
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    pub fn i64s(&self) -> Vec<i64> {
        assert_eq!(self.ty, "Int64", "{}", self.name);
        self.bytes
            .chunks_exact(8)
            .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }
}

pub(crate) fn attr<'a>(tag: &'a str, key: &str) -> Option<&'a str> {
    let pat = format!(" {key}=\"");
    let i = tag.find(&pat)? + pat.len();
    Some(&tag[i..i + tag[i..].find('"')?])
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap())
}

/// Decodes the array that starts at `offset` of an appended section.
fn appended(data: &[u8], offset: usize, compressed: bool) -> Vec<u8> {
    if !compressed {
        let n = u64_at(data, offset) as usize;
        return data[offset + 8..offset + 8 + n].to_vec();
    }
    let blocks = u64_at(data, offset) as usize;
    let block = u64_at(data, offset + 8) as usize;
    let last = u64_at(data, offset + 16) as usize;
    assert_eq!(block, ZLIB_BLOCK);
    let mut at = offset + 24 + 8 * blocks;
    let mut out = Vec::new();
    for b in 0..blocks {
        let size = u64_at(data, offset + 24 + 8 * b) as usize;
        let mut z = flate2::read::ZlibDecoder::new(&data[at..at + size]);
        let mut raw = Vec::new();
        z.read_to_end(&mut raw).unwrap();
        let want = if b + 1 == blocks && last != 0 {
            last
        } else {
            block
        };
        assert_eq!(raw.len(), want, "block {b}");
        out.extend(raw);
        at += size;
    }
    out
}

/// Text of ASCII values as little-endian bytes of type `ty`.
fn ascii(ty: &str, text: &str) -> Vec<u8> {
    text.split_whitespace()
        .flat_map(|v| match ty {
            "Float64" => v.parse::<f64>().unwrap().to_le_bytes().to_vec(),
            "Int64" => v.parse::<i64>().unwrap().to_le_bytes().to_vec(),
            "UInt8" => vec![v.parse::<u8>().unwrap()],
            _ => panic!("type {ty}"),
        })
        .collect()
}

/// Decodes every `<DataArray>` of a VTK XML file in any of the three encodings.
pub(crate) fn read_arrays(file: &[u8]) -> Vec<Decoded> {
    let (xml, data) = match file.windows(14).position(|w| w == b"<AppendedData ") {
        Some(i) => {
            let start = i + file[i..].iter().position(|&b| b == b'_').unwrap() + 1;
            (&file[..i], &file[start..])
        }
        None => (file, &[][..]),
    };
    let xml = std::str::from_utf8(xml).unwrap();
    let vtk_file = &xml[xml.find("<VTKFile").unwrap()..];
    let compressed = attr(vtk_file, "compressor").is_some();
    if !data.is_empty() {
        assert_eq!(attr(vtk_file, "header_type"), Some("UInt64"));
    }
    let mut out = Vec::new();
    let mut rest = xml;
    while let Some(i) = rest.find("<DataArray") {
        let end = rest[i..].find('>').unwrap() + i;
        let tag = &rest[i..end];
        let ty = attr(tag, "type").unwrap().to_string();
        let bytes = match attr(tag, "format").unwrap() {
            "ascii" => {
                let close = rest[end..].find("</DataArray>").unwrap() + end;
                ascii(&ty, &rest[end + 1..close])
            }
            "appended" => appended(
                data,
                attr(tag, "offset").unwrap().parse().unwrap(),
                compressed,
            ),
            f => panic!("format {f}"),
        };
        out.push(Decoded {
            name: attr(tag, "Name").unwrap_or("Points").to_string(),
            ty,
            comps: attr(tag, "NumberOfComponents").map_or(1, |c| c.parse().unwrap()),
            bytes,
        });
        rest = &rest[end..];
    }
    out
}

fn table(n: usize) -> ParticleTable {
    let records: Vec<Particle> = (0..n)
        .map(|i| {
            let x = i as f64;
            Particle {
                id: 3 * i as u64 + 1,
                pos: [x / 7.0, -x * 1e-300, f64::MAX / (x + 1.0)],
                vel: [libm::sin(x), f64::NAN, -0.0],
                mass: 1.0 / (x + 3.0),
                rho: 1000.0 + x,
                p: f64::INFINITY,
                e: 5e-324,
                h: 0.1 * x,
            }
        })
        .collect();
    let mut t = table_of(&records);
    t.columns.push(TableColumn {
        name: "stress".into(),
        labels: ["a", "b", "c", "d"].map(String::from).into(),
        values: (0..4 * n).map(|k| k as f64 * 0.5 - 3.0).collect(),
    });
    t
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn vtp_round_trip(n: usize, encoding: VtkEncoding) {
    let t = table(n);
    let mut file = Vec::new();
    vtk::write_vtp(&mut file, &t, encoding, &[]).unwrap();
    let arrays = read_arrays(&file);
    let names: Vec<&str> = arrays.iter().map(|a| a.name.as_str()).collect();
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
            "stress",
            "volume",
            "Points",
            "connectivity",
            "offsets"
        ]
    );
    let by = |name: &str| arrays.iter().find(|a| a.name == name).unwrap();
    let ids: Vec<i64> = t.ids.iter().map(|&i| i as i64).collect();
    assert_eq!(by("id").i64s(), ids);
    for c in t.columns.iter() {
        let a = by(if c.name == "position" {
            "Points"
        } else {
            &c.name
        });
        assert_eq!(a.comps, c.width(), "{}", c.name);
        assert_eq!(a.f64s(), bits(&c.values), "{} ({encoding:?})", c.name);
    }
    assert_eq!(by("connectivity").i64s(), (0..n as i64).collect::<Vec<_>>());
    assert_eq!(by("offsets").i64s(), (1..=n as i64).collect::<Vec<_>>());
    let text = String::from_utf8_lossy(&file);
    let piece = format!("NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\"");
    assert!(text.contains(&piece), "{encoding:?}");
    assert!(text.trim_end().ends_with("</VTKFile>"));
}

#[test]
fn binary_vtp_reads_back_bitwise() {
    for n in [0, 1, 17] {
        vtp_round_trip(n, VtkEncoding::Binary);
    }
}

#[test]
fn compressed_vtp_reads_back_bitwise_across_blocks() {
    // 3000 particles: the 4-component column is 96 000 bytes, three blocks and a partial one
    for n in [0, 1, 17, 3000, ZLIB_BLOCK / 8] {
        vtp_round_trip(n, VtkEncoding::Compressed);
    }
    let mut file = Vec::new();
    vtk::write_vtp(&mut file, &table(1), VtkEncoding::Compressed, &[]).unwrap();
    let text = String::from_utf8_lossy(&file);
    assert!(text.contains("compressor=\"vtkZLibDataCompressor\""));
}

#[test]
fn ascii_vtp_reads_back_bitwise() {
    for n in [0, 1, 17] {
        vtp_round_trip(n, VtkEncoding::Ascii);
    }
}

#[test]
fn vti_reads_back_bitwise_in_every_encoding() {
    let grid = ImageGrid {
        origin: [0.5, -1.0, 0.0],
        spacing: [0.25, 0.25, 1.0],
        dims: [5, 4, 1],
    };
    let field: Vec<f64> = (0..20).map(|k| (k as f64).sqrt() * 1e-3).collect();
    let inside: Vec<u8> = (0..20).map(|k| (k % 3 == 0) as u8).collect();
    let arrays = [
        VtkArray::new("Density", 1, ArrayValues::Float64(&field)),
        VtkArray::new("inside", 1, ArrayValues::UInt8(&inside)),
    ];
    for encoding in [
        VtkEncoding::Ascii,
        VtkEncoding::Binary,
        VtkEncoding::Compressed,
    ] {
        let mut file = Vec::new();
        vtk::write_vti(&mut file, &grid, Some("Density"), &arrays, encoding).unwrap();
        let back = read_arrays(&file);
        assert_eq!(back.len(), 2);
        assert_eq!(back[0].f64s(), bits(&field), "{encoding:?}");
        assert_eq!((back[1].ty.as_str(), &back[1].bytes), ("UInt8", &inside));
        let text = String::from_utf8_lossy(&file);
        assert!(text.contains("WholeExtent=\"0 4 0 3 0 0\" Origin=\"0.5 -1 0\""));
        assert!(text.contains("Spacing=\"0.25 0.25 1\""), "{text}");
    }
    // an array of the wrong length is refused
    let short = [VtkArray::new("x", 1, ArrayValues::Float64(&field[..3]))];
    let err = vtk::write_vti(&mut Vec::new(), &grid, None, &short, VtkEncoding::Binary);
    assert_eq!(err.unwrap_err().kind(), std::io::ErrorKind::InvalidInput);
}

/// Crude XML well-formedness check of the text part: every tag is closed in order.
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

/// Reads a .vtp (any encoding) and checks the point count, the standard arrays and their
/// lengths.
pub(crate) fn check_vtp(path: &std::path::Path, n: usize) {
    let file = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&file);
    match text.find("<AppendedData") {
        Some(i) => check_xml_balanced(&format!("{}</VTKFile>", &text[..i])),
        None => check_xml_balanced(&text),
    }
    let piece = text.lines().find(|l| l.contains("<Piece")).unwrap();
    assert_eq!(attr(piece, "NumberOfPoints"), Some(n.to_string().as_str()));
    assert_eq!(attr(piece, "NumberOfVerts"), Some(n.to_string().as_str()));
    let arrays = read_arrays(&file);
    let names: Vec<&str> = arrays.iter().map(|a| a.name.as_str()).collect();
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
            "volume",
            "Points",
            "connectivity",
            "offsets"
        ]
    );
    for a in &arrays {
        assert_eq!(a.bytes.len(), 8 * n * a.comps, "array {}", a.name);
    }
    assert_eq!(arrays[1].comps, 3);
    assert_eq!(arrays[8].comps, 3);
    assert_eq!(arrays[10].i64s(), (1..=n as i64).collect::<Vec<_>>());
    // the volume is m/ρ of each particle
    let (m, rho, vol) = (arrays[2].f64s(), arrays[3].f64s(), arrays[7].f64s());
    for k in 0..n {
        let expected = f64::from_bits(m[k]) / f64::from_bits(rho[k]);
        assert_eq!(vol[k], expected.to_bits());
    }
}

/// The body names go into the field data as VTK writes strings in ASCII: each name's byte
/// codes, ended by 0 (ParaView and VTK's reader give back `["water", "light"]`, which
/// `tests/python/read_vtk.py` checks with VTK itself).
#[test]
fn body_names_are_a_string_array_of_the_field_data() {
    for encoding in [VtkEncoding::Ascii, VtkEncoding::Binary] {
        let mut file = Vec::new();
        let names = ["water".to_string(), "light".to_string()];
        vtk::write_vtp(&mut file, &table(2), encoding, &names).unwrap();
        let text = String::from_utf8_lossy(&file);
        let field = &text[text.find("<FieldData>").unwrap()..text.find("</FieldData>").unwrap()];
        assert!(
            field.contains(
                "type=\"String\" Name=\"body_names\" NumberOfTuples=\"2\" format=\"ascii\""
            ),
            "{field}"
        );
        assert!(
            field.contains("119 97 116 101 114 0 108 105 103 104 116 0"),
            "{field}"
        );
        assert!(
            text.find("<FieldData>") < text.find("<Piece"),
            "{encoding:?}"
        );
    }
}
