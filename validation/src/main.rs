//! The `dualsph-validation` command: `dualsph-validation report [BENCHMARKS…]` runs the
//! benchmarks, grades them and writes `report.md` with the PNG plots (see
//! `dualsph_validation::report`).

use clap::{Parser, Subcommand};
use dualsph::cli::exit::Failure;
use dualsph::say;
use dualsph_validation::report::{Benchmark, ReportOptions, write_report};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "dualsph-validation",
    version,
    about = "The dualsph validation report: run the benchmarks, grade them, write report.md + PNGs",
    after_help = "Exit status: 0 success, 1 failure (a benchmark that cannot run or be written \
                  up), 2 invalid options."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run benchmarks (the paper's, walls, viscous flows), grade them, write report.md + PNGs.
    Report {
        /// Benchmarks to run (default: the paper's four and the Sedov blast).
        #[arg(value_enum)]
        benchmarks: Vec<Benchmark>,
        /// Folder holding the scene files.
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
        /// Output folder for report.md and the plots.
        #[arg(long, default_value = "out/report")]
        out: PathBuf,
        /// Multiply every particle spacing by this factor (1 = the paper's resolution).
        #[arg(long, default_value_t = 1.0)]
        coarsen: f64,
        /// Replace the dam break's end time (s).
        #[arg(long)]
        end_time: Option<f64>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: Result<(), Failure> = match cli.command {
        Command::Report {
            benchmarks,
            scenes,
            out,
            coarsen,
            end_time,
        } => {
            let list = if benchmarks.is_empty() {
                Benchmark::ALL.to_vec()
            } else {
                benchmarks
            };
            let opts = ReportOptions {
                scenes,
                out,
                coarsen,
                end_time,
                log: true,
            };
            let command: Vec<String> = std::env::args().skip(1).collect();
            let command = format!(
                "cargo run --release -p dualsph-validation -- {}",
                command.join(" ")
            );
            write_report(&list, &opts, &command)
                .map(|path| say!("report written: {}", path.display()))
                .map_err(|e| Failure::from(e.to_string()))
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
