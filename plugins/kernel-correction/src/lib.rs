//! `KernelCorrection()`: kernel-gradient correction `∇̃_iW_ij = L_i ∇_iW_ij` (Eq. 2.10), applied
//! by the pair sweep to every term's `grad` and by the velocity gradient. With the correction
//! the pressure and stress terms use `1/(ρ_iρ_j)` so that angular momentum is conserved
//! exactly (§5.2).
#![warn(missing_docs)]

use dualsph_core::passes;
use dualsph_core::prelude::*;
use serde::Deserialize;

/// Kernel-gradient correction.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KernelCorrection {}

impl SimPlugin for KernelCorrection {
    const NAME: &'static str = "KernelCorrection";
    const SUMMARY: &'static str = "kernel-gradient correction L_i (Eq. 2.10)";

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        passes::ensure_kernel_correction(sim)?;
        Ok(())
    }
}
