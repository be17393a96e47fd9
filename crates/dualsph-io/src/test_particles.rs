//! Particles with the standard values, to build tables and compare them in tests.

use crate::*;

/// One particle's standard values, to build and compare tables in tests.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Particle {
    pub id: u64,
    pub pos: [Real; 3],
    pub vel: [Real; 3],
    pub mass: Real,
    pub rho: Real,
    pub p: Real,
    pub e: Real,
    pub h: Real,
}

/// The [`STANDARD_COLUMNS`] of `ps`, in that order.
pub(crate) fn table_of(ps: &[Particle]) -> ParticleTable {
    let get: [fn(&Particle) -> Vec<Real>; 7] = [
        |p| p.pos.to_vec(),
        |p| p.vel.to_vec(),
        |p| vec![p.mass],
        |p| vec![p.rho],
        |p| vec![p.p],
        |p| vec![p.e],
        |p| vec![p.h],
    ];
    ParticleTable {
        ids: ps.iter().map(|p| p.id).collect(),
        columns: STANDARD_COLUMNS
            .iter()
            .zip(get)
            .map(|((name, labels), get)| TableColumn {
                name: name.to_string(),
                labels: labels.iter().map(|l| l.to_string()).collect(),
                values: ps.iter().flat_map(get).collect(),
            })
            .collect(),
    }
}

/// The standard values of every particle of `t`.
pub(crate) fn particles_of(t: &ParticleTable) -> Vec<Particle> {
    t.rows()
        .map(|r| Particle {
            id: r.id(),
            pos: r.pos(),
            vel: r.vel(),
            mass: r.mass(),
            rho: r.rho(),
            p: r.p(),
            e: r.e(),
            h: r.h(),
        })
        .collect()
}
