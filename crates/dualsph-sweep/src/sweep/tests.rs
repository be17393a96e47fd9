//! Unit tests of the dual-support sweep: pass 1 and pass 2 against a direct pairwise
//! evaluation in the documented order, bitwise.

use super::*;
use crate::pair::{BoundTerm, Out, PairLanes, PairTerm, Reaction};
use bevy_ecs::prelude::Component;
use bevy_ecs::prelude::World;
use dualsph_core::components::Acceleration;
use dualsph_core::kernels::KernelKind;
use dualsph_core::lanes::Lanes;
use dualsph_core::store::{Cloud, insert_column};
use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A column the probe reads (a pressure, say).
#[derive(Component, Clone, Copy)]
struct Pressure(Real);

/// The column of the probe's first scalar register (a power, say: divided by the mass).
#[derive(Component, Clone, Copy, Default)]
struct EnergyRate {
    rate: Real,
}

/// The column of the probe's second scalar register (a density rate, say).
#[derive(Component, Clone, Copy, Default)]
struct DensityRate {
    rate: Real,
}

/// A term with an arbitrary but pair-specific force, owner and neighbour powers and a
/// density rate (one-sided, or with its own value for the neighbour when `rate_to_j`),
/// reading the pressure column it binds.
struct Probe {
    rate_to_j: bool,
}

struct BoundProbe<'w> {
    pressure: &'w [Pressure],
    rho: &'w [dualsph_core::components::Density],
    rate_to_j: bool,
}

impl PairTerm<DVec2> for Probe {
    type Bound<'w> = BoundProbe<'w>;
    fn name(&self) -> &str {
        "probe"
    }
    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, DVec2>) -> Result<BoundProbe<'w>, String> {
        b.force()?;
        let power = |e: &mut EnergyRate, s: &[Real], m: Real| e.rate = s[0] / m;
        b.scalar_register::<EnergyRate, 0>(Reaction::Separate, power)?;
        let rate = |d: &mut DensityRate, s: &[Real], _: Real| d.rate = s[0];
        let reaction = if self.rate_to_j {
            Reaction::Separate
        } else {
            Reaction::OneSided
        };
        b.scalar_register::<DensityRate, 1>(reaction, rate)?;
        Ok(BoundProbe {
            pressure: b.require()?,
            rho: b.data().rho,
            rate_to_j: self.rate_to_j,
        })
    }
}

impl BoundTerm<DVec2> for BoundProbe<'_> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, DVec2>, out: &mut Out<'_, T>) {
        let m_j = p.m_j();
        let p_i = T::splat(self.pressure[p.i()].0);
        let f = p
            .grad()
            .scale::<DVec2>(m_j * p_i)
            .plus::<DVec2>(p.rij().scale::<DVec2>(p.w()));
        out.add_force::<DVec2>(f);
        out.add_scalar::<0>(p.vij().dot::<DVec2>(p.grad_raw()) * m_j);
        out.react_scalar::<0>(p.r() * T::splat(self.rho[p.i()].0));
        out.add_scalar::<1>(m_j * p.vij().dot::<DVec2>(p.grad_raw()));
        if self.rate_to_j {
            out.react_scalar::<1>(p.w() * m_j);
        }
    }
}

/// The same pair values one pair at a time: `(force on i, power of i, power of j, dρ_i/dt,
/// dρ_j/dt)`.
fn probe_pair(
    data: &ParticleData<'_, DVec2>,
    pressure: &[Real],
    (i, j): (usize, usize),
    (rij, r, w, g): (DVec2, Real, Real, DVec2),
) -> (DVec2, Real, Real, Real, Real) {
    let m_j = data.mass[j].0;
    let vij = data.vij(i, j);
    (
        g * (m_j * pressure[i]) + rij * w,
        vij.dot(g) * m_j,
        r * data.rho[i].0,
        m_j * vij.dot(g),
        w * m_j,
    )
}

/// n particles with random positions in a square of side `side`, numbered by rows of
/// unit height (space order, as a generated lattice is) when `ordered`, and their pressures.
fn cloud_in(n: usize, side: Real, ordered: bool) -> (Cloud<DVec2>, Vec<Real>) {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut c = Cloud::<DVec2>::new(n);
    let mut pos: Vec<DVec2> = (0..n)
        .map(|_| DVec2::new(rng.random_range(0.0..side), rng.random_range(0.0..side)))
        .collect();
    if ordered {
        pos.sort_by(|a, b| (a.y.floor(), a.x).partial_cmp(&(b.y.floor(), b.x)).unwrap());
    }
    for i in 0..n {
        c.pos[i] = pos[i];
        c.vel[i] = DVec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        c.mass[i] = rng.random_range(0.5..1.5);
        c.rho[i] = rng.random_range(900.0..1100.0);
        c.h[i] = rng.random_range(0.6..1.8);
    }
    let pressure = (0..n).map(|_| rng.random_range(-1.0..3.0)).collect();
    (c, pressure)
}

fn cloud(n: usize) -> (Cloud<DVec2>, Vec<Real>) {
    cloud_in(n, 10.0, false)
}

/// The cloud as particles with their pressures and the columns the probe sums into.
fn world_of(c: &Cloud<DVec2>, pressure: &[Real]) -> World {
    let mut world = c.spawn();
    insert_column(&mut world, |i| Pressure(pressure[i]));
    insert_column(&mut world, |_| Acceleration(DVec2::ZERO));
    insert_column(&mut world, |_| EnergyRate::default());
    insert_column(&mut world, |_| DensityRate::default());
    world
}

/// Lists of the cloud with a skin of 0.2.
fn lists(c: &Cloud<DVec2>) -> Neighbours<DVec2> {
    let mut nb = Neighbours::new(0.2);
    nb.rebuild(&c.pos, &c.h);
    nb
}

/// Pass 1 and pass 2 of the dual-support sweep (an opposite, a separate and a one-sided sum)
/// against a direct evaluation pair by pair in the same order: bitwise equal.
#[test]
fn row_sweep_equals_pairwise_reference_bitwise() {
    let (c, p) = cloud(400);
    assert_sweep_matches_pairwise(&c, &p, false);
}

/// The same with a density rate that also reaches the neighbour (a third reaction channel).
#[test]
fn row_sweep_with_a_rate_to_the_neighbour_equals_pairwise_reference_bitwise() {
    let (c, p) = cloud(400);
    assert_sweep_matches_pairwise(&c, &p, true);
}

/// The same with several blocks and particles in space order, so that j's reactions are
/// both summed by pass 1 inside j's block and, for particles with owners in another block,
/// stored and gathered after it.
#[test]
fn blocked_sweep_equals_pairwise_reference_bitwise() {
    let n = 3 * MIN_BLOCK + 77;
    let (c, p) = cloud_in(n, 55.0, true);
    let nb = lists(&c);
    let block = block_len(n);
    let (mut inside, mut outside) = (0, 0);
    for j in 0..n {
        let (a, end) = (j / block * block, (j / block * block + block).min(n));
        let owners = nb.dual.row(j);
        let within = owners.iter().all(|&o| (a..end).contains(&(o as usize)));
        if within { inside += 1 } else { outside += 1 }
    }
    assert!(n / block >= 2, "several blocks");
    assert!(
        inside > n / 2 && outside > 50,
        "both paths: {inside} / {outside}"
    );
    assert_sweep_matches_pairwise(&c, &p, true);
}

fn assert_sweep_matches_pairwise(c: &Cloud<DVec2>, pressure: &[Real], rate_to_j: bool) {
    let nb = lists(c);
    let kernel = Kernel::new(KernelKind::CubicSpline, 2);
    let probe = || Arc::new(Probe { rate_to_j });
    let terms: Vec<Arc<dyn DynPairTerm<DVec2>>> = vec![probe(), probe()];
    let mut buf = SweepBuffers::default();
    // a first sweep of the particles moved (other pairs inside h) leaves its reactions in
    // the reused slot buffer: the sweep under test must not read any of them
    let mut moved = c.clone();
    for (k, x) in moved.pos.iter_mut().enumerate() {
        *x += DVec2::new(0.31, -0.17) * ((k % 7) as Real - 3.0);
    }
    let warm_world = world_of(&moved, pressure);
    let warm_data = ParticleData::of(&warm_world).unwrap();
    let warm = SweepCtx::new(warm_data, &nb, &kernel, Formulation::DualSupport);
    evaluate(&warm, &terms, &mut buf).unwrap();
    let world = world_of(c, pressure);
    let data = ParticleData::of(&world).unwrap();
    let ctx = SweepCtx::new(data, &nb, &kernel, Formulation::DualSupport);
    evaluate(&ctx, &terms, &mut buf).unwrap();
    let n = c.pos.len();
    let (mut force, mut power) = (vec![DVec2::ZERO; n], vec![0.0; n]);
    let mut rate = vec![0.0; n];
    let mut reaction = vec![Vec::new(); n];
    for i in 0..n {
        let (mut fo, mut po, mut ro) = (DVec2::ZERO, 0.0, 0.0);
        ctx.for_each_neighbour(i, |j, rij, r, w, g| {
            let (f, p_i, p_j, d, d_j) = probe_pair(&data, pressure, (i, j), (rij, r, w, g));
            // two probes: each pair value is (0 + one) + one
            let (f, p_i, p_j, d, d_j) = (f + f, p_i + p_i, p_j + p_j, d + d, d_j + d_j);
            fo += f;
            po += p_i;
            ro += d;
            reaction[j].push((i, f, p_j, d_j));
        });
        force[i] = fo;
        power[i] = po;
        rate[i] = ro;
    }
    for j in 0..n {
        reaction[j].sort_by_key(|r| r.0);
        let (mut fd, mut pd, mut rd) = (DVec2::ZERO, 0.0, 0.0);
        for &(_, fr, pr, dr) in &reaction[j] {
            fd -= fr;
            pd += pr;
            rd += dr;
        }
        force[j] += fd;
        power[j] += pd;
        if rate_to_j {
            rate[j] += rd;
        }
        let drho = buf.sum_of::<DensityRate>(j).unwrap()[0];
        assert_eq!(drho.to_bits(), rate[j].to_bits(), "dρ/dt of {j}");
        let f = buf.sum_of::<Acceleration<DVec2>>(j).unwrap();
        assert_eq!(DVec2::new(f[0], f[1]), force[j], "force on {j}");
        let p = buf.sum_of::<EnergyRate>(j).unwrap()[0];
        assert_eq!(p.to_bits(), power[j].to_bits(), "power of {j}");
    }
}
