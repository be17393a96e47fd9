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

use crate::components::{Acceleration, DensityRate, EnergyRate, ParticleId};
use crate::kernels::{Kernel, KernelKind};
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

/// One owner's support `H_i` as the sweep hands it to [`PairTerm::interact_row`]: the
/// neighbours `j` strictly inside `h_i`, ascending, with the pair geometry as parallel slices
/// (`rij[k]`, `r[k]`, `grad_raw[k]`, `grad[k]` belong to `j[k]`).
#[derive(Clone, Copy, Debug)]
pub struct Row<'a, V: Vector> {
    /// The owner i.
    pub i: usize,
    /// `j ∈ H_i`, ascending.
    pub j: &'a [u32],
    /// `r_ij = r_i − r_j`.
    pub rij: &'a [V],
    /// `|r_ij|`.
    pub r: &'a [Real],
    /// `∇_i W_ij` as is (Eq. 2.2).
    pub grad_raw: &'a [V],
    /// `∇_i W_ij` with `L_i` applied when the correction is active (Eq. 2.10); the same slice
    /// as `grad_raw` otherwise.
    pub grad: &'a [V],
    /// The owner's kernel (for `W_ij`, computed on demand by [`Row::w`]).
    pub kernel: OwnerKernel,
    /// All particle data.
    pub fields: &'a Fields<V>,
}

impl<'a, V: Vector> Row<'a, V> {
    /// Number of pairs.
    #[inline]
    pub fn len(&self) -> usize {
        self.j.len()
    }

    /// True when `H_i` is empty.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.j.is_empty()
    }

    /// `W_ij = W(r_ij, h_i)` of the k-th pair (Eq. 2.1).
    #[inline]
    pub fn w(&self, k: usize) -> Real {
        self.kernel.w(self.r[k])
    }

    /// The k-th pair of the row.
    #[inline]
    pub fn pair(&self, k: usize) -> Pair<'a, V> {
        Pair {
            i: self.i,
            j: self.j[k] as usize,
            rij: self.rij[k],
            r: self.r[k],
            w: self.w(k),
            grad_raw: self.grad_raw[k],
            grad: self.grad[k],
            fields: self.fields,
        }
    }
}

/// A physics term that joins the pair sweep. Implementations add their contribution to `out`
/// for the pair (i owner, j ∈ H_i) and inherit the sweep's conservation and determinism.
///
/// Only [`PairTerm::interact`] must be written. The sweep calls [`PairTerm::interact_row`]
/// once per owner and term; its default loops over the row calling `interact`, statically
/// dispatched and inlined, so a term costs one dynamic call per particle, not per pair.
/// Override it only to vectorise a term by hand; it must give the same `out` as the default.
pub trait PairTerm<V: Vector>: Send + Sync + 'static {
    /// Name shown by `plan`.
    fn name(&self) -> &str;
    /// Adds this term's force and energy rates for the pair.
    fn interact(&self, pair: &Pair<'_, V>, out: &mut PairOut<V>);
    /// Adds this term to `out[k]` for every pair `k` of the row (`out.len() == row.len()`).
    #[inline]
    fn interact_row(&self, row: &Row<'_, V>, out: &mut [PairOut<V>]) {
        for (k, o) in out.iter_mut().enumerate() {
            self.interact(&row.pair(k), o);
        }
    }
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

/// The kernel of one owner i with its normalisations computed once:
/// `W(r, h_i) = C_d h_i^{-d} f(r/h_i)` (Eq. 2.1) and `∇_iW = C_d h_i^{-d-1} f'(r/h_i) r_ij/r`
/// (Eq. 2.2) — what [`Kernel::w`] and [`Kernel::grad`] give inside the support (to round-off:
/// `q = r · (1/h_i)`), without their per-call divisions by powers of h.
#[derive(Clone, Copy, Debug)]
pub struct OwnerKernel {
    kind: KernelKind,
    inv_h: Real,
    /// `h_i²`: a candidate is in `H_i` when `r² < h_i²`.
    pub h2: Real,
    w_norm: Real,
    g_norm: Real,
}

impl OwnerKernel {
    /// The kernel of an owner with support radius `h`.
    #[inline]
    pub fn new(kernel: &Kernel, h: Real) -> Self {
        let hd = match kernel.dim {
            1 => h,
            2 => h * h,
            _ => h * h * h,
        };
        OwnerKernel {
            kind: kernel.kind,
            inv_h: 1.0 / h,
            h2: h * h,
            w_norm: kernel.norm / hd,
            g_norm: kernel.norm / (hd * h),
        }
    }

    /// `W(r, h_i)` (Eq. 2.1) for `r < h_i`.
    #[inline(always)]
    pub fn w(&self, r: Real) -> Real {
        self.w_norm * self.kind.profile(r * self.inv_h)
    }

    /// `∇_iW_ij` (Eq. 2.2) for `r = |r_ij| < h_i` (0 at `r = 0`).
    #[inline(always)]
    pub fn grad<V: Vector>(&self, rij: V, r: Real) -> V {
        if r > 0.0 {
            rij * (self.g_norm * self.kind.profile_derivative(r * self.inv_h) / r)
        } else {
            V::zero()
        }
    }

    /// `(W_ij, ∇_iW_ij)` for `r = |r_ij| < h_i`.
    #[inline(always)]
    pub fn eval<V: Vector>(&self, rij: V, r: Real) -> (Real, V) {
        (self.w(r), self.grad(rij, r))
    }
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
                let k = OwnerKernel::new(self.kernel, hi);
                for &j in self.neighbours.support.row(i) {
                    let j = j as usize;
                    let rij = xi - fl.pos[j];
                    let r2 = rij.length_squared();
                    if r2 < k.h2 {
                        let r = r2.sqrt();
                        let (w, g) = k.eval(rij, r);
                        f(j, rij, r, w, g);
                    }
                }
            }
        }
    }
}

/// Particles per parallel work item of the sweep (a chunk's slots are contiguous).
const CHUNK: usize = 64;

/// Splits a slot buffer at the slot boundaries of consecutive chunks of `CHUNK` rows.
fn split_chunks_mut<'a, T>(mut buf: &'a mut [T], offsets: &[u32]) -> Vec<&'a mut [T]> {
    let n = offsets.len().saturating_sub(1);
    let mut out = Vec::with_capacity(n.div_ceil(CHUNK));
    let mut start = 0;
    while start < n {
        let end = (start + CHUNK).min(n);
        let (chunk, rest) = buf.split_at_mut((offsets[end] - offsets[start]) as usize);
        out.push(chunk);
        buf = rest;
        start = end;
    }
    out
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
    /// When true, the dual-support sweep also forms the own-support continuity sum
    /// `dρ_i/dt = Σ_{j∈H_i} m_j v_ij·∇_iW_ij` (Eq. 4.9) from the kernel gradients it evaluates
    /// anyway, into `density_rate` (same terms, same order as [`crate::passes::continuity_pairwise`]).
    pub with_density_rate: bool,
    /// `dρ_i/dt` from the last sweep (when `with_density_rate`).
    pub density_rate: Vec<Real>,
}

/// Marker resource: the scene integrates the density with the pairwise continuity equation
/// (Eq. 4.9), which the dual-support sweep then computes alongside the pair terms.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct ContinuityInSweep;

/// True when the pair sweep of this step forms `dρ/dt` (Eq. 4.9): continuity is requested,
/// there are pair terms and the formulation uses the dual-support path.
pub fn continuity_in_sweep(requested: bool, has_terms: bool, formulation: Formulation) -> bool {
    requested
        && has_terms
        && matches!(
            formulation,
            Formulation::DualSupport | Formulation::ConstantH
        )
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

/// Per-thread scratch of pass 1: one row's pairs (SoA), their slots and their results.
#[derive(Default)]
struct RowScratch<V: Vector> {
    j: Vec<u32>,
    slot: Vec<u32>,
    rij: Vec<V>,
    r: Vec<Real>,
    grad_raw: Vec<V>,
    grad: Vec<V>,
    out: Vec<PairOut<V>>,
}

/// Compacts the candidates inside `h_i` into the row arrays (returns their number) and zeroes
/// the reaction slots of the others. Separate slices let the compiler keep them in registers.
#[inline(always)]
fn gather_row<V: Vector>(
    cand: &[u32],
    pos: &[V],
    xi: V,
    k: &OwnerKernel,
    (js, slots, rijs, rs, grads): (&mut [u32], &mut [u32], &mut [V], &mut [Real], &mut [V]),
    frow: &mut [V],
    prow: &mut [Real],
) -> usize {
    let mut n = 0;
    for (slot, &j) in cand.iter().enumerate() {
        let rij = xi - pos[j as usize];
        let r2 = rij.length_squared();
        if r2 < k.h2 {
            let r = r2.sqrt();
            js[n] = j;
            slots[n] = slot as u32;
            rijs[n] = rij;
            rs[n] = r;
            grads[n] = k.grad(rij, r);
            n += 1;
        } else {
            frow[slot] = V::zero();
            prow[slot] = 0.0;
        }
    }
    n
}

/// Pass 1 for one owner i: gathers `H_i` from the candidate row, evaluates every term row by
/// row, returns i's own sums and writes the reactions into the row's slots (zero for
/// candidates outside `h_i`).
#[inline]
fn owner_row<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn PairTerm<V>>],
    i: usize,
    s: &mut RowScratch<V>,
    frow: &mut [V],
    prow: &mut [Real],
    drho: Option<&mut Real>,
) -> (V, Real) {
    let fl = ctx.fields;
    let (xi, k) = (fl.pos[i], OwnerKernel::new(ctx.kernel, fl.h[i]));
    let cand = ctx.neighbours.support.row(i);
    let m = cand.len();
    s.j.resize(m, 0);
    s.slot.resize(m, 0);
    s.rij.resize(m, V::zero());
    s.r.resize(m, 0.0);
    s.grad_raw.resize(m, V::zero());
    let n = gather_row(
        cand,
        &fl.pos,
        xi,
        &k,
        (&mut s.j, &mut s.slot, &mut s.rij, &mut s.r, &mut s.grad_raw),
        frow,
        prow,
    );
    let corrected = !fl.correction.is_empty();
    if corrected {
        let l = fl.correction[i];
        s.grad.clear();
        s.grad.extend(s.grad_raw[..n].iter().map(|&g| l.mul_vec(g)));
    }
    s.out.clear();
    s.out.resize(n, PairOut::default());
    let row = Row {
        i,
        j: &s.j[..n],
        rij: &s.rij[..n],
        r: &s.r[..n],
        grad_raw: &s.grad_raw[..n],
        grad: if corrected {
            &s.grad[..n]
        } else {
            &s.grad_raw[..n]
        },
        kernel: k,
        fields: fl,
    };
    for t in terms {
        t.interact_row(&row, &mut s.out);
    }
    if let Some(d) = drho {
        let (vi, vel, mass) = (fl.vel[i], &fl.vel[..], &fl.mass[..]);
        let mut sum = 0.0;
        for (&j, &g) in row.j.iter().zip(row.grad_raw) {
            let j = j as usize;
            sum += mass[j] * (vi - vel[j]).dot(g);
        }
        *d = sum;
    }
    let mut f_own = V::zero();
    let mut p_own = 0.0;
    for (o, &slot) in s.out.iter().zip(&s.slot[..n]) {
        f_own += o.force;
        p_own += o.power_i;
        frow[slot as usize] = o.force;
        prow[slot as usize] = o.power_j;
    }
    (f_own, p_own)
}

fn dual_support<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn PairTerm<V>>],
    buf: &mut SweepBuffers<V>,
) {
    let nb = ctx.neighbours;
    let offsets = &nb.support.offsets;
    let slots = nb.support.indices.len();
    // every slot is written by pass 1: no clearing needed
    buf.pair_force.resize(slots, V::zero());
    buf.pair_power.resize(slots, 0.0);
    let f_chunks = split_chunks_mut(&mut buf.pair_force, offsets);
    let p_chunks = split_chunks_mut(&mut buf.pair_power, offsets);
    let with_drho = buf.with_density_rate;
    buf.density_rate.resize(ctx.fields.len(), 0.0);
    // pass 1: own support, store reactions per slot; chunks of CHUNK owners
    buf.force
        .par_chunks_mut(CHUNK)
        .zip(buf.power.par_chunks_mut(CHUNK))
        .zip(buf.density_rate.par_chunks_mut(CHUNK))
        .zip(f_chunks.into_par_iter().zip(p_chunks))
        .enumerate()
        .for_each_init(
            RowScratch::default,
            |s, (c, (((fc, pc), dc), (pfc, ppc)))| {
                let base = offsets[c * CHUNK] as usize;
                for (k, ((fi, pi), di)) in fc.iter_mut().zip(pc.iter_mut()).zip(dc).enumerate() {
                    let i = c * CHUNK + k;
                    let r = offsets[i] as usize - base..offsets[i + 1] as usize - base;
                    let drho = with_drho.then_some(di);
                    (*fi, *pi) =
                        owner_row(ctx, terms, i, s, &mut pfc[r.clone()], &mut ppc[r], drho);
                }
            },
        );
    // pass 2: reactions through the dual-support (transpose), ascending i
    let (pf, pp) = (&buf.pair_force, &buf.pair_power);
    buf.force
        .par_iter_mut()
        .zip(buf.power.par_iter_mut())
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(j, (fj, pj))| {
            let mut f_dual = V::zero();
            let mut p_dual = 0.0;
            for &slot in &nb.dual_slot[nb.dual.slots(j)] {
                let slot = slot as usize;
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
#[inline(never)] // a frame of its own in profiles
pub fn pair_sweep_system<V: Vector>(
    fields: Res<Fields<V>>,
    neighbours: Res<Neighbours<V>>,
    terms: Res<PairTerms<V>>,
    kernel: Res<KernelRes>,
    formulation: Res<Formulation>,
    mut buf: ResMut<SweepBuffers<V>>,
    continuity: Option<Res<ContinuityInSweep>>,
    mut q: Query<(
        &ParticleId,
        &mut Acceleration<V>,
        Option<&mut EnergyRate>,
        Option<&mut DensityRate>,
    )>,
) {
    let ctx = SweepCtx {
        fields: &fields,
        neighbours: &neighbours,
        kernel: &kernel.0,
        formulation: *formulation,
    };
    buf.with_density_rate =
        continuity_in_sweep(continuity.is_some(), !terms.terms.is_empty(), *formulation);
    evaluate(&ctx, &terms.terms, &mut buf);
    let with_drho = buf.with_density_rate;
    q.par_iter_mut().for_each(|(id, mut a, e, d)| {
        let i = id.0 as usize;
        a.0 = buf.force[i] / fields.mass[i];
        if let Some(mut e) = e {
            e.rate = buf.power[i] / fields.mass[i];
        }
        if with_drho && let Some(mut d) = d {
            d.rate = buf.density_rate[i];
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
