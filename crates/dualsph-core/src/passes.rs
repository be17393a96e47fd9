//! Own-support passes: per-particle sums over `H_i` that need no reaction (the paper keeps
//! the continuity equation in its single-support form, §4). Each is a scheduled system that
//! reads the particles' columns and writes its result column in place (see [`crate::store`]).

use crate::chunks::{DENSE, MIN_LEN};
use crate::columns::ColumnSpec;
use crate::components::*;
use crate::kernels::Kernel;
use crate::math::{Matrix, Real, Vector};
use crate::neighbours::Neighbours;
use crate::sim::{KernelRes, Sim, SimError, StepSet};
use crate::store::{CoreColumns, ParticleData, single_table};
use crate::sweep::{
    ContinuityInSweep, Formulation, OwnerKernel, PairTerms, Support, SweepCtx, continuity_in_sweep,
};
use bevy_ecs::prelude::*;
use rayon::prelude::*;

/// Fewest particles per rayon piece of a neighbour loop.
const MIN_ROWS: usize = 64;

/// Summation density, Eq. 4.8: `ρ_i = m_i W(0, h_i) + Σ_{j∈H_i} m_j W_ij`.
#[inline(never)] // a frame of its own in profiles
pub fn summation_density<V: Vector>(
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    mut q: Query<(&Position<V>, &SmoothingLength, &Mass, &mut Density)>,
) {
    let Some((pos, h, mass, mut rho)) = single_table(q.contiguous_iter_mut().expect(DENSE)) else {
        return;
    };
    let (kernel, formulation) = (&kernel.0, *form);
    let support = Support {
        pos,
        h,
        neighbours: &nb,
        kernel,
        formulation,
    };
    rho.par_iter_mut()
        .enumerate()
        .with_min_len(MIN_ROWS)
        .for_each(|(i, rho)| {
            let mut s = mass[i].0 * kernel.w(0.0, h[i].0);
            support.for_each_neighbour(i, |j, _, _, w, _| s += mass[j].0 * w);
            rho.0 = s;
        });
}

/// The context of a pass over the particles' core columns (no other column readable).
fn pass_ctx<'a, V: Vector>(
    data: ParticleData<'a, V>,
    correction: Option<&'a [GradientCorrection<V>]>,
    nb: &'a Neighbours<V>,
    kernel: &'a KernelRes,
    form: Formulation,
) -> SweepCtx<'a, V> {
    SweepCtx {
        data,
        correction,
        neighbours: nb,
        kernel: &kernel.0,
        formulation: form,
    }
}

/// Kernel-gradient correction, Eq. 2.10: `L_i = [Σ_{j∈H_i} V_j ∇_iW_ij ⊗ (r_j − r_i)]^{-1}`;
/// the identity where the sum is singular (too few neighbours).
#[inline(never)] // a frame of its own in profiles
pub fn kernel_correction<V: Vector>(
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    mut q: Query<(CoreColumns<V>, &mut GradientCorrection<V>)>,
) {
    let tables = q.contiguous_iter_mut().expect(DENSE);
    let Some((core, mut l)) = single_table(tables) else {
        return;
    };
    let data = ParticleData::from_columns(core);
    let ctx = pass_ctx(data, None, &nb, &kernel, *form);
    l.par_iter_mut()
        .enumerate()
        .with_min_len(MIN_ROWS)
        .for_each(|(i, l)| {
            let mut a = V::Mat::zero();
            ctx.for_each_neighbour(i, |j, rij, _, _, g| a += V::outer(g, -rij) * data.volume(j));
            l.0 = a.try_inverse(1e-6).unwrap_or_else(V::Mat::identity);
        });
}

/// Velocity gradient, Eq. 7.4: `(∇⊗v)_i = −Σ_{j∈H_i} V_j v_ij ⊗ ∇̃_iW_ij`, entries `∂v_k/∂x_l`
/// (exact for linear fields when the correction is active).
#[inline(never)] // a frame of its own in profiles
pub fn velocity_gradient<V: Vector>(
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    mut q: Query<(
        CoreColumns<V>,
        Option<&GradientCorrection<V>>,
        &mut VelocityGradient<V>,
    )>,
) {
    let tables = q.contiguous_iter_mut().expect(DENSE);
    let Some((core, correction, mut grads)) = single_table(tables) else {
        return;
    };
    let data = ParticleData::from_columns(core);
    let ctx = pass_ctx(data, correction, &nb, &kernel, *form);
    grads
        .par_iter_mut()
        .enumerate()
        .with_min_len(MIN_ROWS)
        .for_each(|(i, grad)| {
            let mut gsum = V::Mat::zero();
            ctx.for_each_neighbour(i, |j, _, _, _, g| {
                let vij = data.vij(i, j);
                gsum += V::outer(vij, ctx.corrected(i, g)) * (-data.volume(j));
            });
            grad.0 = gsum;
        });
}

/// Continuity, Eq. 4.9: `dρ_i/dt = Σ_{j∈H_i} m_j v_ij · ∇_iW_ij`.
#[inline(never)] // a frame of its own in profiles
pub fn continuity_pairwise<V: Vector>(
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    fused: Option<Res<ContinuityInSweep>>,
    terms: Option<Res<PairTerms<V>>>,
    mut q: Query<(CoreColumns<V>, &mut DensityRate)>,
) {
    let has_terms = terms.is_some_and(|t| !t.terms.is_empty());
    if continuity_in_sweep(fused.is_some(), has_terms, *form) {
        return; // the pair sweep forms the same sums (see `SweepBuffers::with_density_rate`)
    }
    let tables = q.contiguous_iter_mut().expect(DENSE);
    let Some((core, mut rates)) = single_table(tables) else {
        return;
    };
    let data = ParticleData::from_columns(core);
    let ctx = pass_ctx(data, None, &nb, &kernel, *form);
    rates
        .par_iter_mut()
        .enumerate()
        .with_min_len(MIN_ROWS)
        .for_each(|(i, out)| {
            out.rate = if *form == Formulation::AveragedKernel {
                let mut s = 0.0;
                ctx.for_each_neighbour(i, |j, _, _, _, g| {
                    s += data.mass[j].0 * data.vij(i, j).dot(g)
                });
                s
            } else {
                own_support_continuity(&data, nb.support.row(i), i, &kernel.0)
            };
        });
}

/// `Σ_{j∈H_i} m_j v_ij·∇_iW_ij` over a candidate row (Eq. 4.9), the same sum as through
/// [`SweepCtx::for_each_neighbour`] without evaluating `W`.
#[inline]
pub fn own_support_continuity<V: Vector>(
    data: &ParticleData<'_, V>,
    row: &[u32],
    i: usize,
    kernel: &Kernel,
) -> Real {
    let (pos, vel, mass) = (data.pos, data.vel, data.mass);
    let (xi, vi, k) = (pos[i].0, vel[i].0, OwnerKernel::new(kernel, data.h[i].0));
    let mut s = 0.0;
    for &j in row {
        let j = j as usize;
        let rij = xi - pos[j].0;
        let r2 = rij.length_squared();
        if r2 < k.h2 {
            s += mass[j].0 * (vi - vel[j].0).dot(k.grad(rij, r2.sqrt()));
        }
    }
    s
}

/// Adds the pairwise continuity equation (Eq. 4.9): the [`continuity_pairwise`] system, which
/// leaves the sums to the dual-support pair sweep when there is one.
pub fn add_continuity_pairwise<V: Vector>(sim: &mut Sim<V>) {
    sim.world.insert_resource(ContinuityInSweep);
    sim.add_system(
        StepSet::Forces,
        "continuity (Eq. 4.9; in the pair sweep when there is one)",
        continuity_pairwise::<V>,
    );
}

/// Continuity from the velocity divergence (paper §7.3): `dρ_i/dt = −ρ_i tr(∇⊗v)_i`.
#[inline(never)] // a frame of its own in profiles
pub fn continuity_divergence<V: Vector>(
    mut q: Query<(&Density, &VelocityGradient<V>, &mut DensityRate)>,
) {
    for (rho, grad, mut rates) in q.contiguous_iter_mut().expect(DENSE) {
        let rows = (rho, grad, &mut *rates)
            .into_par_iter()
            .with_min_len(MIN_LEN);
        rows.for_each(|(rho, g, r)| r.rate = -rho.0 * g.0.trace());
    }
}

/// Adds summation density once.
pub fn ensure_summation_density<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if sim.enable_feature("summation_density") {
        sim.add_system(
            StepSet::Density,
            "summation_density (Eq. 4.8)",
            summation_density::<V>,
        );
    }
    Ok(())
}

/// Adds the kernel-gradient correction once.
pub fn ensure_kernel_correction<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if sim.enable_feature("kernel_correction") {
        let spec = ColumnSpec::restart_only("gradient_correction");
        sim.add_column(spec, |_| GradientCorrection::<V>(V::Mat::identity()))?;
        sim.add_system(
            StepSet::Correction,
            "kernel_correction (Eq. 2.10)",
            kernel_correction::<V>,
        );
    }
    Ok(())
}

/// Adds the velocity-gradient pass once.
pub fn ensure_velocity_gradient<V: Vector>(sim: &mut Sim<V>) -> Result<(), SimError> {
    if sim.enable_feature("velocity_gradient") {
        let spec = ColumnSpec::restart_only("velocity_gradient");
        sim.add_column(spec, |_| VelocityGradient::<V>(V::Mat::zero()))?;
        sim.add_system(
            StepSet::Gradients,
            "velocity_gradient (Eq. 7.4)",
            velocity_gradient::<V>,
        );
    }
    Ok(())
}
