//! The support / dual-support pair sweep (paper 001 §6).
//!
//! For every `j ∈ H_i` a pair quantity is evaluated **once** with i's kernel
//! (`W_ij = w(r_ij/h_i)`, `∇_i W_ij`); i receives it and j receives the reaction through its
//! dual-support `H'_j`. Implementation, free of atomics and data races:
//!
//! 1. in parallel over i, loop over i's support slots, evaluate every [`PairTerm`], add the
//!    result to i's own sums and store the reaction in a per-slot buffer;
//! 2. in parallel over j, gather the stored reactions through the transposed (dual-support)
//!    list, in ascending order of i.
//!
//! Every particle's sums are formed in a fixed order that does not depend on the number of
//! threads, so results are bitwise identical on 1 or N threads, and because each pair's
//! action and reaction are the same stored numbers with opposite sign, linear momentum (and
//! the energy exchanged by each pair) balances to round-off for any field of h.
//!
//! [`Formulation`] selects the paper's comparison cases:
//! * `DualSupport` — the method;
//! * `SingleSupport` — variable h, each particle sums the full classical expression over its own
//!   support only with its own kernel, no reaction (paper Cases I/II): the classical term
//!   `F_i = Σ_{j∈H_i} [T(i←j; ∇_iW_ij(h_i)) − T(j←i; −∇_iW_ij(h_i))]`;
//! * `ConstantH` — classical SPH with one h (run with the dual-support sweep, to which it is
//!   identical when every h is equal);
//! * `AveragedKernel` — the conventional reference, Eq. 2.13:
//!   `W̄_ij = ½[W(r, h_i) + W(r, h_j)]` over `H_i ∪ H'_i`, classical symmetric sums.

use crate::components::{Acceleration, EnergyRate, ParticleId};
use crate::kernels::Kernel;
use crate::math::{Matrix, Real, Vector};
use crate::neighbours::Neighbours;
use crate::sim::{KernelRes, Sim, StepSet};
use bevy_ecs::prelude::*;
use rayon::prelude::*;
use std::sync::Arc;

/// How pair interactions are summed (see module docs).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// Support + dual-support, pair once with reaction (the DS-SPH method).
    DualSupport,
    /// Variable h, own support only, no reaction (not conservative).
    SingleSupport,
    /// One h for all particles.
    ConstantH,
    /// Averaged kernel over the union of support and dual-support (Eq. 2.13).
    AveragedKernel,
}

/// Dense per-particle arrays, indexed by [`ParticleId`], used by the hot loops. Optional
/// arrays are empty when the scene has no plugin that fills them.
#[derive(Resource, Clone, Debug)]
pub struct Fields<V: Vector> {
    /// Positions.
    pub pos: Vec<V>,
    /// Velocities.
    pub vel: Vec<V>,
    /// Masses.
    pub mass: Vec<Real>,
    /// Densities.
    pub rho: Vec<Real>,
    /// Support radii.
    pub h: Vec<Real>,
    /// Pressures (equation of state).
    pub pressure: Vec<Real>,
    /// Sound speeds (equation of state).
    pub sound: Vec<Real>,
    /// Specific internal energies (energy equation).
    pub eps: Vec<Real>,
    /// Thermal conductivities (heat conduction).
    pub kappa: Vec<Real>,
    /// Kernel-gradient corrections `L_i` (Eq. 2.10).
    pub correction: Vec<V::Mat>,
    /// Velocity gradients (Eq. 7.4).
    pub vgrad: Vec<V::Mat>,
}

impl<V: Vector> Default for Fields<V> {
    fn default() -> Self {
        Fields {
            pos: Vec::new(),
            vel: Vec::new(),
            mass: Vec::new(),
            rho: Vec::new(),
            h: Vec::new(),
            pressure: Vec::new(),
            sound: Vec::new(),
            eps: Vec::new(),
            kappa: Vec::new(),
            correction: Vec::new(),
            vgrad: Vec::new(),
        }
    }
}

impl<V: Vector> Fields<V> {
    /// Sizes the always-present arrays for n particles.
    pub fn resize(&mut self, n: usize) {
        self.pos.resize(n, V::zero());
        self.vel.resize(n, V::zero());
        self.mass.resize(n, 0.0);
        self.rho.resize(n, 0.0);
        self.h.resize(n, 0.0);
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// `m_i / ρ_i`.
    #[inline]
    pub fn volume(&self, i: usize) -> Real {
        self.mass[i] / self.rho[i]
    }

    /// Applies `L_owner` (Eq. 2.10) to a kernel gradient if the correction is active.
    #[inline]
    pub fn corrected(&self, owner: usize, g: V) -> V {
        if self.correction.is_empty() {
            g
        } else {
            self.correction[owner].mul_vec(g)
        }
    }
}

/// One evaluation of a pair: `owner` is the particle whose kernel and support are used.
#[derive(Clone, Copy, Debug)]
pub struct Pair<'a, V: Vector> {
    /// The owner i (kernel `W(·, h_i)`).
    pub i: usize,
    /// The neighbour j ∈ H_i.
    pub j: usize,
    /// `r_ij = r_i − r_j`.
    pub rij: V,
    /// `|r_ij|`.
    pub r: Real,
    /// `W_ij`.
    pub w: Real,
    /// `∇_i W_ij` as is.
    pub grad_raw: V,
    /// `∇_i W_ij`, with the kernel-gradient correction `L_i` applied when it is active.
    pub grad: V,
    /// All particle data.
    pub fields: &'a Fields<V>,
}

impl<V: Vector> Pair<'_, V> {
    /// `v_ij = v_i − v_j`.
    #[inline]
    pub fn vij(&self) -> V {
        self.fields.vel[self.i] - self.fields.vel[self.j]
    }
}

/// What one term gives for one pair: the force on the owner i (j receives `−force`) and the
/// rates of internal energy `m ε̇` credited to i and to j. A term conserves energy when
/// `power_i + power_j = −force · v_ij` (the pair's work goes into heat, nothing is lost).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairOut<V: Vector> {
    /// Force on i; the reaction `−force` acts on j.
    pub force: V,
    /// `m_i dε_i/dt` contribution.
    pub power_i: Real,
    /// `m_j dε_j/dt` contribution.
    pub power_j: Real,
}

impl<V: Vector> Default for PairOut<V> {
    fn default() -> Self {
        PairOut {
            force: V::zero(),
            power_i: 0.0,
            power_j: 0.0,
        }
    }
}

/// A physics term that joins the pair sweep. Implementations add their contribution to `out`
/// for the pair (i owner, j ∈ H_i) and inherit the sweep's conservation and determinism.
pub trait PairTerm<V: Vector>: Send + Sync + 'static {
    /// Name shown by `plan`.
    fn name(&self) -> &str;
    /// Adds this term's force and energy rates for the pair.
    fn interact(&self, pair: &Pair<'_, V>, out: &mut PairOut<V>);
}

/// The terms fused into the sweep, in order.
#[derive(Resource)]
pub struct PairTerms<V: Vector> {
    /// Terms.
    pub terms: Vec<Arc<dyn PairTerm<V>>>,
}

impl<V: Vector> Default for PairTerms<V> {
    fn default() -> Self {
        PairTerms { terms: Vec::new() }
    }
}

/// Everything a pass over neighbours needs.
#[derive(Clone, Copy)]
pub struct SweepCtx<'a, V: Vector> {
    /// Particle data.
    pub fields: &'a Fields<V>,
    /// Lists.
    pub neighbours: &'a Neighbours<V>,
    /// Kernel.
    pub kernel: &'a Kernel,
    /// Formulation.
    pub formulation: Formulation,
}

/// Visits the union of two ascending lists in ascending order.
fn for_each_union(a: &[u32], b: &[u32], mut f: impl FnMut(usize)) {
    let (mut x, mut y) = (0, 0);
    while x < a.len() || y < b.len() {
        let j = match (a.get(x), b.get(y)) {
            (Some(&p), Some(&q)) if p == q => {
                x += 1;
                y += 1;
                p
            }
            (Some(&p), Some(&q)) if p < q => {
                x += 1;
                p
            }
            (Some(_), Some(&q)) => {
                y += 1;
                q
            }
            (Some(&p), None) => {
                x += 1;
                p
            }
            (None, Some(&q)) => {
                y += 1;
                q
            }
            (None, None) => unreachable!(),
        };
        f(j as usize);
    }
}

impl<V: Vector> SweepCtx<'_, V> {
    /// Visits i's interpolation neighbourhood: `j ∈ H_i` with `W(r, h_i)` and its raw gradient,
    /// or for `AveragedKernel` the union `H_i ∪ H'_i` with the averaged kernel (Eq. 2.13).
    /// Callback: `(j, r_ij, r, W, ∇_iW)`. Used by own-support passes (density, correction,
    /// velocity gradient), which need no reaction.
    #[inline]
    pub fn for_each_neighbour(&self, i: usize, mut f: impl FnMut(usize, V, Real, Real, V)) {
        let fl = self.fields;
        let (xi, hi) = (fl.pos[i], fl.h[i]);
        match self.formulation {
            Formulation::AveragedKernel => for_each_union(
                self.neighbours.support.row(i),
                self.neighbours.dual.row(i),
                |j| {
                    let rij = xi - fl.pos[j];
                    let r = rij.length();
                    let hj = fl.h[j];
                    if r < hi.max(hj) {
                        let w = 0.5 * (self.kernel.w(r, hi) + self.kernel.w(r, hj));
                        let g = (self.kernel.grad(rij, r, hi) + self.kernel.grad(rij, r, hj)) * 0.5;
                        f(j, rij, r, w, g);
                    }
                },
            ),
            _ => {
                for &j in self.neighbours.support.row(i) {
                    let j = j as usize;
                    let rij = xi - fl.pos[j];
                    let r2 = rij.length_squared();
                    if r2 < hi * hi {
                        let r = r2.sqrt();
                        f(
                            j,
                            rij,
                            r,
                            self.kernel.w(r, hi),
                            self.kernel.grad(rij, r, hi),
                        );
                    }
                }
            }
        }
    }
}

/// Splits a slot buffer into the rows of a CSR.
fn split_rows_mut<'a, T>(mut buf: &'a mut [T], offsets: &[u32]) -> Vec<&'a mut [T]> {
    let mut rows = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (row, rest) = buf.split_at_mut((w[1] - w[0]) as usize);
        rows.push(row);
        buf = rest;
    }
    rows
}

#[inline]
fn eval_terms<V: Vector>(terms: &[Arc<dyn PairTerm<V>>], pair: &Pair<'_, V>) -> PairOut<V> {
    let mut out = PairOut::default();
    for t in terms {
        t.interact(pair, &mut out);
    }
    out
}

/// Reusable buffers of the sweep.
#[derive(Resource, Default)]
pub struct SweepBuffers<V: Vector> {
    pair_force: Vec<V>,
    pair_power: Vec<Real>,
    /// Total force on each particle from the last sweep.
    pub force: Vec<V>,
    /// Total `m ε̇` of each particle from the last sweep.
    pub power: Vec<Real>,
}

/// Evaluates all pair terms: the total force and internal-energy power `m ε̇` per particle.
pub fn evaluate<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn PairTerm<V>>],
    buf: &mut SweepBuffers<V>,
) {
    let n = ctx.fields.len();
    buf.force.resize(n, V::zero());
    buf.power.resize(n, 0.0);
    match ctx.formulation {
        Formulation::DualSupport | Formulation::ConstantH => dual_support(ctx, terms, buf),
        Formulation::SingleSupport | Formulation::AveragedKernel => classical(ctx, terms, buf),
    }
}

fn dual_support<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn PairTerm<V>>],
    buf: &mut SweepBuffers<V>,
) {
    let (fl, nb, kernel) = (ctx.fields, ctx.neighbours, ctx.kernel);
    let slots = nb.support.indices.len();
    buf.pair_force.clear();
    buf.pair_force.resize(slots, V::zero());
    buf.pair_power.clear();
    buf.pair_power.resize(slots, 0.0);
    let f_rows = split_rows_mut(&mut buf.pair_force, &nb.support.offsets);
    let p_rows = split_rows_mut(&mut buf.pair_power, &nb.support.offsets);
    // pass 1: own support, store reactions per slot
    f_rows
        .into_par_iter()
        .zip(p_rows)
        .zip(buf.force.par_iter_mut().zip(buf.power.par_iter_mut()))
        .enumerate()
        .for_each(|(i, ((frow, prow), (fi, pi)))| {
            let (xi, hi) = (fl.pos[i], fl.h[i]);
            let mut f_own = V::zero();
            let mut p_own = 0.0;
            for (k, &j) in nb.support.row(i).iter().enumerate() {
                let j = j as usize;
                let rij = xi - fl.pos[j];
                let r2 = rij.length_squared();
                if r2 >= hi * hi {
                    continue;
                }
                let r = r2.sqrt();
                let g = kernel.grad(rij, r, hi);
                let pair = Pair {
                    i,
                    j,
                    rij,
                    r,
                    w: kernel.w(r, hi),
                    grad_raw: g,
                    grad: fl.corrected(i, g),
                    fields: fl,
                };
                let out = eval_terms(terms, &pair);
                f_own += out.force;
                p_own += out.power_i;
                frow[k] = out.force;
                prow[k] = out.power_j;
            }
            *fi = f_own;
            *pi = p_own;
        });
    // pass 2: reactions through the dual-support (transpose), ascending i
    let (pf, pp) = (&buf.pair_force, &buf.pair_power);
    buf.force
        .par_iter_mut()
        .zip(buf.power.par_iter_mut())
        .enumerate()
        .for_each(|(j, (fj, pj))| {
            let mut f_dual = V::zero();
            let mut p_dual = 0.0;
            for s in nb.dual.slots(j) {
                let slot = nb.dual_slot[s] as usize;
                f_dual -= pf[slot];
                p_dual += pp[slot];
            }
            *fj += f_dual;
            *pj += p_dual;
        });
}

fn classical<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn PairTerm<V>>],
    buf: &mut SweepBuffers<V>,
) {
    let fl = ctx.fields;
    buf.force
        .par_iter_mut()
        .zip(buf.power.par_iter_mut())
        .enumerate()
        .for_each(|(i, (fi, pi))| {
            let mut f = V::zero();
            let mut p = 0.0;
            ctx.for_each_neighbour(i, |j, rij, r, w, g| {
                let own = Pair {
                    i,
                    j,
                    rij,
                    r,
                    w,
                    grad_raw: g,
                    grad: fl.corrected(i, g),
                    fields: fl,
                };
                let mirror = Pair {
                    i: j,
                    j: i,
                    rij: -rij,
                    r,
                    w,
                    grad_raw: -g,
                    grad: fl.corrected(j, -g),
                    fields: fl,
                };
                let a = eval_terms(terms, &own);
                let b = eval_terms(terms, &mirror);
                f += a.force - b.force;
                p += a.power_i + b.power_j;
            });
            *fi = f;
            *pi = p;
        });
}

/// The sweep as a scheduled system: writes `Acceleration` and, if present, `EnergyRate.rate`.
pub fn pair_sweep_system<V: Vector>(
    fields: Res<Fields<V>>,
    neighbours: Res<Neighbours<V>>,
    terms: Res<PairTerms<V>>,
    kernel: Res<KernelRes>,
    formulation: Res<Formulation>,
    mut buf: ResMut<SweepBuffers<V>>,
    mut q: Query<(&ParticleId, &mut Acceleration<V>, Option<&mut EnergyRate>)>,
) {
    let ctx = SweepCtx {
        fields: &fields,
        neighbours: &neighbours,
        kernel: &kernel.0,
        formulation: *formulation,
    };
    evaluate(&ctx, &terms.terms, &mut buf);
    q.par_iter_mut().for_each(|(id, mut a, e)| {
        let i = id.0 as usize;
        a.0 = buf.force[i] / fields.mass[i];
        if let Some(mut e) = e {
            e.rate = buf.power[i] / fields.mass[i];
        }
    });
}

pub(crate) fn add_sweep_system<V: Vector>(sim: &mut Sim<V>) {
    sim.world.insert_resource(SweepBuffers::<V>::default());
    sim.add_system(
        StepSet::Forces,
        "pair_sweep (support + dual-support)",
        pair_sweep_system::<V>,
    );
}

fn zero_accelerations<V: Vector>(mut q: Query<&mut Acceleration<V>>) {
    for mut a in &mut q {
        a.0 = V::zero();
    }
}

pub(crate) fn add_zero_acceleration_system<V: Vector>(sim: &mut Sim<V>) {
    sim.add_system(
        StepSet::Forces,
        "zero_accelerations",
        zero_accelerations::<V>,
    );
}
