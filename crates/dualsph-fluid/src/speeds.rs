//! The speeds a scene implies beyond its particles' own (an inlet's), published by the plugins
//! that impose them, and the mark a liquid leaves when its sound speed was derived from the
//! speeds known when it was built (`TaitEos(c0: Auto(..))`): a speed imposed after that would
//! not have been counted, so the plugin imposing it refuses, naming the order to list them in.

use bevy_ecs::prelude::{Resource, World};
use dualsph_core::math::Real;
use dualsph_core::sim::SimError;

/// Speeds imposed by plugins, each with what imposes it (`"Inlet: its velocity"`).
#[derive(Resource, Debug, Default, Clone)]
pub struct SpeedScales(pub Vec<(Real, String)>);

/// Present when a liquid's sound speed was derived from the speeds then known; holds the
/// plugin that derived it.
#[derive(Resource, Debug, Clone)]
pub struct SoundSpeedDerived(pub &'static str);

/// Publishes the speed `speed` that `what` imposes; an error when a sound speed was already
/// derived without it (the plugin must be listed before the one that derives it).
pub fn impose_speed(world: &mut World, speed: Real, what: &str) -> Result<(), SimError> {
    refuse_after_derived(world, what)?;
    world
        .get_resource_or_insert_with(SpeedScales::default)
        .0
        .push((speed, what.to_string()));
    Ok(())
}

/// An error naming the order when `what` (a plugin that sets a speed scale: gravity, an inlet)
/// is built after a liquid derived its sound speed without it.
pub fn refuse_after_derived(world: &World, what: &str) -> Result<(), SimError> {
    match world.get_resource::<SoundSpeedDerived>() {
        Some(d) => Err(SimError::Build(format!(
            "{what}: list it before {}, whose c0: Auto(..) is derived from the speeds the \
             plugins before it impose",
            d.0
        ))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_speed_imposed_after_a_derived_sound_speed_is_refused_naming_the_order() {
        let mut w = World::new();
        impose_speed(&mut w, 2.0, "Inlet").unwrap();
        assert_eq!(
            w.resource::<SpeedScales>().0,
            vec![(2.0, "Inlet".to_string())]
        );
        w.insert_resource(SoundSpeedDerived("TaitEos"));
        let e = impose_speed(&mut w, 3.0, "Inlet").unwrap_err().to_string();
        assert!(e.contains("Inlet: list it before TaitEos"), "{e}");
        assert_eq!(w.resource::<SpeedScales>().0.len(), 1);
    }
}
