//! Where the current run writes its files.
//!
//! The runner inserts [`RunOutputDir`] into the world before the first evaluation; a plugin
//! that writes files of its own (e.g. probes) looks for it and keeps its data in memory when
//! it is absent (a `Sim` driven from library code without an output directory).

use bevy_ecs::prelude::Resource;
use std::path::PathBuf;

/// The output directory of the run (absent when no run output is being written).
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct RunOutputDir(pub PathBuf);

/// The step count at which the run stops (the scene's `max_steps`), inserted by the runner
/// when there is one, so that samplers can record the last state as they do at `t_end`.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepLimit(pub u64);

/// Reads the values of a group of a plugin's columns of `diagnostics.csv` from the world.
pub type DiagnosticReader =
    Box<dyn Fn(&bevy_ecs::world::World) -> Vec<crate::math::Real> + Send + Sync>;

/// The columns plugins add to `diagnostics.csv`, after the engine's own, in the order they
/// were added: names and how to read their values at a diagnostics row. A plugin adds them
/// in its `build` ([`DiagnosticColumns::add`], [`DiagnosticColumns::add_group`]); the runner
/// writes them on every row.
#[derive(Resource, Default)]
pub struct DiagnosticColumns {
    groups: Vec<(Vec<String>, DiagnosticReader)>,
}

impl std::fmt::Debug for DiagnosticColumns {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}

impl DiagnosticColumns {
    /// Adds the column `name`; the error names a name taken already.
    pub fn add(
        &mut self,
        name: impl Into<String>,
        read: impl Fn(&bevy_ecs::world::World) -> crate::math::Real + Send + Sync + 'static,
    ) -> Result<(), String> {
        self.add_group(vec![name.into()], move |w| vec![read(w)])
    }

    /// Adds the columns `names`, whose values `read` gives together (one for each name, in
    /// order); the error names a name taken already.
    pub fn add_group(
        &mut self,
        names: Vec<String>,
        read: impl Fn(&bevy_ecs::world::World) -> Vec<crate::math::Real> + Send + Sync + 'static,
    ) -> Result<(), String> {
        if let Some(n) = names.iter().find(|n| self.names().any(|m| m == n.as_str())) {
            return Err(format!("diagnostics column `{n}` is added twice"));
        }
        self.groups.push((names, Box::new(read)));
        Ok(())
    }

    /// The names, in order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.groups
            .iter()
            .flat_map(|(names, _)| names.iter().map(String::as_str))
    }

    /// The values now, in the order of [`DiagnosticColumns::names`] (a group whose reader
    /// gives the wrong count is padded with NaN or cut to its names).
    pub fn values(&self, world: &bevy_ecs::world::World) -> Vec<crate::math::Real> {
        let mut out = Vec::new();
        for (names, read) in &self.groups {
            let mut v = read(world);
            v.resize(names.len(), crate::math::Real::NAN);
            out.extend(v);
        }
        out
    }
}

/// Reads a quantity derived from the particles' columns: one value per particle, in row
/// order (the order of any query over the particles' table).
pub type DerivedReader =
    Box<dyn Fn(&bevy_ecs::world::World) -> Vec<crate::math::Real> + Send + Sync>;

/// Per-particle quantities plugins add to the snapshots and `final.csv` that are derived
/// from stored columns and so not stored themselves (a refined particle's size and level):
/// computed when a file is written, after the registered columns, in the order added. A
/// plugin adds them in its `build` ([`DerivedColumns::add`]); the scene's `output.columns`
/// may name them.
#[derive(Resource, Default)]
pub struct DerivedColumns {
    columns: Vec<(String, DerivedReader)>,
}

impl std::fmt::Debug for DerivedColumns {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}

impl DerivedColumns {
    /// Adds the column `name`; the error names a name taken already.
    pub fn add(
        &mut self,
        name: impl Into<String>,
        read: impl Fn(&bevy_ecs::world::World) -> Vec<crate::math::Real> + Send + Sync + 'static,
    ) -> Result<(), String> {
        let name = name.into();
        if self.names().any(|n| n == name) {
            return Err(format!("snapshot column `{name}` is added twice"));
        }
        self.columns.push((name, Box::new(read)));
        Ok(())
    }

    /// The names, in order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.columns.iter().map(|(n, _)| n.as_str())
    }

    /// The columns as `(name, values in row order)`, those for which `keep(name)` holds.
    pub fn values(
        &self,
        world: &bevy_ecs::world::World,
        keep: impl Fn(&str) -> bool,
    ) -> Vec<(String, Vec<crate::math::Real>)> {
        self.columns
            .iter()
            .filter(|(n, _)| keep(n))
            .map(|(n, read)| (n.clone(), read(world)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_derived_column_is_read_when_asked_and_named_once() {
        let mut cols = DerivedColumns::default();
        cols.add("twice", |_| vec![2.0, 4.0]).unwrap();
        cols.add("none", |_| Vec::new()).unwrap();
        assert!(
            cols.add("twice", |_| Vec::new())
                .unwrap_err()
                .contains("`twice`")
        );
        let world = bevy_ecs::world::World::new();
        let got = cols.values(&world, |n| n == "twice");
        assert_eq!(got, vec![("twice".to_string(), vec![2.0, 4.0])]);
        assert_eq!(cols.names().collect::<Vec<_>>(), ["twice", "none"]);
    }
}
