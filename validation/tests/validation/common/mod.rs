//! Shared helpers of the validation tests: those of the facade's end-to-end tests
//! (`tests/e2e/common` at the workspace root, included, not copied) and the report's options.
#![allow(dead_code)]

#[path = "../../../../tests/e2e/common/mod.rs"]
mod facade;
#[allow(unused_imports)]
pub use facade::*;

use dualsph::prelude::*;

/// The report's options for the repository's scenes folder, writing to the temporary
/// directory without a log: spacing × `coarsen`, to `end_time` (the scene's when `None`).
pub fn report_options(
    coarsen: Real,
    end_time: Option<Real>,
) -> dualsph_validation::report::ReportOptions {
    dualsph_validation::report::ReportOptions {
        scenes: std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes"),
        out: std::env::temp_dir(),
        coarsen,
        end_time,
        log: false,
    }
}
