//! Investigation aid: steps a scene, every K steps prints the closest pair relative to the
//! owner's h, the most negative pressure and the density range; at the first health problem
//! dumps the offending particle and its support.
//!
//! ```sh
//! cargo run --release --features dev-tools --example blowup_probe -- SCENE K
//! ```
use dualsph::core::neighbours::Neighbours;
use dualsph::diagnostics::Health;
use dualsph::prelude::*;
use dualsph::run_loop::{EveryStep, Flow, run_to_end};
use dualsph::runner::RunError;
use dualsph::{build_sim, default_registry, scene::Scene, with_dimension};

/// The particles' positions, densities, h and pressures (0 without an equation of state).
struct View<V: Vector> {
    pos: Vec<V>,
    vel: Vec<V>,
    rho: Vec<Real>,
    h: Vec<Real>,
    mass: Vec<Real>,
    pressure: Vec<Real>,
}

fn view<V: Vector>(sim: &Sim<V>) -> View<V> {
    let d = ParticleData::<V>::of(&sim.world).expect("particles");
    let p = d.column::<Pressure>();
    View {
        pos: d.pos.iter().map(|x| x.0).collect(),
        vel: d.vel.iter().map(|x| x.0).collect(),
        rho: d.rho.iter().map(|x| x.0).collect(),
        h: d.h.iter().map(|x| x.0).collect(),
        mass: d.mass.iter().map(|x| x.0).collect(),
        pressure: (0..d.len()).map(|i| p.map_or(0.0, |p| p[i].0)).collect(),
    }
}

fn summary<V: Vector>(sim: &Sim<V>) -> String {
    let f = view(sim);
    let nb = sim.world.resource::<Neighbours<V>>();
    let (mut qmin, mut qi, mut qj) = (Real::INFINITY, 0, 0);
    for i in 0..f.pos.len() {
        for &j in nb.support.row(i) {
            let j = j as usize;
            let q = (f.pos[i] - f.pos[j]).length() / f.h[i];
            if q < qmin {
                (qmin, qi, qj) = (q, i, j);
            }
        }
    }
    let (mut pmin, mut pi) = (Real::INFINITY, 0);
    for i in 0..f.pos.len() {
        if f.pressure[i] < pmin {
            (pmin, pi) = (f.pressure[i], i);
        }
    }
    let rmin = f.rho.iter().cloned().fold(Real::INFINITY, Real::min);
    let rmax = f.rho.iter().cloned().fold(0.0, Real::max);
    format!(
        "closest r/h_i {qmin:.3} ({qi},{qj}; h {:.4} {:.4}; p {:.2e} {:.2e}; x {:.3} {:.3}) pmin {pmin:.3e} @{pi} (h {:.4}) rho [{rmin:.2}, {rmax:.2}]",
        f.h[qi],
        f.h[qj],
        f.pressure[qi],
        f.pressure[qj],
        f.pos[qi].get(0),
        f.pos[qi].get(1),
        f.h[pi]
    )
}

fn dump<V: Vector>(sim: &Sim<V>, i: usize) {
    let f = view(sim);
    let nb = sim.world.resource::<Neighbours<V>>();
    println!(
        "particle {i}: x {:?} v {:?} rho {:.3} p {:.3e} h {:.4} m {:.3e}",
        f.pos[i].to_xyz(),
        f.vel[i].to_xyz(),
        f.rho[i],
        f.pressure[i],
        f.h[i],
        f.mass[i]
    );
    let mut rows: Vec<usize> = nb.support.row(i).iter().map(|&j| j as usize).collect();
    rows.sort_by(|&a, &b| {
        (f.pos[a] - f.pos[i])
            .length()
            .total_cmp(&(f.pos[b] - f.pos[i]).length())
    });
    for j in rows.into_iter().take(12) {
        println!(
            "  j {j}: r/h_i {:.3} rho {:.3} p {:.3e} h {:.4} v {:?}",
            (f.pos[j] - f.pos[i]).length() / f.h[i],
            f.rho[j],
            f.pressure[j],
            f.h[j],
            f.vel[j].to_xyz()
        );
    }
}

fn run<V: Vector>(scene: &Scene, every: u64) -> Result<(), RunError> {
    let mut sim = build_sim::<V>(scene)?;
    sim.initialize()?;
    let mut report = EveryStep(|sim: &mut Sim<V>| {
        let c = sim.clock();
        if c.step.is_multiple_of(every) {
            println!(
                "step {} t {:.5e} dt {:.3e}: {}",
                c.step,
                c.t,
                c.dt,
                summary(sim)
            );
        }
        Ok(Flow::Continue)
    });
    match run_to_end(&mut sim, &mut [&mut report]) {
        Err(RunError::Sim(e)) => {
            println!("{e}");
            if let Some((id, _, _)) = sim.world.resource::<Health>().problem {
                println!("{}", summary(&sim));
                dump(&sim, id as usize);
            }
            return Ok(());
        }
        Err(e) => return Err(e),
        Ok(_) => {}
    }
    let d = sim.diagnostics();
    println!(
        "reached t = {:.5e}, step {}; P {:?} L {:?}",
        d.t, d.step, d.momentum, d.angular_momentum
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap();
    let every: u64 = args.next().map_or(Ok(200), |s| s.parse())?;
    let scene = Scene::load(path.as_ref(), &default_registry())?;
    with_dimension!(scene.dimension, V => run::<V>(&scene, every))?;
    Ok(())
}
