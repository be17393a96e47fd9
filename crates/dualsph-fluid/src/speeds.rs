//! The speeds a scene implies beyond its particles' own (an inlet's), published by the plugins
//! that impose them while the simulation is prepared (`SimPlugin::prepare`, before any plugin
//! builds), so that a sound speed derived from them (`TaitEos(c0: Auto(..))`) counts them
//! whatever the order of the plugin list.

use bevy_ecs::prelude::{Resource, World};
use dualsph_core::math::Real;

/// Speeds imposed by plugins, each with what imposes it (`"Inlet: its velocity"`).
#[derive(Resource, Debug, Default, Clone)]
pub struct SpeedScales(pub Vec<(Real, String)>);

/// Publishes the speed `speed` that `what` imposes.
pub fn impose_speed(world: &mut World, speed: Real, what: &str) {
    world
        .get_resource_or_insert_with(SpeedScales::default)
        .0
        .push((speed, what.to_string()));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imposed_speeds_are_kept_with_what_imposes_them() {
        let mut w = World::new();
        impose_speed(&mut w, 2.0, "Inlet");
        impose_speed(&mut w, 3.0, "Inlet");
        assert_eq!(
            w.resource::<SpeedScales>().0,
            vec![(2.0, "Inlet".to_string()), (3.0, "Inlet".to_string())]
        );
    }
}
