//! PNG plots for dualsph reports.
//!
//! A thin layer over [`plotters`]: line/marker charts ([`LinePlot`]) and particle scatter
//! pictures ([`ScatterPlot`]) and filled-contour maps of gridded fields with a colour bar
//! ([`ContourPlot`]). Text is drawn with the DejaVu Sans font embedded through the
//! `dejavu` crate, so no system font is needed. Every PNG is rendered into memory and written
//! with [`dualsph_io::write_atomic`], so a plot file is never left half written.
#![warn(missing_docs)]

mod chart;
mod font;
mod heatmap;

pub use chart::{LinePlot, ScatterPlot, Series, SeriesStyle, palette};
pub use heatmap::{ContourPlot, viridis};

use std::path::PathBuf;

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// plotters failed while drawing.
    #[error("drawing {path}: {message}")]
    Draw {
        /// The plot being drawn.
        path: PathBuf,
        /// What plotters said.
        message: String,
    },
    /// PNG encoding or writing failed.
    #[error("writing {path}: {message}")]
    Write {
        /// The plot being written.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}
