//! Reading `probes.csv` back and plotting it with `dualsph-plot`.

use crate::{PROBE_POINTS_FILE, PROBES_FILE};
use dualsph_core::math::Real;
use dualsph_plot::{LinePlot, Series, SeriesStyle};
use std::path::{Path, PathBuf};

/// `probes.csv` and `probes_points.csv` read back.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeTable {
    /// Column names after `t,step`.
    pub columns: Vec<String>,
    /// Per column: `(probe, kind, quantity, position)` from `probes_points.csv`.
    pub meta: Vec<(String, String, String, [Real; 3])>,
    /// Sample times.
    pub t: Vec<Real>,
    /// Sample steps.
    pub step: Vec<u64>,
    /// `values[row][column]`.
    pub values: Vec<Vec<Real>>,
}

fn lines(path: &Path) -> Result<Vec<String>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok(text.lines().map(str::to_owned).collect())
}

fn num(path: &Path, line: usize, s: &str) -> Result<Real, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("{}, line {line}: {s:?} is not a number", path.display()))
}

/// Reads `DIR/probes.csv` and `DIR/probes_points.csv`; every row must have one value per
/// column (the error names file and line otherwise).
pub fn read_probes(dir: &Path) -> Result<ProbeTable, String> {
    let path = dir.join(PROBES_FILE);
    let rows = lines(&path)?;
    let header: Vec<&str> = rows
        .first()
        .ok_or_else(|| format!("{}: empty file", path.display()))?
        .split(',')
        .collect();
    if header.len() < 3 || header[0] != "t" || header[1] != "step" {
        return Err(format!(
            "{}, line 1: expected header t,step,<columns>",
            path.display()
        ));
    }
    let columns: Vec<String> = header[2..].iter().map(|s| s.to_string()).collect();
    let mut table = ProbeTable {
        columns,
        meta: Vec::new(),
        t: Vec::new(),
        step: Vec::new(),
        values: Vec::new(),
    };
    for (k, row) in rows.iter().enumerate().skip(1) {
        let f: Vec<&str> = row.split(',').collect();
        if f.len() != header.len() {
            return Err(format!(
                "{}, line {}: {} fields, expected {}",
                path.display(),
                k + 1,
                f.len(),
                header.len()
            ));
        }
        table.t.push(num(&path, k + 1, f[0])?);
        table.step.push(
            f[1].parse()
                .map_err(|_| format!("{}, line {}: bad step", path.display(), k + 1))?,
        );
        table.values.push(
            f[2..]
                .iter()
                .map(|s| num(&path, k + 1, s))
                .collect::<Result<_, _>>()?,
        );
    }
    let mpath = dir.join(PROBE_POINTS_FILE);
    for (k, row) in lines(&mpath)?.iter().enumerate().skip(1) {
        let f: Vec<&str> = row.split(',').collect();
        if f.len() != 7 {
            return Err(format!(
                "{}, line {}: expected 7 fields",
                mpath.display(),
                k + 1
            ));
        }
        let p = [
            num(&mpath, k + 1, f[4])?,
            num(&mpath, k + 1, f[5])?,
            num(&mpath, k + 1, f[6])?,
        ];
        table
            .meta
            .push((f[1].to_string(), f[2].to_string(), f[3].to_string(), p));
    }
    if table.meta.len() != table.columns.len() {
        return Err(format!(
            "{} lists {} columns but {} has {}",
            mpath.display(),
            table.meta.len(),
            path.display(),
            table.columns.len()
        ));
    }
    Ok(table)
}

fn unit(quantity: &str) -> &'static str {
    match quantity {
        "density" => "density (kg/m³)",
        "pressure" => "pressure (Pa)",
        "velocity.x" | "velocity.y" | "velocity.z" | "speed" => "velocity (m/s)",
        "internal_energy" => "specific internal energy (J/kg)",
        "water_height" => "water height (m)",
        _ => "value",
    }
}

/// Plots the probes of `DIR` into PNGs next to them and returns their paths:
/// * `probes_<quantity>.png`: the time series of every point probe and gauge of that quantity;
/// * `probe_<line>.png`: each line's profile along its length at up to six times.
///
/// `NaN` values (dry sensors) are left out of the curves.
pub fn plot_probes(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let table = read_probes(dir)?;
    let mut written = Vec::new();
    let mut quantities: Vec<&str> = Vec::new();
    for (_, kind, q, _) in &table.meta {
        if kind != "line" && !quantities.contains(&q.as_str()) {
            quantities.push(q);
        }
    }
    for q in quantities {
        let mut plot = LinePlot::new(format!("probes: {q}"), "t (s)", unit(q));
        for (c, (_, kind, quantity, _)) in table.meta.iter().enumerate() {
            if kind == "line" || quantity != q {
                continue;
            }
            let pts = table
                .t
                .iter()
                .zip(&table.values)
                .map(|(&t, row)| (t, row[c]))
                .collect();
            let colour = plot.series.len();
            plot.series.push(Series::new(
                table.columns[c].clone(),
                pts,
                SeriesStyle::Line,
                colour,
            ));
        }
        let path = dir.join(format!("probes_{q}.png"));
        plot.write_png(&path).map_err(|e| e.to_string())?;
        written.push(path);
    }
    let mut line_names: Vec<&str> = Vec::new();
    for (probe, kind, _, _) in &table.meta {
        if kind == "line" && !line_names.contains(&probe.as_str()) {
            line_names.push(probe);
        }
    }
    for name in line_names {
        let cols: Vec<usize> = (0..table.meta.len())
            .filter(|&c| table.meta[c].0 == name && table.meta[c].1 == "line")
            .collect();
        let p0 = table.meta[cols[0]].3;
        let p1 = table.meta[cols[cols.len() - 1]].3;
        // an axis-parallel line is drawn against its coordinate, any other against distance
        let varying: Vec<usize> = (0..3).filter(|&k| p1[k] != p0[k]).collect();
        let axis = (varying.len() == 1).then(|| varying[0]);
        let dist = |c: usize| {
            let p = table.meta[c].3;
            match axis {
                Some(k) => p[k],
                None => ((p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2) + (p[2] - p0[2]).powi(2))
                    .sqrt(),
            }
        };
        let x_label = match axis {
            Some(k) => format!("{} (m)", ["x", "y", "z"][k]),
            None => format!("distance from ({}, {}, {}) (m)", p0[0], p0[1], p0[2]),
        };
        let q = table.meta[cols[0]].2.clone();
        let mut plot = LinePlot::new(format!("line probe {name} ({q})"), x_label, unit(&q));
        let rows = table.values.len();
        let mut picks: Vec<usize> = (0..6).map(|k| k * rows.saturating_sub(1) / 5).collect();
        picks.dedup();
        for (colour, &r) in picks.iter().enumerate().filter(|_| rows > 0) {
            let pts = cols
                .iter()
                .map(|&c| (dist(c), table.values[r][c]))
                .collect();
            plot.series.push(Series::new(
                format!("t = {:.4} s", table.t[r]),
                pts,
                SeriesStyle::Line,
                colour,
            ));
        }
        let path = dir.join(format!("probe_{name}.png"));
        plot.write_png(&path).map_err(|e| e.to_string())?;
        written.push(path);
    }
    Ok(written)
}
