//! Fields sampled on a regular grid: a VTK ImageData file (`.vti`, written by
//! [`dualsph_io::write_vti`] in any [`VtkEncoding`]) for ParaView and a filled contour PNG.
//!
//! Every grid point gets the Shepard-normalised SPH interpolant of the chosen quantity (named
//! as the probes name it, [`dualsph_probes::quantity`]: a scalar column `density`, a component
//! `velocity.x`, `speed`, `shepard_sum`, …),
//! `A(x) = Σ_j A_j V_j W_j / Σ_j V_j W_j`, with each particle's own kernel and support radius
//! (see [`dualsph_core::sampling`]), and the Shepard sum `σ(x) = Σ_j V_j W_j`. Points with
//! `σ < 0.5` are outside the fluid (σ = ½ at a flat free surface): they are white in the PNG
//! and hold 0 with `inside = 0` in the `.vti` (threshold on `inside` or `shepard_sum` in
//! ParaView to hide them).
//!
//! From code (the facade re-exports this module as `dualsph::gridded`):
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let table = dualsph_io::read_particle_table_vtp("out/dam_break_2d/particles_000100.vtp".as_ref())?;
//! let kernel = dualsph_core::kernels::KernelKind::CubicSpline;
//! let (vti, png) =
//!     dualsph_run::gridded::write_density_grid(&table, 2, kernel, 0.01, "out/dam_break_2d".as_ref())?;
//! # Ok(()) }
//! ```

use dualsph_core::sampling::SamplingCloud;
use dualsph_fluid::prelude::*;
use dualsph_io::{ArrayValues, ImageGrid, POSITION, ParticleTable, VtkArray, VtkEncoding};
use dualsph_probes::Quantity;
use std::path::{Path, PathBuf};

pub(crate) mod field;

/// Points with a Shepard sum below this are outside the fluid.
pub const INSIDE_SHEPARD: Real = 0.5;

/// A regular grid of points `origin + (i, j, k)·spacing`, `i < dims[0]`, … (unused axes 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// First point.
    pub origin: [Real; 3],
    /// Distance between neighbouring points (the same on every axis).
    pub spacing: Real,
    /// Points per axis.
    pub dims: [usize; 3],
}

impl Grid {
    /// The grid of spacing `dx` covering `[lo, hi]` on the first `dim` axes.
    pub fn covering(lo: [Real; 3], hi: [Real; 3], dx: Real, dim: usize) -> Grid {
        let mut dims = [1; 3];
        for k in 0..dim {
            dims[k] = ((hi[k] - lo[k]) / dx + 1e-9).floor().max(0.0) as usize + 1;
        }
        let mut origin = [0.0; 3];
        origin[..dim].copy_from_slice(&lo[..dim]);
        Grid {
            origin,
            spacing: dx,
            dims,
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// True if the grid has no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Point number `n` (x fastest, then y, then z).
    pub fn point(&self, n: usize) -> [Real; 3] {
        let (i, j, k) = (
            n % self.dims[0],
            (n / self.dims[0]) % self.dims[1],
            n / (self.dims[0] * self.dims[1]),
        );
        [
            self.origin[0] + i as Real * self.spacing,
            self.origin[1] + j as Real * self.spacing,
            self.origin[2] + k as Real * self.spacing,
        ]
    }
}

/// A quantity sampled on a grid.
#[derive(Clone, Debug)]
pub struct GriddedField {
    /// Quantity name (as in the probes: `density`, `velocity.x`, …).
    pub name: String,
    /// The grid.
    pub grid: Grid,
    /// Spatial dimension of the particles (1, 2 or 3).
    pub dim: usize,
    /// Shepard-normalised values, `None` where `σ < 0.5` (outside the fluid).
    pub values: Vec<Option<Real>>,
    /// Shepard sums σ.
    pub shepard: Vec<Real>,
}

/// Why gridded output failed.
#[derive(Debug, thiserror::Error)]
pub enum GridError {
    /// Bad arguments (the message says which).
    #[error("{0}")]
    Invalid(String),
    /// Writing a file failed.
    #[error(transparent)]
    Io(#[from] dualsph_io::OutputError),
    /// Drawing the PNG failed.
    #[error(transparent)]
    Plot(#[from] dualsph_plot::PlotError),
}

/// The particles' positions (first `d` components), masses, densities and support radii.
fn sample_dim<V: Vector>(
    table: &ParticleTable,
    kernel: KernelKind,
    a: &[Real],
    shepard_only: bool,
    grid: Grid,
) -> Result<(Vec<Option<Real>>, Vec<Real>), GridError> {
    let col = |name: &str| field::column(table, name, V::DIM).map(|c| c.values.as_slice());
    let to_v = |p: &[Real]| V::from_slice(&p[..V::DIM]).unwrap_or_else(V::zero);
    let cloud = SamplingCloud::from_particles(
        Kernel::new(kernel, V::DIM),
        col(POSITION)?.chunks_exact(3).map(to_v).collect(),
        col("mass")?,
        col("density")?,
        col("smoothing_length")?.to_vec(),
    );
    let points: Vec<V> = (0..grid.len()).map(|n| to_v(&grid.point(n))).collect();
    let samples = cloud.sample_many(&points, a);
    let values = samples
        .iter()
        .map(|s| {
            (s.shepard_sum >= INSIDE_SHEPARD).then(|| {
                if shepard_only {
                    s.shepard_sum
                } else {
                    s.shepard.unwrap_or(0.0)
                }
            })
        })
        .collect();
    Ok((values, samples.iter().map(|s| s.shepard_sum).collect()))
}

/// The particles' bounding box grown by the largest h.
fn bounding_box(table: &ParticleTable, dim: usize) -> Result<([Real; 3], [Real; 3]), GridError> {
    let h = field::column(table, "smoothing_length", dim)?;
    let h = h.values.iter().copied().fold(0.0, Real::max);
    let (mut lo, mut hi) = ([Real::INFINITY; 3], [Real::NEG_INFINITY; 3]);
    for r in field::column(table, POSITION, dim)?.values.chunks_exact(3) {
        for k in 0..3 {
            lo[k] = lo[k].min(r[k] - h);
            hi[k] = hi[k].max(r[k] + h);
        }
    }
    Ok((lo, hi))
}

/// Samples quantity `q` of a particle table (as written to a snapshot or `final.csv` and
/// read back; it needs the columns `position`, `mass`, `density` and `smoothing_length`) on
/// the grid of spacing `dx` covering `bounds` (default: the particles' bounding box grown by
/// the largest h). `dim` and `kernel` must be those of the run (the table does not carry
/// them). The error says what is wrong: an argument, or a column the table lacks (with the
/// quantities it has).
pub fn sample_table(
    table: &ParticleTable,
    dim: usize,
    kernel: KernelKind,
    q: &Quantity,
    dx: Real,
    bounds: Option<([Real; 3], [Real; 3])>,
) -> Result<GriddedField, GridError> {
    if !(1..=3).contains(&dim) || !kernel.supports_dimension(dim) {
        return Err(GridError::Invalid(format!(
            "dimension {dim} with kernel {kernel:?} is not supported"
        )));
    }
    if !(dx.is_finite() && dx > 0.0) {
        return Err(GridError::Invalid(format!("dx must be > 0, got {dx}")));
    }
    if table.is_empty() {
        return Err(GridError::Invalid("no particles to sample".into()));
    }
    let a = field::values(table, q, dim)?;
    let (lo, hi) = match bounds {
        Some(b) => b,
        None => bounding_box(table, dim)?,
    };
    let grid = Grid::covering(lo, hi, dx, dim);
    if grid.len() > 50_000_000 || grid.dims[..dim].iter().any(|&n| n < 2) {
        return Err(GridError::Invalid(format!(
            "dx = {dx} gives a {:?} grid: choose a spacing with 2 to 50 million points",
            &grid.dims[..dim]
        )));
    }
    let shepard_only = q.name() == dualsph_probes::quantity::SHEPARD_SUM;
    let (values, shepard) = match dim {
        1 => sample_dim::<Vec1>(table, kernel, &a, shepard_only, grid)?,
        2 => sample_dim::<glam::DVec2>(table, kernel, &a, shepard_only, grid)?,
        _ => sample_dim::<glam::DVec3>(table, kernel, &a, shepard_only, grid)?,
    };
    Ok(GriddedField {
        name: q.name().to_string(),
        grid,
        dim,
        values,
        shepard,
    })
}

/// Samples quantity `q` of a live simulation (its kernel, dimension and current particles)
/// on the grid of spacing `dx` covering the domain box.
pub fn sample_sim<V: Vector>(
    sim: &mut Sim<V>,
    q: &Quantity,
    dx: Real,
) -> Result<GriddedField, GridError> {
    let kernel = sim.world.resource::<KernelRes>().0.kind;
    let domain = *sim.world.resource::<Domain<V>>();
    let table = crate::runner::column_table(sim);
    let bounds = (domain.min.to_xyz(), domain.max.to_xyz());
    sample_table(&table, V::DIM, kernel, q, dx, Some(bounds))
}

/// The particles of a file a run of `scene` wrote (a `.vtp` snapshot, or a particle CSV:
/// `final.csv`, `particles_NNNNNN.csv`) as a table whose columns are named as in snapshots
/// (`velocity`, not `vx, vy, vz`): the CSV's labels are grouped by the scene's registered
/// columns, which this builds the scene's simulation to know.
pub fn read_particles(scene: &dualsph_scene::Scene, path: &Path) -> Result<ParticleTable, String> {
    let vtp = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("vtp"));
    let groups = crate::with_dimension!(scene.dimension, V => {
        let sim = crate::build_sim::<V>(scene).map_err(|e| e.to_string())?;
        let columns = sim.world.resource::<dualsph_core::columns::Columns>();
        columns
            .iter()
            .filter(|c| c.shape != dualsph_core::columns::Shape::Record)
            .map(|c| (c.spec.name.to_string(), c.labels(V::DIM)))
            .collect::<Vec<_>>()
    });
    if vtp {
        // a VTK array is named by its column; its components take the column's labels
        // (`vx, vy, vz`), which tell a vector from a matrix as in the CSV
        let mut table = dualsph_io::read_particle_table_vtp(path).map_err(|e| e.to_string())?;
        for c in &mut table.columns {
            let own = groups
                .iter()
                .find(|(n, l)| *n == c.name && l.len() == c.width());
            if let Some((_, labels)) = own {
                c.labels = labels.clone();
            }
        }
        return Ok(table);
    }
    let table = dualsph_io::read_particle_table_csv(path).map_err(|e| e.to_string())?;
    Ok(table.grouped(&groups))
}

/// Writes the field as VTK XML ImageData (`.vti`, point data `<name>` and `shepard_sum`
/// as Float64, `inside` as UInt8) in `encoding`, atomically.
pub fn write_vti(path: &Path, f: &GriddedField, encoding: VtkEncoding) -> Result<(), GridError> {
    let g = f.grid;
    let grid = ImageGrid {
        origin: g.origin,
        spacing: [g.spacing; 3],
        dims: g.dims,
    };
    let values: Vec<Real> = f.values.iter().map(|v| v.unwrap_or(0.0)).collect();
    let inside: Vec<u8> = f.values.iter().map(|v| v.is_some() as u8).collect();
    let arrays = [
        VtkArray::new(&f.name, 1, ArrayValues::Float64(&values)),
        VtkArray::new("shepard_sum", 1, ArrayValues::Float64(&f.shepard)),
        VtkArray::new("inside", 1, ArrayValues::UInt8(&inside)),
    ];
    dualsph_io::write_atomic_with(path, |w| {
        dualsph_io::write_vti(w, &grid, Some(&f.name), &arrays, encoding)
    })?;
    Ok(())
}

fn unit(name: &str) -> &'static str {
    match name {
        "density" => "density (kg/m³)",
        "pressure" => "pressure (Pa)",
        "velocity.x" | "velocity.y" | "velocity.z" | "speed" => "velocity (m/s)",
        "internal_energy" => "internal energy (J/kg)",
        _ => "value",
    }
}

/// Writes a filled-contour PNG of a 2-D field (for 3-D, of the middle z slice), white where
/// `σ < 0.5`. A 1-D field is an error (plot it as a line instead).
pub fn write_png(path: &Path, f: &GriddedField, title: &str) -> Result<(), GridError> {
    if f.dim < 2 {
        return Err(GridError::Invalid(
            "a contour plot needs a 2-D or 3-D field".into(),
        ));
    }
    let g = f.grid;
    let (nx, ny) = (g.dims[0], g.dims[1]);
    let k = g.dims[2] / 2;
    let values = f.values[k * nx * ny..(k + 1) * nx * ny].to_vec();
    let span = |a: usize| {
        (
            g.origin[a],
            g.origin[a] + (g.dims[a] - 1) as Real * g.spacing,
        )
    };
    let plot =
        dualsph_plot::ContourPlot::new(title, unit(&f.name), (nx, ny), values, span(0), span(1));
    plot.write_png(path)?;
    Ok(())
}

/// The density of a particle table on a grid of spacing `dx` (bounds: the particles'
/// box grown by h) written as `DIR/density_grid.vti` (binary) and `DIR/density_grid.png`;
/// returns the two paths.
pub fn write_density_grid(
    table: &ParticleTable,
    dim: usize,
    kernel: KernelKind,
    dx: Real,
    out_dir: &Path,
) -> Result<(PathBuf, PathBuf), GridError> {
    let f = sample_table(table, dim, kernel, &Quantity::density(), dx, None)?;
    write_field(
        &f,
        out_dir,
        "density_grid",
        "density (SPH interpolant, σ ≥ 0.5)",
        VtkEncoding::default(),
    )
}

/// [`write_density_grid`] for a live simulation (grid over its domain box).
pub fn write_density_grid_sim<V: Vector>(
    sim: &mut Sim<V>,
    dx: Real,
    out_dir: &Path,
) -> Result<(PathBuf, PathBuf), GridError> {
    let f = sample_sim(sim, &Quantity::density(), dx)?;
    let t = sim.clock().t;
    write_field(
        &f,
        out_dir,
        "density_grid",
        &format!("density at t = {t:.3} s"),
        VtkEncoding::default(),
    )
}

/// Writes `DIR/<stem>.vti` (arrays stored as `encoding` says) and, in 2-D/3-D,
/// `DIR/<stem>.png` (in 1-D the PNG path is returned but not written).
pub fn write_field(
    f: &GriddedField,
    out_dir: &Path,
    stem: &str,
    title: &str,
    encoding: VtkEncoding,
) -> Result<(PathBuf, PathBuf), GridError> {
    std::fs::create_dir_all(out_dir).map_err(|source| dualsph_io::OutputError::Io {
        path: out_dir.to_path_buf(),
        op: "create directory",
        source,
    })?;
    let (vti, png) = (
        out_dir.join(format!("{stem}.vti")),
        out_dir.join(format!("{stem}.png")),
    );
    write_vti(&vti, f, encoding)?;
    if f.dim >= 2 {
        write_png(&png, f, title)?;
    }
    Ok((vti, png))
}

#[cfg(test)]
mod tests;
