//! The scene parser's fuzz corpus on a stable toolchain (the `fuzz/` target needs cargo-fuzz):
//! the regression inputs, and seeded mutations of every shipped, malformed and test scene,
//! each parsed and validated. Whatever the input, the result is `Ok` or one error message
//! naming the file — never a panic — and no input takes more than a few seconds.

use crate::common::ron_files;

use dualsph::scene::Scene;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::time::{Duration, Instant};

/// Particles a mutated scene may generate (a mutation that multiplies the count is refused
/// at the estimate, as the command line refuses what does not fit in memory).
const LIMIT: usize = 2_000_000;

/// The longest one input may take to parse and validate.
const PER_INPUT: Duration = Duration::from_secs(10);

/// Parses and validates `text` as `fuzz.ron`; a failure says which input and why.
/// `Ok(true)` when it is a valid scene, `Ok(false)` when it is refused cleanly.
fn parse_cleanly(text: &str, what: &str) -> Result<bool, String> {
    let registry = dualsph::default_registry();
    let path = Path::new("fuzz.ron");
    let started = Instant::now();
    let outcome = std::panic::catch_unwind(|| {
        Scene::parse_only(text, path, &registry).and_then(|s| {
            s.validate_with_limit(path, LIMIT, " (the test's limit)")
                .map(|()| s)
        })
    });
    let took = started.elapsed();
    match outcome {
        Err(_) => Err(format!("{what}: panicked on:\n{text}")),
        Ok(_) if took > PER_INPUT => Err(format!("{what}: took {took:?} on:\n{text}")),
        Ok(Ok(s)) if !(1..=3).contains(&s.dimension) => {
            Err(format!("{what}: accepted dimension {}", s.dimension))
        }
        Ok(Err(e)) if !e.to_string().starts_with("fuzz.ron") => {
            Err(format!("{what}: message without the file: {e}"))
        }
        Ok(Ok(_)) => Ok(true),
        Ok(Err(_)) => Ok(false),
    }
}

/// Tokens a mutation may insert: numbers at the edges of f64, brackets, names.
const TOKENS: [&str; 16] = [
    "1e308",
    "-0.0",
    "NaN",
    "inf",
    "(",
    ")",
    "[",
    "]",
    ",",
    "\"",
    "0",
    "99999999999999999999",
    "Block(",
    "Some(",
    "h_factor: 1e-9",
    "spacing: 1e-300",
];

/// One random edit of `text`: flip a byte, cut a span, repeat a span or insert a token.
fn mutate(text: &str, rng: &mut ChaCha8Rng) -> String {
    let mut b = text.as_bytes().to_vec();
    let at = rng.random_range(0..b.len().max(1));
    let span = rng.random_range(1..=16).min(b.len() - at.min(b.len()));
    match rng.random_range(0..4) {
        0 if !b.is_empty() => b[at] ^= 1 << rng.random_range(0..7),
        1 => {
            b.drain(at..at + span);
        }
        2 => {
            let piece = b[at..at + span].to_vec();
            b.splice(at..at, piece);
        }
        _ => {
            let token = TOKENS[rng.random_range(0..TOKENS.len())];
            b.splice(at..at, token.bytes());
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}

#[test]
fn regression_inputs_parse_or_fail_cleanly() {
    let files = ron_files("fuzz/regressions/parse_scene");
    assert!(!files.is_empty());
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        parse_cleanly(&text, &f.display().to_string()).unwrap();
    }
}

#[test]
fn mutated_scenes_parse_or_fail_cleanly() {
    mutations_parse_or_fail_cleanly(300, 0x5eed_d5a9);
}

#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): half a million parses"]
fn many_more_mutated_scenes_parse_or_fail_cleanly() {
    mutations_parse_or_fail_cleanly(5_000, 0x0dd_5eed);
}

/// `per_seed` mutations of every seed scene, from the random stream `stream`.
fn mutations_parse_or_fail_cleanly(per_seed: usize, stream: u64) {
    let mut seeds = Vec::new();
    for dir in ["scenes", "scenes/hard", "tests/bad_scenes", "tests/restart"] {
        seeds.extend(ron_files(dir));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(stream);
    let (mut failures, mut valid, mut tried) = (Vec::new(), 0, 0);
    for seed in &seeds {
        let Ok(text) = std::fs::read_to_string(seed) else {
            continue; // the malformed scenes include one that is not UTF-8
        };
        for k in 0..per_seed {
            // one to three edits, each on the result of the last
            let mut m = text.clone();
            for _ in 0..rng.random_range(1..=3) {
                m = mutate(&m, &mut rng);
            }
            let what = format!("{} mutation {k}", seed.display());
            tried += 1;
            match parse_cleanly(&m, &what) {
                Ok(ok) => valid += usize::from(ok),
                Err(e) => failures.push(e),
            }
        }
    }
    println!("{tried} mutated scenes: {valid} valid, the others refused");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    // the mutations reach the validator and the generators, not only the parser
    assert!(
        valid * 20 > tried,
        "only {valid} of {tried} mutated scenes were valid"
    );
}
