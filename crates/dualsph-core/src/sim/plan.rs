//! What a scene will run ([`Plan`]): the systems in order with the plugin that added each and
//! the particle columns (the pair sweeps list their terms themselves).

use super::Sim;
use super::StepSet;
use crate::columns::Columns;
use crate::math::Vector;

/// What a scene will run: the systems in order and the particle components.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// `(set, label, plugin)` in execution order; the plugin that added the system (`core`
    /// for the engine's own).
    pub systems: Vec<(StepSet, String, String)>,
    /// The particles' columns in registration order: type, name, output labels, whether
    /// checkpointed.
    pub components: Vec<String>,
}

impl<V: Vector> Sim<V> {
    /// The systems in execution order and the particle components.
    pub fn plan(&mut self) -> Plan {
        let order = self
            .ordered()
            .unwrap_or_else(|_| (0..self.systems.len()).collect());
        let systems = order
            .into_iter()
            .map(|k| {
                let place = &self.systems[k].place;
                (
                    self.systems[k].set,
                    place.label.clone(),
                    place.plugin.clone(),
                )
            })
            .collect();
        let components = std::iter::once("ParticleId (id)".to_string())
            .chain(self.world.resource::<Columns>().iter().map(|c| {
                let output = if c.spec.output {
                    format!("output {}", c.labels(V::DIM).join(","))
                } else {
                    "not output".into()
                };
                let restart = if c.spec.restart {
                    "checkpointed"
                } else {
                    "scratch"
                };
                format!("{} ({}: {output}; {restart})", c.type_name, c.spec.name)
            }))
            .collect();
        Plan {
            systems,
            components,
        }
    }
}
