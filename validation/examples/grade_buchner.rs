//! Grades the far-wall sensor of Buchner dam break runs: `cargo run --release -p
//! dualsph-validation --example grade_buchner -- DIR...` (each DIR a run of
//! `scenes/dam_break_buchner_2d.ron`, or of a variant of it, holding `probes.csv`).
use dualsph_validation::report::walls::wall_pressure::{grade, sensor, trixi_sensor};

fn main() {
    for dir in std::env::args().skip(1) {
        let table = match dualsph_probes::read_probes(std::path::Path::new(&dir)) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("{dir}: {e}");
                continue;
            }
        };
        let trixi = trixi_sensor(&table);
        let g = grade(sensor(&table), trixi.as_deref());
        println!(
            "{dir}: whole {:.3} first {:.3} wet {:.3} ({:.3}) trixi {:.3} (second {:.3}, peak t* {:.2} vs {:.2})",
            g.whole.0,
            g.first.0,
            g.wet.0,
            g.wet.1,
            g.trixi.0,
            g.trixi_second,
            g.second_peak.0,
            g.second_peak.1
        );
    }
}
