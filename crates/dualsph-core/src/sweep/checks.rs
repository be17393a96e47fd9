//! Test helpers for pair terms that override [`PairTerm::interact_row`]: the row path must
//! give bitwise the results of the pair-by-pair path.

use super::*;

/// Checks [`check_row_matches_interact`] for a 2-D term on a jittered 20 × 20 lattice with
/// varying h, velocities, masses, densities, pressures and sound speeds (a fixed LCG), first
/// without and then with a non-trivial kernel-gradient correction: the fixture every plugin
/// that overrides `interact_row` tests itself on.
pub fn check_row_override_2d(term: &dyn PairTerm<glam::DVec2>) -> Result<(), String> {
    use glam::{DMat2, DVec2};
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as Real / (1u64 << 53) as Real
    };
    let n = 20 * 20;
    let mut f = Fields::<DVec2>::default();
    f.resize(n);
    f.pressure = vec![0.0; n];
    f.sound = vec![0.0; n];
    for i in 0..n {
        f.pos[i] = DVec2::new((i % 20) as Real, (i / 20) as Real) + DVec2::new(rnd(), rnd()) * 0.4;
        f.vel[i] = DVec2::new(rnd() - 0.5, rnd() - 0.5);
        f.mass[i] = 0.8 + 0.4 * rnd();
        f.rho[i] = 950.0 + 100.0 * rnd();
        f.h[i] = 1.2 + 1.5 * rnd();
        f.pressure[i] = rnd() * 1e3 - 200.0;
        f.sound[i] = 10.0 + rnd();
    }
    let mut nb = Neighbours::new(0.1);
    nb.rebuild(&f.pos, &f.h);
    let kernel = Kernel::new(crate::kernels::KernelKind::CubicSpline, 2);
    for corrected in [false, true] {
        if corrected {
            f.correction = (0..n)
                .map(|i| {
                    let a = 1.0 + 0.01 * (i % 7) as Real;
                    DMat2::from_cols_array(&[a, 0.02, -0.01, 1.0 / a])
                })
                .collect();
        }
        let ctx = SweepCtx {
            fields: &f,
            neighbours: &nb,
            kernel: &kernel,
            formulation: Formulation::DualSupport,
        };
        check_row_matches_interact(term, &ctx)
            .map_err(|e| format!("correction {corrected}: {e}"))?;
    }
    Ok(())
}

/// Checks that a term's [`PairTerm::interact_row`] gives bitwise the same results as its
/// [`PairTerm::interact`] on every row of `ctx` (for terms that override `interact_row`);
/// the error names the first differing pair.
pub fn check_row_matches_interact<V: Vector>(
    term: &dyn PairTerm<V>,
    ctx: &SweepCtx<'_, V>,
) -> Result<(), String> {
    let fl = ctx.fields;
    for i in 0..fl.len() {
        let (mut js, mut rijs, mut rs, mut raw, mut grad, mut pairs) =
            (vec![], vec![], vec![], vec![], vec![], vec![]);
        ctx.for_each_neighbour(i, |j, rij, r, w, g| {
            let gc = fl.corrected(i, g);
            js.push(j as u32);
            rijs.push(rij);
            rs.push(r);
            raw.push(g);
            grad.push(gc);
            let mut out = PairOut::default();
            let pair = Pair {
                i,
                j,
                rij,
                r,
                w,
                grad_raw: g,
                grad: gc,
                fields: fl,
            };
            term.interact(&pair, &mut out);
            pairs.push(out);
        });
        let vijs: Vec<V> = js.iter().map(|&j| fl.vel[i] - fl.vel[j as usize]).collect();
        let row = Row {
            i,
            j: &js,
            rij: &rijs,
            r: &rs,
            vij: &vijs,
            grad_raw: &raw,
            grad: &grad,
            kernel: OwnerKernel::new(ctx.kernel, fl.h[i]),
            fields: fl,
        };
        let mut outs = vec![PairOut::default(); js.len()];
        term.interact_row(&row, &mut outs);
        for (k, (a, b)) in outs.iter().zip(&pairs).enumerate() {
            let same = a.force.to_xyz().map(f64::to_bits) == b.force.to_xyz().map(f64::to_bits)
                && a.power_i.to_bits() == b.power_i.to_bits()
                && a.power_j.to_bits() == b.power_j.to_bits();
            if !same {
                return Err(format!(
                    "{}: pair ({i}, {}): interact_row {a:?}, interact {b:?}",
                    term.name(),
                    js[k]
                ));
            }
        }
    }
    Ok(())
}
