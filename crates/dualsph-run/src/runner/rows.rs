//! The rows the run loop writes at each diagnostics step: the totals to `diagnostics.csv`,
//! and the loads on the fixed and prescribed bodies to its load columns and to `bodies.csv`.

use super::EXTRA_COLUMNS;
use dualsph_core::bevy_ecs::world::World;
use dualsph_core::bodies::Bodies;
use dualsph_core::output::DiagnosticColumns;
use dualsph_diagnostics::{BodyLoad, BodyTotals, Diagnostics};
use dualsph_io::{BodyLoadRow, DiagnosticsRow, OutputDir, OutputError};

/// What the diagnostics rows of a run hold: the dimension and the bodies' names.
pub(crate) struct DiagnosticsOutput {
    dim: usize,
    names: Vec<String>,
    /// Whether some body is fixed or prescribed (then `bodies.csv` is written).
    loads: bool,
}

impl DiagnosticsOutput {
    /// The rows of a run of `bodies` in dimension `dim`.
    pub(crate) fn new(bodies: &Bodies, dim: usize) -> Self {
        DiagnosticsOutput {
            dim,
            names: bodies.names(),
            loads: bodies.0.iter().any(|b| !b.is_fluid()),
        }
    }

    /// The extra columns of `diagnostics.csv`: [`EXTRA_COLUMNS`]; then, for a scene of
    /// several bodies, each body's totals, `mass[name]`, `px[name]`, …, `e_pot[name]`,
    /// `dissipated[name]`; then the load on each fixed or prescribed body (see
    /// [`BodyLoad`]), `fx[name]`, `fy[name]` and `mz[name]` in 2-D, `fx[name]`, `fy[name]`,
    /// `fz[name]`, `mx[name]`, `my[name]` and `mz[name]` in 3-D; then the columns the
    /// scene's plugins add ([`DiagnosticColumns`]).
    pub(crate) fn columns(&self, world: &World) -> Vec<String> {
        let bodies = world.resource::<Bodies>();
        let mut columns: Vec<String> = EXTRA_COLUMNS.iter().map(|s| s.to_string()).collect();
        if bodies.0.len() > 1 {
            for b in &bodies.0 {
                columns.extend(BodyTotals::NAMES.iter().map(|q| format!("{q}[{}]", b.name)));
            }
        }
        for b in bodies.0.iter().filter(|b| !b.is_fluid()) {
            let names = BodyLoad::names(self.dim);
            columns.extend(names.iter().map(|q| format!("{q}[{}]", b.name)));
        }
        if let Some(plugin) = world.get_resource::<DiagnosticColumns>() {
            columns.extend(plugin.names().map(str::to_string));
        }
        columns
    }

    /// Starts `bodies.csv` in `out` when the scene has a fixed or prescribed body, and gives
    /// `out` the body names its `.vtp` files list.
    pub(crate) fn open(&self, out: &mut OutputDir) -> Result<(), OutputError> {
        out.set_body_names(self.names.clone());
        if self.loads {
            out.enable_body_loads()?;
        }
        Ok(())
    }

    /// Writes the row of `d` to `diagnostics.csv` (with the plugins' columns read from
    /// `world` now), and its loads to `bodies.csv`.
    pub(crate) fn push(
        &self,
        out: &mut OutputDir,
        d: &Diagnostics,
        world: &World,
    ) -> Result<(), OutputError> {
        let mut row = self.row(d);
        if let Some(plugin) = world.get_resource::<DiagnosticColumns>() {
            row.extra.extend(plugin.values(world));
        }
        out.push_diagnostics(row)?;
        if self.loads {
            let rows: Vec<BodyLoadRow> = d
                .loads
                .iter()
                .map(|l| BodyLoadRow {
                    t: d.t,
                    step: d.step,
                    body: self.names[l.body].clone(),
                    force: l.force,
                    moment: l.moment,
                })
                .collect();
            out.push_body_loads(d.step, &rows)?;
        }
        Ok(())
    }

    /// The `diagnostics.csv` row of `d`, its extra values in the order of
    /// [`DiagnosticsOutput::columns`] but for the plugins' columns.
    pub(crate) fn row(&self, d: &Diagnostics) -> DiagnosticsRow {
        let several = d.per_body.len() > 1;
        let per_body = d.per_body.iter().filter(move |_| several);
        DiagnosticsRow {
            t: d.t,
            step: d.step,
            dt: d.dt,
            n: d.n,
            mass: d.mass,
            p: d.momentum,
            lz: d.angular_momentum[2],
            e_kin: d.e_kin,
            e_int: d.e_int,
            e_pot: d.e_pot,
            e_tot: d.e_tot,
            extra: [
                d.angular_momentum[0],
                d.angular_momentum[1],
                d.max_density_variation,
                d.dissipated,
            ]
            .into_iter()
            .chain(per_body.flat_map(BodyTotals::values))
            .chain(d.loads.iter().flat_map(|l| l.values(self.dim)))
            .collect(),
        }
    }
}
