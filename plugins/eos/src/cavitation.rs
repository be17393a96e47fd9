//! The density floor of a cavitating liquid (`TaitEos(cavitation: true)`): after every step
//! each particle's density is raised to its law's floor `ρ_c`, the density where Eq. 7.5 gives
//! the cavitation pressure `p_c` (0 unless `min_pressure` sets it).
//!
//! The equation of state applies the floor where it evaluates the pressure (so the forces of
//! a step never see a stretched liquid); this system applies it to the state the step ends
//! with, so the next step starts from it. Without it a leapfrog step would integrate from the
//! stored, unfloored density, and a splash's density would keep falling step after step
//! while its pressure reads `p_c`. The raise changes no velocity and no internal energy, so
//! the energy account stays exact.

use crate::{Eos, materials};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::chunks::DENSE;
use dualsph_fluid::BodyEos;
use dualsph_fluid::prelude::*;
use rayon::prelude::*;

/// The step's label.
pub const FLOOR_LABEL: &str = "cavitation_floor (ρ ≥ ρ_c, TaitEos cavitation)";

/// True when some body's law floors its density.
pub fn any_floor(laws: &[Eos]) -> bool {
    laws.iter()
        .any(|e| matches!(e, Eos::Tait { rho_min, .. } if rho_min.is_finite()))
}

/// Raises every particle's density to its body's floor ([`Eos::floored`]).
#[inline(never)] // a frame of its own in profiles
pub fn floor_density(laws: Res<BodyEos>, mut q: Query<(&BodyId, &mut Density)>) {
    let laws = &materials(&laws);
    for (body, mut rho) in q.contiguous_iter_mut().expect(DENSE) {
        let rho = rho.bypass_change_detection();
        (body, rho)
            .into_par_iter()
            .with_min_len(1024)
            .for_each(|(b, rho)| rho.0 = laws[b.0 as usize].floored(rho.0));
    }
}
