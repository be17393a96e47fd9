//! The validation tests, in one binary so that the engine is linked once: each module grades
//! one benchmark family against its reference (the paper's cases, the walls of particles, the
//! viscous flows, the hard cases). Most are second tier (`#[ignore = "second tier …"]`);
//! `cargo test --release -p dualsph-validation --test validation cavity::` runs one family.

mod adaptive_sod;
mod benchmarks;
mod cavity;
mod common;
mod cylinder;
mod dam_break_obstacle;
mod dam_break_pressure;
mod doc_figures;
mod grad_h;
mod hard_cases;
mod hydrostatic;
mod open_channel;
mod perf_fingerprint;
mod periodic;
mod poiseuille;
mod refinement;
mod sedov;
mod stl_tank;
mod three_d;
mod walls_dam_break;
