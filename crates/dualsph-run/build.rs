//! Records the git revision the binary is built from (for `run.json`), when it is built from a
//! git checkout with `git` on the PATH; otherwise nothing.

use std::path::Path;
use std::process::Command;

fn main() {
    // the repository's root is two levels up (crates/dualsph-run)
    for f in [
        "../../.git/HEAD",
        "../../.git/refs/heads",
        "../../.git/packed-refs",
    ] {
        if Path::new(f).exists() {
            println!("cargo:rerun-if-changed={f}");
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
    let revision = Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty());
    if let Some(r) = revision {
        println!("cargo:rustc-env=DUALSPH_GIT_REVISION={r}");
    }
}
