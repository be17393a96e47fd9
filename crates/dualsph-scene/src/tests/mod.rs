//! Shared fixtures: two tiny plugins, two tiny sections, a registry, a valid base scene and
//! helpers.

mod generate;
mod output;
mod parse;
mod particles_file;
mod periodic;
mod polygon_file;
mod shapes;
mod shapes_validate;
mod stl;
mod validate;

use crate::{Registry, Scene, SceneError};
use dualsph_core::math::Vector;
use dualsph_core::plugin::{SceneInfo, SceneSection, SectionProblem, SimPlugin};
use dualsph_core::sim::{Sim, SimError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Test plugin with settings.
#[derive(Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct Gravity {
    pub g: Vec<f64>,
}

impl SimPlugin for Gravity {
    const NAME: &'static str = "Gravity";
    const SUMMARY: &'static str = "test gravity";
    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        if self.g.len() == info.dimension {
            Ok(())
        } else {
            Err(format!(
                "`g` needs {} components, got {}",
                info.dimension,
                self.g.len()
            ))
        }
    }
    fn build<V: Vector>(&self, _sim: &mut Sim<V>) -> Result<(), SimError> {
        Ok(())
    }
}

/// Test plugin without settings.
#[derive(Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct Walls {}

impl SimPlugin for Walls {
    const NAME: &'static str = "SpecularWalls";
    const SUMMARY: &'static str = "test walls";
    fn build<V: Vector>(&self, _sim: &mut Sim<V>) -> Result<(), SimError> {
        Ok(())
    }
}

/// Test `integrator` section: `(dt: Fixed(x))` or `(dt: Adaptive(courant: x))`.
#[derive(Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct Steps {
    pub dt: Dt,
    #[serde(default)]
    pub max_dt: Option<f64>,
}

/// The test section's step rule.
#[derive(Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
pub(super) enum Dt {
    Fixed(f64),
    Adaptive {
        #[serde(default)]
        courant: f64,
    },
}

impl SceneSection for Steps {
    const KEY: &'static str = "integrator";
    fn validate(&self, _info: &SceneInfo) -> Result<(), SectionProblem> {
        match self.dt {
            Dt::Fixed(dt) if dt <= 0.0 || dt.is_nan() => Err(SectionProblem::new(
                "integrator.dt",
                format!("must be > 0, got {dt}"),
            )),
            _ => Ok(()),
        }
    }
}

/// Test `health` section.
#[derive(Debug, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct Health {
    pub limit: f64,
}

impl SceneSection for Health {
    const KEY: &'static str = "health";
}

/// Test body kind with settings: `Spin(rate: 2.0)`, a rate > 0 (the law is not used).
#[derive(Debug, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct Spin {
    pub rate: f64,
}

impl dualsph_core::bodies::BodyKind for Spin {
    const NAME: &'static str = "Spin";
    const SUMMARY: &'static str = "test kind";
    fn validate(&self, _info: &SceneInfo) -> Result<(), SectionProblem> {
        if self.rate > 0.0 {
            Ok(())
        } else {
            Err(SectionProblem::new("rate", "must be > 0"))
        }
    }
    fn motion(&self) -> Option<std::sync::Arc<dyn dualsph_core::bodies::BodyMotion>> {
        Some(std::sync::Arc::new(dualsph_core::bodies::Hold))
    }
}

pub(super) fn registry() -> Registry {
    let mut r = Registry::new();
    r.register::<Gravity>().register::<Walls>();
    r.register_section::<Steps>().register_section::<Health>();
    r.register_body_kind::<dualsph_core::bodies::Fluid>()
        .register_body_kind::<dualsph_core::bodies::Fixed>()
        .register_body_kind::<Spin>();
    r
}

/// A valid 2-D scene: a 1 × 0.5 staggered block and a disk of radius 0.5, both at Δx 0.05.
pub(super) const BASE: &str = r#"Scene(
    name: "test",
    dimension: 2,
    domain: (min: [0.0, 0.0], max: [4.0, 3.0]),
    kernel: CubicSpline,
    formulation: DualSupport,
    particles: [
        Block(min: [0.0, 0.0], max: [1.0, 0.5], spacing: 0.05, lattice: Staggered, density: 1000.0, h_factor: 2.0),
        Disk(center: [3.0, 2.0], radius: 0.5, spacing: 0.05, lattice: Square, density: 500.0, h_factor: 1.5),
    ],
    plugins: [Gravity(g: [0.0, -9.81]), SpecularWalls()],
    integrator: (dt: Fixed(1e-4)),
    end_time: 1.0,
)
"#;

/// `BASE` with each `(from, to)` replaced once; panics if `from` is absent, so a stale
/// fixture cannot make a test pass vacuously.
pub(super) fn edit(edits: &[(&str, &str)]) -> String {
    let mut text = BASE.to_owned();
    for (from, to) in edits {
        assert!(text.contains(from), "fixture does not contain {from:?}");
        text = text.replacen(from, to, 1);
    }
    text
}

pub(super) fn path() -> &'static Path {
    Path::new("scenes/test.ron")
}

pub(super) fn load(text: &str) -> Result<Scene, SceneError> {
    Scene::from_str(text, path(), &registry())
}

/// 1-based line and column of the first occurrence of `needle` in `text`.
pub(super) fn line_col(text: &str, needle: &str) -> (usize, usize) {
    let at = text.find(needle).expect("needle present");
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = at - before.rfind('\n').map_or(0, |n| n + 1) + 1;
    (line, col)
}

/// The parse error of `text` as (line, col, message); fails the test otherwise.
pub(super) fn parse_error(text: &str) -> (usize, usize, String) {
    match Scene::parse_only(text, path(), &registry()) {
        Err(SceneError::Parse {
            line, col, message, ..
        }) => (line, col, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// The validation error of `text` as (field, message); fails the test otherwise.
pub(super) fn invalid(text: &str) -> (String, String) {
    match load(text) {
        Err(SceneError::Invalid { field, message, .. }) => (field, message),
        other => panic!("expected a validation error, got {other:?}"),
    }
}
