//! Particles as they are written: ids and named columns (the scene's registered output
//! columns, or the standard set of a [`ParticleRecord`] list).

use crate::{ParticleRecord, Real};

/// The name of the column that gives the VTK points.
pub const POSITION: &str = "position";

/// One column of a [`ParticleTable`]: its VTK array name, one CSV label per component, and
/// `labels.len()` values per particle in the table's row order.
#[derive(Clone, Debug, PartialEq)]
pub struct TableColumn {
    /// VTK array name (`velocity`, `pressure`, …; [`POSITION`] gives the points).
    pub name: String,
    /// CSV header labels, one per component (`vx`, `vy`, `vz`).
    pub labels: Vec<String>,
    /// The values, `labels.len()` per particle.
    pub values: Vec<Real>,
}

impl TableColumn {
    /// Components per particle.
    pub fn width(&self) -> usize {
        self.labels.len()
    }

    /// Particle `k`'s components.
    pub fn row(&self, k: usize) -> &[Real] {
        let w = self.width();
        &self.values[k * w..(k + 1) * w]
    }
}

/// Particles as written to a snapshot: ids and columns, rows in id order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParticleTable {
    /// Particle ids, one per row.
    pub ids: Vec<u64>,
    /// The columns, in the order they are written.
    pub columns: Vec<TableColumn>,
}

impl ParticleTable {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// The column named `name`.
    pub fn column(&self, name: &str) -> Option<&TableColumn> {
        self.columns.iter().find(|c| c.name == name)
    }

    /// The standard columns of `records`: `position` (x, y, z), `velocity` (vx, vy, vz),
    /// `mass` (m), `density` (rho), `pressure` (p), `internal_energy` (e) and
    /// `smoothing_length` (h).
    pub fn from_records(records: &[ParticleRecord]) -> Self {
        let vector =
            |name: &str, prefix: &str, get: fn(&ParticleRecord) -> [Real; 3]| TableColumn {
                name: name.into(),
                labels: ["x", "y", "z"].map(|a| format!("{prefix}{a}")).into(),
                values: records.iter().flat_map(get).collect(),
            };
        let scalar = |name: &str, label: &str, get: fn(&ParticleRecord) -> Real| TableColumn {
            name: name.into(),
            labels: vec![label.into()],
            values: records.iter().map(get).collect(),
        };
        ParticleTable {
            ids: records.iter().map(|r| r.id).collect(),
            columns: vec![
                vector(POSITION, "", |r| r.pos),
                vector("velocity", "v", |r| r.vel),
                scalar("mass", "m", |r| r.mass),
                scalar("density", "rho", |r| r.rho),
                scalar("pressure", "p", |r| r.p),
                scalar("internal_energy", "e", |r| r.e),
                scalar("smoothing_length", "h", |r| r.h),
            ],
        }
    }

    /// Every column's values fit the row count; the error names the first that does not.
    pub fn check(&self) -> Result<(), String> {
        for c in &self.columns {
            if c.labels.is_empty() || c.values.len() != c.width() * self.len() {
                return Err(format!(
                    "column {} has {} values for {} particles of width {}",
                    c.name,
                    c.values.len(),
                    self.len(),
                    c.width()
                ));
            }
        }
        Ok(())
    }
}

impl ParticleTable {
    /// The table with the one-component columns named by the labels of each of `groups`
    /// (`(name, labels)`, e.g. `("velocity", ["vx", "vy", "vz"])`) joined into one column of
    /// that name, for a table read from a CSV file ([`crate::read_particle_table_csv`]): a
    /// group whose labels are not all present, and every column in no group, stay as they are.
    pub fn grouped(&self, groups: &[(String, Vec<String>)]) -> ParticleTable {
        let mut used = vec![false; self.columns.len()];
        let mut columns = Vec::new();
        for (name, labels) in groups {
            let at: Option<Vec<usize>> = labels
                .iter()
                .map(|l| {
                    self.columns
                        .iter()
                        .position(|c| c.width() == 1 && &c.name == l)
                })
                .collect();
            let Some(at) = at.filter(|a| !a.is_empty()) else {
                continue;
            };
            let values = (0..self.len())
                .flat_map(|k| at.iter().map(move |&c| (c, k)))
                .map(|(c, k)| self.columns[c].values[k])
                .collect();
            at.iter().for_each(|&c| used[c] = true);
            columns.push(TableColumn {
                name: name.clone(),
                labels: labels.clone(),
                values,
            });
        }
        columns.extend(
            self.columns
                .iter()
                .zip(&used)
                .filter(|(_, u)| !**u)
                .map(|(c, _)| c.clone()),
        );
        ParticleTable {
            ids: self.ids.clone(),
            columns,
        }
    }
}
