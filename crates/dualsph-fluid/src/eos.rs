//! The equation of state of each body as the other plugins see it: any equation of state (the
//! built-in ones or a user's own) publishes its law per body in [`BodyEos`], and what needs
//! the law outside the equation's own system — the walls' pressure extrapolation (a density
//! from a pressure), a liquid's reference density — reads it there, through [`EosLaw`].

use bevy_ecs::prelude::Resource;
use dualsph_core::math::Real;
use std::any::Any;
use std::sync::Arc;

/// One body's equation of state: its pressure and sound speed from its density (and specific
/// internal energy), and, for a liquid, the inverse.
pub trait EosLaw: Any + Send + Sync + std::fmt::Debug {
    /// `(p, c)` at density `rho` and specific internal energy `eps`.
    fn eval(&self, rho: Real, eps: Real) -> (Real, Real);

    /// The density at which the law gives pressure `p`, for a liquid; `None` for a law whose
    /// pressure depends on more than the density (a gas), or for a pressure no density gives.
    fn density_at(&self, p: Real) -> Option<Real>;

    /// The reference (rest) density `ρ0` of a liquid; `None` for a gas.
    fn reference_density(&self) -> Option<Real>;

    /// The pressure at depth `s` below a free surface at rest under gravity `|g| = g`
    /// (`dp/ds = ρ(p) g`, `p(0) = 0`), for a liquid whose law has it in closed form; `None`
    /// (the default) otherwise, and a hydrostatic start then leaves the body's density as
    /// the scene gives it.
    fn hydrostatic_pressure(&self, _g: Real, _s: Real) -> Option<Real> {
        None
    }
}

/// The equation of state of every body, indexed by `BodyId`: set by the scene's equation of
/// state when it is built (with `Sim::enable::<EquationOfState>()`), read by the plugins that
/// run after it.
#[derive(Resource, Clone, Debug)]
pub struct BodyEos(pub Vec<Arc<dyn EosLaw>>);

impl BodyEos {
    /// Body `b`'s law as the concrete type `L`, when it is one (an equation-of-state plugin
    /// reading back its own laws).
    pub fn law_as<L: EosLaw>(&self, b: usize) -> Option<&L> {
        let law: &dyn Any = self.0.get(b)?.as_ref();
        law.downcast_ref::<L>()
    }
}
