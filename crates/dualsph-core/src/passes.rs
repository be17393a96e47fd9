//! Own-support passes: per-particle sums over `H_i` that need no reaction (the paper keeps
//! the continuity equation in its single-support form, §4). Each is a scheduled system that
//! reads the dense [`Fields`] and writes both the dense array and the particle component.

use crate::components::*;
use crate::kernels::Kernel;
use crate::math::{Matrix, Real, Vector};
use crate::neighbours::Neighbours;
use crate::sim::{KernelRes, Sim, StepSet};
use crate::sweep::{
    ContinuityInSweep, Fields, Formulation, OwnerKernel, PairTerms, SweepCtx, continuity_in_sweep,
};
use bevy_ecs::prelude::*;
use rayon::prelude::*;

macro_rules! ctx {
    ($f:expr, $nb:expr, $k:expr, $form:expr) => {
        SweepCtx {
            fields: &$f,
            neighbours: &$nb,
            kernel: &$k.0,
            formulation: *$form,
        }
    };
}

/// Summation density, Eq. 4.8: `ρ_i = m_i W(0, h_i) + Σ_{j∈H_i} m_j W_ij`.
#[inline(never)] // a frame of its own in profiles
pub fn summation_density<V: Vector>(
    mut fields: ResMut<Fields<V>>,
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    mut q: Query<(&ParticleId, &mut Density)>,
) {
    let rho: Vec<Real> = {
        let ctx = ctx!(fields, nb, kernel, form);
        (0..fields.len())
            .into_par_iter()
            .map(|i| {
                let mut s = fields.mass[i] * kernel.0.w(0.0, fields.h[i]);
                ctx.for_each_neighbour(i, |j, _, _, w, _| s += fields.mass[j] * w);
                s
            })
            .collect()
    };
    for (id, mut d) in &mut q {
        d.0 = rho[id.0 as usize];
    }
    fields.rho = rho;
}

/// Kernel-gradient correction, Eq. 2.10: `L_i = [Σ_{j∈H_i} V_j ∇_iW_ij ⊗ (r_j − r_i)]^{-1}`;
/// the identity where the sum is singular (too few neighbours).
#[inline(never)] // a frame of its own in profiles
pub fn kernel_correction<V: Vector>(
    mut fields: ResMut<Fields<V>>,
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    mut q: Query<(&ParticleId, &mut GradientCorrection<V>)>,
) {
    let l: Vec<V::Mat> = {
        let ctx = ctx!(fields, nb, kernel, form);
        (0..fields.len())
            .into_par_iter()
            .map(|i| {
                let mut a = V::Mat::zero();
                ctx.for_each_neighbour(i, |j, rij, _, _, g| {
                    a += V::outer(g, -rij) * fields.volume(j)
                });
                a.try_inverse(1e-6).unwrap_or_else(V::Mat::identity)
            })
            .collect()
    };
    for (id, mut c) in &mut q {
        c.0 = l[id.0 as usize];
    }
    fields.correction = l;
}

/// Velocity gradient, Eq. 7.4: `(∇⊗v)_i = −Σ_{j∈H_i} V_j v_ij ⊗ ∇̃_iW_ij`, entries `∂v_k/∂x_l`
/// (exact for linear fields when the correction is active).
#[inline(never)] // a frame of its own in profiles
pub fn velocity_gradient<V: Vector>(
    mut fields: ResMut<Fields<V>>,
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    mut q: Query<(&ParticleId, &mut VelocityGradient<V>)>,
) {
    let grads: Vec<V::Mat> = {
        let ctx = ctx!(fields, nb, kernel, form);
        (0..fields.len())
            .into_par_iter()
            .map(|i| {
                let mut gsum = V::Mat::zero();
                ctx.for_each_neighbour(i, |j, _, _, _, g| {
                    let vij = fields.vel[i] - fields.vel[j];
                    gsum += V::outer(vij, fields.corrected(i, g)) * (-fields.volume(j));
                });
                gsum
            })
            .collect()
    };
    for (id, mut c) in &mut q {
        c.0 = grads[id.0 as usize];
    }
    fields.vgrad = grads;
}

/// Continuity, Eq. 4.9: `dρ_i/dt = Σ_{j∈H_i} m_j v_ij · ∇_iW_ij`.
#[inline(never)] // a frame of its own in profiles
pub fn continuity_pairwise<V: Vector>(
    fields: Res<Fields<V>>,
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    form: Res<Formulation>,
    mut scratch: Local<Vec<Real>>,
    fused: Option<Res<ContinuityInSweep>>,
    terms: Option<Res<PairTerms<V>>>,
    mut q: Query<(&ParticleId, &mut DensityRate)>,
) {
    let has_terms = terms.is_some_and(|t| !t.terms.is_empty());
    if continuity_in_sweep(fused.is_some(), has_terms, *form) {
        return; // the pair sweep forms the same sums (see `SweepBuffers::with_density_rate`)
    }
    let ctx = ctx!(fields, nb, kernel, form);
    let mut rates = std::mem::take(&mut *scratch);
    rates.resize(fields.len(), 0.0);
    let f = &*fields;
    rates
        .par_iter_mut()
        .enumerate()
        .with_min_len(64)
        .for_each(|(i, out)| {
            *out = if *form == Formulation::AveragedKernel {
                let mut s = 0.0;
                ctx.for_each_neighbour(i, |j, _, _, _, g| {
                    s += f.mass[j] * (f.vel[i] - f.vel[j]).dot(g)
                });
                s
            } else {
                own_support_continuity(f, nb.support.row(i), i, &kernel.0)
            };
        });
    for (id, mut r) in &mut q {
        r.rate = rates[id.0 as usize];
    }
    *scratch = rates;
}

/// `Σ_{j∈H_i} m_j v_ij·∇_iW_ij` over a candidate row (Eq. 4.9), the same sum as through
/// [`SweepCtx::for_each_neighbour`] without evaluating `W`.
#[inline]
pub(crate) fn own_support_continuity<V: Vector>(
    f: &Fields<V>,
    row: &[u32],
    i: usize,
    kernel: &Kernel,
) -> Real {
    let (xi, vi, k) = (f.pos[i], f.vel[i], OwnerKernel::new(kernel, f.h[i]));
    let (pos, vel, mass) = (&f.pos[..], &f.vel[..], &f.mass[..]);
    let mut s = 0.0;
    for &j in row {
        let j = j as usize;
        let rij = xi - pos[j];
        let r2 = rij.length_squared();
        if r2 < k.h2 {
            s += mass[j] * (vi - vel[j]).dot(k.grad(rij, r2.sqrt()));
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
    fields: Res<Fields<V>>,
    mut q: Query<(&ParticleId, &mut DensityRate)>,
) {
    for (id, mut r) in &mut q {
        let i = id.0 as usize;
        r.rate = -fields.rho[i] * fields.vgrad[i].trace();
    }
}

/// Adds summation density once.
pub fn ensure_summation_density<V: Vector>(sim: &mut Sim<V>) {
    if sim.enable_feature("summation_density") {
        sim.add_system(
            StepSet::Density,
            "summation_density (Eq. 4.8)",
            summation_density::<V>,
        );
    }
}

/// Adds the kernel-gradient correction once.
pub fn ensure_kernel_correction<V: Vector>(sim: &mut Sim<V>) {
    if sim.enable_feature("kernel_correction") {
        sim.insert_particle_component(|_| GradientCorrection::<V>(V::Mat::identity()));
        sim.add_system(
            StepSet::Correction,
            "kernel_correction (Eq. 2.10)",
            kernel_correction::<V>,
        );
    }
}

/// Adds the velocity-gradient pass once.
pub fn ensure_velocity_gradient<V: Vector>(sim: &mut Sim<V>) {
    if sim.enable_feature("velocity_gradient") {
        sim.insert_particle_component(|_| VelocityGradient::<V>(V::Mat::zero()));
        sim.add_system(
            StepSet::Gradients,
            "velocity_gradient (Eq. 7.4)",
            velocity_gradient::<V>,
        );
    }
}
