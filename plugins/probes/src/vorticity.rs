//! `Vorticity()`: the vorticity `ω = ∇ × v` of the fluid particles as a snapshot column
//! (`vorticity`, ω_z, in 2-D; `vorticity_x`, `vorticity_y`, `vorticity_z` in 3-D; 1/s),
//! computed when a snapshot or `final.csv` is written and not stored.
//!
//! At each particle i of the sampled bodies (the fluid bodies, or those named in `bodies`) the
//! velocity gradient is the first-order consistent, kernel-corrected gradient of the sampling
//! cloud of those bodies' particles ([`dualsph_core::sampling`]: Ren, Dai, Zhuang & Rabczuk,
//! *Dual-support SPH*, Eq. 2.10 with the difference form about the weighted least-squares
//! value), `∂v_k/∂x_l = [L(x_i) Σ_j (v_{k,j} − v_{k,1}(x_i)) V_j ∇W(x_i − x_j, h_j)]_l`,
//! and `ω = (∂v_z/∂y − ∂v_y/∂z, ∂v_x/∂z − ∂v_z/∂x, ∂v_y/∂x − ∂v_x/∂y)`. It is exact for a
//! linear velocity field (a rigid rotation gives `2Ω` everywhere) on any particle cloud,
//! including one cut off by a wall or a free surface, where the fit is one-sided: walls of
//! particles do not enter it, so the no-slip wall model does not bias the wall vorticity.
//! Across a periodic face the cloud holds the images of the particles beyond it.
//! Particles of other bodies, and those whose support is too small to fit (fewer neighbours
//! than a plane needs), read NaN.

use dualsph_core::bevy_ecs::prelude::World;
use dualsph_core::bodies::{Bodies, BodyId};
use dualsph_core::output::DerivedColumns;
use dualsph_core::sampling::SamplingCloud;
use dualsph_fluid::prelude::*;
use serde::{Deserialize, Serialize};

/// The vorticity snapshot column (module docs).
#[derive(Debug, Clone, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Vorticity {
    /// The bodies whose particles get a vorticity and make the cloud it is fitted on (default:
    /// every fluid body).
    #[serde(default)]
    pub bodies: Vec<String>,
}

/// The names of the columns in `dim` dimensions.
pub fn column_names(dim: usize) -> &'static [&'static str] {
    match dim {
        2 => &["vorticity"],
        _ => &["vorticity_x", "vorticity_y", "vorticity_z"],
    }
}

impl SimPlugin for Vorticity {
    const NAME: &'static str = "Vorticity";
    const SUMMARY: &'static str =
        "snapshot column: the vorticity of the fluid from the corrected velocity gradient";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        if info.dimension < 2 {
            return Err("a 1-D flow has no vorticity: Vorticity needs a 2-D or 3-D scene".into());
        }
        for (k, b) in self.bodies.iter().enumerate() {
            info.check_body(&format!("bodies[{k}]"), b)?;
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        let sampled = crate::sampled_bodies(sim.world.resource::<Bodies>(), &self.bodies);
        let mut cols = sim.world.resource_mut::<DerivedColumns>();
        for (k, name) in column_names(V::DIM).iter().enumerate() {
            let sampled = sampled.clone();
            let axis = if V::DIM == 2 { 2 } else { k };
            cols.add(*name, move |w| {
                vorticity::<V>(w, &sampled)
                    .into_iter()
                    .map(|o| o[axis])
                    .collect()
            })
            .map_err(SimError::Build)?;
        }
        Ok(())
    }
}

/// The vorticity `(ω_x, ω_y, ω_z)` of every particle, in row order: NaN for the particles of
/// bodies not `sampled` and where the corrected gradient does not exist.
pub fn vorticity<V: Vector>(world: &World, sampled: &[bool]) -> Vec<[Real; 3]> {
    let Some(kernel) = world.get_resource::<KernelRes>().map(|k| k.0) else {
        return Vec::new();
    };
    type Row<'a, V> = (
        &'a BodyId,
        &'a Position<V>,
        &'a Velocity<V>,
        &'a Mass,
        &'a Density,
        &'a SmoothingLength,
    );
    let Some(mut q) = world.try_query::<Row<'_, V>>() else {
        return Vec::new();
    };
    let rows: Vec<_> = q.iter(world).collect();
    let keep: Vec<bool> = (rows.iter())
        .map(|r| sampled.get(r.0.0 as usize).copied().unwrap_or(false))
        .collect();
    let mut cloud: Vec<Neighbour<V>> = (rows.iter().zip(&keep))
        .filter(|(_, k)| **k)
        .map(|(r, _)| (r.1.0, r.2.0, r.3.0 / r.4.0, r.5.0))
        .collect();
    let points: Vec<V> = cloud.iter().map(|c| c.0).collect();
    if let Some(domain) = world.get_resource::<Domain<V>>() {
        add_periodic_images(&mut cloud, domain);
    }
    let velocity: Vec<Vec<Real>> = (0..V::DIM)
        .map(|k| cloud.iter().map(|c| c.1.get(k)).collect())
        .collect();
    let (pos, volume, h) = (
        cloud.iter().map(|c| c.0).collect(),
        cloud.iter().map(|c| c.2).collect(),
        cloud.iter().map(|c| c.3).collect(),
    );
    let cloud = SamplingCloud::new(kernel, pos, volume, h);
    // grad[k][i]: the corrected gradient of v_k at the i-th sampled particle
    let grad: Vec<Vec<Option<V>>> = (velocity.iter())
        .map(|v| {
            (cloud.sample_many(&points, v).into_iter())
                .map(|s| s.gradient_corrected)
                .collect()
        })
        .collect();
    let mut at = 0;
    keep.iter()
        .map(|&k| {
            if !k {
                return [Real::NAN; 3];
            }
            let i = at;
            at += 1;
            curl::<V>(&grad, i)
        })
        .collect()
}

/// A particle of the cloud: position, velocity, volume `m/ρ`, support radius.
type Neighbour<V> = (V, V, Real, Real);

/// Adds to `cloud` the images across the domain's periodic faces of the particles within the
/// largest support radius of a face (each combination of the periodic axes' shifts whose image
/// lands within that radius of the box), so that a particle by a periodic face is fitted on
/// the particles beyond it as the pair sweep sees them.
fn add_periodic_images<V: Vector>(cloud: &mut Vec<Neighbour<V>>, domain: &Domain<V>) {
    let axes: Vec<usize> = (0..V::DIM).filter(|&a| domain.periodic[a]).collect();
    if axes.is_empty() {
        return;
    }
    let reach = cloud.iter().map(|c| c.3).fold(0.0, Real::max);
    let inside = |x: V| {
        (0..V::DIM)
            .all(|a| x.get(a) > domain.min.get(a) - reach && x.get(a) < domain.max.get(a) + reach)
    };
    let mut images = Vec::new();
    for combination in 1..3usize.pow(axes.len() as u32) {
        let mut shift = [0.0; 3];
        for (n, &a) in axes.iter().enumerate() {
            let s = (combination / 3usize.pow(n as u32)) % 3;
            let length = domain.max.get(a) - domain.min.get(a);
            shift[a] = [0.0, length, -length][s];
        }
        let shift = V::from_slice(&shift[..V::DIM]).unwrap_or_else(V::zero);
        images.extend(
            (cloud.iter())
                .map(|c| (c.0 + shift, c.1, c.2, c.3))
                .filter(|c| inside(c.0)),
        );
    }
    cloud.extend(images);
}

/// The curl at particle `i` from the gradients of the velocity components, NaN when one is
/// missing: `ω_z = ∂v_y/∂x − ∂v_x/∂y` (and in 3-D the other two).
fn curl<V: Vector>(grad: &[Vec<Option<V>>], i: usize) -> [Real; 3] {
    let d = |k: usize, l: usize| grad[k][i].map_or(Real::NAN, |g| g.get(l));
    let z = d(1, 0) - d(0, 1);
    if V::DIM == 2 {
        return [0.0, 0.0, z];
    }
    [d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), z]
}

#[cfg(test)]
#[path = "vorticity_tests.rs"]
mod tests;
