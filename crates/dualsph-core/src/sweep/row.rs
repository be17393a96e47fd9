//! Pass 1 of the dual-support sweep for one owner row: the candidates inside `h_i` are
//! compacted into per-thread SoA scratch, their kernel gradients evaluated in one dispatch-free
//! loop, every [`PairTerm`] called once on the row, and i's sums and the reactions formed.

use super::SweepCtx;
use crate::math::{Matrix, Real, Vector};
use crate::pair::{OwnerKernel, PairOut, PairTerm, Row};
use std::sync::Arc;

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
    factor: Vec<Real>,
    grad_raw: Vec<V>,
    grad: Vec<V>,
    out: Vec<PairOut<V>>,
}

impl<V: Vector> RowScratch<V> {
    /// Makes every array hold at least `m` entries (grows only; never shrinks).
    #[inline]
    fn reserve(&mut self, m: usize) {
        if self.j.len() < m {
            self.j.resize(m, 0);
            self.slot.resize(m, 0);
            self.rij.resize(m, V::zero());
            self.r.resize(m, 0.0);
            self.vij.resize(m, V::zero());
            self.factor.resize(m, 0.0);
            self.grad_raw.resize(m, V::zero());
            self.grad.resize(m, V::zero());
            self.out.resize(m, PairOut::default());
        }
    }
}

/// Compacts the candidates with `|r_ij|² < h_i²` into the front of the row arrays (`j`, slot,
/// `r_ij`, `|r_ij|²` in `r2s`) and returns their number. Branch-free: every candidate is
/// written at the next free place and the place is kept only if it is inside; every reaction
/// slot is zeroed (pass 1 overwrites those of the pairs afterwards).
#[inline(always)]
fn compact_row<V: Vector>(
    cand: &[u32],
    pos: &[V],
    xi: V,
    h2: Real,
    (js, slots, rijs, r2s): (&mut [u32], &mut [u32], &mut [V], &mut [Real]),
    reactions: &mut [Reaction<V>],
) -> usize {
    let m = cand.len();
    let (js, slots, rijs, r2s) = (&mut js[..m], &mut slots[..m], &mut rijs[..m], &mut r2s[..m]);
    let reactions = &mut reactions[..m];
    let mut n = 0;
    for (slot, &j) in cand.iter().enumerate() {
        let rij = xi - pos[j as usize];
        let r2 = rij.length_squared();
        // n <= slot < m: the writes stay in bounds
        let at = n.min(slot);
        js[at] = j;
        slots[at] = slot as u32;
        rijs[at] = rij;
        r2s[at] = r2;
        reactions[slot] = Reaction::default();
        n += (r2 < h2) as usize;
    }
    n
}

/// Pass 1 for one owner i: gathers `H_i` from the candidate row, evaluates every term row by
/// row, returns i's own sums and writes the reactions into the row's slots (zero for
/// candidates outside `h_i`); with `drho`, also `dρ_i/dt = Σ_{j∈H_i} m_j v_ij·∇_iW_ij`
/// (Eq. 4.9).
#[inline]
pub(super) fn owner_row<V: Vector>(
    ctx: &SweepCtx<'_, V>,
    terms: &[Arc<dyn PairTerm<V>>],
    i: usize,
    s: &mut RowScratch<V>,
    reactions: &mut [Reaction<V>],
    drho: Option<&mut Real>,
) -> (V, Real) {
    let fl = ctx.fields;
    let (xi, k) = (fl.pos[i], OwnerKernel::new(ctx.kernel, fl.h[i]));
    let cand = ctx.neighbours.support.row(i);
    s.reserve(cand.len());
    let n = compact_row(
        cand,
        &fl.pos,
        xi,
        k.h2,
        (&mut s.j, &mut s.slot, &mut s.rij, &mut s.r),
        reactions,
    );
    // r² → r, then (1/r) ∂W/∂r, then ∇_iW = r_ij · factor (Eq. 2.2)
    for r in &mut s.r[..n] {
        *r = r.sqrt();
    }
    k.grad_factors(&s.r[..n], &mut s.factor[..n]);
    for ((g, &rij), &f) in s.grad_raw[..n]
        .iter_mut()
        .zip(&s.rij[..n])
        .zip(&s.factor[..n])
    {
        *g = rij * f;
    }
    let (vi, vel) = (fl.vel[i], &fl.vel[..]);
    for (v, &j) in s.vij[..n].iter_mut().zip(&s.j[..n]) {
        *v = vi - vel[j as usize];
    }
    let corrected = !fl.correction.is_empty();
    if corrected {
        let l = fl.correction[i];
        for (g, &raw) in s.grad[..n].iter_mut().zip(&s.grad_raw[..n]) {
            *g = l.mul_vec(raw);
        }
    }
    let out = &mut s.out[..n];
    out.fill(PairOut::default());
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
        fields: fl,
    };
    for t in terms {
        t.interact_row(&row, out);
    }
    if let Some(d) = drho {
        let mass = &fl.mass[..];
        let mut sum = 0.0;
        for ((&j, &v), &g) in row.j.iter().zip(row.vij).zip(row.grad_raw) {
            sum += mass[j as usize] * v.dot(g);
        }
        *d = sum;
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
