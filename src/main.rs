//! The `dualsph` command with the built-in plugins (see `dualsph::cli`).

fn main() -> std::process::ExitCode {
    dualsph::cli::main(dualsph::default_registry())
}
