//! Line charts and particle scatter pictures.

use crate::{PlotError, font};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use std::path::Path;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeriesStyle {
    /// A polyline through the points.
    Line,
    /// A marker at each point.
    Markers,
    /// Both.
    LineMarkers,
}

/// One labelled set of (x, y) points.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points in data units.
    pub points: Vec<(f64, f64)>,
    /// Line, markers or both.
    pub style: SeriesStyle,
    /// Index into [`palette`].
    pub colour: usize,
}

impl Series {
    /// A series with the given style and palette colour.
    pub fn new(
        label: impl Into<String>,
        points: Vec<(f64, f64)>,
        style: SeriesStyle,
        colour: usize,
    ) -> Self {
        Series {
            label: label.into(),
            points,
            style,
            colour,
        }
    }
}

/// A 2-D chart of one or more series.
#[derive(Clone, Debug)]
pub struct LinePlot {
    /// Caption above the chart.
    pub title: String,
    /// Horizontal axis label (with units).
    pub x_label: String,
    /// Vertical axis label (with units).
    pub y_label: String,
    /// The series, drawn in order.
    pub series: Vec<Series>,
    /// Axis ranges; `None` fits the data with a 5 % margin.
    pub x_range: Option<(f64, f64)>,
    /// See `x_range`.
    pub y_range: Option<(f64, f64)>,
    /// Logarithmic axes (all values must be positive).
    pub log_x: bool,
    /// See `log_x`.
    pub log_y: bool,
    /// Picture size in pixels.
    pub size: (u32, u32),
}

impl LinePlot {
    /// An empty linear chart of 900 × 600 pixels.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        LinePlot {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            log_x: false,
            log_y: false,
            size: (900, 600),
        }
    }

    /// Adds a series.
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Renders the chart and writes it as a PNG atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        let xs = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.0));
        let ys = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1));
        let (x, log_x) = axis(self.x_range, xs, self.log_x);
        let (y, log_y) = axis(self.y_range, ys, self.log_y);
        render(path, self.size, |area| match (log_x, log_y) {
            (false, false) => self.draw(area, x.0..x.1, y.0..y.1, (false, false)),
            (true, false) => self.draw(area, (x.0..x.1).log_scale(), y.0..y.1, (true, false)),
            (false, true) => self.draw(area, x.0..x.1, (y.0..y.1).log_scale(), (false, true)),
            (true, true) => self.draw(
                area,
                (x.0..x.1).log_scale(),
                (y.0..y.1).log_scale(),
                (true, true),
            ),
        })
    }

    /// Draws the chart on `x` and `y`; `log` says which of them are logarithmic.
    fn draw<X, Y>(&self, area: &Area<'_>, x: X, y: Y, log: (bool, bool)) -> Result<(), String>
    where
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let mut chart = ChartBuilder::on(area)
            .caption(&self.title, (font::FAMILY, 22))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(x, y)
            .map_err(|e| e.to_string())?;
        let sci = |v: &f64| log_tick(*v);
        let mut mesh = chart.configure_mesh();
        mesh.x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style((font::FAMILY, 15))
            .axis_desc_style((font::FAMILY, 17))
            .light_line_style(RGBColor(240, 240, 240));
        if log.0 {
            mesh.x_label_formatter(&sci);
        }
        if log.1 {
            mesh.y_label_formatter(&sci);
        }
        mesh.draw().map_err(|e| e.to_string())?;
        for s in &self.series {
            let colour = palette(s.colour);
            let legend_style = ShapeStyle::from(colour).stroke_width(2);
            let finite: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            let label = s.label.clone();
            if matches!(s.style, SeriesStyle::Line | SeriesStyle::LineMarkers) {
                chart
                    .draw_series(LineSeries::new(finite.clone(), legend_style))
                    .map_err(|e| e.to_string())?
                    .label(label.clone())
                    .legend(move |(lx, ly)| {
                        PathElement::new(vec![(lx, ly), (lx + 20, ly)], legend_style)
                    });
            }
            if matches!(s.style, SeriesStyle::Markers | SeriesStyle::LineMarkers) {
                let anno = chart
                    .draw_series(finite.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                    .map_err(|e| e.to_string())?;
                if s.style == SeriesStyle::Markers {
                    anno.label(label)
                        .legend(move |(lx, ly)| Circle::new((lx + 10, ly), 4, colour.filled()));
                }
            }
        }
        chart
            .configure_series_labels()
            .label_font((font::FAMILY, 15))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| e.to_string())
    }
}

/// Particles drawn as dots coloured by a class (e.g. the initial band of a dam break).
#[derive(Clone, Debug)]
pub struct ScatterPlot {
    /// Caption.
    pub title: String,
    /// (x, y, class) per particle; the class indexes [`palette`].
    pub points: Vec<(f64, f64, usize)>,
    /// Horizontal extent drawn.
    pub x_range: (f64, f64),
    /// Vertical extent drawn.
    pub y_range: (f64, f64),
    /// Width in pixels; the height follows from the aspect ratio of the ranges.
    pub width: u32,
    /// Dot radius in pixels.
    pub radius: i32,
}

impl ScatterPlot {
    /// Renders the particles with equal axis scales and writes a PNG atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        let (x, y) = (self.x_range, self.y_range);
        let plot_w = self.width.saturating_sub(90).max(50) as f64;
        let height = (plot_w * (y.1 - y.0) / (x.1 - x.0)) as u32 + 100;
        render(path, (self.width, height), |area| {
            let mut chart = ChartBuilder::on(area)
                .caption(&self.title, (font::FAMILY, 20))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d(x.0..x.1, y.0..y.1)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc("x (m)")
                .y_desc("y (m)")
                .label_style((font::FAMILY, 14))
                .draw()
                .map_err(|e| e.to_string())?;
            chart
                .draw_series(
                    self.points.iter().map(|&(px, py, c)| {
                        Circle::new((px, py), self.radius, palette(c).filled())
                    }),
                )
                .map_err(|e| e.to_string())?;
            Ok(())
        })
    }
}

/// A colour-blind-friendly palette (Okabe–Ito), cycling.
pub fn palette(i: usize) -> RGBColor {
    const P: [RGBColor; 8] = [
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(0, 0, 0),
        RGBColor(240, 228, 66),
    ];
    P[i % P.len()]
}

pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Renders into an RGB buffer, encodes PNG and writes it atomically.
pub(crate) fn render(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<(), String>,
) -> Result<(), PlotError> {
    font::ensure_registered();
    let mut buf = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let area = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        let drawn = area
            .fill(&WHITE)
            .map_err(|e| e.to_string())
            .and_then(|_| draw(&area))
            .and_then(|_| area.present().map_err(|e| e.to_string()));
        drawn.map_err(|message| PlotError::Draw {
            path: path.to_path_buf(),
            message,
        })?;
    }
    let write_err = |message: String| PlotError::Write {
        path: path.to_path_buf(),
        message,
    };
    let img = image::RgbImage::from_raw(size.0, size.1, buf)
        .ok_or_else(|| write_err("buffer size mismatch".into()))?;
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png)
        .map_err(|e| write_err(e.to_string()))?;
    dualsph_io::write_atomic(path, png.get_ref()).map_err(|e| write_err(e.to_string()))
}

/// An axis's range and whether it is drawn logarithmic: the range given, or the data's
/// ([`fit_range`]). A logarithmic axis whose range spans less than a decade is drawn linear
/// (fitted again without the logarithm): its log scale would carry no labelled tick.
fn axis(
    range: Option<(f64, f64)>,
    values: impl Iterator<Item = f64> + Clone,
    log: bool,
) -> ((f64, f64), bool) {
    let r = range.unwrap_or_else(|| fit_range(values.clone(), log));
    if log && r.1 < 10.0 * r.0 {
        (range.unwrap_or_else(|| fit_range(values, false)), false)
    } else {
        (r, log)
    }
}

/// A log axis's tick label: `1e-2`, `2e-2`, `5e-2`, …; the ticks between (3, 4, 6–9 times a
/// power of ten) are left unlabelled, where their labels would run into each other.
fn log_tick(v: f64) -> String {
    if v.is_nan() || v <= 0.0 {
        return String::new();
    }
    let mantissa = v / libm::pow(10f64, libm::log10(v).floor());
    let labelled = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .any(|m| (mantissa - m).abs() < 1e-6 * m);
    if labelled {
        format!("{v:.0e}")
    } else {
        String::new()
    }
}

/// The data range with a 5 % margin (multiplicative on log axes); never empty.
fn fit_range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let (l, h) = (libm::log10(lo), libm::log10(hi).max(libm::log10(lo) + 1e-3));
        let m = 0.05 * (h - l).max(0.1);
        (libm::pow(10f64, l - m), libm::pow(10f64, h + m))
    } else {
        let span = (hi - lo).max(1e-12 * hi.abs().max(1.0));
        (lo - 0.05 * span, hi + 0.05 * span)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_plot_writes_a_png() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let pts: Vec<(f64, f64)> = (0..50)
            .map(|i| (i as f64 * 0.1, libm::sin(i as f64 * 0.1)))
            .collect();
        LinePlot::new("sin", "x (m)", "y")
            .with(Series::new("sin x", pts.clone(), SeriesStyle::Line, 0))
            .with(Series::new("samples", pts, SeriesStyle::Markers, 1))
            .write_png(&path)
            .unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        // Text and lines were drawn: the picture is not blank.
        let img = image::load_from_memory(&bytes).unwrap().to_rgb8();
        assert!(img.pixels().filter(|p| p.0 != [255, 255, 255]).count() > 2000);
    }

    #[test]
    fn log_log_and_scatter() {
        let dir = tempfile::tempdir().unwrap();
        let mut p = LinePlot::new("err", "CPU s", "L1");
        p.log_x = true;
        p.log_y = true;
        p.series.push(Series::new(
            "a",
            vec![(1.0, 0.1), (10.0, 0.01)],
            SeriesStyle::LineMarkers,
            2,
        ));
        p.write_png(&dir.path().join("b.png")).unwrap();
        let s = ScatterPlot {
            title: "t".into(),
            points: vec![(0.1, 0.1, 0), (0.5, 0.2, 1)],
            x_range: (0.0, 4.0),
            y_range: (0.0, 2.0),
            width: 400,
            radius: 2,
        };
        s.write_png(&dir.path().join("c.png")).unwrap();
        assert!(dir.path().join("c.png").exists());
    }

    #[test]
    fn a_log_axis_under_a_decade_is_drawn_linear() {
        let short = [0.15, 0.22];
        let (r, log) = axis(None, short.into_iter(), true);
        assert!(!log && r.0 < 0.15 && r.1 > 0.22);
        let (_, log) = axis(None, [0.01, 0.3].into_iter(), true);
        assert!(log);
        assert_eq!(log_tick(0.02), "2e-2");
        assert_eq!(log_tick(500.0), "5e2");
        assert_eq!(log_tick(70.0), "");
        assert_eq!(log_tick(1.0), "1e0");
    }

    #[test]
    fn fit_range_handles_degenerate_data() {
        assert_eq!(fit_range(std::iter::empty(), false), (0.0, 1.0));
        let (lo, hi) = fit_range([2.0, 2.0].into_iter(), false);
        assert!(lo < 2.0 && hi > 2.0);
        let (lo, hi) = fit_range([1e-3, 1e-1].into_iter(), true);
        assert!(lo < 1e-3 && hi > 1e-1 && lo > 0.0);
    }
}
