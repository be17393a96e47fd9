//! How far density and h stray from their ranges at initialisation over a whole run: the
//! factors the sane-range blow-up check (`health` section) must allow for a scene.
//!
//! ```sh
//! cargo run --release --features dev-tools --example health_extremes -- scenes/sod_1d.ron scenes/hard/*.ron
//! ```
//!
//! Prints per scene the factors by which density and h went below their initial minimum
//! (`ρ_min0/min ρ`) and above their initial maximum (`max ρ/ρ_max0`), over every step to the
//! end time (or to the first non-finite/non-positive value or escape).

use dualsph::diagnostics::{Health, HealthBounds, InitialDensity};
use dualsph::prelude::*;
use dualsph::run_loop::{EveryStep, Flow, run_to_end};
use dualsph::runner::RunError;
use dualsph::{build_sim, default_registry, scene::Scene, with_dimension};

fn extremes<V: Vector>(sim: &mut Sim<V>) -> ((Real, Real), (Real, Real)) {
    let world = &mut sim.world;
    let mut q = world.query::<(&Density, &SmoothingLength)>();
    let mut r: ((Real, Real), (Real, Real)) = ((Real::INFINITY, 0.0), (Real::INFINITY, 0.0));
    for (rho, h) in q.iter(world) {
        r.0 = (r.0.0.min(rho.0), r.0.1.max(rho.0));
        r.1 = (r.1.0.min(h.0), r.1.1.max(h.0));
    }
    r
}

fn run<V: Vector>(scene: &Scene) -> Result<String, RunError> {
    let mut sim = build_sim::<V>(scene)?;
    {
        let mut b = sim.world.resource_mut::<HealthBounds>();
        let inf = (Real::INFINITY, Real::INFINITY);
        (b.density, b.h) = (inf, inf);
    }
    sim.initialize()?;
    let rho0 = {
        let init = dualsph::core::store::column::<InitialDensity>(&sim.world).unwrap_or(&[]);
        init.iter()
            .map(|r| r.0)
            .fold((Real::INFINITY, 0.0 as Real), |r, x| {
                (r.0.min(x), r.1.max(x))
            })
    };
    let h0 = extremes(&mut sim).1;
    // [ρ below, ρ above, h below, h above]: the factor beyond the initial range reached
    let mut f = [1.0 as Real; 4];
    let mut at = [0.0 as Real; 4];
    let mut track = EveryStep(|sim: &mut Sim<V>| {
        let (rho, h) = extremes(sim);
        let now = [rho0.0 / rho.0, rho.1 / rho0.1, h0.0 / h.0, h.1 / h0.1];
        for k in 0..4 {
            if now[k] > f[k] {
                (f[k], at[k]) = (now[k], sim.clock().t);
            }
        }
        Ok(Flow::Continue)
    });
    let stop = match run_to_end(&mut sim, &mut [&mut track]) {
        Ok(_) => String::new(),
        Err(e) => match sim.world.resource::<Health>().problem {
            Some((id, what, v)) => format!(
                " STOPPED at t = {:.4e}: particle {id} {what} = {v:e}",
                sim.clock().t
            ),
            None => return Err(e),
        },
    };
    Ok(format!(
        "ρ0 [{:.4e}, {:.4e}] below ×{:.4} (t {:.3e}) above ×{:.4} (t {:.3e}); h0 [{:.4e}, {:.4e}] below ×{:.4} (t {:.3e}) above ×{:.4} (t {:.3e}); t_end {:.4e}{stop}",
        rho0.0,
        rho0.1,
        f[0],
        at[0],
        f[1],
        at[1],
        h0.0,
        h0.1,
        f[2],
        at[2],
        f[3],
        at[3],
        sim.clock().t
    ))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for path in std::env::args().skip(1) {
        let scene = Scene::load(path.as_ref(), &default_registry())?;
        let line = with_dimension!(scene.dimension, V => run::<V>(&scene))?;
        println!("{path}: {line}");
    }
    Ok(())
}
