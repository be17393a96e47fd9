//! # dualsph-validation
//!
//! The validation of the `dualsph` engine, outside the facade crate so that no user binary
//! carries it: the validation report ([`report`]: the benchmarks run case by case, graded
//! against their references and written up as `report.md` with PNG plots; the binary
//! `dualsph-validation report`) and the benchmark cases of the benches and the `perf` example
//! ([`perf`]).
#![warn(missing_docs)]

pub mod perf;
pub mod report;
