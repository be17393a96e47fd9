//! A closed triangle mesh read from an STL file (binary or ASCII, read by `stl_io`), and
//! the checks that make it fillable: finite vertices, no degenerate triangle, every edge
//! shared by exactly two triangles, and the two traversing it in opposite directions (one
//! consistent orientation, either way round).

use std::collections::HashMap;
use std::path::Path;

/// A triangle mesh in the file's coordinates: vertices welded where their coordinates are
/// equal (`-0.0` and `0.0` alike), triangles as vertex indices in the file's order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Mesh {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// A mesh from triangles given by their corners, welding equal corners.
    pub(crate) fn from_corners(corners: impl IntoIterator<Item = [[f64; 3]; 3]>) -> Self {
        let mut index: HashMap<[u64; 3], u32> = HashMap::new();
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for tri in corners {
            let t = tri.map(|v| {
                // `+ 0.0` turns -0.0 into 0.0, so the two weld
                let key = v.map(|x| (x + 0.0).to_bits());
                *index.entry(key).or_insert_with(|| {
                    vertices.push(v);
                    (vertices.len() - 1) as u32
                })
            });
            triangles.push(t);
        }
        Mesh {
            vertices,
            triangles,
        }
    }

    /// The corners of triangle `t`.
    pub(crate) fn corners(&self, t: usize) -> [[f64; 3]; 3] {
        self.triangles[t].map(|i| self.vertices[i as usize])
    }
}

/// Reads the STL file at `path` (binary or ASCII).
pub(crate) fn read_stl(path: &Path) -> Result<Mesh, String> {
    // the STL reader's own message can quote the file; a file that is not an STL mesh is
    // never printed, so its content errors are told in our words
    let fail = |e: std::io::Error| {
        let why = match e.kind() {
            std::io::ErrorKind::InvalidData | std::io::ErrorKind::UnexpectedEof => {
                "not a binary or ASCII STL mesh".to_owned()
            }
            _ => e.to_string(),
        };
        format!("cannot read STL file `{}`: {why}", path.display())
    };
    let mut file = dualsph_io::open_input(path, dualsph_io::INPUT_FILE_LIMIT).map_err(fail)?;
    let reader = stl_io::create_stl_reader(&mut file).map_err(fail)?;
    let mut corners = Vec::new();
    for t in reader {
        let t = t.map_err(fail)?;
        corners.push(t.vertices.map(|v| v.0.map(f64::from)));
    }
    if corners.is_empty() {
        return Err(format!("STL file `{}` has no triangles", path.display()));
    }
    Ok(Mesh::from_corners(corners))
}

/// Twice the area of a triangle, `|(b − a) × (c − a)|`, and its longest edge squared.
fn area2_and_edge2(t: &[[f64; 3]; 3]) -> (f64, f64) {
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let (u, v, w) = (sub(t[1], t[0]), sub(t[2], t[0]), sub(t[2], t[1]));
    let cr = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len2 = |a: [f64; 3]| a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    (len2(cr).sqrt(), len2(u).max(len2(v)).max(len2(w)))
}

/// Checks that `mesh` bounds a solid: finite vertices; no degenerate triangle (twice its
/// area at most `10⁻¹⁰` of its longest edge squared: a repeated vertex or three collinear
/// ones); every edge shared by exactly two triangles (no hole, no non-manifold edge); and
/// each edge traversed once in each direction by its two triangles (a consistent
/// orientation). The message counts the offending edges or triangles.
pub(crate) fn check_closed(mesh: &Mesh) -> Result<(), String> {
    if let Some(i) = mesh
        .vertices
        .iter()
        .position(|v| !v.iter().all(|x| x.is_finite()))
    {
        return Err(format!("vertex {i} is not finite ({:?})", mesh.vertices[i]));
    }
    let degenerate: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&t| {
            let (a2, e2) = area2_and_edge2(&mesh.corners(t));
            a2 <= 1e-10 * e2
        })
        .collect();
    if let Some(&first) = degenerate.first() {
        return Err(format!(
            "{} degenerate triangle(s) (zero area: a repeated vertex or three collinear ones), \
             the first is triangle {first} with corners {:?}",
            degenerate.len(),
            mesh.corners(first)
        ));
    }
    // per undirected edge: how many triangles hold it, and the sum of its directions
    let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let e = edges.entry((a.min(b), a.max(b))).or_insert((0, 0));
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
    }
    let count = |f: &dyn Fn(&(u32, i32)) -> bool| edges.values().filter(|e| f(e)).count();
    let (open, non_manifold) = (count(&|e| e.0 == 1), count(&|e| e.0 > 2));
    if open > 0 || non_manifold > 0 {
        return Err(format!(
            "open STL: {open} edge(s) belong to one triangle only and {non_manifold} to more \
             than two (of {} edges); a fill needs a closed surface, every edge shared by \
             exactly two triangles",
            edges.len()
        ));
    }
    let flipped = count(&|e| e.1 != 0);
    if flipped > 0 {
        return Err(format!(
            "{flipped} edge(s) join two triangles of opposite orientation: the vertex order of \
             every facet must run the same way round (all counter-clockwise seen from outside, \
             or all clockwise)"
        ));
    }
    Ok(())
}
