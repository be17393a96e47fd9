//! Test helpers for pair terms: a term written over [`dualsph_core::lanes::Lanes`] must give, two
//! pairs at a time, bitwise what it gives one pair at a time.

use crate::block::RowTerm;
use crate::ctx::GradientCorrection;
use crate::pair::ParticleData;
use crate::pair::{Extra, Out, OwnerKernel};
use crate::{
    Binder, BoundTerm, DynPairTerm, PairLanes, PairTerm, SweepBuffers, SweepCtx, evaluate,
};
use bevy_ecs::prelude::*;
use dualsph_core::components::Acceleration;
use dualsph_core::kernels::Kernel;
use dualsph_core::lanes::{LaneVec, Lanes};
use dualsph_core::math::{Real, Vector};
use dualsph_core::neighbours::Neighbours;
use dualsph_core::sim::Formulation;
use dualsph_core::store::{Cloud, insert_column};
use std::sync::Arc;
use wide::f64x2;

/// A jittered 20 × 20 lattice with varying h, velocities, masses and densities (a fixed
/// LCG), the acceleration and a non-trivial kernel-gradient correction, as a world of
/// particles: the fixture of [`check_lanes_2d`] (a layer above adds the columns of its
/// vocabulary with [`check_lanes_2d_with`]).
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
    for i in 0..n {
        c.pos[i] = DVec2::new((i % 20) as Real, (i / 20) as Real) + DVec2::new(rnd(), rnd()) * 0.4;
        c.vel[i] = DVec2::new(rnd() - 0.5, rnd() - 0.5);
        c.mass[i] = 0.8 + 0.4 * rnd();
        c.rho[i] = 950.0 + 100.0 * rnd();
        c.h[i] = 1.2 + 1.5 * rnd();
    }
    let mut world = c.spawn();
    insert_column(&mut world, |_| Acceleration(DVec2::ZERO));
    insert_column(&mut world, |i| {
        let a = 1.0 + 0.01 * (i % 7) as Real;
        GradientCorrection::<DVec2>(glam::DMat2::from_cols_array(&[a, 0.02, -0.01, 1.0 / a]))
    });
    world
}

/// Runs `check` on [`lattice_2d`]'s particles (with the columns `extra` adds) with their
/// lists and the cubic spline, first without and then with the kernel-gradient correction;
/// its error is prefixed with which.
fn on_lattice(
    extra: impl FnOnce(&mut World),
    mut check: impl FnMut(&SweepCtx<'_, glam::DVec2>) -> Result<(), String>,
) -> Result<(), String> {
    let mut world = lattice_2d();
    extra(&mut world);
    let mut nb = Neighbours::new(0.1);
    {
        let data = ParticleData::<glam::DVec2>::of(&world).ok_or("no particles")?;
        let pos: Vec<_> = data.pos.iter().map(|p| p.0).collect();
        let h: Vec<_> = data.h.iter().map(|h| h.0).collect();
        nb.rebuild(&pos, &h);
    }
    let kernel = Kernel::new(dualsph_core::kernels::KernelKind::CubicSpline, 2);
    for corrected in [false, true] {
        let data = ParticleData::of(&world).ok_or("no particles")?;
        let mut ctx = SweepCtx::new(data, &nb, &kernel, Formulation::DualSupport);
        if !corrected {
            ctx.correction = None;
        }
        check(&ctx).map_err(|e| format!("correction {corrected}: {e}"))?;
    }
    Ok(())
}

/// Checks a 2-D term on [`lattice_2d`], first without and then with a non-trivial
/// kernel-gradient correction: every row evaluated as the sweep does (two pairs per lane
/// group) gives bitwise what each pair alone gives; the error names the first differing pair
/// and channel.
pub fn check_lanes_2d(term: &dyn DynPairTerm<glam::DVec2>) -> Result<(), String> {
    check_lanes_2d_with(term, |_| {})
}

/// [`check_lanes_2d`] for a term that reads or writes columns beyond the lattice's: `extra`
/// puts them on the lattice's particles (e.g. with `dualsph_core::store::insert_column`).
pub fn check_lanes_2d_with(
    term: &dyn DynPairTerm<glam::DVec2>,
    extra: impl FnOnce(&mut World),
) -> Result<(), String> {
    on_lattice(extra, |ctx| {
        let mut layout = crate::accum::Layout::default();
        let binder = &mut Binder::new(ctx.data, ctx.kernel, &mut layout, term.name());
        let bound = term.bind_dyn(binder)?;
        check_rows(term.name(), &*bound, ctx, &layout)
    })
}

/// Checks a 2-D term on [`lattice_2d`], without and with the kernel-gradient correction: as a
/// sweep's only term — its block loop compiled for the term — it gives bitwise the sums it
/// gives through a dynamic call per two pairs beside a term with no sums.
pub fn check_block_loop_2d(term: Arc<dyn DynPairTerm<glam::DVec2>>) -> Result<(), String> {
    check_block_loop_2d_with(term, |_| {})
}

/// [`check_block_loop_2d`] with the columns `extra` puts on the lattice's particles (see
/// [`check_lanes_2d_with`]).
pub fn check_block_loop_2d_with(
    term: Arc<dyn DynPairTerm<glam::DVec2>>,
    extra: impl FnOnce(&mut World),
) -> Result<(), String> {
    on_lattice(extra, |ctx| {
        let (mut alone, mut beside) = (SweepBuffers::default(), SweepBuffers::default());
        evaluate(ctx, std::slice::from_ref(&term), &mut alone)?;
        evaluate(ctx, &[term.clone(), Arc::new(NoSums)], &mut beside)?;
        let same = alone.sums.len() == beside.sums.len()
            && alone
                .sums
                .iter()
                .zip(&beside.sums)
                .all(|(a, b)| a.to_bits() == b.to_bits());
        match same {
            true => Ok(()),
            false => Err(format!(
                "{}: its block loop gives other sums than its dynamic calls",
                term.name()
            )),
        }
    })
}

/// A term with a pair part and no sums (see [`check_block_loop_2d`]).
struct NoSums;

impl<V: Vector> PairTerm<V> for NoSums {
    type Bound<'w> = NoSums;
    fn name(&self) -> &str {
        "no sums"
    }
    fn bind<'w>(&'w self, _: &mut Binder<'_, 'w, V>) -> Result<NoSums, String> {
        Ok(NoSums)
    }
}

impl<V: Vector> BoundTerm<V> for NoSums {
    type Owner = ();
    fn owner(&self, _: usize) {}
    fn interact<T: Lanes>(&self, _: &(), _: &PairLanes<'_, T, V>, _: &mut Out<'_, T>) {}
}

/// Every row of `ctx` through `term` two pairs at a time and pair by pair: bitwise the same
/// outputs.
fn check_rows<V: Vector>(
    name: &str,
    term: &dyn RowTerm<V>,
    ctx: &SweepCtx<'_, V>,
    layout: &crate::accum::Layout,
) -> Result<(), String> {
    let (data, corrected) = (&ctx.data, ctx.correction.is_some());
    for i in 0..ctx.len() {
        let k_i = OwnerKernel::new(ctx.kernel, data.h[i].0);
        let mut pairs = Vec::new();
        ctx.for_each_neighbour(i, |j, rij, r, _, g| {
            pairs.push((j as u32, rij, r, data.vij(i, j), g, ctx.corrected(i, g)));
        });
        for two in pairs.chunks_exact(2) {
            let lv = |f: &dyn Fn(usize) -> V| LaneVec::<f64x2>::from_fn(f);
            let geometry = (
                lv(&|l| two[l].1),
                f64x2::new([two[0].2, two[1].2]),
                lv(&|l| two[l].3),
                lv(&|l| two[l].4),
                lv(&|l| two[l].5),
            );
            let p = PairLanes::new(
                (i, [two[0].0, two[1].0]),
                geometry,
                (None, corrected),
                k_i,
                data,
            );
            let mut e2 = Extra::<f64x2>::default();
            let mut out2 = Out::new(&mut e2);
            term.pairs2(&p, &mut out2);
            for (l, &(j, rij, r, vij, g, gc)) in two.iter().enumerate() {
                let s = |x: V| LaneVec::<Real>::splat(x);
                let p = PairLanes::new(
                    (i, [j; 2]),
                    (s(rij), r, s(vij), s(g), s(gc)),
                    (None, corrected),
                    k_i,
                    data,
                );
                let mut e1 = Extra::<Real>::default();
                let mut out1 = Out::new(&mut e1);
                term.pair1(&p, &mut out1);
                let (out1, out2) = (&out1, &out2);
                let channels = layout.slots.iter().flat_map(|s| {
                    (0..s.width).flat_map(move |c| {
                        [
                            (out2.owner_value(s, c).lane(l), out1.owner_value(s, c)),
                            (
                                out2.neighbour_value(s, c).lane(l),
                                out1.neighbour_value(s, c),
                            ),
                        ]
                    })
                });
                for (c, (a, b)) in channels.enumerate() {
                    if a.to_bits() != b.to_bits() {
                        return Err(format!(
                            "{name}: pair ({i}, {j}), channel {c}: {a:e} in two lanes, {b:e} alone"
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}
