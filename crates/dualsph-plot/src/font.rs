//! The embedded font: plotters' `ab_glyph` backend needs fonts registered by family name.

use plotters::style::{FontStyle, register_font};
use std::sync::Once;

/// The family name every chart asks for.
pub(crate) const FAMILY: &str = "sans-serif";

/// Registers DejaVu Sans (regular and bold) once per process.
pub(crate) fn ensure_registered() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TrueType font shipped by the `dejavu` crate; registration only
        // fails on unparsable bytes, in which case text would be missing rather than wrong.
        let _ = register_font(FAMILY, FontStyle::Normal, dejavu::sans::regular());
        let _ = register_font(FAMILY, FontStyle::Bold, dejavu::sans::bold());
    });
}
