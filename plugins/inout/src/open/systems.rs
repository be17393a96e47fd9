//! The systems of the open boundaries, in step order:
//!
//! 1. `Population` ([`cross`]): particles that crossed an open plane change body — an inflow's
//!    buffer particle past its plane joins the fluid and a new buffer particle is created one
//!    buffer depth `L` behind it (`x − L n`); a fluid particle past an outflow's plane joins its
//!    buffer; an outflow's buffer particle past the far face is deleted. A fluid particle that
//!    drifts back into an inflow's buffer is deleted, and an outflow's buffer particle that
//!    drifts back upstream of the plane rejoins the fluid. Every change is applied in
//!    particle-id order, through the core's `Population` for the new and deleted ones; the
//!    creations and the far face's deletions wait for a step that rebuilds the neighbour
//!    lists while the fluid cannot tell ([`super::owed`]).
//! 2. `Predict`, after the bodies' drive ([`move_buffers`]): each buffer particle moves from
//!    its start-of-step position (kept in the core's `Anchor` column) by its velocity — the
//!    inflow's exact travel `u(x) n (S(t + Δt) − S(t))` ([`super::profile::ramp_integral`]),
//!    the outflow's `Δt v`.
//! 3. `Eos`, before the equation of state ([`super::extrapolate`]): the zero-gradient extrapolation
//!    of Tafuni et al. (2018, §3: values at the mirror image of each buffer particle in the
//!    open plane, interpolated from the fluid with first-order consistency): `φ_b = a`, where
//!    `a + b·(x_f − x_g)` is the linear fit to the fluid's `φ_f` minimising
//!    `Σ_f W(x_g − x_f, h_b) V_f (φ_f − a − b·(x_f − x_g))²` ([`super::extrapolate::linear_fit`]), `x_g = x_b − 2 d_b n`,
//!    `V_f = m_f/ρ_f`, over the fluid particles within `h_b` of the mirror point `x_g`; the
//!    Shepard average `Σ_f φ_f W V_f / Σ_f W V_f` (Shepard 1968) where the fit is singular. A
//!    linear field is extrapolated exactly next to a wall, where the truncated support makes the
//!    Shepard average lean towards the interior. The inflow takes the density so (or the prescribed pressure's), the outflow the
//!    velocity and the density (or the prescribed pressure's, which a non-reflecting outflow
//!    moves with the leaving waves, [`super::impedance`]). A buffer particle with no fluid
//!    near its mirror point keeps its values.
//! 4. `Correct`, after the drive and the density's corrector ([`hold_buffers`]): the buffer
//!    particles get back their velocity and density (the integrator's update is discarded).
//! 5. `Diagnostics` ([`account`]): the load on each buffer and the impulse on the fluid
//!    ([`super::ledger`]); a non-reflecting outflow's running mean velocity advances
//!    ([`super::impedance`]).

use super::impedance::{Impedance, Relaxed};
use super::ledger::{BoundaryLedger, OpenLedger, add3};
use super::owed::{Owed, OwedParticle};
pub use super::state::{Boundaries, Boundary, BufferState, Inflow};
use super::zone::Zone;
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Anchor, Bodies, DriveBodies};
use dualsph_core::chunks::DENSE;
use dualsph_core::neighbours::Neighbours;
use dualsph_core::population::Population;
use dualsph_core::store::single_table;
use dualsph_fluid::EquationOfState;
use dualsph_fluid::prelude::*;
use dualsph_integrate::Updates;

/// Refuses a boundary whose buffer overlaps another's or shares its body, and an outflow
/// upstream of an inflow (or an inflow downstream of an outflow) on the same axis.
pub(crate) fn refuse_conflicts<V: Vector>(
    sim: &Sim<V>,
    what: &str,
    zone: &Zone<V>,
) -> Result<(), SimError> {
    let Some(all) = sim.world.get_resource::<Boundaries<V>>() else {
        return Ok(());
    };
    for other in &all.list {
        let o = &other.zone;
        let overlap =
            (0..V::DIM).all(|k| zone.min.get(k) < o.max.get(k) && o.min.get(k) < zone.max.get(k));
        if overlap {
            return Err(SimError::Build(format!(
                "{what} (min: {:?}, max: {:?}): its buffer overlaps another open boundary's \
                 (min: {:?}, max: {:?})",
                super::comps(zone.min),
                super::comps(zone.max),
                super::comps(o.min),
                super::comps(o.max)
            )));
        }
        let is_inflow = what == "InflowBoundary";
        let same_flow = o.axis == zone.axis && o.sign == zone.sign;
        if same_flow && is_inflow != other.inflow.is_some() {
            let (inlet, outlet) = if is_inflow { (zone, o) } else { (o, zone) };
            if zone.sign * (outlet.plane - inlet.plane) <= 0.0 {
                return Err(SimError::Build(format!(
                    "{what}: the outflow's open plane (axis {} at {}) is upstream of the \
                     inflow's (at {}) for a flow along {}{}: the outflow must lie downstream",
                    zone.axis,
                    outlet.plane,
                    inlet.plane,
                    if zone.sign > 0.0 { "+" } else { "-" },
                    ["x", "y", "z"][zone.axis]
                )));
            }
        }
    }
    Ok(())
}

/// Adds `boundary` (its buffer the body `name`): on the first one, the resources, the
/// `buffer_state` column and the systems.
pub(crate) fn install<V: Vector>(
    sim: &mut Sim<V>,
    boundary: Boundary<V>,
    name: &str,
) -> Result<(), SimError> {
    if !sim.has::<Boundaries<V>>() {
        let n = sim.world.resource::<Bodies>().0.len();
        sim.world.insert_resource(Boundaries::<V> {
            list: Vec::new(),
            of_body: vec![None; n],
        });
        sim.world.insert_resource(OpenLedger::default());
        sim.keep_resource::<OpenLedger>("open_boundaries");
        sim.world.insert_resource(Impedance::default());
        sim.keep_resource::<Impedance>("open_boundaries_impedance");
        sim.world.insert_resource(Owed::default());
        sim.keep_resource::<Owed>("open_boundaries_owed");
        sim.enable_population();
        let spec = ColumnSpec::restart_only("buffer_state");
        sim.add_column(spec, |seed| BufferState {
            v: seed.init.vel,
            rho: seed.init.density,
        })?;
        add_systems(sim);
        sim.add_finish_hook("open_boundaries", check_finished::<V>);
    }
    let mut all = sim.world.resource_mut::<Boundaries<V>>();
    let b = usize::from(boundary.buffer);
    if all.of_body[b].is_some() {
        return Err(SimError::Build(format!(
            "the body `{name}` is the buffer of two open boundaries; give each its own"
        )));
    }
    all.of_body[b] = Some(all.list.len());
    all.list.push(boundary);
    let k = all.list.len() - 1;
    sim.world
        .resource_mut::<OpenLedger>()
        .0
        .push(BoundaryLedger::default());
    (sim.world.resource_mut::<Impedance>().0).push(Relaxed::default());
    let mut cols = sim
        .world
        .resource_mut::<dualsph_core::output::DiagnosticColumns>();
    super::ledger::add_columns::<V>(&mut cols, k, name).map_err(SimError::Build)
}

fn add_systems<V: Vector>(sim: &mut Sim<V>) {
    sim.add_system(
        StepSet::Population,
        "open_boundaries_cross (conversions, new and deleted buffer particles)",
        cross::<V>,
    );
    sim.add_system(
        StepSet::Predict,
        "open_boundaries_move (buffer particles, after the predictor)",
        move_buffers::<V>,
    )
    .after::<DriveBodies>();
    sim.add_system(
        StepSet::Eos,
        "open_boundaries_extrapolate (zero gradient, Tafuni et al. 2018)",
        super::extrapolate::extrapolate::<V>,
    )
    .before::<EquationOfState>();
    sim.add_system(
        StepSet::Correct,
        "open_boundaries_hold (buffer particles, after the corrector)",
        hold_buffers::<V>,
    )
    .after::<DriveBodies>()
    .after::<Updates<Density>>();
    sim.add_system(
        StepSet::Diagnostics,
        "open_boundaries_account (loads and impulses)",
        account::<V>,
    );
}

/// Refuses, once every plugin is built, a scheme other than the leapfrog (the ledger's
/// impulse is its corrector's trapezoid), a `WallPressure` that treats a buffer as a wall and
/// a prescribed pressure without a liquid's equation of state.
fn check_finished<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    let scheme = sim.integrator();
    if scheme.is_some_and(|s| s != "LeapfrogPC") {
        return Err(SimError::Build(format!(
            "the open boundaries' accounting follows the LeapfrogPC integrator's corrector; \
             this scene's is {}",
            scheme.unwrap_or_default()
        )));
    }
    let all = sim.world.resource::<Boundaries<V>>();
    if let Some(walls) = sim.world.get_resource::<dualsph_walls::WallBodies>() {
        let bodies = sim.world.resource::<Bodies>();
        for (b, _) in all.of_body.iter().enumerate().filter(|(_, k)| k.is_some()) {
            if walls.0.get(b).copied().unwrap_or(false) {
                return Err(SimError::Build(format!(
                    "WallPressure treats the buffer `{}` as a wall; name the walls in \
                     WallPressure(bodies: [..])",
                    bodies.0[b].name
                )));
            }
        }
    }
    refuse_pressure_without_law(sim)
}

/// Refuses a prescribed pressure that no equation of state turns into a density (no
/// equation of state, or a gas's, for the boundary's fluid): it would be ignored silently.
fn refuse_pressure_without_law<V: Vector>(sim: &Sim<V>) -> Result<(), SimError> {
    let all = sim.world.resource::<Boundaries<V>>();
    let eos = sim.world.get_resource::<dualsph_fluid::BodyEos>();
    let names = sim.world.resource::<Bodies>().names();
    for b in all.list.iter() {
        let Some(p) = b.pressure else {
            continue;
        };
        let law = eos.and_then(|e| e.0.get(usize::from(b.fluid)));
        if law.and_then(|l| l.density_at(p)).is_none() {
            return Err(SimError::Build(format!(
                "the open boundary of the buffer `{}` prescribes pressure {p}: the fluid `{}` \
                 needs a liquid's equation of state (TaitEos) to give the density at it",
                names[usize::from(b.buffer)],
                names[usize::from(b.fluid)]
            )));
        }
    }
    Ok(())
}

/// What happens to a particle at the start of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Change {
    /// Joins the fluid from boundary k's buffer.
    Enter(usize),
    /// Leaves the fluid into boundary k's buffer.
    Leave(usize),
    /// A fluid particle leaves the fluid through boundary k and is deleted.
    LeaveDeleted(usize),
    /// A buffer particle of boundary k is deleted.
    Delete(usize),
}

/// The change of a particle of `body` at `x`, if any (module docs, step 1).
fn change_of<V: Vector>(all: &Boundaries<V>, body: u16, x: V) -> Option<Change> {
    if let Some(Some(k)) = all.of_body.get(usize::from(body)) {
        let b = &all.list[*k];
        let d = b.zone.depth_of(x);
        return match (b.inflow.is_some(), d >= 0.0, d > b.zone.depth()) {
            (true, true, _) => Some(Change::Enter(*k)),
            (false, false, _) => Some(Change::Enter(*k)),
            (false, _, true) => Some(Change::Delete(*k)),
            _ => None,
        };
    }
    for (k, b) in all.list.iter().enumerate() {
        if b.fluid != body || !b.zone.in_section(x) {
            continue;
        }
        let d = b.zone.depth_of(x);
        if b.inflow.is_some() && d < 0.0 && d >= -b.zone.depth() {
            return Some(Change::LeaveDeleted(k));
        }
        if b.inflow.is_none() && d >= 0.0 {
            return Some(Change::Leave(k));
        }
    }
    None
}

/// The particle data [`cross`] reads and changes.
type CrossQuery<'w, 's, V> = Query<
    'w,
    's,
    (
        Entity,
        &'static ParticleId,
        &'static mut BodyId,
        &'static Position<V>,
        &'static Velocity<V>,
        &'static Mass,
        &'static Density,
        Option<&'static InternalEnergy>,
        &'static mut Acceleration<V>,
        &'static mut Anchor<V>,
        &'static mut BufferState<V>,
    ),
>;

/// The neighbour lists and the particles' positions and support radii in row order: what
/// [`cross`] decides from whether the changes of the particle count wait ([`super::owed`]).
type ListsQuery<'w, 's, V> = (
    Res<'w, Neighbours<V>>,
    Query<'w, 's, (&'static Position<V>, &'static SmoothingLength)>,
);

/// True when this step's changes of the particle count are applied now rather than held
/// ([`super::owed`]): the lists will be rebuilt anyway, another change is asked for, or an
/// owed particle is due.
fn apply_now<V: Vector>(
    lists: &ListsQuery<V>,
    asked: bool,
    all: &Boundaries<V>,
    owed: &Owed,
    t: Real,
) -> bool {
    if asked {
        return true;
    }
    let (nb, q) = lists;
    let Some((pos, h)) = single_table(q.contiguous_iter().expect(DENSE)) else {
        return true;
    };
    if nb.needs_rebuild_with(pos.len(), |i| pos[i].0) {
        return true;
    }
    if owed.0.is_empty() {
        return false;
    }
    let h_max = h.iter().map(|h| h.0).fold(0.0, Real::max);
    let reach = super::owed::reach(h_max);
    owed.0.iter().any(|o| o.due(all, t, reach))
}

/// Step 1 of the module docs.
#[inline(never)] // a frame of its own in profiles
pub fn cross<V: Vector>(
    clock: Res<SimClock>,
    all: Res<Boundaries<V>>,
    mut ledger: ResMut<OpenLedger>,
    mut owed: ResMut<Owed>,
    mut population: ResMut<Population<V>>,
    lists: ListsQuery<V>,
    mut q: CrossQuery<V>,
) {
    let mut changes: Vec<(u32, Entity, Change)> = q
        .iter()
        .filter_map(|(e, id, b, r, ..)| change_of(&all, b.0, r.0).map(|c| (id.0, e, c)))
        .collect();
    changes.sort_unstable_by_key(|c| c.0);
    let asked = population.pending() > 0
        || changes
            .iter()
            .any(|c| matches!(c.2, Change::LeaveDeleted(_)));
    let mut deletions = Vec::new();
    for (_, e, change) in changes {
        let Ok((_, _, mut body, r, v, m, rho, eps, mut a, mut anchor, mut st)) = q.get_mut(e)
        else {
            continue;
        };
        let energy = 0.5 * m.0 * v.0.length_squared() + m.0 * eps.map_or(0.0, |e| e.0);
        match change {
            Change::Enter(k) => {
                let (b, l) = (&all.list[k], &mut ledger.0[k]);
                l.mass_in += m.0;
                add3(&mut l.p_in, v.0 * m.0);
                l.e_in += energy;
                l.counts[0] += 1;
                body.0 = b.fluid;
                // a new fluid particle starts with zero acceleration (its first half-kick
                // is its first sweep's), as a particle the population adds does
                a.0 = V::zero();
                if b.inflow.is_some() {
                    let pos = r.0 - b.zone.normal() * b.zone.depth();
                    owed.0.push(OwedParticle::new(k, pos, st.rho, clock.t));
                }
            }
            Change::Leave(k) | Change::LeaveDeleted(k) => {
                let l = &mut ledger.0[k];
                l.mass_out += m.0;
                add3(&mut l.p_out, v.0 * m.0);
                l.e_out += energy;
                add3(&mut l.pending, a.0 * m.0);
                l.counts[1] += 1;
                if change == Change::Leave(k) {
                    body.0 = all.list[k].buffer;
                    anchor.0 = r.0;
                    *st = BufferState { v: v.0, rho: rho.0 };
                } else {
                    population.remove(e);
                    l.counts[3] += 1;
                }
            }
            Change::Delete(k) => deletions.push((e, k)),
        }
    }
    if apply_now(&lists, asked, &all, &owed, clock.t) {
        for (e, k) in deletions {
            population.remove(e);
            ledger.0[k].counts[3] += 1;
        }
        create_owed(&clock, &all, &mut ledger, &mut owed, &mut population);
    }
}

/// Creates every owed particle where its inflow has carried it by now, in the order they
/// became due ([`super::owed`]).
fn create_owed<V: Vector>(
    clock: &SimClock,
    all: &Boundaries<V>,
    ledger: &mut OpenLedger,
    owed: &mut Owed,
    population: &mut Population<V>,
) {
    for o in owed.0.drain(..) {
        let b = &all.list[o.boundary];
        let Some(inflow) = &b.inflow else {
            continue;
        };
        let pos = o.position(all, clock.t);
        population.spawn(ParticleInit {
            pos,
            vel: b.inflow_velocity(pos, clock.t),
            density: o.density,
            ..inflow.template
        });
        ledger.0[o.boundary].counts[2] += 1;
    }
}

/// Step 2 of the module docs.
#[inline(never)] // a frame of its own in profiles
pub fn move_buffers<V: Vector>(
    clock: Res<SimClock>,
    all: Res<Boundaries<V>>,
    nb: Res<Neighbours<V>>,
    mut q: Query<(
        &BodyId,
        &mut Position<V>,
        &mut Velocity<V>,
        &mut Anchor<V>,
        &BufferState<V>,
    )>,
) {
    let (t, dt) = (clock.t, clock.dt);
    for (body, mut r, mut v, mut anchor, st) in &mut q {
        let Some(Some(k)) = all.of_body.get(usize::from(body.0)) else {
            continue;
        };
        let b = &all.list[*k];
        let (shift, vel) = match &b.inflow {
            Some(_) => (
                b.inflow_travel(anchor.0, t, t + dt),
                b.inflow_velocity(anchor.0, t + dt),
            ),
            None => (st.v * dt, st.v),
        };
        // an outflow's particle may drift across a periodic face: kept in the box, as the
        // fluid's are, so that its mirror image reads the fluid across the period
        anchor.0 = match &nb.period {
            Some(p) => p.wrap(anchor.0 + shift),
            None => anchor.0 + shift,
        };
        r.0 = anchor.0;
        v.0 = vel;
    }
}

/// Step 4 of the module docs.
#[inline(never)] // a frame of its own in profiles
pub fn hold_buffers<V: Vector>(
    clock: Res<SimClock>,
    all: Res<Boundaries<V>>,
    mut q: Query<(
        &BodyId,
        &mut Position<V>,
        &mut Velocity<V>,
        &mut Density,
        &Anchor<V>,
        &BufferState<V>,
    )>,
) {
    let t = clock.t + clock.dt;
    for (body, mut r, mut v, mut rho, anchor, st) in &mut q {
        let Some(Some(k)) = all.of_body.get(usize::from(body.0)) else {
            continue;
        };
        let b = &all.list[*k];
        r.0 = anchor.0;
        v.0 = match b.inflow {
            Some(_) => b.inflow_velocity(anchor.0, t),
            None => st.v,
        };
        rho.0 = st.rho;
    }
}

/// Step 5 of the module docs: `L_B = Σ_{i∈B} m_i a_i` in id order, and the impulse; the
/// running means of the non-reflecting outflows advance over the step.
#[inline(never)] // a frame of its own in profiles
pub fn account<V: Vector>(
    clock: Res<SimClock>,
    all: Res<Boundaries<V>>,
    mut ledger: ResMut<OpenLedger>,
    mut impedance: ResMut<Impedance>,
    q: Query<(&ParticleId, &BodyId, &Mass, &Acceleration<V>)>,
) {
    if !clock.initializing {
        for (b, r) in all.list.iter().zip(impedance.0.iter_mut()) {
            if let Some(tau) = b.non_reflecting {
                r.relax(clock.dt, tau);
            }
        }
    }
    let mut rows: Vec<(u32, usize, V)> = q
        .iter()
        .filter_map(|(id, b, m, a)| match all.of_body.get(usize::from(b.0)) {
            Some(Some(k)) => Some((id.0, *k, a.0 * m.0)),
            _ => None,
        })
        .collect();
    rows.sort_unstable_by_key(|r| r.0);
    let mut loads = vec![[0.0; 3]; all.list.len()];
    for (_, k, f) in rows {
        add3(&mut loads[k], f);
    }
    let half = 0.5 * clock.dt;
    for (l, load) in ledger.0.iter_mut().zip(loads) {
        if !clock.initializing {
            for a in 0..3 {
                l.impulse[a] -= half * (l.load[a] + load[a] + l.pending[a]);
            }
        }
        l.load = load;
        l.pending = [0.0; 3];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::open::Profile;
    use glam::DVec2;

    /// An inflow (buffer body 2) on x ∈ [−0.1, 0] and an outflow (buffer body 3) on
    /// x ∈ [1, 1.1], both for the fluid body 1, flow towards +x.
    fn boundaries() -> Boundaries<DVec2> {
        let template = ParticleInit {
            pos: DVec2::ZERO,
            vel: DVec2::ZERO,
            mass: 1.0,
            density: 1.0,
            h: 0.1,
            internal_energy: 0.0,
            body: 2,
        };
        let zone =
            |x0, x1, inflow| Zone::new(DVec2::new(x0, 0.0), DVec2::new(x1, 1.0), 0, 1.0, inflow);
        let inflow = Boundary {
            zone: zone(-0.1, 0.0, true),
            buffer: 2,
            fluid: 1,
            inflow: Some(Inflow {
                profile: Profile::Uniform(1.0),
                ramp: 0.0,
                template,
            }),
            pressure: None,
            non_reflecting: None,
        };
        let outflow = Boundary {
            zone: zone(1.0, 1.1, false),
            buffer: 3,
            fluid: 1,
            inflow: None,
            pressure: Some(0.0),
            non_reflecting: None,
        };
        Boundaries {
            list: vec![inflow, outflow],
            of_body: vec![None, None, Some(0), Some(1)],
        }
    }

    #[test]
    fn particles_change_role_where_they_cross() {
        let all = boundaries();
        let at = |x: f64| DVec2::new(x, 0.5);
        // the inflow's buffer particles join the fluid at the plane
        assert_eq!(change_of(&all, 2, at(-0.01)), None);
        assert_eq!(change_of(&all, 2, at(0.0)), Some(Change::Enter(0)));
        // fluid that drifts back into the inflow's buffer is deleted; fluid elsewhere stays
        assert_eq!(change_of(&all, 1, at(-0.05)), Some(Change::LeaveDeleted(0)));
        assert_eq!(change_of(&all, 1, at(0.5)), None);
        assert_eq!(
            change_of(&all, 1, DVec2::new(1.05, 1.5)),
            None,
            "outside the section"
        );
        // the outflow takes the fluid at its plane, deletes past its far face, and gives back
        // what drifts upstream
        assert_eq!(change_of(&all, 1, at(1.0)), Some(Change::Leave(1)));
        assert_eq!(change_of(&all, 3, at(1.05)), None);
        assert_eq!(change_of(&all, 3, at(1.11)), Some(Change::Delete(1)));
        assert_eq!(change_of(&all, 3, at(0.99)), Some(Change::Enter(1)));
        // walls (body 0) never change
        assert_eq!(change_of(&all, 0, at(1.05)), None);
    }
}
