//! VTK XML output, the one writer of the workspace: PolyData (`.vtp`) of particles, ImageData
//! (`.vti`) of fields on a grid, and the ParaView collection (`.pvd`) of the snapshots.
//!
//! Data arrays are stored as [`VtkEncoding`] says: as text inside each `<DataArray>`
//! (`Ascii`), or after the XML in one `<AppendedData encoding="raw">` section (`Binary`,
//! `Compressed`). Appended files declare `header_type="UInt64"`: each array there is a
//! UInt64 byte count followed by its little-endian values (`Binary`), or the zlib block
//! header `[blocks, block size, size of the last partial block (0 if none), compressed size
//! of each block]` (UInt64 each) followed by the compressed blocks (`Compressed`, with
//! `compressor="vtkZLibDataCompressor"` on `<VTKFile>`). Each `<DataArray>` gives its
//! `offset`, counted in bytes from the first byte after the `_` that opens the section.

use std::io::{self, Write};

use flate2::Compression;
use flate2::write::ZlibEncoder;

use crate::csv_out::{SnapshotEntry, fmt_real, push_real};
use crate::table::{POSITION, ParticleTable};

/// Values per line inside ASCII `DataArray`s (purely cosmetic).
const PER_LINE: usize = 9;

/// Uncompressed bytes per zlib block of a `Compressed` array (VTK's default block size).
pub const ZLIB_BLOCK: usize = 1 << 15;

/// How the data arrays of a VTK XML file are stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum VtkEncoding {
    /// Text inside each `<DataArray format="ascii">`; reals with the shortest digits that
    /// read back to the same `f64`.
    Ascii,
    /// Raw little-endian bytes in the appended section, each array after a UInt64 byte count.
    #[default]
    Binary,
    /// Like `Binary`, but each array zlib-compressed in blocks of [`ZLIB_BLOCK`] bytes.
    Compressed,
}

/// The values of one data array, with their VTK type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ArrayValues<'a> {
    /// `Float64` values.
    Float64(&'a [f64]),
    /// `Int64` values.
    Int64(&'a [i64]),
    /// `UInt8` values.
    UInt8(&'a [u8]),
}

impl ArrayValues<'_> {
    /// The VTK type name (`Float64`, …).
    pub fn type_name(&self) -> &'static str {
        match self {
            ArrayValues::Float64(_) => "Float64",
            ArrayValues::Int64(_) => "Int64",
            ArrayValues::UInt8(_) => "UInt8",
        }
    }

    /// Number of values (components of all tuples).
    pub fn len(&self) -> usize {
        match self {
            ArrayValues::Float64(v) => v.len(),
            ArrayValues::Int64(v) => v.len(),
            ArrayValues::UInt8(v) => v.len(),
        }
    }

    /// True without values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The values as little-endian bytes.
    fn le_bytes(&self) -> Vec<u8> {
        match self {
            ArrayValues::Float64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ArrayValues::Int64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ArrayValues::UInt8(v) => v.to_vec(),
        }
    }

    /// Appends value `i` as text.
    fn push_text(&self, i: usize, out: &mut String) {
        match self {
            ArrayValues::Float64(v) => push_real(out, v[i]),
            ArrayValues::Int64(v) => out.push_str(&v[i].to_string()),
            ArrayValues::UInt8(v) => out.push_str(&v[i].to_string()),
        }
    }
}

/// One `<DataArray>`: its name (none for the points), components per tuple and values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VtkArray<'a> {
    /// The `Name` attribute; `None` writes none (the points of a PolyData).
    pub name: Option<&'a str>,
    /// Components per tuple (`NumberOfComponents`, written when above 1).
    pub components: usize,
    /// The values, `components` per tuple.
    pub values: ArrayValues<'a>,
}

impl<'a> VtkArray<'a> {
    /// A named array.
    pub fn new(name: &'a str, components: usize, values: ArrayValues<'a>) -> Self {
        VtkArray {
            name: Some(name),
            components,
            values,
        }
    }
}

/// A regular grid of points `origin + (i·spacing[0], j·spacing[1], k·spacing[2])`,
/// `i < dims[0]`, … (unused axes have 1 point), the extent of an ImageData file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageGrid {
    /// First point.
    pub origin: [f64; 3],
    /// Distance between neighbouring points along each axis.
    pub spacing: [f64; 3],
    /// Points per axis (each >= 1).
    pub dims: [usize; 3],
}

/// A VTK XML file being assembled: the XML text and, for the appended encodings, the bytes
/// of the appended section.
struct VtkXml {
    encoding: VtkEncoding,
    text: String,
    appended: Vec<u8>,
}

impl VtkXml {
    /// The XML declaration and the opening `<VTKFile>` of a file of `kind`.
    fn new(kind: &str, encoding: VtkEncoding) -> Self {
        let attrs = match encoding {
            VtkEncoding::Ascii => "version=\"0.1\" byte_order=\"LittleEndian\"",
            VtkEncoding::Binary => {
                "version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\""
            }
            VtkEncoding::Compressed => {
                "version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\""
            }
        };
        VtkXml {
            encoding,
            text: format!("<?xml version=\"1.0\"?>\n<VTKFile type=\"{kind}\" {attrs}>\n"),
            appended: Vec::new(),
        }
    }

    fn line(&mut self, s: &str) {
        self.text.push_str(s);
        self.text.push('\n');
    }

    /// One `<DataArray>` at the usual depth (inside a Piece's PointData, Points or Verts).
    fn array(&mut self, a: &VtkArray) -> io::Result<()> {
        let name = a
            .name
            .map_or(String::new(), |n| format!(" Name=\"{}\"", xml_attr(n)));
        let comps = if a.components > 1 {
            format!(" NumberOfComponents=\"{}\"", a.components)
        } else {
            String::new()
        };
        let ty = a.values.type_name();
        if self.encoding == VtkEncoding::Ascii {
            self.line(&format!(
                "        <DataArray type=\"{ty}\"{name}{comps} format=\"ascii\">"
            ));
            let per_line = (PER_LINE / a.components.max(1)).max(1) * a.components.max(1);
            let n = a.values.len();
            let mut i = 0;
            while i < n {
                let mut l = String::from("         ");
                for k in i..(i + per_line).min(n) {
                    l.push(' ');
                    a.values.push_text(k, &mut l);
                }
                self.line(&l);
                i += per_line;
            }
            self.line("        </DataArray>");
            return Ok(());
        }
        let offset = self.appended.len();
        self.line(&format!(
            "        <DataArray type=\"{ty}\"{name}{comps} format=\"appended\" offset=\"{offset}\"/>"
        ));
        let bytes = a.values.le_bytes();
        if self.encoding == VtkEncoding::Binary {
            self.appended
                .extend_from_slice(&(bytes.len() as u64).to_le_bytes());
            self.appended.extend_from_slice(&bytes);
        } else {
            let blocks = bytes
                .chunks(ZLIB_BLOCK)
                .map(|block| {
                    let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
                    z.write_all(block)?;
                    z.finish()
                })
                .collect::<io::Result<Vec<Vec<u8>>>>()?;
            let header = [
                blocks.len() as u64,
                ZLIB_BLOCK as u64,
                (bytes.len() % ZLIB_BLOCK) as u64,
            ]
            .into_iter()
            .chain(blocks.iter().map(|b| b.len() as u64));
            for h in header {
                self.appended.extend_from_slice(&h.to_le_bytes());
            }
            for b in &blocks {
                self.appended.extend_from_slice(b);
            }
        }
        Ok(())
    }

    /// Writes the XML, the appended section (if any) and the closing `</VTKFile>`.
    fn finish(self, w: &mut dyn Write) -> io::Result<()> {
        w.write_all(self.text.as_bytes())?;
        if self.encoding != VtkEncoding::Ascii {
            w.write_all(b"  <AppendedData encoding=\"raw\">\n   _")?;
            w.write_all(&self.appended)?;
            w.write_all(b"\n  </AppendedData>\n")?;
        }
        w.write_all(b"</VTKFile>\n")
    }
}

/// The name of the point-data array that carries each particle's volume `m/ρ` in a `.vtp`
/// (derived for the viewer, so that fine and coarse particles can be sized apart; no column
/// of the state, and not read back).
pub const VOLUME_ARRAY: &str = "volume";

/// The name of the field-data array of a `.vtp` that lists the body names, in `BodyId` order
/// (the `body` point array holds the index).
pub const BODY_NAMES_ARRAY: &str = "body_names";

/// Writes a VTK XML PolyData file: one point and one vertex cell per particle, the
/// [`POSITION`] column as the points (Float64), and point data `id` (Int64) and every other
/// column of the table (Float64, as many components as it has labels), then [`VOLUME_ARRAY`]
/// `= mass/density` when the table has both. `bodies` (the body names by index, may be empty)
/// goes into the field data as the string array [`BODY_NAMES_ARRAY`] (ASCII: each name as its
/// byte codes, ended by 0, as VTK writes strings). Connectivity and offsets are Int64. Ids
/// above `i64::MAX` are written as their two's complement bits.
pub(crate) fn write_vtp(
    w: &mut dyn Write,
    table: &ParticleTable,
    encoding: VtkEncoding,
    bodies: &[String],
) -> io::Result<()> {
    let n = table.len();
    let mut x = VtkXml::new("PolyData", encoding);
    x.line("  <PolyData>");
    if !bodies.is_empty() {
        let codes: Vec<String> = bodies
            .iter()
            .map(|b| {
                let mut c: Vec<String> = b.bytes().map(|u| u.to_string()).collect();
                c.push("0".into());
                c.join(" ")
            })
            .collect();
        x.line("    <FieldData>");
        x.line(&format!(
            "      <DataArray type=\"String\" Name=\"{BODY_NAMES_ARRAY}\" NumberOfTuples=\"{}\" format=\"ascii\">",
            bodies.len()
        ));
        x.line(&format!("        {}", codes.join(" ")));
        x.line("      </DataArray>");
        x.line("    </FieldData>");
    }
    x.line(&format!(
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    ));
    let active = |name: &str, attr: &str| match table.column(name) {
        Some(_) => format!(" {attr}=\"{name}\""),
        None => String::new(),
    };
    x.line(&format!(
        "      <PointData{}{}>",
        active("density", "Scalars"),
        active("velocity", "Vectors")
    ));
    let ids: Vec<i64> = table.ids.iter().map(|&id| id as i64).collect();
    x.array(&VtkArray::new("id", 1, ArrayValues::Int64(&ids)))?;
    for c in table.columns.iter().filter(|c| c.name != POSITION) {
        x.array(&VtkArray::new(
            &c.name,
            c.width(),
            ArrayValues::Float64(&c.values),
        ))?;
    }
    let one = |name: &str| table.column(name).filter(|c| c.width() == 1);
    if let (Some(m), Some(rho)) = (one("mass"), one("density")) {
        let volume: Vec<f64> = m
            .values
            .iter()
            .zip(&rho.values)
            .map(|(m, r)| m / r)
            .collect();
        x.array(&VtkArray::new(
            VOLUME_ARRAY,
            1,
            ArrayValues::Float64(&volume),
        ))?;
    }
    x.line("      </PointData>");
    x.line("      <Points>");
    let zeros;
    let (comps, points) = match table.column(POSITION) {
        Some(c) => (c.width(), c.values.as_slice()),
        None => {
            zeros = vec![0.0; 3 * n];
            (3, zeros.as_slice())
        }
    };
    x.array(&VtkArray {
        name: None,
        components: comps,
        values: ArrayValues::Float64(points),
    })?;
    x.line("      </Points>");
    x.line("      <Verts>");
    let connectivity: Vec<i64> = (0..n as i64).collect();
    let offsets: Vec<i64> = (1..=n as i64).collect();
    x.array(&VtkArray::new(
        "connectivity",
        1,
        ArrayValues::Int64(&connectivity),
    ))?;
    x.array(&VtkArray::new("offsets", 1, ArrayValues::Int64(&offsets)))?;
    x.line("      </Verts>");
    x.line("    </Piece>");
    x.line("  </PolyData>");
    x.finish(w)
}

/// Writes a VTK XML ImageData file of `grid` with the given point data arrays (each holding
/// one tuple per grid point, x fastest, then y, then z); `scalars` names the active scalars.
/// Returns an `InvalidInput` error when an array does not have one tuple per point or an
/// axis has no points.
pub fn write_vti(
    w: &mut dyn Write,
    grid: &ImageGrid,
    scalars: Option<&str>,
    arrays: &[VtkArray],
    encoding: VtkEncoding,
) -> io::Result<()> {
    let points: usize = grid.dims.iter().product();
    if grid.dims.contains(&0) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "an ImageData grid of {:?} points has an empty axis",
                grid.dims
            ),
        ));
    }
    if let Some(a) = arrays
        .iter()
        .find(|a| a.values.len() != points * a.components.max(1))
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "array {} has {} values for {points} points of {} components",
                a.name.unwrap_or("(unnamed)"),
                a.values.len(),
                a.components
            ),
        ));
    }
    let ext = format!(
        "0 {} 0 {} 0 {}",
        grid.dims[0] - 1,
        grid.dims[1] - 1,
        grid.dims[2] - 1
    );
    let triple = |v: [f64; 3]| v.map(fmt_real).join(" ");
    let mut x = VtkXml::new("ImageData", encoding);
    x.line(&format!(
        "  <ImageData WholeExtent=\"{ext}\" Origin=\"{}\" Spacing=\"{}\">",
        triple(grid.origin),
        triple(grid.spacing)
    ));
    x.line(&format!("    <Piece Extent=\"{ext}\">"));
    let active = scalars.map_or(String::new(), |s| format!(" Scalars=\"{}\"", xml_attr(s)));
    x.line(&format!("      <PointData{active}>"));
    for a in arrays {
        x.array(a)?;
    }
    x.line("      </PointData>");
    x.line("    </Piece>");
    x.line("  </ImageData>");
    x.finish(w)
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
