//! The perf fingerprint docs/performance.md quotes is the one the code gives: the reference
//! case (`perf 2 uniform dam 500 N`) stepped in this process on one thread, its state's
//! fingerprint against the figure in the doc. A change of arithmetic fails here until the
//! doc is updated in the same commit.

use dualsph_validation::perf::{Case, REFERENCE_STEPS, state_fingerprint};
use std::path::Path;

/// The fingerprint the doc quotes after `steps` steps: the 16 hex digits in backticks on the
/// sentence that names `perf 2 uniform dam {steps} N`.
fn quoted(doc: &str, steps: usize) -> Option<String> {
    let flat = doc.split_whitespace().collect::<Vec<_>>().join(" ");
    let at = flat.find(&format!("perf 2 uniform dam {steps} N"))?;
    let rest = &flat[at..];
    let sentence = &rest[..rest.find(". ").unwrap_or(rest.len())];
    sentence
        .split('`')
        .find(|w| w.len() == 16 && w.chars().all(|c| c.is_ascii_hexdigit()))
        .map(str::to_string)
}

#[test]
fn the_documented_perf_fingerprint_is_the_codes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/performance.md");
    let doc = std::fs::read_to_string(&path).unwrap();
    let documented = quoted(&doc, REFERENCE_STEPS).unwrap_or_else(|| {
        panic!(
            "{} quotes no fingerprint for perf 2 uniform dam {REFERENCE_STEPS} N",
            path.display()
        )
    });
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let computed = pool.install(|| {
        let mut sim = Case::dam_column_2d().sim::<glam::DVec2>();
        for _ in 0..REFERENCE_STEPS {
            sim.step().unwrap();
        }
        format!("{:016x}", state_fingerprint(&mut sim))
    });
    assert_eq!(
        computed, documented,
        "the reference case's fingerprint after {REFERENCE_STEPS} steps is {computed}; docs/performance.md quotes {documented}: update the doc if the arithmetic changed on purpose"
    );
}

#[test]
fn the_quote_is_found_across_a_line_break() {
    let doc = "after 500 steps\nof the reference case (`perf 2 uniform dam 500 N`) it is\n`0123456789abcdef`. Next `fedcba9876543210`.";
    assert_eq!(quoted(doc, 500).as_deref(), Some("0123456789abcdef"));
    assert_eq!(quoted(doc, 400), None);
}
