//! Fields sampled on a regular grid: a VTK ImageData file (`.vti`, written by
//! [`dualsph_io::write_vti`] in any [`VtkEncoding`]) for ParaView and a filled contour PNG.
//!
//! Every grid point gets the Shepard-normalised SPH interpolant of the chosen quantity,
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
//! let records = dualsph_io::read_particles_csv("out/dam_break_2d/final.csv".as_ref())?;
//! let kernel = dualsph_core::kernels::KernelKind::CubicSpline;
//! let (vti, png) =
//!     dualsph_run::gridded::write_density_grid(&records, 2, kernel, 0.01, "out/dam_break_2d".as_ref())?;
//! # Ok(()) }
//! ```

use dualsph_core::sampling::SamplingCloud;
use dualsph_fluid::prelude::*;
use dualsph_io::{ArrayValues, ImageGrid, ParticleRecord, VtkArray, VtkEncoding};
use dualsph_probes::Quantity;
use std::path::{Path, PathBuf};

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
    /// Quantity name (as in the probes: `Density`, `Pressure`, …).
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

fn quantity_values(records: &[ParticleRecord], q: Quantity) -> Vec<Real> {
    records
        .iter()
        .map(|r| match q {
            Quantity::Density | Quantity::ShepardSum => r.rho,
            Quantity::Pressure => r.p,
            Quantity::VelocityX => r.vel[0],
            Quantity::VelocityY => r.vel[1],
            Quantity::VelocityZ => r.vel[2],
            Quantity::Speed => (r.vel[0].powi(2) + r.vel[1].powi(2) + r.vel[2].powi(2)).sqrt(),
            Quantity::InternalEnergy => r.e,
        })
        .collect()
}

fn sample_dim<V: Vector>(
    records: &[ParticleRecord],
    kernel: KernelKind,
    q: Quantity,
    grid: Grid,
) -> (Vec<Option<Real>>, Vec<Real>) {
    let to_v = |p: [Real; 3]| V::from_slice(&p[..V::DIM]).unwrap_or_else(V::zero);
    let cloud = SamplingCloud::from_particles(
        Kernel::new(kernel, V::DIM),
        records.iter().map(|r| to_v(r.pos)).collect(),
        &records.iter().map(|r| r.mass).collect::<Vec<_>>(),
        &records.iter().map(|r| r.rho).collect::<Vec<_>>(),
        records.iter().map(|r| r.h).collect(),
    );
    let points: Vec<V> = (0..grid.len()).map(|n| to_v(grid.point(n))).collect();
    let a = quantity_values(records, q);
    let samples = cloud.sample_many(&points, &a);
    let values = samples
        .iter()
        .map(|s| {
            (s.shepard_sum >= INSIDE_SHEPARD).then(|| {
                if q == Quantity::ShepardSum {
                    s.shepard_sum
                } else {
                    s.shepard.unwrap_or(0.0)
                }
            })
        })
        .collect();
    (values, samples.iter().map(|s| s.shepard_sum).collect())
}

/// Samples quantity `q` of particle records (as read from a snapshot or `final.csv`) on the
/// grid of spacing `dx` covering `bounds` (default: the particles' bounding box grown by the
/// largest h). `dim` and `kernel` must be those of the run (the records do not carry them).
pub fn sample_records(
    records: &[ParticleRecord],
    dim: usize,
    kernel: KernelKind,
    q: Quantity,
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
    if records.is_empty() {
        return Err(GridError::Invalid("no particles to sample".into()));
    }
    let (lo, hi) = bounds.unwrap_or_else(|| {
        let h = records.iter().map(|r| r.h).fold(0.0, Real::max);
        let (mut lo, mut hi) = ([Real::INFINITY; 3], [Real::NEG_INFINITY; 3]);
        for r in records {
            for k in 0..3 {
                lo[k] = lo[k].min(r.pos[k] - h);
                hi[k] = hi[k].max(r.pos[k] + h);
            }
        }
        (lo, hi)
    });
    let grid = Grid::covering(lo, hi, dx, dim);
    if grid.len() > 50_000_000 || grid.dims[..dim].iter().any(|&n| n < 2) {
        return Err(GridError::Invalid(format!(
            "dx = {dx} gives a {:?} grid: choose a spacing with 2 to 50 million points",
            &grid.dims[..dim]
        )));
    }
    let (values, shepard) = match dim {
        1 => sample_dim::<Vec1>(records, kernel, q, grid),
        2 => sample_dim::<glam::DVec2>(records, kernel, q, grid),
        _ => sample_dim::<glam::DVec3>(records, kernel, q, grid),
    };
    Ok(GriddedField {
        name: format!("{q:?}"),
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
    q: Quantity,
    dx: Real,
) -> Result<GriddedField, GridError> {
    let kernel = sim.world.resource::<KernelRes>().0.kind;
    let domain = *sim.world.resource::<Domain<V>>();
    let records = crate::runner::particle_records(sim);
    let bounds = (domain.min.to_xyz(), domain.max.to_xyz());
    sample_records(&records, V::DIM, kernel, q, dx, Some(bounds))
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
        "Density" => "density (kg/m³)",
        "Pressure" => "pressure (Pa)",
        "VelocityX" | "VelocityY" | "VelocityZ" | "Speed" => "velocity (m/s)",
        "InternalEnergy" => "internal energy (J/kg)",
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

/// The density of particle records on a grid of spacing `dx` (bounds: the particles'
/// box grown by h) written as `DIR/density_grid.vti` (binary) and `DIR/density_grid.png`;
/// returns the two paths.
pub fn write_density_grid(
    records: &[ParticleRecord],
    dim: usize,
    kernel: KernelKind,
    dx: Real,
    out_dir: &Path,
) -> Result<(PathBuf, PathBuf), GridError> {
    let f = sample_records(records, dim, kernel, Quantity::Density, dx, None)?;
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
    let f = sample_sim(sim, Quantity::Density, dx)?;
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
