//! The accounting of the open boundaries: what crosses each open plane and the impulse of
//! each buffer on the fluid, cumulative from t = 0, kept in checkpoints and written to
//! `diagnostics.csv`.
//!
//! The fluid's momentum over a step of the leapfrog predictor–corrector (its corrector
//! `v^{n+1} = v^n + Δt/2 (a^n + a^{n+1})`, RenDSSPH §6) changes by
//!
//! `P^{n+1} − P^n = P_in − P_out + Δt/2 [G^n + G^{n+1}] − Δt/2 Σ_B [L_B^n + L_B^{n+1}]
//!                  − Δt/2 Σ_{i ∈ out} m_i a_i^n`,
//!
//! with `P_in`, `P_out` the momentum `m v` of the particles that became fluid and that
//! stopped being fluid at the start of the step, `G` the body forces on the fluid, `L_B` the
//! load on every driven body B (walls and buffers: the exact sum of the reactions of the
//! dual-support sweep, `Σ_{i∈B} m_i a_i`), and the last term the start-of-step forces of the
//! particles that left the fluid (they were in the sum `G^n − Σ_B L_B^n` of the fluid's forces
//! at the last evaluation, but no longer take part in its update). A particle that becomes
//! fluid starts with zero acceleration, as a new particle does (`dualsph_core::population`),
//! so it brings no such term. Each boundary keeps its share: `P_in`, `P_out`, and its
//! impulse `J_B = −Σ_steps Δt/2 [(L_B^n + L_B^{n+1}) + Σ_{i∈out_B} m_i a_i^n]`; the walls'
//! loads and the body forces are the diagnostics' own columns. With them the balance closes
//! to round-off (the e2e test `open_boundary`).
//!
//! Mass: `M^{n+1} − M^n = M_in − M_out` exactly (particles keep their mass). Energy: the
//! kinetic plus internal energy `½ m v² + m ε` of the particles converted is counted too; the
//! work the buffers do on the fluid is not (so the energy balance is not closed here).

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::math::{Real, Vector};
use dualsph_core::output::DiagnosticColumns;
use serde::{Deserialize, Serialize};

/// One boundary's account (vectors in the 3-D embedding).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BoundaryLedger {
    /// Mass that became fluid (kg).
    pub mass_in: Real,
    /// Momentum that became fluid (kg m/s).
    pub p_in: [Real; 3],
    /// Kinetic + internal energy that became fluid (J).
    pub e_in: Real,
    /// Mass that stopped being fluid (kg).
    pub mass_out: Real,
    /// Momentum that stopped being fluid (kg m/s).
    pub p_out: [Real; 3],
    /// Kinetic + internal energy that stopped being fluid (J).
    pub e_out: Real,
    /// The impulse of the buffer on the fluid, `J_B` (N s).
    pub impulse: [Real; 3],
    /// The load on the buffer at the last evaluation, `L_B^n` (N).
    pub load: [Real; 3],
    /// `Σ m a^n` of the particles that left the fluid at the start of this step (N).
    pub pending: [Real; 3],
    /// Particles converted into the fluid, out of it, created and deleted in the buffer.
    pub counts: [u64; 4],
}

/// The accounts of the scene's boundaries, in the order they are built (kept in checkpoints,
/// key `open_boundaries`).
#[derive(Resource, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OpenLedger(pub Vec<BoundaryLedger>);

/// Adds `v` to `acc` (3-D embedding).
pub(crate) fn add3<V: Vector>(acc: &mut [Real; 3], v: V) {
    for (a, x) in acc.iter_mut().zip(v.to_xyz()) {
        *a += x;
    }
}

/// The columns of `diagnostics.csv` of boundary `k`, whose buffer is the body `name`:
/// `mass_in[name]`, `px_in[name]`.. (one per axis), `e_in[name]`, the same `_out`, and the
/// impulse on the fluid `jx[name]`..
pub(crate) fn add_columns<V: Vector>(
    cols: &mut DiagnosticColumns,
    k: usize,
    name: &str,
) -> Result<(), String> {
    let axes = ["x", "y", "z"];
    let d = V::DIM;
    let mut names = vec![format!("mass_in[{name}]")];
    names.extend((0..d).map(|a| format!("p{}_in[{name}]", axes[a])));
    names.push(format!("e_in[{name}]"));
    names.push(format!("mass_out[{name}]"));
    names.extend((0..d).map(|a| format!("p{}_out[{name}]", axes[a])));
    names.push(format!("e_out[{name}]"));
    names.extend((0..d).map(|a| format!("j{}[{name}]", axes[a])));
    cols.add_group(names, move |w| {
        let Some(l) = w
            .get_resource::<OpenLedger>()
            .and_then(|l| l.0.get(k).cloned())
        else {
            return Vec::new();
        };
        let mut v = vec![l.mass_in];
        v.extend(&l.p_in[..d]);
        v.push(l.e_in);
        v.push(l.mass_out);
        v.extend(&l.p_out[..d]);
        v.push(l.e_out);
        v.extend(&l.impulse[..d]);
        v
    })
}
