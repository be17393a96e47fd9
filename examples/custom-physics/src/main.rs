//! The whole `dualsph` command line with this crate's plugins registered beside the built-in
//! ones: `custom-physics run|check|plan|plugins …`, `--resume` included.

fn main() -> std::process::ExitCode {
    let mut registry = dualsph::default_registry();
    registry.register::<custom_physics::PairDrag>();
    registry.register::<custom_physics::LinearEos>();
    dualsph::cli::main(registry)
}
