//! The worked extension plugin `SurfaceTension` (plugins/surface-tension): a `Sim` built in
//! code, not from RON, with two particle spacings under DualSupport.
//!
//! * Conservation: the cohesion force joins the support/dual-support sweep through
//!   `PairTerm`, so total linear and angular momentum stay at their initial values to
//!   round-off over many steps for any h field (§5 of Ren, Dai, Zhuang & Rabczuk,
//!   *Dual-support Smoothed Particle Hydrodynamics*, preprint; RenDSSPH in
//!   docs/references.md); the same set-up with SingleSupport drifts by orders of magnitude
//!   more (the check can fail).
//! * Physics: a 2:1 rectangular drop in zero gravity rounds up: within half the Rayleigh
//!   period of the n = 2 capillary mode (`ω² = 6σ/(ρR³)`, T ≈ 0.65 s) its second-moment axis
//!   ratio falls from 2 below 1.7 (measured 1.64 at Δx = 0.05 m here, 1.54 at Δx = 0.025 m),
//!   while the same drop without cohesion keeps its shape. Inviscid linear theory would reach
//!   1 at T/4: the model rounds the drop more slowly (large amplitude, artificial viscosity,
//!   an effective σ below the mean-field calibration at R/h ≈ 2–4).

use dualsph::core::sim::{Domain, SimConfig, TimeStepping};
use dualsph::plugins::*;
use dualsph::prelude::*;
use glam::DVec2;

const RHO: Real = 1000.0;
const SIGMA: Real = 1000.0;

/// A `[-a, a] × [-b, b]` block: the left half at spacing `dx`, the right half at `dx/2`
/// (when `two_level`), h = `h_factor` × the local spacing, velocity `u + ω ẑ × r`.
fn rectangle(
    a: Real,
    b: Real,
    dx: Real,
    h_factor: Real,
    two_level: bool,
    u: DVec2,
    omega: Real,
) -> Vec<ParticleInit<DVec2>> {
    let mut out = Vec::new();
    let halves: [(Real, Real, Real); 2] = if two_level {
        [(-a, 0.0, dx), (0.0, a, 0.5 * dx)]
    } else {
        [(-a, 0.0, dx), (0.0, a, dx)]
    };
    for (x0, x1, s) in halves {
        let (nx, ny) = (
            ((x1 - x0) / s).round() as usize,
            (2.0 * b / s).round() as usize,
        );
        for iy in 0..ny {
            for ix in 0..nx {
                let pos = DVec2::new(x0 + (ix as Real + 0.5) * s, -b + (iy as Real + 0.5) * s);
                out.push(ParticleInit {
                    pos,
                    vel: u + DVec2::new(-pos.y, pos.x) * omega,
                    mass: RHO * s * s,
                    density: RHO,
                    h: h_factor * s,
                    internal_energy: 0.0,
                    body: 0,
                });
            }
        }
    }
    out
}

/// Water-like drop physics plus the custom plugin, built in code.
fn drop_sim(
    particles: &[ParticleInit<DVec2>],
    formulation: Formulation,
    sigma: Real,
) -> Sim<DVec2> {
    let mut sim = Sim::<DVec2>::new(SimConfig {
        kernel: KernelKind::CubicSpline,
        formulation,
        domain: Domain::closed(DVec2::splat(-3.0), DVec2::splat(3.0)),
        skin: 0.15,
        skin_rule: SkinRule::Fixed,
        time_stepping: TimeStepping::Adaptive {
            courant: 0.1,
            force: 0.25,
            viscous: 0.125,
            max_dt: Real::INFINITY,
        },
    });
    sim.spawn_particles(particles).expect("fresh particle ids");
    dualsph::add_default_plugins(&mut sim).expect("the default plugins build");
    let plugins: [&dyn PluginConfig; 5] = [
        &ContinuityDensity {
            form: ContinuityForm::Pairwise,
        },
        &TaitEos {
            rho0: RHO,
            gamma: 7.0,
            c0: Some(100.0.into()),
            p0: None,
            min_pressure: None,
            cavitation: false,
            background: 0.0,
            materials: Vec::new(),
        },
        &PressureForce {},
        &ArtificialViscosity {
            alpha: 0.05,
            beta: 0.0,
            eta_factor: 0.1,
            materials: Vec::new(),
            dissipation: false,
        },
        &SurfaceTension { sigma },
    ];
    for p in plugins {
        p.build_into(&mut sim).expect("plugin builds");
    }
    sim.finish().expect("schedule");
    sim.initialize().expect("initial evaluation");
    sim
}

/// `(max |P(t) − P(0)|, max |L(t) − L(0)|) / Σ|m v|(0)` over `steps` steps (L per unit length R).
fn momentum_drifts(sim: &mut Sim<DVec2>, steps: usize, r: Real) -> (Real, Real) {
    let d0 = sim.diagnostics();
    let (mut dp, mut dl) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        sim.step().expect("step");
        let d = sim.diagnostics();
        let p = glam::DVec3::from_array(d.momentum) - glam::DVec3::from_array(d0.momentum);
        dp = dp.max(p.length());
        dl = dl.max((d.angular_momentum[2] - d0.angular_momentum[2]).abs() / r);
    }
    (dp / d0.momentum_scale, dl / d0.momentum_scale)
}

#[test]
fn cohesion_conserves_momentum_and_angular_momentum_with_two_spacings() {
    let particles = rectangle(0.5, 0.25, 0.05, 4.0, true, DVec2::new(0.3, -0.2), 2.0);
    let hs: Vec<Real> = particles.iter().map(|p| p.h).collect();
    assert!(hs.contains(&0.2) && hs.contains(&0.1), "two h levels");
    let mut sim = drop_sim(&particles, Formulation::DualSupport, SIGMA);
    let (dp, dl) = momentum_drifts(&mut sim, 400, 0.5);
    println!(
        "DualSupport, {} particles, 400 steps: momentum drift {dp:.2e}, angular {dl:.2e}",
        particles.len()
    );
    assert!(dp <= 1e-12, "momentum drift {dp:e}");
    assert!(dl <= 1e-12, "angular momentum drift {dl:e}");
    let quoted = format!("over 400 steps (measured {dp:.1e} and {dl:.1e}");
    let anchor = "`tests/e2e/surface_tension.rs` builds a `Sim`";
    crate::common::assert_doc_quotes("docs/extending.md", anchor, &quoted);

    // The same particles without the support/dual-support bookkeeping: the pair forces no
    // longer balance where h changes, so the conservation checks above can fail.
    let mut single = drop_sim(&particles, Formulation::SingleSupport, SIGMA);
    let (sp, sl) = momentum_drifts(&mut single, 100, 0.5);
    println!("SingleSupport, 100 steps: momentum drift {sp:.2e}, angular {sl:.2e}");
    assert!(sp > 1e-8, "SingleSupport momentum drift only {sp:e}");
    let quoted = format!("SingleSupport on the same particles drifts by {sp:.2}");
    let anchor = "`tests/e2e/surface_tension.rs` builds a `Sim`";
    crate::common::assert_doc_quotes("docs/extending.md", anchor, &quoted);
}

/// `√(⟨(x − x̄)²⟩ / ⟨(y − ȳ)²⟩)`, volume-weighted: 2 for the 2:1 rectangle, 1 for a disk.
fn axis_ratio(sim: &mut Sim<DVec2>) -> Real {
    let mut q = sim
        .world
        .query::<(&Position<DVec2>, &Mass, &dualsph::core::components::Density)>();
    let rows: Vec<(DVec2, Real)> = q
        .iter(&sim.world)
        .map(|(r, m, d)| (r.0, m.0 / d.0))
        .collect();
    let w: Real = rows.iter().map(|r| r.1).sum();
    let c = rows.iter().fold(DVec2::ZERO, |s, r| s + r.0 * r.1) / w;
    let v = rows.iter().fold(DVec2::ZERO, |s, r| {
        let d = r.0 - c;
        s + d * d * r.1
    }) / w;
    (v.x / v.y).sqrt()
}

/// Runs to `t_end`, returning the smallest axis ratio and when it occurred.
fn min_ratio(sim: &mut Sim<DVec2>, t_end: Real) -> (Real, Real) {
    let mut best = (axis_ratio(sim), 0.0);
    while sim.clock().t < t_end {
        sim.step().expect("step");
        if sim.clock().step.is_multiple_of(20) {
            let r = axis_ratio(sim);
            if r < best.0 {
                best = (r, sim.clock().t);
            }
        }
    }
    best
}

#[test]
fn elongated_drop_rounds_up_under_cohesion_and_not_without() {
    // 1 m × 0.5 m, equivalent radius R = √(0.5/π); Rayleigh n = 2 period T = 2π √(ρR³/(6σ)).
    let radius = (0.5 / std::f64::consts::PI).sqrt();
    let period = 2.0 * std::f64::consts::PI * (RHO * radius.powi(3) / (6.0 * SIGMA)).sqrt();
    let particles = rectangle(0.5, 0.25, 0.05, 4.0, false, DVec2::ZERO, 0.0);
    let t_end = 0.5 * period;

    let mut sim = drop_sim(&particles, Formulation::DualSupport, SIGMA);
    let r0 = axis_ratio(&mut sim);
    let (rmin, tmin) = min_ratio(&mut sim, t_end);
    println!(
        "σ = {SIGMA}: axis ratio {r0:.3} → min {rmin:.3} at t = {tmin:.3} s (T/4 = {:.3} s)",
        0.25 * period
    );
    let mut control = drop_sim(&particles, Formulation::DualSupport, 0.0);
    let (cmin, _) = min_ratio(&mut control, t_end);
    println!("σ = 0: axis ratio min {cmin:.3}");
    let quoted = format!("(axis ratio {r0:.2} → {rmin:.2} in {tmin:.2} s at Δx = 0.05 m");
    let anchor = "`tests/e2e/surface_tension.rs` builds a `Sim`";
    crate::common::assert_doc_quotes("docs/extending.md", anchor, &quoted);

    // Cell-centred lattice: ⟨x²⟩ = (L² − Δx²)/12, so the ratio starts at 2.0019.
    assert!((r0 - 2.0).abs() < 0.01, "initial ratio {r0}");
    assert!(
        cmin > 0.99 * r0,
        "without cohesion the drop must keep its shape: {cmin}"
    );
    assert!(
        rmin < 1.7,
        "cohesion should round the drop: ratio only fell to {rmin}"
    );
}

#[test]
fn negative_sigma_in_a_scene_is_an_error_naming_the_field() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cohesion_drop_2d.ron");
    let text = std::fs::read_to_string(&path).unwrap().replace(
        "SurfaceTension(sigma: 1000.0)",
        "SurfaceTension(sigma: -1.0)",
    );
    let err = dualsph::scene::Scene::from_str(&text, &path, &dualsph::default_registry())
        .expect_err("negative σ must be rejected")
        .to_string();
    assert!(
        err.contains("SurfaceTension") && err.contains("sigma"),
        "{err}"
    );
}
