use super::*;
use dualsph_core::kernels::KernelKind;
use dualsph_core::neighbours::SkinRule;
use dualsph_core::sim::{ParticleInit, Sim, SimConfig, TimeStepping};
use dualsph_sweep::Formulation;
use glam::DVec2;

/// Two particles at rest, densities 1000 and 1200, h 0.1 and 0.2; no forces.
fn sim() -> Sim<DVec2> {
    let mut sim = Sim::<DVec2>::new(SimConfig {
        kernel: KernelKind::CubicSpline,
        formulation: Formulation::DualSupport,
        domain: Domain::closed(DVec2::ZERO, DVec2::ONE),
        skin: 0.1,
        skin_rule: SkinRule::Fixed,
        time_stepping: TimeStepping::Fixed(1e-3),
    });
    let p = |x: f64, density: f64, h: f64| ParticleInit {
        pos: DVec2::new(x, 0.5),
        vel: DVec2::ZERO,
        mass: 1.0,
        density,
        h,
        internal_energy: 0.0,
        body: 0,
    };
    sim.spawn_particles(&[p(0.2, 1000.0, 0.1), p(0.8, 1200.0, 0.2)])
        .expect("fresh particle ids");
    let plugins: [&dyn dualsph_core::plugin::PluginConfig; 2] = [
        &crate::DiagnosticsPlugin {},
        &dualsph_integrator::LeapfrogPC::default(),
    ];
    for p in plugins {
        sim.build_plugin(p).unwrap();
    }
    sim.initialize().unwrap();
    sim
}

fn set(sim: &mut Sim<DVec2>, id: u32, rho: Real, h: Real) {
    let mut q = sim
        .world
        .query::<(&ParticleId, &mut Density, &mut SmoothingLength)>();
    for (pid, mut d, mut s) in q.iter_mut(&mut sim.world) {
        if pid.0 == id {
            (d.0, s.0) = (rho, h);
        }
    }
}

fn problem(sim: &mut Sim<DVec2>) -> Option<(u32, &'static str, Real)> {
    use dualsph_core::bevy_ecs::system::RunSystemOnce;
    sim.world.run_system_once(check_health::<DVec2>).unwrap();
    sim.world.resource::<Health>().problem
}

#[test]
fn density_and_h_are_checked_against_the_initial_ranges_widened_by_their_factors() {
    let mut s = sim();
    assert_eq!(problem(&mut s), None);
    let b = s.world.resource::<HealthBounds>().clone();
    assert_eq!(b.rho_range, Some((1000.0, 1200.0)));
    assert_eq!(b.h_range, Some((0.1, 0.2)));
    s.world.resource_mut::<HealthBounds>().density = (3.0, 3.0);
    s.world.resource_mut::<HealthBounds>().h = (3.0, 3.0);
    // factors 3: ρ ∈ [333.3, 3600], h ∈ [0.0333, 0.6]; values just inside pass
    set(&mut s, 0, 3599.0, 0.59);
    set(&mut s, 1, 334.0, 0.034);
    assert_eq!(problem(&mut s), None);
    set(&mut s, 1, 3601.0, 0.1);
    assert_eq!(problem(&mut s), Some((1, DENSITY_ABOVE, 3601.0)));
    set(&mut s, 1, 333.0, 0.1);
    assert_eq!(problem(&mut s), Some((1, DENSITY_BELOW, 333.0)));
    set(&mut s, 1, 1000.0, 0.61);
    assert_eq!(problem(&mut s), Some((1, H_ABOVE, 0.61)));
    set(&mut s, 1, 1000.0, 0.033);
    assert_eq!(problem(&mut s), Some((1, H_BELOW, 0.033)));
    // the lowest id is reported; non-positive values keep their own name
    set(&mut s, 0, -1.0, 0.1);
    assert_eq!(problem(&mut s), Some((0, "density", -1.0)));
    let (lo, hi) = s
        .world
        .resource::<HealthBounds>()
        .interval(H_BELOW)
        .unwrap();
    assert!((lo - 0.1 / 3.0).abs() < 1e-15 && (hi - 0.6).abs() < 1e-15);
}

#[test]
fn the_density_range_comes_from_the_initial_densities_when_they_are_restored() {
    let mut s = sim();
    // a resumed run: fresh bounds, InitialDensity restored from the checkpoint
    s.world.insert_resource(HealthBounds {
        density: (1.5, 1.5),
        h: (2.0, 2.0),
        rho_range: None,
        h_range: Some((0.1, 0.2)),
    });
    for (id, mut r0) in s
        .world
        .query::<(&ParticleId, &mut InitialDensity)>()
        .iter_mut(&mut s.world)
    {
        r0.0 = [900.0, 1000.0][id.0 as usize];
    }
    set(&mut s, 0, 1499.0, 0.1);
    assert_eq!(problem(&mut s), None);
    assert_eq!(
        s.world.resource::<HealthBounds>().rho_range,
        Some((900.0, 1000.0))
    );
    set(&mut s, 0, 1501.0, 0.1);
    assert_eq!(problem(&mut s), Some((0, DENSITY_ABOVE, 1501.0)));
}

#[test]
fn a_widened_h_range_admits_what_the_ratio_allows_both_ways() {
    let mut b = HealthBounds {
        h_range: Some((0.1, 0.2)),
        ..HealthBounds::default()
    };
    b.widen_h_range(4.0);
    assert_eq!(b.h_range, Some((0.025, 0.8)));
    let mut unknown = HealthBounds::default();
    unknown.widen_h_range(4.0);
    assert_eq!(unknown.h_range, None);
}
