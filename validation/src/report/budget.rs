//! The energy budget of a run from its diagnostics rows: where the energy released went.
//!
//! With `E_kin`, `E_pot`, `E_int` the totals of `diagnostics.csv` and `D = Σ m_i d_i` its
//! `dissipated` column (the time integral of the artificial viscosity's heating,
//! `dualsph_fluid::components::Dissipated`), the changes since t = 0 are
//!
//! `ΔE_kin + ΔE_pot + W_c + D = ΔE_tot`, with `W_c = ΔE_int − D`
//!
//! the reversible part of the internal energy (the compression work of the pressure force,
//! `p/ρ²` work, returned when the fluid expands). `ΔE_tot` is zero to round-off with the
//! integrators' work-consistent update; `D ≥ 0` never decreases (each pair's heat is ≥ 0).
//! `W_c` is derived, not stored.

use super::{CaseRun, ReportError, Table};
use dualsph_diagnostics::Diagnostics;
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use std::path::Path;

/// One row of the budget: the changes since the first row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// Simulated time.
    pub t: f64,
    /// `E_kin(t) − E_kin(0)`.
    pub kinetic: f64,
    /// `E_pot(t) − E_pot(0)`.
    pub potential: f64,
    /// `W_c = E_int(t) − E_int(0) − D(t)`: the reversible (compression) part.
    pub compression: f64,
    /// `D(t)`, the dissipated energy.
    pub dissipated: f64,
    /// `E_tot(t) − E_tot(0)`, the sum of the four.
    pub total: f64,
}

impl Budget {
    /// The budget of `d` against the first row `d0`.
    pub fn of(d0: &Diagnostics, d: &Diagnostics) -> Self {
        let dissipated = d.dissipated - d0.dissipated;
        Budget {
            t: d.t,
            kinetic: d.e_kin - d0.e_kin,
            potential: d.e_pot - d0.e_pot,
            compression: d.e_int - d0.e_int - dissipated,
            dissipated,
            total: d.e_tot - d0.e_tot,
        }
    }
}

/// The budget of every recorded row of `run`.
pub fn series(run: &CaseRun) -> Vec<Budget> {
    let d0 = &run.diagnostics[0];
    run.diagnostics.iter().map(|d| Budget::of(d0, d)).collect()
}

/// Whether the dissipated energy never decreases from row to row.
pub fn dissipated_never_decreases(rows: &[Budget]) -> bool {
    rows.windows(2).all(|w| w[1].dissipated >= w[0].dissipated)
}

/// The last recorded row at or before each of `times`, and the last row.
fn rows_at(rows: &[Budget], times: &[f64]) -> Vec<Budget> {
    let mut out: Vec<Budget> = times
        .iter()
        .filter_map(|&t| rows.iter().rev().find(|b| b.t <= t + 1e-12).copied())
        .collect();
    if let Some(&last) = rows.last() {
        out.push(last);
    }
    out.dedup_by(|a, b| a.t == b.t);
    out
}

/// A markdown table of the budget of `rows` at `times` (and at the end), in J per metre of
/// depth (2-D).
pub fn table(rows: &[Budget], times: &[f64]) -> String {
    let mut table = Table::new([
        "t (s)",
        "ΔE_kin",
        "ΔE_pot",
        "W_c = ΔE_int − D",
        "D (dissipated)",
        "ΔE_tot",
    ]);
    for b in rows_at(rows, times) {
        table.row(vec![
            format!("{:.3}", b.t),
            format!("{:.1}", b.kinetic),
            format!("{:.1}", b.potential),
            format!("{:.1}", b.compression),
            format!("{:.1}", b.dissipated),
            format!("{:.1e}", b.total),
        ]);
    }
    table.render()
}

/// Plots the four parts and the total against time.
pub fn plot(rows: &[Budget], title: &str, png: &Path) -> Result<(), ReportError> {
    let line = |name: &str, k: usize, f: fn(&Budget) -> f64| {
        let pts = rows.iter().map(|b| (b.t, f(b))).collect();
        Series::new(name, pts, SeriesStyle::Line, k)
    };
    LinePlot::new(title, "t (s)", "change since t = 0 (J/m)")
        .with(line("kinetic", 0, |b| b.kinetic))
        .with(line("potential", 1, |b| b.potential))
        .with(line("internal: compression W_c", 2, |b| b.compression))
        .with(line("internal: dissipated D", 3, |b| b.dissipated))
        .with(line("total", 4, |b| b.total))
        .write_png(png)?;
    Ok(())
}

/// What the budget of `label` says at its last row, from the numbers: the share of the
/// potential energy released that is kinetic, compression and dissipated, whether `D` never
/// decreased, and how closely the four add up.
pub fn finding(label: &str, rows: &[Budget]) -> String {
    let Some(b) = rows.last() else {
        return String::new();
    };
    let released = -b.potential;
    if released <= 0.0 {
        return format!(
            "{label}: no potential energy released by t = {:.2} s (ΔE_pot = {:.1} J/m).",
            b.t, b.potential
        );
    }
    let pct = |x: f64| 100.0 * x / released;
    let monotone = if dissipated_never_decreases(rows) {
        "never decreases between the recorded rows"
    } else {
        "decreases between some recorded rows"
    };
    format!(
        "{label}: by t = {:.2} s the fluid has released {:.1} J/m of potential energy, of which {:.1} % is \
         kinetic energy, {:.1} % compression work (W_c) and {:.1} % dissipated by the artificial viscosity (D); \
         D {monotone}, and the four changes add up to ΔE_tot = {:.1e} J/m ({:.1e} of the energy released).",
        b.t,
        released,
        pct(b.kinetic),
        pct(b.compression),
        pct(b.dissipated),
        b.total,
        b.total.abs() / released,
    )
}
