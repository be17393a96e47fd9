use super::*;
use crate::build_sim;
use dualsph_core::glam::DVec2;
use dualsph_scene::Scene;
use std::path::Path;

/// A water column 0.2 m × 0.2 m in a 0.5 m box (Δx = 0.02 m), to `end_time`, with the time
/// step `dt` and `max_steps` as given.
fn column(end_time: f64, dt: &str, max_steps: &str) -> Sim<DVec2> {
    let text = format!(
        "Scene(name: \"column\", dimension: 2, kernel: WendlandC2,
           domain: (min: [0.0, 0.0], max: [0.5, 0.5]),
           particles: [Block(min: [0.0, 0.0], max: [0.2, 0.2], spacing: 0.02, lattice: Square,
                             density: 1000.0, h_factor: 3.0)],
           plugins: [Gravity(g: [0.0, -9.81]), TaitEos(rho0: 1000.0, gamma: 7.0, c0: 20.0),
                     PressureForce(), SpecularWalls()],
           integrator: (dt: {dt}), end_time: {end_time}, max_steps: {max_steps})"
    );
    let scene = Scene::from_str(
        &text,
        Path::new("column.ron"),
        &dualsph_builtin::default_registry(),
    )
    .unwrap();
    build_sim::<DVec2>(&scene).unwrap()
}

/// Counts its calls; stops the run after `stop_after` steps when given.
#[derive(Default)]
struct Count {
    steps: u64,
    ends: u64,
    stop_after: Option<u64>,
}

impl Observer<DVec2> for Count {
    fn after_step(&mut self, _: &mut Sim<DVec2>) -> Result<Flow, RunError> {
        self.steps += 1;
        Ok(match self.stop_after {
            Some(n) if self.steps >= n => Flow::Stop,
            _ => Flow::Continue,
        })
    }
    fn at_end(&mut self, _: &mut Sim<DVec2>) -> Result<(), RunError> {
        self.ends += 1;
        Ok(())
    }
}

#[test]
fn the_loop_lands_on_the_end_time_and_calls_every_observer_each_step() {
    let mut sim = column(0.01, "Fixed(1e-4)", "None");
    sim.initialize().unwrap();
    let (mut a, mut b) = (Count::default(), Count::default());
    let s = run_to_end(&mut sim, &mut [&mut a, &mut b]).unwrap();
    assert_eq!(sim.clock().step, 100);
    assert!((sim.clock().t - 0.01).abs() < 1e-15, "{}", sim.clock().t);
    assert_eq!(
        (s.steps, a.steps, b.steps, a.ends, b.ends),
        (100, 100, 100, 1, 1)
    );
    assert_eq!(s.particle_steps, 100 * sim.particle_count() as u64);
    // a second call at the end takes no step
    let s = run_to_end(&mut sim, &mut [&mut a]).unwrap();
    assert_eq!((s.steps, a.steps, a.ends), (0, 100, 2));
}

#[test]
fn max_steps_and_an_observer_stop_the_run() {
    let mut sim = column(1.0, "Fixed(1e-4)", "Some(7)");
    let mut a = Count::default();
    run_to_end(&mut sim, &mut [&mut a]).unwrap();
    assert_eq!((sim.clock().step, a.steps, a.ends), (7, 7, 1));
    let mut sim = column(1.0, "Fixed(1e-4)", "None");
    let (mut stop, mut after) = (
        Count {
            stop_after: Some(3),
            ..Count::default()
        },
        Count::default(),
    );
    run_to_end(&mut sim, &mut [&mut stop, &mut after]).unwrap();
    // the observers after the one that stopped do not see that step; all see the end
    assert_eq!((sim.clock().step, stop.steps, after.steps), (3, 3, 2));
    assert_eq!((stop.ends, after.ends), (1, 1));
}

#[test]
fn a_failed_step_is_the_loops_error_and_no_observer_sees_it() {
    // a fixed dt ten times the CFL limit 0.25 h/(c + |v|) = 0.25 · 0.06/20 = 7.5e-4
    let mut sim = column(1.0, "Fixed(7.5e-3)", "None");
    let mut a = Count::default();
    let e = run_to_end(&mut sim, &mut [&mut a]).unwrap_err().to_string();
    assert!(
        e.contains("step 1, t = 7.500000e-3: the fixed dt = 7.500e-3 is above the CFL limit"),
        "{e}"
    );
    assert_eq!((a.steps, a.ends), (0, 0));
}
