//! Filled-contour pictures of a field on a regular grid, with a colour bar.

use crate::chart::{Area, render};
use crate::{PlotError, font};
use plotters::prelude::*;
use std::path::Path;

/// A scalar field on a regular 2-D grid drawn as filled contour bands (a colour map quantised
/// into `levels` bands) with a colour bar. Cells whose value is `None` (or not finite) are
/// left white — e.g. where the Shepard sum says there is no fluid.
#[derive(Clone, Debug)]
pub struct ContourPlot {
    /// Caption.
    pub title: String,
    /// Label of the colour bar (quantity and unit).
    pub value_label: String,
    /// Grid points along x and y.
    pub nx: usize,
    /// See `nx`.
    pub ny: usize,
    /// Values at the grid points, x fastest: `values[ix + nx * iy]`.
    pub values: Vec<Option<f64>>,
    /// x of the first and last column of points.
    pub x_range: (f64, f64),
    /// y of the first and last row of points.
    pub y_range: (f64, f64),
    /// Colour range; `None` fits the finite values.
    pub value_range: Option<(f64, f64)>,
    /// Number of colour bands (≥ 2); 0 draws a continuous colour map.
    pub levels: usize,
    /// Width in pixels; the height follows from the aspect ratio of the ranges.
    pub width: u32,
}

impl ContourPlot {
    /// A plot of `values` (x fastest) on an `nx × ny` grid spanning the given ranges, with
    /// 12 bands, 1000 pixels wide.
    pub fn new(
        title: impl Into<String>,
        value_label: impl Into<String>,
        (nx, ny): (usize, usize),
        values: Vec<Option<f64>>,
        x_range: (f64, f64),
        y_range: (f64, f64),
    ) -> Self {
        ContourPlot {
            title: title.into(),
            value_label: value_label.into(),
            nx,
            ny,
            values,
            x_range,
            y_range,
            value_range: None,
            levels: 12,
            width: 1000,
        }
    }

    /// The colour range used: `value_range` or the finite data range (never empty).
    pub fn colour_range(&self) -> (f64, f64) {
        if let Some(r) = self.value_range {
            return r;
        }
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in self.values.iter().flatten().filter(|v| v.is_finite()) {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        if !lo.is_finite() {
            return (0.0, 1.0);
        }
        if hi <= lo {
            let pad = 1e-9 * lo.abs().max(1.0);
            return (lo - pad, hi + pad);
        }
        (lo, hi)
    }

    /// The colour of value v for the range `(lo, hi)`, quantised into `levels` bands.
    pub fn colour_of(&self, v: f64, (lo, hi): (f64, f64)) -> RGBColor {
        let mut f = ((v - lo) / (hi - lo)).clamp(0.0, 1.0);
        if self.levels >= 2 {
            let band = (f * self.levels as f64)
                .floor()
                .min(self.levels as f64 - 1.0);
            f = (band + 0.5) / self.levels as f64;
        }
        viridis(f)
    }

    /// Renders the picture and writes it as a PNG atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        let draw_err = |message: String| PlotError::Draw {
            path: path.to_path_buf(),
            message,
        };
        if self.nx < 2 || self.ny < 2 || self.values.len() != self.nx * self.ny {
            return Err(draw_err(format!(
                "grid {} × {} needs {} values (≥ 2 × 2), got {}",
                self.nx,
                self.ny,
                self.nx * self.ny,
                self.values.len()
            )));
        }
        let (x, y) = (self.x_range, self.y_range);
        let bar_w = 130u32;
        let plot_w = self.width.saturating_sub(bar_w + 70).max(100) as f64;
        let height = ((plot_w * (y.1 - y.0) / (x.1 - x.0)) as u32 + 90).clamp(200, 4000);
        let range = self.colour_range();
        let (hx, hy) = (
            0.5 * (x.1 - x.0) / (self.nx - 1) as f64,
            0.5 * (y.1 - y.0) / (self.ny - 1) as f64,
        );
        render(path, (self.width, height), |area: &Area<'_>| {
            let (left, right) = area.split_horizontally(self.width - bar_w);
            let mut chart = ChartBuilder::on(&left)
                .caption(&self.title, (font::FAMILY, 20))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(55)
                .build_cartesian_2d(x.0 - hx..x.1 + hx, y.0 - hy..y.1 + hy)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc("x (m)")
                .y_desc("y (m)")
                .label_style((font::FAMILY, 14))
                .draw()
                .map_err(|e| e.to_string())?;
            let cells = (0..self.ny).flat_map(|iy| (0..self.nx).map(move |ix| (ix, iy)));
            chart
                .draw_series(cells.filter_map(|(ix, iy)| {
                    let v = self.values[ix + self.nx * iy].filter(|v| v.is_finite())?;
                    let cx = x.0 + 2.0 * hx * ix as f64;
                    let cy = y.0 + 2.0 * hy * iy as f64;
                    Some(Rectangle::new(
                        [(cx - hx, cy - hy), (cx + hx, cy + hy)],
                        self.colour_of(v, range).filled(),
                    ))
                }))
                .map_err(|e| e.to_string())?;
            // colour bar
            let mut bar = ChartBuilder::on(&right)
                .margin_top(40)
                .margin_bottom(50)
                .margin_right(10)
                .y_label_area_size(75)
                .build_cartesian_2d(0.0..1.0, range.0..range.1)
                .map_err(|e| e.to_string())?;
            bar.configure_mesh()
                .disable_mesh()
                .disable_x_axis()
                .y_desc(&self.value_label)
                .label_style((font::FAMILY, 13))
                .axis_desc_style((font::FAMILY, 14))
                .draw()
                .map_err(|e| e.to_string())?;
            let steps = 200;
            let dv = (range.1 - range.0) / steps as f64;
            bar.draw_series((0..steps).map(|k| {
                let v0 = range.0 + k as f64 * dv;
                Rectangle::new(
                    [(0.0, v0), (1.0, v0 + dv)],
                    self.colour_of(v0 + 0.5 * dv, range).filled(),
                )
            }))
            .map_err(|e| e.to_string())?;
            Ok(())
        })
    }
}

/// The viridis colour map (perceptually uniform), linearly interpolated between 9 anchors;
/// `f ∈ [0, 1]`.
pub fn viridis(f: f64) -> RGBColor {
    const A: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = f.clamp(0.0, 1.0) * (A.len() - 1) as f64;
    let k = (t.floor() as usize).min(A.len() - 2);
    let s = t - k as f64;
    let mix = |a: u8, b: u8| (a as f64 + s * (b as f64 - a as f64)).round() as u8;
    RGBColor(
        mix(A[k].0, A[k + 1].0),
        mix(A[k].1, A[k + 1].1),
        mix(A[k].2, A[k + 1].2),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contour_plot_masks_missing_values_and_draws_a_colour_bar() {
        let dir = tempfile::tempdir().unwrap();
        let (nx, ny) = (60, 30);
        // a quarter disc of "fluid" with a linear field; the rest is masked
        let values = (0..nx * ny)
            .map(|k| {
                let (x, y) = ((k % nx) as f64 / 59.0, (k / nx) as f64 / 29.0);
                (x * x + y * y < 0.5).then_some(1000.0 + 10.0 * y)
            })
            .collect();
        let plot = ContourPlot::new("t", "ρ (kg/m³)", (nx, ny), values, (0.0, 2.0), (0.0, 1.0));
        let path = dir.path().join("c.png");
        plot.write_png(&path).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        // top-right of the plot area is masked: white
        let (w, h) = img.dimensions();
        let p = img.get_pixel(w - 200, 70).0;
        assert_eq!(p, [255, 255, 255], "masked cell not white");
        // bottom-left is coloured with the low end of viridis (dark)
        let q = img.get_pixel(90, h - 70).0;
        assert!(q[0] < 120 && q[2] > 60, "unexpected colour {q:?}");
        // the highest fluid row is y = 20/29 (x = 0): range [1000, 1000 + 200/29]
        let (lo, hi) = plot.colour_range();
        assert!(lo == 1000.0 && (hi - (1000.0 + 200.0 / 29.0)).abs() < 1e-9);
        // 12 bands: values in the same band get the same colour
        let r = (0.0, 12.0);
        assert_eq!(plot.colour_of(0.1, r), plot.colour_of(0.9, r));
        assert_ne!(plot.colour_of(0.9, r), plot.colour_of(1.1, r));
        // wrong sizes are an error, not a panic
        let bad = ContourPlot::new("t", "v", (3, 3), vec![None; 4], (0.0, 1.0), (0.0, 1.0));
        assert!(bad.write_png(&path).is_err());
    }

    #[test]
    fn viridis_ends() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(-3.0), viridis(0.0));
    }
}
