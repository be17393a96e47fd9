//! Pass 1 of the dual-support sweep for one owner row: the candidates inside `h_i` are
//! compacted into per-thread SoA scratch, their kernel gradients evaluated in one dispatch-free
//! loop, every [`PairTerm`] called once on the row, and i's sums and the reactions formed.

use super::{Bound, SweepCtx};
use crate::components::Position;
use crate::kernels::with_kernel_kind;
use crate::math::{Matrix, Real, Vector};
use crate::pair::{OwnerKernel, PairOut, Row};

/// What pass 1 stores for one support slot (i owner, j the slot's particle): the force on i,
/// whose reaction `−force` j receives, and the power credited to j (`m_j ε̇_j`). Zero for a
/// candidate outside `h_i`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Reaction<V: Vector> {
    pub(super) force: V,
    pub(super) power: Real,
}

impl<V: Vector> Default for Reaction<V> {
    fn default() -> Self {
        Reaction {
            force: V::zero(),
            power: 0.0,
        }
    }
}

/// Per-thread scratch of pass 1: one row's pairs (SoA), their slots and their results.
#[derive(Default)]
pub(super) struct RowScratch<V: Vector> {
    j: Vec<u32>,
    slot: Vec<u32>,
    rij: Vec<V>,
    r: Vec<Real>,
    vij: Vec<V>,
    grad_raw: Vec<V>,
    grad: Vec<V>,
    out: Vec<PairOut<V>>,
}

impl<V: Vector> RowScratch<V> {
    /// The compacted pairs `0..n`: `j`, slot, `r_ij`, `|r_ij|²` (see [`compact_row_into`]).
    #[inline(always)]
    pub(super) fn compacted(&self, n: usize) -> (&[u32], &[u32], &[V], &[Real]) {
        (&self.j[..n], &self.slot[..n], &self.rij[..n], &self.r[..n])
    }

    /// Makes every array hold at least `m` entries (grows only; never shrinks).
    #[inline(always)]
    fn reserve(&mut self, m: usize) {
        if self.j.len() < m {
            self.grow(m);
        }
    }

    #[cold]
    #[inline(never)]
    fn grow(&mut self, m: usize) {
        self.j.resize(m, 0);
        self.slot.resize(m, 0);
        self.rij.resize(m, V::zero());
        self.r.resize(m, 0.0);
        self.vij.resize(m, V::zero());
        self.grad_raw.resize(m, V::zero());
        self.grad.resize(m, V::zero());
        self.out.resize(m, PairOut::default());
    }
}

/// Compacts the candidates with `|r_ij|² < h_i²` into the front of the row arrays (`j`, slot,
/// `r_ij`, `|r_ij|²` in `r2s`) and returns their number. Branch-free: every candidate is
/// written at the next free place and the place is kept only if it is inside. Every reaction
/// slot of the row is zeroed on the way (pass 1 overwrites those of the pairs afterwards).
#[inline(always)]
fn compact_row<V: Vector>(
    cand: &[u32],
    pos: &[Position<V>],
    xi: V,
    h2: Real,
    (js, slots, rijs, r2s): (&mut [u32], &mut [u32], &mut [V], &mut [Real]),
    reactions: &mut [Reaction<V>],
) -> usize {
    let m = cand.len();
    let (js, slots, rijs, r2s) = (&mut js[..m], &mut slots[..m], &mut rijs[..m], &mut r2s[..m]);
    let mut n = 0;
    for ((slot, &j), reaction) in cand.iter().enumerate().zip(&mut reactions[..m]) {
        let rij = xi - pos[j as usize].0;
        let r2 = rij.length_squared();
        // n <= slot < m: the writes stay in bounds
        js[n] = j;
        slots[n] = slot as u32;
        rijs[n] = rij;
        r2s[n] = r2;
        *reaction = Reaction::default();
        n += (r2 < h2) as usize;
    }
    n
}

/// Owner i's kernel, and i's candidates inside `h_i` compacted into the scratch (see
/// [`compact_row`]; `|r_ij|²` goes to `r`) with i's reaction slots zeroed: returns the kernel
/// and the number of pairs.
#[inline(always)]
pub(super) fn compact_row_into<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    i: usize,
    s: &mut RowScratch<V>,
    reactions: &mut [Reaction<V>],
) -> (OwnerKernel, usize) {
    let data = &ctx.data;
    let k = OwnerKernel::new(ctx.kernel, data.h[i].0);
    let cand = ctx.neighbours.support.row(i);
    s.reserve(cand.len());
    let n = compact_row(
        cand,
        data.pos,
        data.pos[i].0,
        k.h2,
        (&mut s.j, &mut s.slot, &mut s.rij, &mut s.r),
        reactions,
    );
    (k, n)
}

/// The per-pair quantities of the compacted row `0..n`, in one loop (a loop per quantity
/// costs a mispredicted exit each on rows of ~12 pairs): `r = √r²`, `∇_iW_ij = r_ij ·`
/// [`OwnerKernel::grad_factor`] (Eq. 2.2, the kind resolved once for the row), `v_ij`,
/// `L_i ∇_iW_ij` when `corrected` (Eq. 2.10), the zeroed term output, and, when `drho`, returns
/// `Σ_{j∈H_i} m_j v_ij·∇_iW_ij` (Eq. 4.9, summed in the row's order).
#[inline(always)]
fn prepare_pairs<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    i: usize,
    k: OwnerKernel,
    drho: bool,
    n: usize,
    s: &mut RowScratch<V>,
) -> Real {
    let (vel, mass) = (ctx.data.vel, ctx.data.mass);
    let vi = vel[i].0;
    let corrected = ctx.correction.is_some();
    let l = match ctx.correction {
        Some(l) => l[i].0,
        None => V::Mat::identity(),
    };
    let (kind, g_norm, inv_h) = k.factor_parts();
    let mut sum = 0.0;
    macro_rules! each {
        ($kind:expr) => {{
            let rows = s.r[..n]
                .iter_mut()
                .zip(&s.rij[..n])
                .zip(&s.j[..n])
                .zip(&mut s.grad_raw[..n])
                .zip(&mut s.grad[..n])
                .zip(&mut s.vij[..n])
                .zip(&mut s.out[..n]);
            for ((((((r, &rij), &j), g_raw), g), v), o) in rows {
                *r = r.sqrt();
                let raw = rij * OwnerKernel::factor_of($kind, g_norm, inv_h, *r);
                *g_raw = raw;
                let vij = vi - vel[j as usize].0;
                *v = vij;
                if corrected {
                    *g = l.mul_vec(raw);
                }
                if drho {
                    sum += mass[j as usize].0 * vij.dot(raw);
                }
                *o = PairOut::default();
            }
        }};
    }
    with_kernel_kind!(kind, K => each!(K));
    sum
}

/// Pass 1 for one owner i: gathers `H_i` from the candidate row, evaluates every term row by
/// row, returns i's own sums and writes the reactions into the row's slots (zero for
/// candidates outside `h_i`); with `drho`, also `dρ_i/dt = Σ_{j∈H_i} m_j v_ij·∇_iW_ij`
/// (Eq. 4.9).
#[inline]
pub(super) fn owner_row<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &Bound<'_, V>,
    i: usize,
    s: &mut RowScratch<V>,
    reactions: &mut [Reaction<V>],
    drho: Option<&mut Real>,
) -> (V, Real) {
    let (k, n) = compact_row_into(ctx, i, s, reactions);
    let corrected = ctx.correction.is_some();
    let drho_sum = prepare_pairs(ctx, i, k, drho.is_some(), n, s);
    let out = &mut s.out[..n];
    let row = Row {
        i,
        j: &s.j[..n],
        rij: &s.rij[..n],
        r: &s.r[..n],
        vij: &s.vij[..n],
        grad_raw: &s.grad_raw[..n],
        grad: if corrected {
            &s.grad[..n]
        } else {
            &s.grad_raw[..n]
        },
        kernel: k,
        data: &ctx.data,
    };
    for t in terms {
        t.interact_row(&row, out);
    }
    if let Some(d) = drho {
        *d = drho_sum;
    }
    let mut f_own = V::zero();
    let mut p_own = 0.0;
    for (o, &slot) in out.iter().zip(&s.slot[..n]) {
        f_own += o.force;
        p_own += o.power_i;
        reactions[slot as usize] = Reaction {
            force: o.force,
            power: o.power_j,
        };
    }
    (f_own, p_own)
}
