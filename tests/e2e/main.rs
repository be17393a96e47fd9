//! The end-to-end tests of the facade crate, in one binary so that the engine is linked once:
//! each module is one area (the command line, bad scenes, restart, conservation, ...). The
//! quick tier is every test not marked `#[ignore = "second tier …"]`; `-- --ignored` runs
//! the second tier. `cargo test --release --test e2e restart::` runs one area.

mod bad_scenes;
mod bodies;
mod cavitation;
mod cli;
mod common;
mod conservation;
mod determinism;
mod doc_commands;
mod energy_budget;
mod energy_in_time;
mod field_docs;
mod fuzz_corpus;
mod hard_cases_cli;
mod hostile_fields;
mod hostile_files;
mod hostile_run;
mod layers;
mod limited;
mod loads;
mod open_boundary;
mod open_reflection;
mod order;
mod output;
mod particles_file;
mod population;
mod probes;
mod refinement;
mod restart;
mod run_hygiene;
mod scenes;
mod set;
mod sound_speed;
mod surface_tension;
