//! Feeds arbitrary bytes to the scene parser, the validator and (through the registry) the
//! plugins' settings parsers: whatever the input, the result must be `Ok` or a `SceneError`,
//! never a panic, an abort or an allocation that exhausts memory.

#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::OnceLock;

fn registry() -> &'static dualsph::core::plugin::Registry {
    static REGISTRY: OnceLock<dualsph::core::plugin::Registry> = OnceLock::new();
    REGISTRY.get_or_init(dualsph::default_registry)
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let path = Path::new("fuzz.ron");
    match dualsph::scene::Scene::from_str(text, path, registry()) {
        Ok(scene) => assert!((1..=3).contains(&scene.dimension)),
        Err(e) => {
            // every error renders as one message naming the file
            let msg = e.to_string();
            assert!(msg.starts_with("fuzz.ron"), "message without the file: {msg}");
        }
    }
});
