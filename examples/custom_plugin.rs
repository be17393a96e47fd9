//! A user's own physics, defined here and nowhere in the engine: a pairwise drag (the
//! dissipative force of dissipative particle dynamics),
//!
//! `f_i ← j = −γ m_i m_j (1 − r/h_i)² (v_ij · ê) ê`,  `ê = r_ij/|r_ij|`,  `f_j ← i = −f_i ← j`,
//!
//! written as a `PairTerm`, wrapped in a `SimPlugin`, registered under its own name and used
//! from a RON scene. The sweep evaluates it once per pair in i's support and applies the
//! reaction to j, so total momentum and angular momentum (the force is central) are conserved
//! to round-off while the shear flow's kinetic energy decays; the dissipated work `−f·v_ij`
//! goes to internal energy, half to each particle (used when the scene integrates it).
//!
//! ```sh
//! cargo run --release --example custom_plugin
//! ```

use dualsph::prelude::*;
use dualsph::{build_sim, default_registry, scene::Scene};
use glam::DVec2;
use serde::Deserialize;
use std::path::Path;

/// The settings, as written in the scene: `PairDrag(gamma: 20.0)`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct PairDrag {
    /// Drag coefficient γ (1/(kg·s)), ≥ 0.
    gamma: Real,
}

/// The pair term the plugin adds to the sweep.
#[derive(Debug, Clone, Copy)]
struct PairDragTerm {
    gamma: Real,
}

impl<V: Vector> PairTerm<V> for PairDragTerm {
    /// The term reads only the core columns (positions, velocities, masses, h): it is its own
    /// bound term.
    type Bound<'w> = PairDragTerm;

    fn name(&self) -> &str {
        "pair drag (DPD dissipative force)"
    }

    fn bind<'w>(&'w self, _: &ParticleData<'w, V>) -> Result<PairDragTerm, String> {
        Ok(*self)
    }
}

impl<V: Vector> BoundTerm<V> for PairDragTerm {
    fn interact(&self, p: &Pair<'_, V>, out: &mut PairOut<V>) {
        if p.r == 0.0 {
            return;
        }
        let (d, e) = (p.data, p.rij / p.r);
        let w = 1.0 - p.r / d.h[p.i].0;
        let vij = p.vij();
        let force = e * (-self.gamma * d.mass[p.i].0 * d.mass[p.j].0 * w * w * vij.dot(e));
        out.force += force;
        let heat = -0.5 * force.dot(vij); // ≥ 0: dissipated work, shared ½/½
        out.power_i += heat;
        out.power_j += heat;
    }
}

impl SimPlugin for PairDrag {
    const NAME: &'static str = "PairDrag";
    const SUMMARY: &'static str = "pairwise drag (DPD dissipative force), from examples/";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if !(self.gamma.is_finite() && self.gamma >= 0.0) {
            return Err(format!("gamma: must be >= 0, got {}", self.gamma));
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.add_pair_term(PairDragTerm { gamma: self.gamma });
        Ok(())
    }
}

/// A shear flow `v = (y, 0)` in a block with two spacings, only the custom plugin acting.
const SCENE: &str = r#"Scene(
    name: "shear flow damped by a pairwise drag",
    dimension: 2,
    domain: (min: [-2.0, -2.0], max: [2.0, 2.0]),
    kernel: CubicSpline,
    formulation: DualSupport,
    particles: [
        Block(min: [-0.5, -0.5], max: [0.0, 0.5], spacing: 0.05, lattice: Square, density: 1.0,
              h_factor: 2.0, velocity: Linear([[0.0, 1.0], [0.0, 0.0]])),
        Block(min: [0.0, -0.5], max: [0.5, 0.5], spacing: 0.025, lattice: Square, density: 1.0,
              h_factor: 2.0, velocity: Linear([[0.0, 1.0], [0.0, 0.0]])),
    ],
    plugins: [ PairDrag(gamma: GAMMA) ],
    integrator: (dt: Fixed(1e-3)),
    end_time: 0.5,
)"#;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut registry = default_registry();
    registry.register::<PairDrag>(); // now usable from RON as `PairDrag(...)`

    // Bad input is an error naming the field, not a panic.
    let bad = Scene::from_str(
        &SCENE.replace("GAMMA", "-1.0"),
        Path::new("inline.ron"),
        &registry,
    );
    println!("gamma = -1: {}", bad.expect_err("rejected"));

    let scene = Scene::from_str(
        &SCENE.replace("GAMMA", "20000.0"),
        Path::new("inline.ron"),
        &registry,
    )?;
    let mut sim = build_sim::<DVec2>(&scene)?;
    println!("pair terms: {:?}", sim.plan().pair_terms);
    sim.initialize()?;
    let d0 = sim.diagnostics();
    while sim.clock().t < scene.end_time * (1.0 - 1e-12) {
        sim.step()?;
    }
    let d = sim.diagnostics();
    let dp = (0..3)
        .map(|k| (d.momentum[k] - d0.momentum[k]).abs())
        .fold(0.0, f64::max);
    let dl = (d.angular_momentum[2] - d0.angular_momentum[2]).abs();
    println!("{} particles, {} steps to t = {}", d.n, d.step, d.t);
    println!(
        "kinetic energy {:.4e} → {:.4e} (shear damped)",
        d0.e_kin, d.e_kin
    );
    println!(
        "|ΔP| = {dp:.1e}, |ΔL| = {dl:.1e} (of Σ|m v| = {:.3e})",
        d0.momentum_scale
    );
    Ok(())
}
