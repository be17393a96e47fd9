//! The totals of the state: mass, linear and angular momentum, kinetic / internal /
//! potential / total energy, the dissipated part of the internal energy, per body and in all,
//! and the largest density variation, summed in particle-id order (deterministic).
//!
//! The energy budget: `e_kin + e_int + e_pot` is conserved (to round-off with the integrators'
//! work-consistent update), and the internal energy gained since the start splits into the
//! heat of the dissipative terms and the rest, the reversible compression work:
//! `e_int − e_int(0) = (e_int − dissipated − e_int(0)) + dissipated`, with
//! `dissipated = Σ m_i d_i ≥ 0` never decreasing ([`Dissipated`]: the time integral of the
//! artificial viscosity's heating, 0 in a scene without it).
//!
//! The load on every body that is not a fluid ([`BodyLoad`]): the force and the moment the
//! rest of the system exerts on its particles.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Bodies, Body, BodyId};
use dualsph_core::components::*;
use dualsph_core::math::{Real, Vector};
use dualsph_core::potentials::ExternalPotentials;
use dualsph_core::sim::SimClock;
use dualsph_fluid::components::*;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Totals of the current state.
#[derive(Resource, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Diagnostics {
    /// Simulated time.
    pub t: Real,
    /// Step.
    pub step: u64,
    /// dt of the last step.
    pub dt: Real,
    /// Particle count.
    pub n: u64,
    /// Total mass.
    pub mass: Real,
    /// Linear momentum Σ m v (3-D embedding).
    pub momentum: [Real; 3],
    /// Angular momentum Σ m r × v about the origin.
    pub angular_momentum: [Real; 3],
    /// Σ ½ m v².
    pub e_kin: Real,
    /// Σ m ε.
    pub e_int: Real,
    /// Σ m φ(r) over the particles of fluid bodies (body forces act on them only).
    pub e_pot: Real,
    /// e_kin + e_int + e_pot.
    pub e_tot: Real,
    /// Σ m d: the part of `e_int` that the dissipative terms put in ([`Dissipated`]; 0 when
    /// the particles have no such column).
    pub dissipated: Real,
    /// max |ρ_i/ρ_i(0) − 1| over the particles, with ρ_i(0) their [`InitialDensity`]
    /// (NaN when the particles have none: a simulation without the plugin).
    pub max_density_variation: Real,
    /// Σ |m v| (scale for relative momentum errors).
    pub momentum_scale: Real,
    /// The totals of each body, indexed by [`BodyId`].
    pub per_body: Vec<BodyTotals>,
    /// The load on each fixed or prescribed body, in body order (none for a fluid body).
    pub loads: Vec<BodyLoad>,
}

/// The load on a fixed or prescribed body B: the force and the moment about its reference
/// point `c_B` (`Body::moment_about`) that the rest of the system (the fluid and the other
/// bodies) exerts on it,
///
/// `F_B = Σ_{i∈B} f_i`, `M_B = Σ_{i∈B} (x_i − c_B) × f_i`, with `f_i = m_i a_i`,
///
/// summed in particle-id order (so the same on any number of threads). `a_i` is the
/// acceleration the last force evaluation left: the pair forces on i over m_i, as body forces
/// act on fluid bodies only (gravity's documentation), and the integrator does not write it
/// (it replaces the motion of such a particle by the body's law). The pair forces between two
/// particles of B are exact opposites in the dual-support sweep, so they cancel in the sum
/// (to round-off): `F_B` is the force of the fluid and of the other bodies on B, equal and
/// opposite to B's force on them (with a non-conservative formulation, `SingleSupport` or
/// `AveragedKernel`, the pair forces are not opposite and that balance holds only to the
/// formulation's error). The sign convention: the force *on* the body. In 2-D the moment is
/// about the z axis (`moment[2]`), in 1-D there is none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BodyLoad {
    /// The body (its [`BodyId`]).
    pub body: usize,
    /// `F_B` (3-D embedding).
    pub force: [Real; 3],
    /// `M_B` about `c_B` (3-D embedding; only z in 2-D).
    pub moment: [Real; 3],
}

impl BodyLoad {
    /// The names of [`BodyLoad::values`] in dimension `dim`: the force components, then the
    /// moment's (`mz` in 2-D, `mx, my, mz` in 3-D, none in 1-D).
    pub fn names(dim: usize) -> Vec<&'static str> {
        let force = ["fx", "fy", "fz"].into_iter().take(dim.min(3));
        let moment: &[&'static str] = match dim {
            2 => &["mz"],
            3 => &["mx", "my", "mz"],
            _ => &[],
        };
        force.chain(moment.iter().copied()).collect()
    }

    /// The load as a list in the order of [`BodyLoad::names`].
    pub fn values(&self, dim: usize) -> Vec<Real> {
        let force = self.force.into_iter().take(dim.min(3));
        let moment: &[Real] = match dim {
            2 => &self.moment[2..],
            3 => &self.moment,
            _ => &[],
        };
        force.chain(moment.iter().copied()).collect()
    }
}

/// Mass, momentum and energies of one body's particles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BodyTotals {
    /// Σ m.
    pub mass: Real,
    /// Σ m v (3-D embedding).
    pub momentum: [Real; 3],
    /// Σ ½ m v².
    pub e_kin: Real,
    /// Σ m ε.
    pub e_int: Real,
    /// Σ m φ(r) over the particles of fluid bodies (body forces act on them only).
    pub e_pot: Real,
    /// Σ m d.
    pub dissipated: Real,
}

impl BodyTotals {
    /// The names of [`BodyTotals::values`], in order.
    pub const NAMES: [&'static str; 8] = [
        "mass",
        "px",
        "py",
        "pz",
        "e_kin",
        "e_int",
        "e_pot",
        "dissipated",
    ];

    /// The totals as a list, in the order of [`BodyTotals::NAMES`].
    pub fn values(&self) -> [Real; 8] {
        let [px, py, pz] = self.momentum;
        let energies = [self.e_kin, self.e_int, self.e_pot, self.dissipated];
        let [e_kin, e_int, e_pot, dissipated] = energies;
        [self.mass, px, py, pz, e_kin, e_int, e_pot, dissipated]
    }

    /// The totals from a list in the order of [`BodyTotals::NAMES`].
    pub fn from_values(v: &[Real; 8]) -> Self {
        BodyTotals {
            mass: v[0],
            momentum: [v[1], v[2], v[3]],
            e_kin: v[4],
            e_int: v[5],
            e_pot: v[6],
            dissipated: v[7],
        }
    }
}

/// Steps between diagnostics evaluations (the scene's `output.diagnostics_every`; default 1).
/// [`compute_diagnostics`] sums over all particles in id order, so it runs only on those
/// steps (and at t = 0); [`SimDiagnostics::diagnostics`](crate::SimDiagnostics::diagnostics) brings a stale value up to date on demand.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct DiagnosticsEvery(pub u64);

impl Default for DiagnosticsEvery {
    fn default() -> Self {
        DiagnosticsEvery(1)
    }
}

/// A particle's reference density for the density-variation diagnostic and the health
/// check's density range: its density after the initial evaluation of the rates, or at its
/// creation for a particle added during the run (a column, kept in checkpoints).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct InitialDensity(pub Real);
dualsph_core::scalar_column!(InitialDensity);

/// Sets every particle's [`InitialDensity`] to its density, at the initial evaluation only.
pub fn capture_initial_density(
    clock: Res<SimClock>,
    mut q: Query<(&Density, &mut InitialDensity)>,
) {
    if clock.initializing {
        for (rho, mut r0) in &mut q {
            r0.0 = rho.0;
        }
    }
}

/// The particle data the diagnostics read.
type DiagQuery<'w, 's, V> = Query<
    'w,
    's,
    (
        &'static ParticleId,
        &'static Position<V>,
        &'static Velocity<V>,
        &'static Mass,
        &'static Density,
        Option<&'static InternalEnergy>,
        Option<&'static Dissipated>,
        &'static BodyId,
        Option<&'static InitialDensity>,
        &'static Acceleration<V>,
    ),
>;

/// Computes [`Diagnostics`] at t = 0 and every [`DiagnosticsEvery`] steps.
pub fn compute_diagnostics<V: Vector>(
    every: Res<DiagnosticsEvery>,
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    bodies: Res<Bodies>,
    diag: ResMut<Diagnostics>,
    q: DiagQuery<V>,
) {
    if clock.initializing || clock.step.is_multiple_of(every.0.max(1)) {
        compute_diagnostics_now(clock, potentials, bodies, diag, q);
    }
}

/// Computes [`Diagnostics`] now.
#[inline(never)] // a frame of its own in profiles
pub fn compute_diagnostics_now<V: Vector>(
    clock: Res<SimClock>,
    potentials: Res<ExternalPotentials>,
    bodies: Res<Bodies>,
    mut diag: ResMut<Diagnostics>,
    q: DiagQuery<V>,
) {
    let mut rows: Vec<_> = q.iter().collect();
    rows.sort_unstable_by_key(|r| r.0.0);
    let mut d = Diagnostics {
        t: clock.t,
        step: clock.step,
        dt: clock.dt,
        n: rows.len() as u64,
        per_body: vec![BodyTotals::default(); bodies.0.len()],
        ..Default::default()
    };
    let mut loads = Loads::<V>::new(&bodies);
    let mut p = DVec3::ZERO;
    let mut l = DVec3::ZERO;
    for (_, r, v, m, rho, e, diss, body, r0, a) in rows {
        let (x, u) = (r.0.to_xyz(), v.0.to_xyz());
        let mv = DVec3::from_array(u) * m.0;
        let e_kin = 0.5 * m.0 * v.0.length_squared();
        let e_int = e.map_or(0.0, |e| m.0 * e.0);
        let dissipated = diss.map_or(0.0, |x| m.0 * x.0);
        let mut e_pot = 0.0;
        // body forces act on fluid bodies only (see gravity's documentation)
        if !loads.add(body.0 as usize, r.0, a.0 * m.0) {
            for (phi, par) in potentials.terms.iter().zip(&potentials.params) {
                e_pot += m.0 * phi(&x, par);
            }
        }
        d.mass += m.0;
        p += mv;
        d.momentum_scale += mv.length();
        l += V::cross3(r.0, v.0) * m.0;
        d.e_kin += e_kin;
        d.e_int += e_int;
        d.e_pot += e_pot;
        d.dissipated += dissipated;
        if let Some(b) = d.per_body.get_mut(body.0 as usize) {
            b.mass += m.0;
            for (k, x) in b.momentum.iter_mut().enumerate() {
                *x += mv[k];
            }
            b.e_kin += e_kin;
            b.e_int += e_int;
            b.e_pot += e_pot;
            b.dissipated += dissipated;
        }
        d.max_density_variation = match r0 {
            Some(r0) => d.max_density_variation.max((rho.0 / r0.0 - 1.0).abs()),
            None => Real::NAN,
        };
    }
    d.momentum = p.to_array();
    d.angular_momentum = l.to_array();
    d.e_tot = d.e_kin + d.e_int + d.e_pot;
    d.loads = loads.finish();
    *diag = d;
}

/// The sums of [`BodyLoad`] in progress: per body, its reference point and the load so far,
/// `None` for a fluid body.
struct Loads<V: Vector>(Vec<Option<(V, BodyLoad)>>);

impl<V: Vector> Loads<V> {
    fn new(bodies: &Bodies) -> Self {
        let at = |b: &Body| V::from_slice(&b.moment_about[..V::DIM]).expect("DIM <= 3");
        let load = |(k, b): (usize, &Body)| {
            let zero = BodyLoad {
                body: k,
                ..Default::default()
            };
            (!b.is_fluid()).then(|| (at(b), zero))
        };
        Loads(bodies.0.iter().enumerate().map(load).collect())
    }

    /// Adds the force `f` on a particle at `x` of `body` to its body's load; false when the
    /// body has none (a fluid).
    fn add(&mut self, body: usize, x: V, f: V) -> bool {
        let Some(Some((c, load))) = self.0.get_mut(body) else {
            return false;
        };
        let m = V::cross3(x - *c, f);
        for (k, fk) in f.to_xyz().into_iter().enumerate() {
            load.force[k] += fk;
            load.moment[k] += m[k];
        }
        true
    }

    fn finish(self) -> Vec<BodyLoad> {
        self.0.into_iter().flatten().map(|(_, l)| l).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::bevy_ecs::system::RunSystemOnce;
    use dualsph_core::bodies::install_bodies;
    use dualsph_core::sim::{Domain, ParticleInit, SimConfig};
    use dualsph_sweep::prelude::*;
    use glam::DVec2;

    #[test]
    fn load_columns_follow_the_dimension() {
        let l = BodyLoad {
            body: 1,
            force: [1.0, 2.0, 3.0],
            moment: [4.0, 5.0, 6.0],
        };
        assert_eq!(BodyLoad::names(1), ["fx"]);
        assert_eq!(BodyLoad::names(2), ["fx", "fy", "mz"]);
        assert_eq!(BodyLoad::names(3), ["fx", "fy", "fz", "mx", "my", "mz"]);
        assert_eq!(l.values(1), [1.0]);
        assert_eq!(l.values(2), [1.0, 2.0, 6.0]);
        assert_eq!(l.values(3), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    }

    /// A fluid particle and two particles of a fixed body with given accelerations: the load
    /// is `Σ m a` over the fixed ones and its moment `Σ (x − c) × m a` about the body's point;
    /// the fluid has none, and its potential energy alone is counted.
    #[test]
    fn the_load_on_a_fixed_body_sums_its_particles_forces_and_moments() {
        let mut sim = Sim::<DVec2>::new(SimConfig {
            kernel: KernelKind::CubicSpline,
            formulation: Formulation::DualSupport,
            domain: Domain::closed(DVec2::splat(-10.0), DVec2::splat(10.0)),
            skin: 0.1,
            skin_rule: SkinRule::Fixed,
            time_stepping: TimeStepping::Fixed(1e-3),
        });
        let p = |x: f64, y: f64, mass: f64, body: u16| ParticleInit {
            pos: DVec2::new(x, y),
            vel: DVec2::ZERO,
            mass,
            density: 1000.0,
            h: 0.1,
            internal_energy: 0.0,
            body,
        };
        let particles = [
            p(0.0, 5.0, 1.0, 0),
            p(1.0, 0.0, 2.0, 1),
            p(3.0, 1.0, 1.0, 1),
        ];
        sim.spawn_particles(&particles).unwrap();
        let wall = Body {
            moment_about: [1.0, -1.0, 0.0],
            ..Body::fixed("wall")
        };
        let bodies = Bodies(vec![Body::fluid("water"), wall]);
        install_bodies(&mut sim, bodies).unwrap();
        sim.world
            .resource_mut::<ExternalPotentials>()
            .terms
            .push(|x, _| x[1]);
        sim.world
            .resource_mut::<ExternalPotentials>()
            .params
            .push([0.0; 3]);
        sim.world.insert_resource(Diagnostics::default());
        let accelerations = [
            DVec2::new(7.0, 7.0),
            DVec2::new(1.0, -2.0),
            DVec2::new(0.0, 3.0),
        ];
        let mut q = sim.world.query::<(&ParticleId, &mut Acceleration<DVec2>)>();
        for (id, mut a) in q.iter_mut(&mut sim.world) {
            a.0 = accelerations[id.0 as usize];
        }
        sim.world
            .run_system_once(compute_diagnostics_now::<DVec2>)
            .unwrap();
        let d = sim.world.resource::<Diagnostics>();
        // f = (2, −4) at (1, 0) and (0, 3) at (3, 1); about (1, −1): r = (0, 1) and (2, 2)
        let moment = (0.0 * -4.0 - 1.0 * 2.0) + (2.0 * 3.0 - 2.0 * 0.0);
        let want = BodyLoad {
            body: 1,
            force: [2.0, -1.0, 0.0],
            moment: [0.0, 0.0, moment],
        };
        assert_eq!(d.loads, [want]);
        assert_eq!(d.e_pot, 5.0);
    }
}
