//! The commands the docs show run as shown: every `dualsph …` / `cargo run --release -- …` line
//! of a fenced `sh` block in the README and `docs/`, in order, one working directory per
//! document (with `scenes/` and `examples/` beside it), and the tutorial's `tank.ron` written
//! from its latest full `Scene(` block before each command. Shortened only where a run would be
//! long: a `run` stops after as many steps as the document's later commands on the same scene
//! file need (the largest step a `particles_NNNNNN` / `checkpoint_NNNNNN` names, else 3) and may reuse its
//! output directory (`--force`: the directory rules have tests of their own). Not run here:
//! builds, installs, tests and benches (`cargo install/test/bench`), the validation report and
//! examples (their own tests), Python (`tests/python`), profilers.

use std::path::Path;
use std::process::Command;

/// The documents whose commands are run.
const DOCS: [&str; 7] = [
    "README.md",
    "docs/cli.md",
    "docs/output.md",
    "docs/tutorial.md",
    "docs/python.md",
    "docs/performance.md",
    "docs/parameters.md",
];

/// One line of a fenced `sh` block: the command (comment cut off) and, for the tutorial,
/// the scene text `tank.ron` holds at that point.
struct Line {
    command: String,
    tank: Option<String>,
}

/// The command lines of `doc`, in order.
fn lines(doc: &str) -> Vec<Line> {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(doc)).unwrap();
    let (mut out, mut block, mut tank, mut ron) =
        (Vec::new(), None::<String>, None, None::<String>);
    for l in text.lines() {
        match (&mut block, &mut ron) {
            (None, None) if l.starts_with("```sh") => block = Some(String::new()),
            (None, None) if l.starts_with("```ron") => ron = Some(String::new()),
            (Some(_), _) if l.starts_with("```") => block = None,
            (_, Some(r)) if l.starts_with("```") => {
                if r.trim_start().starts_with("Scene(") {
                    tank = Some(r.clone());
                }
                ron = None;
            }
            (_, Some(r)) => {
                r.push_str(l);
                r.push('\n');
            }
            (Some(_), _) => {
                let command = l.split(" # ").next().unwrap_or("").trim().to_string();
                if !command.is_empty() && !command.starts_with('#') {
                    out.push(Line {
                        command,
                        tank: tank.clone(),
                    });
                }
            }
            _ => {}
        }
    }
    out
}

/// Whether a command line is one of the engine's command line (else it is not run here).
fn is_cli(command: &str) -> bool {
    let words: Vec<&str> = command.split_whitespace().collect();
    let cli = words.first() == Some(&"dualsph")
        || command.contains("cargo run --release -- ")
        || command.contains("cargo run -- ");
    cli && !command.ends_with('\\')
}

/// The scene file a command names (its first `.ron` word).
fn scene_of(command: &str) -> Option<&str> {
    command.split_whitespace().find(|w| w.ends_with(".ron"))
}

/// The largest step a `particles_NNNNNN` or `checkpoint_NNNNNN` names in `commands`.
fn steps_needed(commands: &[&str]) -> u64 {
    commands
        .iter()
        .flat_map(|c| c.split(|ch: char| !ch.is_ascii_alphanumeric() && ch != '_'))
        .filter_map(|w| {
            let n = w
                .strip_prefix("particles_")
                .or(w.strip_prefix("checkpoint_"))?;
            n.parse::<u64>().ok()
        })
        .max()
        .unwrap_or(0)
}

/// `command` as the test runs it: the binary for `dualsph` / `cargo run …--`, and a `run`
/// shortened to `steps` (with `--force`).
fn rewrite(command: &str, bin: &str, steps: u64) -> String {
    let mut c = command
        .replace("cargo run --release -- ", &format!("{bin} "))
        .replace("cargo run -- ", &format!("{bin} "));
    if c.starts_with("dualsph ") {
        c = format!("{bin}{}", &c["dualsph".len()..]);
    }
    let runs = c
        .split_whitespace()
        .nth(c.split_whitespace().position(|w| w == bin).unwrap_or(0) + 1)
        == Some("run");
    if runs {
        let resume = steps_needed(&[&c]);
        c.push_str(&format!(" --set max_steps={}", (resume + 3).max(steps)));
        if !c.contains("--resume") && !c.contains("--force") {
            c.push_str(" --force");
        }
    }
    c
}

#[test]
#[ignore = "second tier (cargo test --workspace --release -- --ignored): runs parts of the docs' scenes"]
fn every_command_in_the_docs_runs_as_shown() {
    let bin = env!("CARGO_BIN_EXE_dualsph");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut ran = 0;
    for doc in DOCS {
        let dir = tempfile::tempdir().unwrap();
        for sub in ["scenes", "examples"] {
            std::os::unix::fs::symlink(root.join(sub), dir.path().join(sub)).unwrap();
        }
        let all = lines(doc);
        for (k, line) in all.iter().enumerate() {
            if !is_cli(&line.command) {
                continue;
            }
            if let Some(tank) = &line.tank {
                std::fs::write(dir.path().join("tank.ron"), tank).unwrap();
            }
            // the later commands on the same scene file say how far its run must go
            let scene = scene_of(&line.command);
            let later: Vec<&str> = all[k + 1..]
                .iter()
                .map(|l| l.command.as_str())
                .filter(|c| scene.is_some() && scene_of(c) == scene)
                .collect();
            let steps = steps_needed(&later).max(3);
            let command = rewrite(&line.command, bin, steps);
            let out = Command::new("sh")
                .arg("-c")
                .arg(&command)
                .current_dir(dir.path())
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{doc}: `{}` (run as `{command}`) failed:\n{}",
                line.command,
                String::from_utf8_lossy(&out.stderr)
            );
            ran += 1;
        }
    }
    // the command lines of the README, cli.md, output.md, the tutorial, python.md, ...
    assert!(ran >= 25, "only {ran} commands found");
}

#[test]
fn the_harness_finds_and_shortens_the_commands() {
    let cli = lines("docs/cli.md");
    assert!(
        cli.iter()
            .any(|l| l.command == "cargo run --release -- plugins")
    );
    let tutorial = lines("docs/tutorial.md");
    let run = tutorial
        .iter()
        .find(|l| l.command == "dualsph run tank.ron")
        .unwrap();
    assert!(run.tank.as_deref().unwrap().contains("Probes("));
    assert_eq!(
        steps_needed(&["dualsph grid tank.ron --file particles_015000.csv"]),
        15_000
    );
    let c = rewrite(
        "cargo run --release -- run scenes/a.ron --out out/a",
        "/b/dualsph",
        3,
    );
    assert_eq!(
        c,
        "/b/dualsph run scenes/a.ron --out out/a --set max_steps=3 --force"
    );
    let r = rewrite(
        "dualsph run a.ron --resume out/a/checkpoint_004000.ckpt",
        "/b/dualsph",
        3,
    );
    assert_eq!(
        r,
        "/b/dualsph run a.ron --resume out/a/checkpoint_004000.ckpt --set max_steps=4003"
    );
    assert!(!is_cli(
        "cargo run --release -p dualsph-validation -- report"
    ));
    assert!(!is_cli("cargo test --workspace --release"));
}
