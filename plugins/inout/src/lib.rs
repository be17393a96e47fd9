//! Particles that enter and leave during a run, through the core's changing particle count
//! ([`dualsph_core::population`]):
//!
//! * `Inlet(min, max, spacing, velocity, density, h_factor, …)`: a layer of particles on a
//!   lattice of `spacing` over the box `[min, max]` enters with `velocity` every
//!   `Δt_layer = spacing / |velocity|` of simulated time. Layer k is due at `t_k = k Δt_layer`;
//!   it is added at the first step that starts at `t ≥ t_k`, displaced by
//!   `velocity · (t − t_k)`, so successive layers stay one spacing apart whatever dt is.
//!   Mass `ρ Δx^d`, support radius `h_factor Δx`. The count of layers so far is kept in
//!   checkpoints.
//! * `Outlet(min, max)`: every particle of a fluid body inside the box `[min, max]` at the
//!   start of a step is removed.
//!
//! Both act in `StepSet::Population`, at the start of the step; the core applies their
//! requests at the end of that set (removals in id order, then additions in the order asked).
//!
//! An inlet's bare layers and an outlet's cut leave the particles at either end without
//! support beyond them; [`open`] gives a stream buffer zones that hold:
//! `InflowBoundary(..)` and `OutflowBoundary(..)`.
#![warn(missing_docs)]

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::Bodies;
use dualsph_core::plugin::positive;
use dualsph_core::population::Population;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

pub mod open;
mod settings;
pub use open::{Buffer, InflowBoundary, OutflowBoundary};
pub use settings::{check_box, lattice};

/// The most particles one inlet layer may hold (checked before the lattice is built).
pub const MAX_LAYER_PARTICLES: Real = 1e7;

/// An inlet (see the module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Inlet {
    /// Lower corner of the box the layer fills (m).
    pub min: Vec<Real>,
    /// Upper corner of the box the layer fills (m).
    pub max: Vec<Real>,
    /// Particle spacing Δx (m; of the lattice and between layers).
    pub spacing: Real,
    /// Velocity of the entering particles (m/s).
    pub velocity: Vec<Real>,
    /// Density of the entering particles (kg/m³).
    pub density: Real,
    /// Support radius over spacing (dimensionless).
    pub h_factor: Real,
    /// Specific internal energy of the entering particles (J/kg) (with an energy equation).
    #[serde(default)]
    pub internal_energy: Real,
    /// The fluid body the particles join.
    #[serde(default = "default_body")]
    pub body: String,
    /// No layer is due after this time (s) (none: for the whole run).
    #[serde(default)]
    pub until: Option<Real>,
}

fn default_body() -> String {
    dualsph_core::bodies::DEFAULT_BODY.to_string()
}

/// An outlet (see the module docs).
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Outlet {
    /// Lower corner of the box (m).
    pub min: Vec<Real>,
    /// Upper corner of the box (m).
    pub max: Vec<Real>,
}

/// One built inlet: the layer's particles at their nominal place, and its timing.
#[derive(Clone, Debug)]
struct InletLayer<V: Vector> {
    particles: Vec<ParticleInit<V>>,
    velocity: V,
    period: Real,
    until: Real,
}

/// The inlets of a simulation, in scene order.
#[derive(Resource, Clone, Debug)]
struct Inlets<V: Vector>(Vec<InletLayer<V>>);

/// Layers added so far, per inlet (kept in checkpoints).
#[derive(Resource, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InletLayers(pub Vec<u64>);

/// The outlet boxes of a simulation.
#[derive(Resource, Clone, Debug)]
struct Outlets<V: Vector>(Vec<(V, V)>);

impl Inlet {
    /// The particles of one layer: the lattice of `spacing` over the box, in `d` dimensions.
    fn layer_size(&self, d: usize) -> Real {
        Inlet::cells(&self.min, &self.max, self.spacing, d)
    }

    /// The cells of the lattice of `spacing` over the box `[min, max]` (see [`lattice`]), on
    /// its first `d` axes.
    pub(crate) fn cells(min: &[Real], max: &[Real], spacing: Real, d: usize) -> Real {
        (0..d.min(min.len()).min(max.len()))
            .map(|k| ((max[k] - min[k]) / spacing).round().max(1.0))
            .product()
    }

    /// |velocity|, the speed of the layers.
    fn speed(&self) -> Real {
        self.velocity.iter().map(|v| v * v).sum::<Real>().sqrt()
    }
}

impl Inlet {
    /// Refuses an inlet whose box holds a particle of the scene at t = 0: its first layer
    /// would be put on top of that particle (two particles at one place, or a layer inside a
    /// wall). The error names the inlet by its box and the body and place of the particle.
    fn refuse_overlap<V: Vector>(&self, world: &mut World, min: V, max: V) -> Result<(), SimError> {
        let Some((id, pos, body)) = settings::first_inside(world, min, max, self.spacing) else {
            return Ok(());
        };
        let name = (world.get_resource::<Bodies>())
            .and_then(|b| b.names().get(usize::from(body)).cloned())
            .unwrap_or_else(|| format!("#{body}"));
        Err(SimError::Build(format!(
            "Inlet (min: {:?}, max: {:?}): its box holds particle {id} of the body `{name}` at \
             {:?} at t = 0, so its first layer would overlap that body; move the box off the \
             body's particles or start the body's generator past it",
            self.min,
            self.max,
            (0..V::DIM).map(|k| pos.get(k)).collect::<Vec<_>>()
        )))
    }
}

impl SimPlugin for Inlet {
    const NAME: &'static str = "Inlet";
    const SUMMARY: &'static str =
        "adds a layer of particles with a given velocity every spacing/|velocity|";

    /// The layers' spacing scales; the box and the velocity stay.
    fn scale_spacing(&mut self, factor: Real) {
        self.spacing *= factor;
    }

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        let d = info.dimension;
        check_box(&self.min, &self.max, d)?;
        if !(info.in_domain(&self.min) && info.in_domain(&self.max)) {
            return Err(format!(
                "min/max: the inlet's box [{:?}, {:?}] is not inside the domain",
                self.min, self.max
            ));
        }
        if self.velocity.len() != d || self.velocity.iter().any(|v| !v.is_finite()) {
            return Err(format!("velocity: expected {d} finite components"));
        }
        if self.velocity.iter().all(|&v| v == 0.0) {
            return Err("velocity: must not be zero (the layers would never leave)".into());
        }
        positive("spacing", self.spacing)?;
        // |v|² and the layer period Δx/|v| must be numbers: an overflowing speed made the
        // period zero, and layers came due without end
        let speed2: Real = self.velocity.iter().map(|v| v * v).sum();
        let period = self.spacing / speed2.sqrt();
        if !(speed2.is_finite() && period.is_finite() && period > 0.0) {
            return Err(format!(
                "velocity: |velocity|² = {speed2:e} and the layer period spacing/|velocity| = \
                 {period:e} must be finite and > 0"
            ));
        }
        let layer = self.layer_size(d);
        if layer > MAX_LAYER_PARTICLES {
            return Err(format!(
                "spacing: a layer over the box would hold about {layer:.3e} particles, more than \
                 {MAX_LAYER_PARTICLES:e}"
            ));
        }
        positive("density", self.density)?;
        positive("h_factor", self.h_factor)?;
        if !self.internal_energy.is_finite() {
            return Err("internal_energy: must be finite".into());
        }
        if self.until.is_some_and(|u| !u.is_finite()) {
            return Err("until: must be finite".into());
        }
        if !info.bodies.contains(&self.body) {
            return Err(format!(
                "body: no body named `{}` (the scene's: {})",
                self.body,
                info.bodies.join(", ")
            ));
        }
        Ok(())
    }

    /// Publishes the inlet's speed (a speed scale the sound speed's `Auto` counts) before any
    /// plugin builds.
    fn prepare<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let speed = self.speed();
        dualsph_fluid::speeds::impose_speed(&mut sim.world, speed, "Inlet (its velocity)");
        Ok(())
    }

    /// A layer every `spacing/|velocity|` up to `until` (or the end), the first at t = 0.
    fn particles_added(&self, end_time: Real, dimension: usize) -> Real {
        let speed = self.speed();
        let last = self.until.map_or(end_time, |u| u.min(end_time)).max(0.0);
        let layers = (last * speed / self.spacing).floor() + 1.0;
        layers * self.layer_size(dimension)
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let bodies = sim.world.resource::<Bodies>();
        let body = bodies
            .index(&self.body)
            .ok_or_else(|| SimError::Build(format!("Inlet.body: no body `{}`", self.body)))?;
        if !bodies.0[body].is_fluid() {
            return Err(SimError::Build(format!(
                "Inlet.body: `{}` is not a fluid body",
                self.body
            )));
        }
        let vector = |v: &[Real]| {
            V::from_slice(v)
                .ok_or_else(|| SimError::Build("Inlet: a vector of the wrong dimension".into()))
        };
        let (min, max, velocity) = (
            vector(&self.min)?,
            vector(&self.max)?,
            vector(&self.velocity)?,
        );
        self.refuse_overlap(&mut sim.world, min, max)?;
        let dx = self.spacing;
        let template = ParticleInit {
            pos: V::zero(),
            vel: velocity,
            mass: self.density * dx.powi(V::DIM as i32),
            density: self.density,
            h: self.h_factor * dx,
            internal_energy: self.internal_energy,
            body: body as u16,
        };
        let points = lattice(min, max, dx);
        let particles = points
            .into_iter()
            .map(|pos| ParticleInit { pos, ..template })
            .collect();
        let layer = InletLayer {
            particles,
            velocity,
            period: dx / velocity.length(),
            until: self.until.unwrap_or(Real::INFINITY),
        };
        sim.enable_population();
        if !sim.has::<Inlets<V>>() {
            sim.world.insert_resource(Inlets::<V>(Vec::new()));
            sim.world.insert_resource(InletLayers::default());
            sim.keep_resource::<InletLayers>("inlet_layers");
            sim.add_system(StepSet::Population, "feed_inlets", feed_inlets::<V>);
        }
        sim.world.resource_mut::<Inlets<V>>().0.push(layer);
        sim.world.resource_mut::<InletLayers>().0.push(0);
        Ok(())
    }
}

/// Asks for every layer due by the start of this step (see the module docs).
#[inline(never)] // a frame of its own in profiles
fn feed_inlets<V: Vector>(
    clock: Res<SimClock>,
    inlets: Res<Inlets<V>>,
    mut done: ResMut<InletLayers>,
    mut population: ResMut<Population<V>>,
) {
    for (inlet, done) in inlets.0.iter().zip(done.0.iter_mut()) {
        loop {
            let t_k = *done as Real * inlet.period;
            if t_k > clock.t || t_k > inlet.until {
                break;
            }
            let shift = inlet.velocity * (clock.t - t_k);
            for p in &inlet.particles {
                population.spawn(ParticleInit {
                    pos: p.pos + shift,
                    ..*p
                });
            }
            *done += 1;
        }
    }
}

impl SimPlugin for Outlet {
    const NAME: &'static str = "Outlet";
    const SUMMARY: &'static str = "removes the fluid particles inside a box";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        check_box(&self.min, &self.max, info.dimension)
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let vector = |v: &[Real]| {
            V::from_slice(v)
                .ok_or_else(|| SimError::Build("Outlet: a vector of the wrong dimension".into()))
        };
        let b = (vector(&self.min)?, vector(&self.max)?);
        sim.enable_population();
        if !sim.has::<Outlets<V>>() {
            sim.world.insert_resource(Outlets::<V>(Vec::new()));
            sim.add_system(StepSet::Population, "drain_outlets", drain_outlets::<V>);
        }
        sim.world.resource_mut::<Outlets<V>>().0.push(b);
        Ok(())
    }
}

/// True when `x` is inside the box `[lo, hi]` (faces included).
fn inside<V: Vector>(x: V, (lo, hi): &(V, V)) -> bool {
    (0..V::DIM).all(|k| x.get(k) >= lo.get(k) && x.get(k) <= hi.get(k))
}

/// Asks for the removal of every fluid particle inside an outlet box.
#[inline(never)] // a frame of its own in profiles
fn drain_outlets<V: Vector>(
    outlets: Res<Outlets<V>>,
    bodies: Res<Bodies>,
    mut population: ResMut<Population<V>>,
    q: Query<(Entity, &Position<V>, &BodyId)>,
) {
    for (e, r, b) in &q {
        let fluid = bodies.0.get(b.0 as usize).is_some_and(|b| b.is_fluid());
        if fluid && outlets.0.iter().any(|o| inside(r.0, o)) {
            population.remove(e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inlet(until: Option<Real>) -> Inlet {
        Inlet {
            min: vec![0.0, 0.0],
            max: vec![0.1, 0.4],
            spacing: 0.1,
            velocity: vec![0.6, 0.8],
            density: 1000.0,
            h_factor: 2.0,
            internal_energy: 0.0,
            body: "fluid".into(),
            until,
        }
    }

    #[test]
    fn the_particles_an_inlet_adds_are_its_layers_over_the_run() {
        // 4 per layer (the lattice over the box), one every 0.1/|(0.6, 0.8)| = 0.1 s from t = 0
        assert_eq!(
            lattice(glam::DVec2::ZERO, glam::DVec2::new(0.1, 0.4), 0.1).len(),
            4
        );
        assert_eq!(SimPlugin::particles_added(&inlet(None), 1.0, 2), 11.0 * 4.0);
        assert_eq!(
            SimPlugin::particles_added(&inlet(Some(0.45)), 1.0, 2),
            5.0 * 4.0
        );
        assert_eq!(SimPlugin::particles_added(&inlet(Some(3.0)), 0.05, 2), 4.0);
    }
}
