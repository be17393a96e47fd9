//! Grades lid-driven cavity runs against Ghia, Ghia & Shin (1982): `cargo run --release -p
//! dualsph-validation --example grade_cavity -- RE DIR[:FROM-UNTIL]...` (RE 100 or 1000, each
//! DIR a run of `scenes/cavity_2d.ron` or `scenes/cavity_2d_re1000.ron`, or of a variant,
//! holding `probes.csv`; FROM-UNTIL the window of samples averaged, in s, by default from the
//! Reynolds number's steady time to the end). Prints the largest centreline errors in units
//! of U, as `validation/tests/validation/cavity.rs` asserts them, and where each falls.
use dualsph_validation::report::walls::cavity::{CentreLines, Ghia, RE100, RE1000};

fn main() {
    let mut args = std::env::args().skip(1);
    let reference = match args.next().as_deref() {
        Some("100") => RE100,
        Some("1000") => RE1000,
        other => {
            eprintln!("the first argument is the Reynolds number, 100 or 1000 (got {other:?})");
            std::process::exit(2);
        }
    };
    for arg in args {
        let (dir, window) = match arg.rsplit_once(':') {
            Some((d, w)) => (d.to_string(), Some(w.to_string())),
            None => (arg.clone(), None),
        };
        if let Err(e) = grade(&dir, window.as_deref(), reference) {
            eprintln!("{arg}: {e}");
        }
    }
}

/// Grades one run over `window` ("FROM-UNTIL", s).
fn grade(dir: &str, window: Option<&str>, reference: Ghia) -> Result<(), String> {
    let (from, until) = match window {
        Some(w) => {
            let (a, b) = w
                .split_once('-')
                .ok_or_else(|| format!("window {w}: expected FROM-UNTIL"))?;
            let num = |s: &str| s.parse::<f64>().map_err(|e| format!("window {w}: {e}"));
            (num(a)?, num(b)?)
        }
        None => (reference.from, f64::INFINITY),
    };
    let mut table = dualsph_probes::read_probes(std::path::Path::new(dir))?;
    let keep: Vec<usize> = (0..table.t.len())
        .filter(|&k| table.t[k] <= until)
        .collect();
    table.values = keep.iter().map(|&k| table.values[k].clone()).collect();
    table.t = keep.iter().map(|&k| table.t[k]).collect();
    table.step = keep.iter().map(|&k| table.step[k]).collect();
    let lines = CentreLines::of(&table, Ghia { from, ..reference })?;
    if lines.samples == 0 {
        return Err(format!("no samples in {from}-{until} s"));
    }
    let (u, v) = lines.errors();
    let [wu, wv] = lines.worst();
    println!(
        "{dir}: {} samples in {from}-{until} s: u {u:.4} U (at y = {:.4}: {:+.3} against {:+.3}), v {v:.4} U (at x = {:.4}: {:+.3} against {:+.3})",
        lines.samples, wu.0, wu.1, wu.2, wv.0, wv.1, wv.2
    );
    Ok(())
}
