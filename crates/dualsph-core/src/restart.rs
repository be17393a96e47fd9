//! Plugin state outside the particle columns that a resumed run needs: resources a plugin
//! declares with [`Sim::keep_resource`], kept in checkpoints as the exact bytes of their
//! serde encoding ([`postcard`]: reals as their 8 IEEE bytes, so they round-trip bit for bit).
//!
//! A per-particle quantity is a column ([`crate::columns`]); this is for the few values a
//! plugin carries from step to step (an inlet's count of emitted layers, a controller's
//! integral), without which a resumed run would not continue bitwise.

use crate::math::Vector;
use crate::sim::Sim;
use bevy_ecs::prelude::*;
use serde::Serialize;
use serde::de::DeserializeOwned;

/// One kept resource, its type erased.
#[derive(Clone, Copy, Debug)]
pub struct KeptResource {
    /// The key in checkpoints (given by the plugin).
    pub key: &'static str,
    save: fn(&World) -> Option<Vec<u8>>,
    load: fn(&mut World, &[u8]) -> Result<(), String>,
}

impl KeptResource {
    /// The resource's bytes, `None` when the world does not hold it.
    pub fn save(&self, world: &World) -> Option<Vec<u8>> {
        (self.save)(world)
    }

    /// Puts the resource back from its bytes; the error says that they do not decode.
    pub fn load(&self, world: &mut World, bytes: &[u8]) -> Result<(), String> {
        (self.load)(world, bytes)
    }
}

/// The kept resources of a simulation, in the order they were declared.
#[derive(Resource, Clone, Debug, Default)]
pub struct KeptResources(pub Vec<KeptResource>);

fn save<R: Resource + Serialize>(world: &World) -> Option<Vec<u8>> {
    // encoding into memory cannot fail for the plain data a resource holds
    world
        .get_resource::<R>()
        .and_then(|r| postcard::to_stdvec(r).ok())
}

fn load<R: Resource + DeserializeOwned>(world: &mut World, bytes: &[u8]) -> Result<(), String> {
    let r: R = postcard::from_bytes(bytes).map_err(|e| e.to_string())?;
    world.insert_resource(r);
    Ok(())
}

impl<V: Vector> Sim<V> {
    /// Keeps resource `R` in checkpoints under `key` (declaring it again does nothing).
    pub fn keep_resource<R: Resource + Serialize + DeserializeOwned>(&mut self, key: &'static str) {
        let mut kept = self.world.get_resource_or_init::<KeptResources>();
        if kept.0.iter().all(|k| k.key != key) {
            kept.0.push(KeptResource {
                key,
                save: save::<R>,
                load: load::<R>,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Resource, Serialize, Deserialize, Debug, PartialEq)]
    struct Count(u64, f64);

    #[test]
    fn a_kept_resource_round_trips_bit_for_bit() {
        let mut world = World::new();
        world.insert_resource(Count(7, 0.1 + 0.2));
        let kept = KeptResource {
            key: "count",
            save: save::<Count>,
            load: load::<Count>,
        };
        let bytes = kept.save(&world).unwrap();
        let mut other = World::new();
        kept.load(&mut other, &bytes).unwrap();
        assert_eq!(other.resource::<Count>(), &Count(7, 0.1 + 0.2));
        assert!(kept.load(&mut other, &bytes[..1]).is_err());
        assert_eq!(kept.save(&World::new()), None);
    }
}
