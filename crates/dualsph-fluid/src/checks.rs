//! The lane checks of the pair layer (`dualsph_sweep::check_lanes_2d`) on a lattice that
//! carries the fluid's columns too, so that a term reading pressures or writing the power or
//! the density rate can be checked as the built-in terms are.

use crate::components::{
    Conductivity, DensityRate, DissipationRate, EnergyRate, InternalEnergy, Pressure, SoundSpeed,
    VelocityGradient,
};
use bevy_ecs::prelude::World;
use dualsph_core::math::Real;
use dualsph_core::store::insert_column;
use dualsph_sweep::DynPairTerm;
use std::sync::Arc;

/// Puts the fluid's columns on a lattice's particles: pressures, sound speeds, internal
/// energies and conductivities that vary from particle to particle (a fixed LCG), and the
/// rates and the velocity gradient the fluid's sums write.
pub fn fluid_columns(world: &mut World) {
    use glam::DVec2;
    let n = world
        .query::<&dualsph_core::components::Mass>()
        .iter(world)
        .count();
    let mut seed = 6789u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as Real / (1u64 << 53) as Real
    };
    let (p, s): (Vec<Real>, Vec<Real>) =
        (0..n).map(|_| (rnd() * 1e3 - 200.0, 10.0 + rnd())).unzip();
    insert_column(world, |i| Pressure(p[i]));
    insert_column(world, |i| SoundSpeed(s[i]));
    insert_column(world, |i| InternalEnergy(1.0 + 0.1 * (i % 5) as Real));
    insert_column(world, |i| Conductivity(0.5 + 0.01 * (i % 3) as Real));
    insert_column(world, |_| EnergyRate::default());
    insert_column(world, |_| DensityRate::default());
    insert_column(world, |_| DissipationRate::default());
    insert_column(world, |_| VelocityGradient::<DVec2>(glam::DMat2::ZERO));
}

/// `dualsph_sweep::check_lanes_2d` with the fluid's columns ([`fluid_columns`]): two pairs at
/// a time the term gives bitwise what it gives one pair at a time, without and with the
/// kernel-gradient correction.
pub fn check_lanes_2d(term: &dyn DynPairTerm<glam::DVec2>) -> Result<(), String> {
    dualsph_sweep::check_lanes_2d_with(term, fluid_columns)
}

/// [`check_lanes_2d`] for a term that reads or writes columns of its own: `extra` puts them
/// on the lattice's particles after the fluid's.
pub fn check_lanes_2d_with(
    term: &dyn DynPairTerm<glam::DVec2>,
    extra: impl FnOnce(&mut World),
) -> Result<(), String> {
    dualsph_sweep::check_lanes_2d_with(term, |w| {
        fluid_columns(w);
        extra(w)
    })
}

/// `dualsph_sweep::check_block_loop_2d` with the fluid's columns: as a sweep's only term the
/// term's compiled block loop gives bitwise the sums of its dynamic calls.
pub fn check_block_loop_2d(term: Arc<dyn DynPairTerm<glam::DVec2>>) -> Result<(), String> {
    dualsph_sweep::check_block_loop_2d_with(term, fluid_columns)
}
