//! Batching the buffers' additions and deletions with the neighbour lists' rebuilds.
//!
//! Adding or deleting a particle changes the store's rows, and the neighbour lists are built
//! over rows: any change drops them and the step rebuilds them (`dualsph_core::population`).
//! A parabolic inflow has a buffer particle crossing its plane at some height on nearly every
//! step, and a buffer particle leaves an outflow's far face as often, so applying each change
//! at once rebuilds the lists on nearly every step (the DFG cylinder channel: 10,028 builds in
//! 11,512 steps, against one in six steps for the lists' own rule). Both kinds of change can
//! wait for a step on which the lists are rebuilt anyway, as long as the fluid cannot tell:
//!
//! * **Deleting** an outflow's buffer particle that has left the far face: the particle is
//!   already one buffer depth past the open plane and moves on downstream, so it only keeps
//!   the fluid's support there as full as it was. Until its deletion it is a buffer particle
//!   like the others (moved with its velocity, given the extrapolated state).
//! * **Creating** the inflow's particle that replaces one that crossed its plane: it is
//!   created one buffer depth `L` behind the crossing, and travels towards the plane with the
//!   inflow. While its distance to the plane is more than `2 h_max` (`h_max` the largest
//!   support radius of the scene) no fluid particle can reach it within the step — a fluid
//!   particle is at most one step's travel inside the buffer before it is deleted, and one
//!   step's travel is below `h_max/2` at any Courant number below one half — so it is *owed*:
//!   kept here with where and when it was due, and created where the inflow has carried it,
//!   `x_c + n u(x_c) (S(t) − S(t_c))` ([`super::profile::ramp_integral`]), on the first step
//!   that rebuilds the lists, or as soon as it comes within `2 h_max` of the plane.
//!
//! A step applies every waiting change when the lists will be rebuilt (their rule fires on
//! the start-of-step positions), when another change of the particle count is asked for on
//! that step, or when an owed particle is due; otherwise the changes wait. An inflow less
//! than `2 h_max` deep therefore creates at once, as before; a deeper one batches. The owed
//! particles are kept in checkpoints (key `open_boundaries_owed`), so that a resumed run
//! makes the same decisions bitwise.

use super::state::Boundaries;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::math::{Real, Vector};
use serde::{Deserialize, Serialize};

/// An inflow's buffer particle that is owed: where it was due and when.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OwedParticle {
    /// The inflow, by its index in [`Boundaries::list`].
    pub boundary: usize,
    /// Its position when it was due, by component.
    pub at: Vec<Real>,
    /// Its density (the crossing particle's buffer density).
    pub density: Real,
    /// The time it was due (s).
    pub since: Real,
}

/// The inflows' owed particles, in the order they became due (kept in checkpoints).
#[derive(Resource, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Owed(pub Vec<OwedParticle>);

impl OwedParticle {
    /// The owed particle of `boundary`, due at `x` at time `t`.
    pub fn new<V: Vector>(boundary: usize, x: V, density: Real, t: Real) -> Self {
        OwedParticle {
            boundary,
            at: (0..V::DIM).map(|k| x.get(k)).collect(),
            density,
            since: t,
        }
    }

    /// Where the inflow has carried it by time `t`: `x_c + n u(x_c) (S(t) − S(t_c))`.
    pub fn position<V: Vector>(&self, all: &Boundaries<V>, t: Real) -> V {
        let x = V::from_slice(&self.at).unwrap_or_else(V::zero);
        x + all.list[self.boundary].inflow_travel(x, self.since, t)
    }

    /// True when, at time `t`, it is within `reach` of its inflow's open plane and must be
    /// created now.
    pub fn due<V: Vector>(&self, all: &Boundaries<V>, t: Real, reach: Real) -> bool {
        let zone = &all.list[self.boundary].zone;
        -zone.depth_of(self.position(all, t)) < reach
    }
}

/// The distance from an inflow's plane within which an owed particle is created:
/// `2 h_max` (module docs).
pub fn reach(h_max: Real) -> Real {
    2.0 * h_max
}

#[cfg(test)]
mod tests {
    use super::super::profile::{Profile, ramp_integral};
    use super::super::state::{Boundary, Inflow};
    use super::super::zone::Zone;
    use super::*;
    use dualsph_core::sim::ParticleInit;
    use glam::DVec2;

    fn inflow(ramp: Real) -> Boundaries<DVec2> {
        let zone = Zone::new(DVec2::new(-0.04, 0.0), DVec2::new(0.0, 0.4), 0, 1.0, true);
        Boundaries {
            list: vec![Boundary {
                zone,
                buffer: 1,
                fluid: 0,
                inflow: Some(Inflow {
                    profile: Profile::Uniform(0.5),
                    ramp,
                    template: ParticleInit {
                        pos: DVec2::ZERO,
                        vel: DVec2::ZERO,
                        mass: 1.0,
                        density: 1.0,
                        h: 0.015,
                        internal_energy: 0.0,
                        body: 1,
                    },
                }),
                pressure: None,
                non_reflecting: None,
            }],
            of_body: vec![None, Some(0)],
        }
    }

    #[test]
    fn an_owed_particle_travels_with_the_inflow_and_falls_due_near_the_plane() {
        let all = inflow(0.0);
        let owed = OwedParticle::new(0, DVec2::new(-0.039, 0.2), 1.0, 2.0);
        assert_eq!(owed.position(&all, 2.0), DVec2::new(-0.039, 0.2));
        let later = owed.position(&all, 2.02);
        assert!(
            (later.x - (-0.029)).abs() < 1e-15 && later.y == 0.2,
            "{later:?}"
        );
        // 2 h_max = 0.03: due once it is closer than that to the plane at x = 0
        assert!(!owed.due(&all, 2.0, reach(0.015)));
        assert!(owed.due(&all, 2.02, reach(0.015)));
    }

    #[test]
    fn an_owed_particle_moves_by_the_ramp_integral() {
        // ramp over 1 s: S(t) = t²/2 for t ≤ 1, so from t = 0 to 0.5 the travel is 0.125 s
        let all = inflow(1.0);
        let owed = OwedParticle::new(0, DVec2::new(-0.04, 0.1), 1.0, 0.0);
        let x = owed.position(&all, 0.5);
        let want = -0.04 + 0.5 * (ramp_integral(1.0, 0.5) - ramp_integral(1.0, 0.0));
        assert_eq!(x.x, want);
    }
}
