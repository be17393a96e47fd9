//! A headless run: load a scene, build the `Sim` in the scene's dimension, step it through the engine's run loop and print
//! the conservation diagnostics.
//!
//! ```sh
//! cargo run --release --example headless -- scenes/drop_3d.ron 200
//! ```

use dualsph::prelude::*;
use dualsph::run_loop::{EveryStep, Flow, run_to_end};
use dualsph::runner::RunError;
use dualsph::{build_sim, default_registry, scene::Scene, with_dimension};

fn run<V: Vector>(scene: &Scene, steps: u64) -> Result<(), RunError> {
    let mut sim = build_sim::<V>(scene)?;
    sim.initialize()?; // rates at t = 0
    let d0 = sim.diagnostics();
    // the engine's run loop, to the scene's end or `steps` steps, whichever comes first
    let mut limit = EveryStep(|sim: &mut Sim<V>| {
        Ok(if sim.clock().step >= steps {
            Flow::Stop
        } else {
            Flow::Continue
        })
    });
    run_to_end(&mut sim, &mut [&mut limit])?;
    let d = sim.diagnostics();
    println!("{} particles, {} steps, t = {:.4e} s", d.n, d.step, d.t);
    println!("momentum  {:?} → {:?}", d0.momentum, d.momentum);
    println!(
        "angular   {:?} → {:?}",
        d0.angular_momentum, d.angular_momentum
    );
    println!("E_total   {:.6e} → {:.6e}", d0.e_tot, d.e_tot);
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| "scenes/drop_2d.ron".into());
    let steps: u64 = args.next().map_or(Ok(100), |s| s.parse())?;
    let scene = Scene::load(path.as_ref(), &default_registry())?;
    with_dimension!(scene.dimension, V => run::<V>(&scene, steps))?;
    Ok(())
}
