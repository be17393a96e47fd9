//! Potentials of body forces, declared by the plugins that add the forces (gravity) and read
//! by whoever sums energies (the diagnostics plugin).

use crate::math::Real;
use bevy_ecs::prelude::*;

/// Potential of a body force per unit mass at a point, registered by plugins (gravity).
#[derive(Resource, Clone, Default)]
pub struct ExternalPotentials {
    /// `φ(x)` terms; the potential energy is `Σ m_i Σ_k φ_k(x_i)` over the particles of fluid
    /// bodies (body forces act on them only: a fixed or prescribed body's motion is given).
    pub terms: Vec<fn(&[Real; 3], &[Real; 3]) -> Real>,
    /// Parameters of each term (e.g. g).
    pub params: Vec<[Real; 3]>,
}
