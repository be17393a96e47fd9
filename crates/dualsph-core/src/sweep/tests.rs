//! Unit tests of the dual-support sweep: pass 1 and pass 2 against a direct pairwise
//! evaluation in the documented order, bitwise.

use super::*;
use crate::components::Pressure;
use crate::kernels::KernelKind;
use crate::store::{Cloud, insert_column};
use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A term with only `interact` (the default `interact_row` is used): an arbitrary but
/// pair-specific force and powers, reading the pressure column it binds.
struct Probe;

struct BoundProbe<'w> {
    pressure: &'w [Pressure],
}

impl PairTerm<DVec2> for Probe {
    type Bound<'w> = BoundProbe<'w>;
    fn name(&self) -> &str {
        "probe"
    }
    fn bind<'w>(&'w self, data: &ParticleData<'w, DVec2>) -> Result<BoundProbe<'w>, String> {
        Ok(BoundProbe {
            pressure: data.require("probe")?,
        })
    }
}

impl BoundTerm<DVec2> for BoundProbe<'_> {
    fn interact(&self, p: &Pair<'_, DVec2>, out: &mut PairOut<DVec2>) {
        let d = p.data;
        out.force += p.grad * (d.mass[p.j].0 * self.pressure[p.i].0) + p.rij * p.w;
        out.power_i += p.vij().dot(p.grad_raw) * d.mass[p.j].0;
        out.power_j += p.r * d.rho[p.i].0;
    }
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

/// The cloud as particles with their pressures.
fn world_of(c: &Cloud<DVec2>, pressure: &[Real]) -> World {
    let mut world = c.spawn();
    insert_column(&mut world, |i| Pressure(pressure[i]));
    world
}

/// Lists of the cloud with a skin of 0.2.
fn lists(c: &Cloud<DVec2>) -> Neighbours<DVec2> {
    let mut nb = Neighbours::new(0.2);
    nb.rebuild(&c.pos, &c.h);
    nb
}

/// Pass 1 and pass 2 of the dual-support sweep (and the fused continuity sum) against a
/// direct evaluation pair by pair in the same order: bitwise equal.
#[test]
fn row_sweep_equals_pairwise_reference_bitwise() {
    let (c, p) = cloud(400);
    assert_sweep_matches_pairwise(&c, &p);
}

/// The same with several blocks and particles in space order, so that pass 2 runs both
/// behind pass 1 inside a block and, for particles with owners in another block, after it.
#[test]
fn blocked_wavefront_sweep_equals_pairwise_reference_bitwise() {
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
    assert_sweep_matches_pairwise(&c, &p);
}

fn assert_sweep_matches_pairwise(c: &Cloud<DVec2>, pressure: &[Real]) {
    let nb = lists(c);
    let kernel = Kernel::new(KernelKind::CubicSpline, 2);
    let terms: Vec<Arc<dyn DynPairTerm<DVec2>>> = vec![Arc::new(Probe), Arc::new(Probe)];
    let mut buf = SweepBuffers::<DVec2> {
        with_density_rate: true,
        ..Default::default()
    };
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
    let bound: Vec<_> = terms.iter().map(|t| t.bind_dyn(&data).unwrap()).collect();
    let n = c.pos.len();
    let (mut force, mut power) = (vec![DVec2::ZERO; n], vec![0.0; n]);
    let mut reaction = vec![Vec::new(); n];
    for i in 0..n {
        let (mut fo, mut po) = (DVec2::ZERO, 0.0);
        ctx.for_each_neighbour(i, |j, rij, r, w, g| {
            let pair = Pair {
                i,
                j,
                rij,
                r,
                w,
                grad_raw: g,
                grad: g,
                data: &data,
            };
            let mut out = PairOut::default();
            for t in &bound {
                t.interact(&pair, &mut out);
            }
            fo += out.force;
            po += out.power_i;
            reaction[j].push((i, out.force, out.power_j));
        });
        force[i] = fo;
        power[i] = po;
        let cont = crate::passes::own_support_continuity(&data, nb.support.row(i), i, &kernel);
        assert_eq!(
            buf.density_rate[i].to_bits(),
            cont.to_bits(),
            "dρ/dt of {i}"
        );
    }
    for j in 0..n {
        reaction[j].sort_by_key(|r| r.0);
        let (mut fd, mut pd) = (DVec2::ZERO, 0.0);
        for &(_, fr, pr) in &reaction[j] {
            fd -= fr;
            pd += pr;
        }
        force[j] += fd;
        power[j] += pd;
        assert_eq!(buf.force[j], force[j], "force on {j}");
        assert_eq!(buf.power[j].to_bits(), power[j].to_bits(), "power of {j}");
    }
}
