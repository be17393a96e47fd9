//! Plugins and the registry that maps the names used in RON scenes to plugin constructors.
//!
//! A plugin is a settings struct that deserializes from the scene (`Gravity(g: [0.0, -9.81])`)
//! and builds its components, systems and pair terms into a [`Sim`]. Plugins from outside the
//! engine register exactly like the built-in ones: `registry.register::<MyPlugin>()`.
//! Settings a plugin crate owns that a scene gives as a section of its own (`integrator:`,
//! `health:`) register with `registry.register_section::<Settings>()` (see [`section`]), and
//! the kinds of body a scene may name (`kind: Fixed`) with
//! `registry.register_body_kind::<Kind>()` (see [`crate::bodies::kind`]).

pub mod fields;
pub mod section;

use crate::bodies::{BodyKind, BodyKindEntry};
use crate::math::{Real, Vec1, Vector};
use crate::sim::{Sim, SimError};
use glam::{DVec2, DVec3};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::any::Any;
use std::fmt::Debug;

pub use section::{SceneSection, SectionConfig, SectionEntry, SectionProblem};

/// What a plugin may check about the scene it is used in.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneInfo {
    /// Spatial dimension of the scene (1, 2 or 3).
    pub dimension: usize,
    /// The names of the scene's bodies, in order (see [`crate::bodies`]).
    pub bodies: Vec<String>,
    /// The domain box's lower and upper corners (`dimension` components each).
    pub domain: (Vec<Real>, Vec<Real>),
    /// The scene's `max_steps`, the most steps the run takes when it sets one.
    pub max_steps: Option<u64>,
}

impl SceneInfo {
    /// A scene of `dimension` with the one default body and an unbounded domain.
    pub fn of_dimension(dimension: usize) -> Self {
        SceneInfo {
            dimension,
            bodies: vec![crate::bodies::DEFAULT_BODY.to_string()],
            domain: (
                vec![Real::NEG_INFINITY; dimension],
                vec![Real::INFINITY; dimension],
            ),
            max_steps: None,
        }
    }

    /// True when the point `x` lies in the domain box (faces included) on the axes it has
    /// (a point with fewer components than the dimension is checked on the first ones).
    pub fn in_domain(&self, x: &[Real]) -> bool {
        let (lo, hi) = &self.domain;
        x.iter()
            .zip(lo.iter().zip(hi))
            .all(|(&v, (&l, &h))| v >= l && v <= h)
    }

    /// `Ok` when the scene has a body named `name`, else the message plugins' `validate`
    /// gives for it: the field, then ``no body named `name`; the scene's bodies are …``.
    pub fn check_body(&self, field: &str, name: &str) -> Result<(), String> {
        if self.bodies.iter().any(|b| b == name) {
            return Ok(());
        }
        Err(format!(
            "{field}: no body named `{name}`; the scene's bodies are {}",
            self.bodies.join(", ")
        ))
    }
}

/// `Ok` when `x` is a finite number > 0, else the message plugins' `validate` gives for it:
/// `"<field>: must be positive, got <x>"`.
pub fn positive(field: &str, x: Real) -> Result<(), String> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(format!("{field}: must be positive, got {x}"))
    }
}

/// The part a plugin plays in a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// Physics (or anything else): any number per scene, built in the order listed.
    Physics,
    /// The time integration (`dualsph_integrate::Scheme`): one per scene; a scene that names
    /// none gets the default (`LeapfrogPC`), two are an error naming both.
    Integrator,
    /// The diagnostics: one per scene; a scene that names none gets the default.
    Diagnostics,
}

/// A plugin: its settings (deserialized from the scene; serialized for the scene's canonical
/// form, see [`PluginConfig::canonical`]) and how it builds itself.
///
/// The settings' JSON schema ([`schemars::JsonSchema`], derived beside `Deserialize` so that
/// it follows the same serde attributes) is what `dualsph doc NAME` prints: each field's type,
/// default and doc comment.
pub trait SimPlugin:
    Serialize + DeserializeOwned + schemars::JsonSchema + Debug + Send + Sync + 'static
{
    /// The name used in RON scenes.
    const NAME: &'static str;
    /// One line for listings and error messages.
    const SUMMARY: &'static str;
    /// Its part in a scene (physics unless it says otherwise).
    const ROLE: Role = Role::Physics;
    /// Rejects physically meaningless settings; the message names the field.
    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        Ok(())
    }
    /// Publishes what other plugins read while they build — a resource such as gravity's
    /// acceleration or an inlet's speed scale, never a system or a column. Run for every
    /// plugin of a scene before any plugin is built (bevy's `Plugin::build`/`finish` pair is
    /// the pattern), so that a plugin reading it at build time does not depend on the order
    /// of the scene's plugin list. Nothing by default.
    fn prepare<V: Vector>(&self, _sim: &mut Sim<V>) -> Result<(), SimError> {
        Ok(())
    }
    /// Adds the plugin's components, systems and pair terms.
    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError>;
    /// At most how many particles the plugin adds over a run to `end_time` in `dimension`
    /// (an inlet's layers), for the memory estimate `check` and `run` make before the run;
    /// none by default.
    fn particles_added(&self, _end_time: Real, _dimension: usize) -> Real {
        0.0
    }
    /// Multiplies the settings that follow the resolution (particle sizes, and lengths
    /// counted in them, such as a refinement band) by `factor`, so that the scene keeps its
    /// meaning when every generator's spacing is multiplied by `factor` (a convergence study
    /// runs one scene at several resolutions); lengths of the geometry stay. Nothing by
    /// default.
    fn scale_spacing(&mut self, _factor: Real) {}
}

/// A parsed plugin, with its type erased so scenes can hold a list of different plugins.
pub trait PluginConfig: Debug + Send + Sync {
    /// The registered name.
    fn name(&self) -> &'static str;
    /// See [`SimPlugin::ROLE`].
    fn role(&self) -> Role;
    /// See [`SimPlugin::validate`].
    fn validate(&self, info: &SceneInfo) -> Result<(), String>;
    /// See [`SimPlugin::particles_added`].
    fn particles_added(&self, end_time: Real, dimension: usize) -> Real;
    /// Builds into a simulation of any dimension.
    fn build_dyn(&self, sim: &mut dyn Any) -> Result<(), SimError>;
    /// Prepares (see [`SimPlugin::prepare`]) a simulation of any dimension.
    fn prepare_dyn(&self, sim: &mut dyn Any) -> Result<(), SimError>;
    /// The settings in a canonical form: the name, then the settings as they were resolved
    /// (defaults filled in) in postcard's encoding. Two spellings of the same settings (field
    /// order, whitespace, comments, a default written out or left out) give the same bytes; it
    /// does not depend on `Debug`.
    fn canonical(&self) -> Vec<u8>;
    /// See [`SimPlugin::scale_spacing`].
    fn scale_spacing(&mut self, factor: Real);
}

impl<P: SimPlugin> PluginConfig for P {
    fn name(&self) -> &'static str {
        P::NAME
    }
    fn role(&self) -> Role {
        P::ROLE
    }
    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        SimPlugin::validate(self, info)
    }
    fn particles_added(&self, end_time: Real, dimension: usize) -> Real {
        SimPlugin::particles_added(self, end_time, dimension)
    }
    fn scale_spacing(&mut self, factor: Real) {
        SimPlugin::scale_spacing(self, factor)
    }
    fn canonical(&self) -> Vec<u8> {
        let mut bytes = P::NAME.as_bytes().to_vec();
        bytes.push(0);
        // postcard fails only on what it cannot encode (a sequence of unknown length); such
        // settings fall back to their `Debug` text, still one form per value
        postcard::to_extend(self, bytes.clone()).unwrap_or_else(|_| {
            bytes.extend(format!("{self:?}").into_bytes());
            bytes
        })
    }
    fn build_dyn(&self, sim: &mut dyn Any) -> Result<(), SimError> {
        with_sim(
            sim,
            P::NAME,
            |s| self.build(s),
            |s| self.build(s),
            |s| self.build(s),
        )
    }
    fn prepare_dyn(&self, sim: &mut dyn Any) -> Result<(), SimError> {
        with_sim(
            sim,
            P::NAME,
            |s| self.prepare(s),
            |s| self.prepare(s),
            |s| self.prepare(s),
        )
    }
}

/// `f1`, `f2` or `f3` on `sim` as the simulation of its dimension; an error naming `name`
/// for any other type.
fn with_sim(
    sim: &mut dyn Any,
    name: &str,
    f1: impl FnOnce(&mut Sim<Vec1>) -> Result<(), SimError>,
    f2: impl FnOnce(&mut Sim<DVec2>) -> Result<(), SimError>,
    f3: impl FnOnce(&mut Sim<DVec3>) -> Result<(), SimError>,
) -> Result<(), SimError> {
    if let Some(s) = sim.downcast_mut::<Sim<Vec1>>() {
        return f1(s);
    }
    if let Some(s) = sim.downcast_mut::<Sim<DVec2>>() {
        return f2(s);
    }
    if let Some(s) = sim.downcast_mut::<Sim<DVec3>>() {
        return f3(s);
    }
    Err(SimError::Build(format!(
        "{name}: unsupported simulation type"
    )))
}

impl dyn PluginConfig + '_ {
    /// Builds into `sim`.
    pub fn build_into<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        self.build_dyn(sim as &mut dyn Any)
    }

    /// Prepares `sim` (see [`SimPlugin::prepare`]).
    pub fn prepare_into<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        self.prepare_dyn(sim as &mut dyn Any)
    }
}

/// Parses a plugin's settings from their RON text, `(field: value, ...)`, with the scene's
/// options. Text, not a type-erased deserializer: RON hands a bare word (`quantity: density`)
/// to serde's buffering types by name only when it sees their concrete type, which erasure
/// hides, so a plugin is parsed by RON itself.
pub type ParseFn =
    fn(&ron::Options, &str) -> Result<Box<dyn PluginConfig>, ron::error::SpannedError>;

/// One registered plugin.
#[derive(Clone, Copy)]
pub struct PluginEntry {
    /// The RON name.
    pub name: &'static str,
    /// One-line description.
    pub summary: &'static str,
    /// Its part in a scene.
    pub role: Role,
    /// Settings parser.
    pub parse: ParseFn,
    /// The settings' schema (fields, types, defaults, doc comments).
    pub schema: fn() -> schemars::Schema,
}

impl Debug for PluginEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PluginEntry({})", self.name)
    }
}

fn parse_plugin<P: SimPlugin>(
    options: &ron::Options,
    text: &str,
) -> Result<Box<dyn PluginConfig>, ron::error::SpannedError> {
    let p: P = options.from_str(text)?;
    Ok(Box::new(p))
}

/// Name → constructor map for plugins and for body kinds, and key → parser map for the scene
/// sections plugin crates own.
#[derive(Clone, Debug, Default)]
pub struct Registry {
    entries: Vec<PluginEntry>,
    sections: Vec<SectionEntry>,
    kinds: Vec<BodyKindEntry>,
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers `P` under `P::NAME` (a later registration of the same name replaces it).
    pub fn register<P: SimPlugin>(&mut self) -> &mut Self {
        self.entries.retain(|e| e.name != P::NAME);
        self.entries.push(PluginEntry {
            name: P::NAME,
            summary: P::SUMMARY,
            role: P::ROLE,
            parse: parse_plugin::<P>,
            schema: fields::schema_of::<P>,
        });
        self
    }

    /// The entry registered under `name`.
    pub fn get(&self, name: &str) -> Option<&PluginEntry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// Registered names in registration order.
    pub fn names(&self) -> Vec<&'static str> {
        self.entries.iter().map(|e| e.name).collect()
    }

    /// All entries.
    pub fn entries(&self) -> &[PluginEntry] {
        &self.entries
    }

    /// Registers the scene section `S` under `S::KEY` (a later registration of the same key
    /// replaces it).
    pub fn register_section<S: SceneSection>(&mut self) -> &mut Self {
        self.sections.retain(|e| e.key != S::KEY);
        self.sections.push(SectionEntry {
            key: S::KEY,
            parse: section::parse_section::<S>,
            schema: fields::schema_of::<S>,
        });
        self
    }

    /// The registered sections, in registration order.
    pub fn sections(&self) -> &[SectionEntry] {
        &self.sections
    }

    /// The section registered under `key`.
    pub fn section(&self, key: &str) -> Option<&SectionEntry> {
        self.sections.iter().find(|e| e.key == key)
    }

    /// Registers the body kind `K` under `K::NAME` (a later registration of the same name
    /// replaces it).
    pub fn register_body_kind<K: BodyKind>(&mut self) -> &mut Self {
        self.kinds.retain(|e| e.name != K::NAME);
        self.kinds.push(BodyKindEntry::of::<K>());
        self
    }

    /// The body kind registered under `name`.
    pub fn body_kind(&self, name: &str) -> Option<&BodyKindEntry> {
        self.kinds.iter().find(|e| e.name == name)
    }

    /// The registered body kinds, in registration order.
    pub fn body_kinds(&self) -> &[BodyKindEntry] {
        &self.kinds
    }
}

impl<V: Vector> Sim<V> {
    /// Builds `plugin` into the simulation, its systems marked as its own (for the order
    /// constraints' names and messages).
    pub fn build_plugin(&mut self, plugin: &dyn PluginConfig) -> Result<(), SimError> {
        self.as_plugin(plugin.name(), |sim| plugin.build_into(sim))
    }

    /// Runs `plugin`'s [`SimPlugin::prepare`] on the simulation.
    pub fn prepare_plugin(&mut self, plugin: &dyn PluginConfig) -> Result<(), SimError> {
        self.as_plugin(plugin.name(), |sim| plugin.prepare_into(sim))
    }
}
