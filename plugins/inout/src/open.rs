//! Open boundaries with buffer zones: `InflowBoundary(..)` and `OutflowBoundary(..)`, the
//! buffer zones of Lastiwka, Basa & Quinlan (2009), *Permeable and non-reflecting boundary
//! conditions in SPH*, Int. J. Numer. Meth. Fluids 61, 709, and of Tafuni, Domínguez,
//! Vacondio & Crespo (2018), *A versatile algorithm for the treatment of open boundary
//! conditions in smoothed particle hydrodynamics GPU models*, Comput. Methods Appl. Mech.
//! Engrg. 342, 604 (as in DualSPHysics).
//!
//! A buffer is an axis-aligned box next to the fluid, its particles a body of kind `Buffer`
//! that the scene declares (`Body(name: "inflow", kind: Buffer)`). They take part in every pair
//! sum of the fluid as neighbours — they give the particles at the boundary a full support —
//! but the integrator does not move them: the boundary sets their position, velocity and
//! density every step ([`systems`]). Their velocity or density comes from the fluid by
//! zero-gradient extrapolation ([`extrapolate`]: the linear fit to the fluid at
//! the particle's mirror image in the open plane).
//!
//! * **Inflow**: the buffer is filled at t = 0 with a lattice of `spacing`; its particles move
//!   with the prescribed velocity `profile(x) · f(t) · direction` ([`Profile`], the ramp `f`
//!   of [`profile::ramp_factor`]) and take the density extrapolated from the fluid (or, with
//!   `pressure: Some(p)`, the equation of state's density at p). A buffer particle that
//!   crosses the open plane becomes a fluid particle, and a new buffer particle is created one
//!   buffer depth behind it, so the buffer keeps its count and its lattice.
//! * **Outflow**: the buffer is filled at t = 0 with the mirror images of the fluid next to the
//!   open plane; a fluid particle that crosses the open plane becomes a buffer particle; the
//!   buffer's particles move with the velocity extrapolated from the fluid and take its
//!   extrapolated density (or, with `pressure: Some(p)`, the density of the prescribed
//!   pressure); one that leaves the far face is deleted. With `non_reflecting: Some(τ)` the
//!   buffer's pressure moves with the leaving pressure waves at the acoustic impedance of an
//!   open end, so they leave instead of being reflected ([`impedance`]).
//!
//! The accounting ([`ledger`]): the mass, momentum and energy that cross each open plane, and
//! the impulse of the buffer's pair forces on the fluid (the exact reactions of the load on
//! the buffer body), are columns of `diagnostics.csv`, so that the fluid's momentum balance
//! closes to round-off at every step.

pub mod extrapolate;
pub mod impedance;
pub mod ledger;
pub mod owed;
pub mod profile;
pub mod state;
pub mod systems;
pub mod zone;

pub use ledger::{BoundaryLedger, OpenLedger};
pub use profile::Profile;

use crate::settings::{check_box, first_inside, lattice};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::{Bodies, BodyKind, BodyMotion, Hold};
use dualsph_core::neighbours::Neighbours;
use dualsph_core::plugin::{SectionProblem, positive};
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use zone::{Zone, axis_of};

/// The body kind of a buffer's particles: `Body(name: "inflow", kind: Buffer)`. Its particles
/// are set by their open boundary, not integrated; the scene gives them none (the boundary
/// fills the buffer).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Buffer;

impl BodyKind for Buffer {
    const NAME: &'static str = "Buffer";
    const SUMMARY: &'static str =
        "the buffer particles of an open boundary (InflowBoundary, OutflowBoundary)";
    const BARE: bool = true;
    const FILLED_DURING_RUN: bool = true;
    fn validate(&self, _info: &SceneInfo) -> Result<(), SectionProblem> {
        Ok(())
    }
    /// Held by the core's drive; the boundary then sets position and velocity after it.
    fn motion(&self) -> Option<Arc<dyn BodyMotion>> {
        Some(Arc::new(Hold))
    }
}

/// An inflow: a buffer of prescribed velocity upstream of the fluid (module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InflowBoundary {
    /// Lower corner of the buffer's box (m); its downstream face is the open plane.
    pub min: Vec<Real>,
    /// Upper corner of the buffer's box (m).
    pub max: Vec<Real>,
    /// The direction of the flow, along an axis (dimensionless; `[1.0, 0.0]` is towards +x).
    pub direction: Vec<Real>,
    /// Spacing Δx of the buffer's lattice (m).
    pub spacing: Real,
    /// The speed across the section (m/s): `Uniform(U)` or `Parabolic(U)` (peak U).
    pub profile: Profile,
    /// The time over which the speed rises from 0 (s): `f(t) = ½(1 − cos(πt/T))` up to T
    /// (0, the default: the full speed from the start).
    #[serde(default)]
    pub ramp: Real,
    /// Reference density of the buffer particles (kg/m³): their mass is ρ Δx^d.
    pub density: Real,
    /// Support radius over spacing (dimensionless).
    pub h_factor: Real,
    /// A prescribed pressure (Pa) for the buffer (its density then the equation of state's at
    /// it); none (the default): the density is extrapolated from the fluid.
    #[serde(default)]
    pub pressure: Option<Real>,
    /// Specific internal energy of the buffer particles (J/kg) (with an energy equation).
    #[serde(default)]
    pub internal_energy: Real,
    /// The body of the buffer's particles (of kind `Buffer`).
    pub buffer: String,
    /// The fluid body the particles join.
    #[serde(default = "crate::default_body")]
    pub fluid: String,
}

/// An outflow: a buffer downstream of the fluid that the fluid leaves through (module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutflowBoundary {
    /// Lower corner of the buffer's box (m); its upstream face is the open plane.
    pub min: Vec<Real>,
    /// Upper corner of the buffer's box (m).
    pub max: Vec<Real>,
    /// The direction of the flow, along an axis (dimensionless; `[1.0, 0.0]` is towards +x).
    pub direction: Vec<Real>,
    /// A prescribed pressure (Pa) for the buffer (its density then the equation of state's at
    /// it); none (the default): the density is extrapolated from the fluid.
    #[serde(default)]
    pub pressure: Option<Real>,
    /// `Some(τ)`: the outflow lets pressure waves leave instead of reflecting them — the
    /// buffer's pressure is `pressure + ρc (U − Ū)`, with U the mean normal velocity
    /// extrapolated into the buffer and Ū its running mean over τ (s), the relaxation time
    /// (module docs of `impedance`); needs `pressure`. Waves of period well below τ leave;
    /// the mean pressure is `pressure`. None (the default): the pressure is held.
    #[serde(default)]
    pub non_reflecting: Option<Real>,
    /// The body of the buffer's particles (of kind `Buffer`).
    pub buffer: String,
    /// The fluid body that leaves through it.
    #[serde(default = "crate::default_body")]
    pub fluid: String,
}

/// The checks both boundaries share: the box inside the domain, the direction an axis, the
/// pressure finite, the bodies distinct and declared.
fn validate_common(
    what: &str,
    (min, max, direction): (&[Real], &[Real], &[Real]),
    pressure: Option<Real>,
    (buffer, fluid): (&str, &str),
    info: &SceneInfo,
) -> Result<(), String> {
    let d = info.dimension;
    check_box(min, max, d)?;
    if !(info.in_domain(min) && info.in_domain(max)) {
        return Err(format!(
            "min/max: the {what}'s buffer [{min:?}, {max:?}] is not inside the domain \
             [{:?}, {:?}]",
            info.domain.0, info.domain.1
        ));
    }
    axis_of(direction, d)?;
    if pressure.is_some_and(|p| !p.is_finite()) {
        return Err("pressure: must be a finite number".into());
    }
    info.check_body("buffer", buffer)?;
    info.check_body("fluid", fluid)?;
    if buffer == fluid {
        return Err(format!(
            "buffer: the buffer's body must not be the fluid `{fluid}` (declare one of kind \
             Buffer)"
        ));
    }
    Ok(())
}

impl SimPlugin for InflowBoundary {
    const NAME: &'static str = "InflowBoundary";
    const SUMMARY: &'static str =
        "open inflow: a buffer of prescribed velocity (uniform or parabolic, ramped)";

    fn scale_spacing(&mut self, factor: Real) {
        self.spacing *= factor;
    }

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        let dirs = (&self.min[..], &self.max[..], &self.direction[..]);
        let bodies = (self.buffer.as_str(), self.fluid.as_str());
        validate_common("inflow", dirs, self.pressure, bodies, info)?;
        positive("spacing", self.spacing)?;
        positive("density", self.density)?;
        positive("h_factor", self.h_factor)?;
        self.profile.check()?;
        if !(self.ramp.is_finite() && self.ramp >= 0.0) {
            return Err(format!("ramp: must be finite and ≥ 0, got {}", self.ramp));
        }
        if !self.internal_energy.is_finite() {
            return Err("internal_energy: must be finite".into());
        }
        let (k, _) = axis_of(&self.direction, info.dimension)?;
        let depth = self.max[k] - self.min[k];
        let h = self.h_factor * self.spacing;
        if depth < h * (1.0 - 1e-9) {
            return Err(format!(
                "min/max: the buffer is {depth} deep along the flow, less than the support \
                 radius h = h_factor·spacing = {h}: the fluid at the open plane would lack \
                 support (make it at least {} layers deep)",
                self.h_factor.ceil()
            ));
        }
        let cells = crate::Inlet::cells(&self.min, &self.max, self.spacing, info.dimension);
        if cells > crate::MAX_LAYER_PARTICLES {
            return Err(format!(
                "spacing: the buffer would hold about {cells:.3e} particles, more than {:e}",
                crate::MAX_LAYER_PARTICLES
            ));
        }
        Ok(())
    }

    fn prepare<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let speed = self.profile.peak();
        dualsph_fluid::speeds::impose_speed(&mut sim.world, speed, "InflowBoundary (its profile)");
        Ok(())
    }

    /// The buffer's particles, and one for each that enters the fluid over the run.
    fn particles_added(&self, end_time: Real, dimension: usize) -> Real {
        let d = dimension.min(self.min.len()).min(self.max.len());
        let cells = crate::Inlet::cells(&self.min, &self.max, self.spacing, d);
        let Ok((k, _)) = axis_of(&self.direction, d) else {
            return cells;
        };
        let layers = (self.max[k] - self.min[k]) / self.spacing;
        let travelled = self.profile.peak() * end_time.max(0.0) / self.spacing;
        cells * (1.0 + travelled / layers.max(1.0))
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let d = V::DIM;
        let (axis, sign) = axis_of(&self.direction, d).map_err(SimError::Build)?;
        let (min, max) = (vector::<V>(&self.min)?, vector::<V>(&self.max)?);
        let zone = Zone::new(min, max, axis, sign, true).with_periodic(periodic_axes(sim, axis)?);
        let (buffer, fluid) = bodies_of(sim, "InflowBoundary", &self.buffer, &self.fluid)?;
        refuse_overlap(sim, "InflowBoundary", zone, self.spacing)?;
        let dx = self.spacing;
        let template = ParticleInit {
            pos: V::zero(),
            vel: V::zero(),
            mass: self.density * dx.powi(d as i32),
            density: self.density,
            h: self.h_factor * dx,
            internal_energy: self.internal_energy,
            body: buffer,
        };
        let ramp0 = profile::ramp_factor(self.ramp, 0.0);
        let particles: Vec<_> = lattice(min, max, dx)
            .into_iter()
            .map(|pos| ParticleInit {
                pos,
                vel: zone.normal() * (self.profile.speed(&zone, pos) * ramp0),
                ..template
            })
            .collect();
        sim.spawn_particles(&particles)?;
        let boundary = systems::Boundary {
            zone,
            buffer,
            fluid,
            inflow: Some(systems::Inflow {
                profile: self.profile.clone(),
                ramp: self.ramp,
                template,
            }),
            pressure: self.pressure,
            non_reflecting: None,
        };
        systems::install(sim, boundary, &self.buffer)
    }
}

impl SimPlugin for OutflowBoundary {
    const NAME: &'static str = "OutflowBoundary";
    const SUMMARY: &'static str =
        "open outflow: a buffer of extrapolated velocity the fluid leaves through";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        let dirs = (&self.min[..], &self.max[..], &self.direction[..]);
        let bodies = (self.buffer.as_str(), self.fluid.as_str());
        validate_common("outflow", dirs, self.pressure, bodies, info)?;
        match (self.non_reflecting, self.pressure) {
            (Some(tau), _) if !(tau.is_finite() && tau > 0.0) => Err(format!(
                "non_reflecting: the relaxation time must be a positive number of seconds, \
                 got {tau}"
            )),
            (Some(_), None) => Err("non_reflecting: needs the mean pressure it relaxes to, \
                                    `pressure: Some(p)`"
                .into()),
            _ => Ok(()),
        }
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let (axis, sign) = axis_of(&self.direction, V::DIM).map_err(SimError::Build)?;
        let (min, max) = (vector::<V>(&self.min)?, vector::<V>(&self.max)?);
        let zone = Zone::new(min, max, axis, sign, false).with_periodic(periodic_axes(sim, axis)?);
        let (buffer, fluid) = bodies_of(sim, "OutflowBoundary", &self.buffer, &self.fluid)?;
        refuse_overlap(sim, "OutflowBoundary", zone, 0.0)?;
        let h_max = max_h(&mut sim.world, fluid);
        if zone.depth() < h_max * (1.0 - 1e-9) {
            return Err(SimError::Build(format!(
                "OutflowBoundary (min: {:?}, max: {:?}): the buffer is {} deep along the flow, \
                 less than the fluid's support radius {h_max}: the fluid at the open plane \
                 would lack support",
                self.min,
                self.max,
                zone.depth()
            )));
        }
        let images = mirrored_fluid(&mut sim.world, &zone, fluid, buffer);
        sim.spawn_particles(&images)?;
        let boundary = systems::Boundary {
            zone,
            buffer,
            fluid,
            inflow: None,
            pressure: self.pressure,
            non_reflecting: self.non_reflecting,
        };
        systems::install(sim, boundary, &self.buffer)
    }
}

/// A vector of the scene from its components.
fn vector<V: Vector>(v: &[Real]) -> Result<V, SimError> {
    V::from_slice(v).ok_or_else(|| SimError::Build("a vector of the wrong dimension".into()))
}

/// The domain's periodic axes, refusing a boundary whose flow runs along one (a particle that
/// left through the outflow would come back through the inflow).
/// (The error is prefixed with the plugin's name where it is reported.)
fn periodic_axes<V: Vector>(sim: &Sim<V>, axis: usize) -> Result<[bool; 3], SimError> {
    let period = sim.world.resource::<Neighbours<V>>().period;
    let axes = std::array::from_fn(|k| period.is_some_and(|p| p.is_periodic(k)));
    if axes[axis] {
        return Err(SimError::Build(format!(
            "the domain is periodic along the flow's axis {}; an open boundary needs the axis \
             it opens closed (`domain.periodic`)",
            ["x", "y", "z"][axis]
        )));
    }
    Ok(axes)
}

/// The indices of the buffer body (driven: of kind `Buffer`) and of the fluid body.
fn bodies_of<V: Vector>(
    sim: &Sim<V>,
    what: &str,
    buffer: &str,
    fluid: &str,
) -> Result<(u16, u16), SimError> {
    let bodies = sim.world.resource::<Bodies>();
    let index = |name: &str| {
        bodies
            .index(name)
            .ok_or_else(|| SimError::Build(format!("{what}: no body `{name}`")))
    };
    let (b, f) = (index(buffer)?, index(fluid)?);
    if bodies.0[b].is_fluid() {
        return Err(SimError::Build(format!(
            "{what}.buffer: `{buffer}` is a fluid body; declare it `Body(name: \"{buffer}\", \
             kind: Buffer)`"
        )));
    }
    if !bodies.0[f].is_fluid() {
        return Err(SimError::Build(format!(
            "{what}.fluid: `{fluid}` is not a fluid body"
        )));
    }
    Ok((b as u16, f as u16))
}

/// Refuses a buffer whose box holds a particle of the scene at t = 0 (of a body, or fluid
/// past the open plane), naming it; and a buffer that overlaps another boundary's.
fn refuse_overlap<V: Vector>(
    sim: &mut Sim<V>,
    what: &str,
    zone: Zone<V>,
    spacing: Real,
) -> Result<(), SimError> {
    let eps = if spacing > 0.0 { spacing } else { zone.depth() };
    if let Some((id, pos, body)) = first_inside(&mut sim.world, zone.min, zone.max, eps) {
        let name = (sim
            .world
            .resource::<Bodies>()
            .names()
            .get(usize::from(body))
            .cloned())
        .unwrap_or_else(|| format!("#{body}"));
        return Err(SimError::Build(format!(
            "{what} (min: {:?}, max: {:?}): its buffer holds particle {id} of the body \
             `{name}` at {:?} at t = 0; end the body's generators at the buffer's face",
            comps(zone.min),
            comps(zone.max),
            comps(pos)
        )));
    }
    systems::refuse_conflicts(sim, what, &zone)
}

/// The components of `v` in the scene's dimension.
pub(crate) fn comps<V: Vector>(v: V) -> Vec<Real> {
    (0..V::DIM).map(|k| v.get(k)).collect()
}

/// An outflow's buffer at t = 0: the mirror image in the open plane of every particle of
/// `fluid` within the buffer's depth upstream of it and in its section, with the particle's
/// velocity, mass, density, support radius and internal energy (the zero-gradient state, a
/// lattice that ends half a spacing before the plane continued across it), in id order. An
/// empty buffer would leave the fluid at the plane a free surface that runs into it.
fn mirrored_fluid<V: Vector>(
    world: &mut World,
    zone: &Zone<V>,
    fluid: u16,
    buffer: u16,
) -> Vec<ParticleInit<V>> {
    type Row<'a, V> = (
        &'a ParticleId,
        &'a BodyId,
        &'a Position<V>,
        &'a Velocity<V>,
        &'a Mass,
        &'a Density,
        &'a SmoothingLength,
        Option<&'a InternalEnergy>,
    );
    let mut q = world.query::<Row<'_, V>>();
    let mut images: Vec<(u32, ParticleInit<V>)> = (q.iter(world))
        .filter(|r| r.1.0 == fluid && zone.in_section(r.2.0))
        .filter(|r| (zone.depth_of(r.2.0) > -zone.depth()) && zone.depth_of(r.2.0) < 0.0)
        .map(|(id, _, x, v, m, rho, h, e)| {
            let init = ParticleInit {
                pos: zone.mirror(x.0),
                vel: v.0,
                mass: m.0,
                density: rho.0,
                h: h.0,
                internal_energy: e.map_or(0.0, |e| e.0),
                body: buffer,
            };
            (id.0, init)
        })
        .collect();
    images.sort_unstable_by_key(|r| r.0);
    images.into_iter().map(|r| r.1).collect()
}

/// The largest support radius of the particles of `body`.
fn max_h(world: &mut World, body: u16) -> Real {
    let mut q = world.query::<(&BodyId, &SmoothingLength)>();
    q.iter(world)
        .filter(|(b, _)| b.0 == body)
        .map(|(_, h)| h.0)
        .fold(0.0, Real::max)
}
