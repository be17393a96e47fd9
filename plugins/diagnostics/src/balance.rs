//! The balance of the pair forces: net force and torque of the accelerations the sweep wrote,
//! relative to their scale (round-off for the dual-support sweep).

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::chunks::DENSE;
use dualsph_core::components::*;
use dualsph_core::math::{Real, Vector};
use dualsph_core::sim::{Sim, StepSet};
use glam::DVec3;

/// How well the pair forces of the last sweep balance, at the positions they were computed
/// at: `|Σ_i m_i a_i| / Σ_i |m_i a_i|` and `|Σ_i r_i × m_i a_i| / Σ_i |r_i × m_i a_i|`, read
/// right after the sweep (before body forces and boundaries). Round-off for the dual-support
/// sweep whatever the h field (§5); see [`track_pair_balance`].
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct PairBalance {
    /// Relative net force.
    pub force: Real,
    /// Relative net torque about the origin.
    pub torque: Real,
}

/// Computes [`PairBalance`] from the accelerations the sweep just wrote (row order).
pub fn pair_balance<V: Vector>(
    mut balance: ResMut<PairBalance>,
    q: Query<(&Position<V>, &Mass, &Acceleration<V>)>,
) {
    let (mut f, mut f_abs, mut t, mut t_abs) = (DVec3::ZERO, 0.0, DVec3::ZERO, 0.0);
    for (r, m, a) in q.contiguous_iter().expect(DENSE) {
        for ((r, m), a) in r.iter().zip(m).zip(a) {
            let fi = a.0 * m.0;
            let ti = V::cross3(r.0, fi);
            f += DVec3::from_array(fi.to_xyz());
            f_abs += fi.length();
            t += ti;
            t_abs += ti.length();
        }
    }
    *balance = PairBalance {
        force: f.length() / f_abs.max(Real::MIN_POSITIVE),
        torque: t.length() / t_abs.max(Real::MIN_POSITIVE),
    };
}

/// Adds [`pair_balance`] after the force sweep and the force systems added so far (call it
/// after the scene's plugins and before the schedule is built, e.g. in
/// `dualsph_run::build_sim_with`): the [`PairBalance`] resource then holds the balance of
/// every step's sweep.
pub fn track_pair_balance<V: Vector>(sim: &mut Sim<V>) {
    sim.world.insert_resource(PairBalance::default());
    sim.add_system(
        StepSet::Forces,
        "pair_balance (diagnostic)",
        pair_balance::<V>,
    )
    .after::<dualsph_sweep::ForceSweep>();
}
