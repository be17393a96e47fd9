//! Test helpers for pair terms that override [`BoundTerm::interact_row`]: the row path must
//! give bitwise the results of the pair-by-pair path.

use super::*;
use crate::components::{GradientCorrection, Pressure, SoundSpeed};
use crate::store::{Cloud, insert_column};

/// A jittered 20 × 20 lattice with varying h, velocities, masses, densities, pressures and
/// sound speeds (a fixed LCG), as a world of particles: the fixture of
/// [`check_row_override_2d`].
pub fn lattice_2d() -> World {
    use glam::DVec2;
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as Real / (1u64 << 53) as Real
    };
    let n = 20 * 20;
    let mut c = Cloud::<DVec2>::new(n);
    let (mut p, mut s) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n {
        c.pos[i] = DVec2::new((i % 20) as Real, (i / 20) as Real) + DVec2::new(rnd(), rnd()) * 0.4;
        c.vel[i] = DVec2::new(rnd() - 0.5, rnd() - 0.5);
        c.mass[i] = 0.8 + 0.4 * rnd();
        c.rho[i] = 950.0 + 100.0 * rnd();
        c.h[i] = 1.2 + 1.5 * rnd();
        p[i] = rnd() * 1e3 - 200.0;
        s[i] = 10.0 + rnd();
    }
    let mut world = c.spawn();
    insert_column(&mut world, |i| Pressure(p[i]));
    insert_column(&mut world, |i| SoundSpeed(s[i]));
    world
}

/// Checks [`check_row_matches_interact`] for a 2-D term on `lattice_2d`, first without and
/// then with a non-trivial kernel-gradient correction: the fixture every plugin that
/// overrides `interact_row` tests itself on.
pub fn check_row_override_2d(term: &dyn DynPairTerm<glam::DVec2>) -> Result<(), String> {
    use glam::DMat2;
    let mut world = lattice_2d();
    let mut nb = Neighbours::new(0.1);
    {
        let data = ParticleData::<glam::DVec2>::of(&world).ok_or("no particles")?;
        let pos: Vec<_> = data.pos.iter().map(|p| p.0).collect();
        let h: Vec<_> = data.h.iter().map(|h| h.0).collect();
        nb.rebuild(&pos, &h);
    }
    let kernel = Kernel::new(crate::kernels::KernelKind::CubicSpline, 2);
    for corrected in [false, true] {
        if corrected {
            insert_column(&mut world, |i| {
                let a = 1.0 + 0.01 * (i % 7) as Real;
                GradientCorrection::<glam::DVec2>(DMat2::from_cols_array(&[
                    a,
                    0.02,
                    -0.01,
                    1.0 / a,
                ]))
            });
        }
        let data = ParticleData::of(&world).ok_or("no particles")?;
        let ctx = SweepCtx::new(data, &nb, &kernel, Formulation::DualSupport);
        let bound = term.bind_dyn(&data)?;
        check_row_matches_interact(term.name(), &*bound, &ctx)
            .map_err(|e| format!("correction {corrected}: {e}"))?;
    }
    Ok(())
}

/// Checks that a bound term's [`BoundTerm::interact_row`] gives bitwise the same results as
/// its [`BoundTerm::interact`] on every row of `ctx` (for terms that override
/// `interact_row`); the error names the first differing pair.
pub fn check_row_matches_interact<V: Vector>(
    name: &str,
    term: &dyn BoundTerm<V>,
    ctx: &SweepCtx<'_, V>,
) -> Result<(), String> {
    let data = &ctx.data;
    for i in 0..ctx.len() {
        let (mut js, mut rijs, mut rs, mut raw, mut grad, mut pairs) =
            (vec![], vec![], vec![], vec![], vec![], vec![]);
        ctx.for_each_neighbour(i, |j, rij, r, w, g| {
            let gc = ctx.corrected(i, g);
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
                data,
            };
            term.interact(&pair, &mut out);
            pairs.push(out);
        });
        let vijs: Vec<V> = js.iter().map(|&j| data.vij(i, j as usize)).collect();
        let row = Row {
            i,
            j: &js,
            rij: &rijs,
            r: &rs,
            vij: &vijs,
            grad_raw: &raw,
            grad: &grad,
            kernel: OwnerKernel::new(ctx.kernel, data.h[i].0),
            data,
        };
        let mut outs = vec![PairOut::default(); js.len()];
        term.interact_row(&row, &mut outs);
        for (k, (a, b)) in outs.iter().zip(&pairs).enumerate() {
            let same = a.force.to_xyz().map(f64::to_bits) == b.force.to_xyz().map(f64::to_bits)
                && a.power_i.to_bits() == b.power_i.to_bits()
                && a.power_j.to_bits() == b.power_j.to_bits();
            if !same {
                return Err(format!(
                    "{name}: pair ({i}, {}): interact_row {a:?}, interact {b:?}",
                    js[k]
                ));
            }
        }
    }
    Ok(())
}
