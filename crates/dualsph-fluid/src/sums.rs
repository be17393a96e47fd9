//! The fluid's pair sums by name: the power into the internal energy and the density rate
//! are the sweep's two scalar registers (`dualsph_sweep::accum::Standard::Scalar`), so the
//! pair terms that write them run on the sweep's fastest record layout; the dissipation rate
//! is an ordinary accumulator.

use crate::components::{DensityRate, DissipationRate, EnergyRate};
use dualsph_core::lanes::Lanes;
use dualsph_core::math::{Real, Vector};
use dualsph_sweep::accum::{Acc, Binder, Reaction};
use dualsph_sweep::pair::{Out, OwnerSums};

/// The scalar register of the power `m_i ε̇_i`.
pub const POWER: usize = 0;
/// The scalar register of the density rate `dρ_i/dt`.
pub const DENSITY_RATE: usize = 1;

/// The fluid's sums, declared when a term is bound.
pub trait FluidSums {
    /// Declares that the term adds to the power into each particle's internal energy
    /// (`m_i ε̇_i`, [`Reaction::Separate`], with [`FluidOut::add_power`] and
    /// [`FluidOut::react_power`]), which goes into its [`EnergyRate`] (divided by `m_i`);
    /// dropped when the scene integrates no energy.
    fn power(&mut self) -> Result<(), String>;

    /// Declares that the term adds to the dissipation rate of each particle (`m_i ḋ_i`,
    /// [`Reaction::Separate`], with `Out::add` and `Out::react` on the handle returned),
    /// which goes into its [`DissipationRate`] (divided by `m_i`): the part of its power that
    /// is heat, for the energy budget ([`crate::ensure_dissipation`]).
    fn dissipation(&mut self) -> Result<Acc, String>;

    /// Declares that the term adds to the density rate `dρ_i/dt` ([`DensityRate`], with
    /// [`FluidOut::add_density_rate`] and, with [`Reaction::Separate`],
    /// [`FluidOut::react_density_rate`]); the error names the term when the particles have
    /// no density rate (the density is not integrated).
    fn density_rate(&mut self, reaction: Reaction) -> Result<(), String>;
}

impl<V: Vector> FluidSums for Binder<'_, '_, V> {
    fn power(&mut self) -> Result<(), String> {
        let finish = |e: &mut EnergyRate, s: &[Real], m: Real| e.rate = s[0] / m;
        self.scalar_register::<EnergyRate, POWER>(Reaction::Separate, finish)
    }

    fn dissipation(&mut self) -> Result<Acc, String> {
        let finish = |d: &mut DissipationRate, s: &[Real], m: Real| d.rate = s[0] / m;
        self.accumulate::<DissipationRate>(Reaction::Separate, 1, finish)
    }

    fn density_rate(&mut self, reaction: Reaction) -> Result<(), String> {
        self.require::<DensityRate>()?;
        let finish = |d: &mut DensityRate, s: &[Real], _: Real| d.rate = s[0];
        self.scalar_register::<DensityRate, DENSITY_RATE>(reaction, finish)
    }
}

/// The fluid's sums, added per pair.
pub trait FluidOut<T: Lanes> {
    /// Adds `p` to the power into the owner's internal energy ([`FluidSums::power`]).
    fn add_power(&mut self, p: T);
    /// Adds `p` to the power into the neighbour's internal energy ([`FluidSums::power`]).
    fn react_power(&mut self, p: T);
    /// Adds `d` to the owner's density rate ([`FluidSums::density_rate`]).
    fn add_density_rate(&mut self, d: T);
    /// Adds `d` to the neighbour's density rate ([`FluidSums::density_rate`] with
    /// [`Reaction::Separate`]).
    fn react_density_rate(&mut self, d: T);
}

impl<T: Lanes> FluidOut<T> for Out<'_, T> {
    #[inline(always)]
    fn add_power(&mut self, p: T) {
        self.add_scalar::<POWER>(p);
    }
    #[inline(always)]
    fn react_power(&mut self, p: T) {
        self.react_scalar::<POWER>(p);
    }
    #[inline(always)]
    fn add_density_rate(&mut self, d: T) {
        self.add_scalar::<DENSITY_RATE>(d);
    }
    #[inline(always)]
    fn react_density_rate(&mut self, d: T) {
        self.react_scalar::<DENSITY_RATE>(d);
    }
}

/// The fluid's sums of a particle before any pair (a term's per-particle part).
pub trait FluidOwnerSums {
    /// Adds `d` to the density rate ([`FluidSums::density_rate`]).
    fn add_density_rate(&mut self, d: Real);
}

impl FluidOwnerSums for OwnerSums<'_> {
    fn add_density_rate(&mut self, d: Real) {
        self.add_scalar::<DENSITY_RATE>(d);
    }
}
