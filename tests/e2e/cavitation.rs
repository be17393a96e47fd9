//! `TaitEos(cavitation: true)`: the water separates instead of stretching. In the tutorial's
//! tank (a column collapsing against the far wall, specular walls, to 0.5 s), no water particle
//! ends the run below ρ0 — without the setting some do — and the total energy stays exact to
//! round-off, as it is without the setting: raising a density where the pressure is 0 does no
//! work.

use std::path::{Path, PathBuf};
use std::process::Command;

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/tutorial_tank_2d.ron")
}

/// Runs the tank with `cavitation` as given; the water's densities at the end and the total
/// energy of every diagnostics row.
fn run(out: &Path, cavitation: bool) -> (Vec<f64>, Vec<f64>) {
    let sets = [
        "output.snapshot_every=0".to_string(),
        "end_time=0.5".to_string(),
        format!("TaitEos.cavitation={cavitation}"),
    ];
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_dualsph"));
    cmd.args(["run", "--quiet", "--threads", "2"])
        .arg(scene())
        .arg("--out")
        .arg(out);
    for s in &sets {
        cmd.args(["--set", s]);
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let column = |file: &str, name: &str| {
        let text = std::fs::read_to_string(out.join(file)).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let k = header.iter().position(|h| *h == name).unwrap();
        lines
            .map(|l| l.split(',').nth(k).unwrap().parse::<f64>().unwrap())
            .collect::<Vec<_>>()
    };
    let rho = column("final.csv", "rho");
    let energy = column("diagnostics.csv", "e_tot");
    (rho, energy)
}

#[test]
fn cavitating_water_never_ends_below_rho0_and_keeps_its_energy() {
    let dir = tempfile::tempdir().unwrap();
    let (rho, energy) = run(&dir.path().join("cavitation"), true);
    let lowest = rho.iter().copied().fold(f64::INFINITY, f64::min);
    assert_eq!(rho.len(), 1400);
    assert!(lowest >= 1000.0, "a water particle ends below ρ0: {lowest}");
    let e0 = energy[0];
    let drift = energy
        .iter()
        .map(|e| ((e - e0) / e0).abs())
        .fold(0.0, f64::max);
    eprintln!("cavitation: lowest ρ {lowest}, energy drift {drift:.1e}");
    assert!(drift < 1e-13, "total energy drifts by {drift:e}");

    let (rho, _) = run(&dir.path().join("tension"), false);
    let lowest = rho.iter().copied().fold(f64::INFINITY, f64::min);
    eprintln!("without: lowest ρ {lowest}");
    assert!(
        lowest < 999.9,
        "without cavitation the lowest density is {lowest}"
    );
}
