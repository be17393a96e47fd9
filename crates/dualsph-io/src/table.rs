//! Particles as they are written: ids and named columns (the scene's registered output
//! columns), read by name ([`ParticleTable::column`], [`ParticleRow`]).

use crate::Real;

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

    /// Particle `k` (`k < len()`).
    pub fn row(&self, k: usize) -> ParticleRow<'_> {
        ParticleRow { table: self, k }
    }

    /// Every particle, in row order.
    pub fn rows(&self) -> impl ExactSizeIterator<Item = ParticleRow<'_>> + Clone {
        (0..self.len()).map(|k| self.row(k))
    }

    /// The table has every column of `names`; the error names the first missing and the
    /// columns required, and counts the columns the file has without naming them: a file
    /// that is not a particle file (a `File(path: "/etc/passwd")`) has its first line for
    /// labels, and a message must not quote a byte of someone else's file.
    pub fn require(&self, names: &[&str]) -> Result<(), String> {
        match names.iter().find(|n| self.column(n).is_none()) {
            None => Ok(()),
            Some(n) => Err(format!(
                "no column `{n}`: the columns needed are {} (as final.csv and the snapshots \
                 name them), and the file's {} column(s) do not include it",
                names.join(", "),
                self.columns.len()
            )),
        }
    }

    /// Every column's values fit the row count; the error names the first that does not by
    /// its place (its label is the file's, not to be quoted).
    pub fn check(&self) -> Result<(), String> {
        for (k, c) in self.columns.iter().enumerate() {
            if c.labels.is_empty() || c.values.len() != c.width() * self.len() {
                return Err(format!(
                    "column {} (of {}) has {} values for {} particles of width {}",
                    k + 1,
                    self.columns.len(),
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

/// The names and CSV labels under which the engine writes the core columns, the equation of
/// state's pressure and the energy equation's internal energy: what [`crate::read_particles`]
/// groups a CSV file's labels into.
pub const STANDARD_COLUMNS: [(&str, &[&str]); 7] = [
    (POSITION, &["x", "y", "z"]),
    (VELOCITY, &["vx", "vy", "vz"]),
    (MASS, &["m"]),
    (DENSITY, &["rho"]),
    (PRESSURE, &["p"]),
    (INTERNAL_ENERGY, &["e"]),
    (SMOOTHING_LENGTH, &["h"]),
];

/// The velocity column's name.
pub const VELOCITY: &str = "velocity";
/// The mass column's name.
pub const MASS: &str = "mass";
/// The density column's name.
pub const DENSITY: &str = "density";
/// The pressure column's name (written with an equation of state).
pub const PRESSURE: &str = "pressure";
/// The specific internal energy column's name (written with the energy equation).
pub const INTERNAL_ENERGY: &str = "internal_energy";
/// The smoothing-length column's name.
pub const SMOOTHING_LENGTH: &str = "smoothing_length";

/// One particle of a [`ParticleTable`]: its id and its values, by column name.
#[derive(Clone, Copy, Debug)]
pub struct ParticleRow<'a> {
    table: &'a ParticleTable,
    k: usize,
}

impl<'a> ParticleRow<'a> {
    /// The particle's id.
    pub fn id(&self) -> u64 {
        self.table.ids[self.k]
    }

    /// The particle's components of column `name`, `None` when the table has no such column.
    pub fn get(&self, name: &str) -> Option<&'a [Real]> {
        self.table.column(name).map(|c| c.row(self.k))
    }

    /// Component `i` of column `name`; NaN when the table has no such column or component.
    pub fn value(&self, name: &str, i: usize) -> Real {
        self.get(name)
            .and_then(|v| v.get(i).copied())
            .unwrap_or(Real::NAN)
    }

    /// The three components of column `name` (NaN where missing).
    fn xyz(&self, name: &str) -> [Real; 3] {
        [0, 1, 2].map(|i| self.value(name, i))
    }

    /// Position (x, y, z; NaN without a [`POSITION`] column).
    pub fn pos(&self) -> [Real; 3] {
        self.xyz(POSITION)
    }

    /// Velocity (NaN without a [`VELOCITY`] column).
    pub fn vel(&self) -> [Real; 3] {
        self.xyz(VELOCITY)
    }

    /// Mass (NaN without a [`MASS`] column).
    pub fn mass(&self) -> Real {
        self.value(MASS, 0)
    }

    /// Density (NaN without a [`DENSITY`] column).
    pub fn rho(&self) -> Real {
        self.value(DENSITY, 0)
    }

    /// Smoothing length (NaN without a [`SMOOTHING_LENGTH`] column).
    pub fn h(&self) -> Real {
        self.value(SMOOTHING_LENGTH, 0)
    }

    /// Pressure; 0 without a [`PRESSURE`] column (a scene without an equation of state).
    pub fn p(&self) -> Real {
        self.get(PRESSURE).map_or(0.0, |v| v[0])
    }

    /// Specific internal energy; 0 without an [`INTERNAL_ENERGY`] column (a scene without the
    /// energy equation).
    pub fn e(&self) -> Real {
        self.get(INTERNAL_ENERGY).map_or(0.0, |v| v[0])
    }
}
