//! Unit tests of the dual-support sweep: pass 1 and pass 2 against a direct pairwise
//! evaluation in the documented order, bitwise.

use super::*;
use crate::kernels::KernelKind;
use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A term with only `interact` (the default `interact_row` is used): an arbitrary but
/// pair-specific force and powers.
struct Probe;

impl PairTerm<DVec2> for Probe {
    fn name(&self) -> &str {
        "probe"
    }
    fn interact(&self, p: &Pair<'_, DVec2>, out: &mut PairOut<DVec2>) {
        let f = p.fields;
        out.force += p.grad * (f.mass[p.j] * f.pressure[p.i]) + p.rij * p.w;
        out.power_i += p.vij().dot(p.grad_raw) * f.mass[p.j];
        out.power_j += p.r * f.rho[p.i];
    }
}

/// n particles with random positions in a square of side `side`, numbered by rows of
/// unit height (space order, as a generated lattice is) when `ordered`.
fn cloud_in(n: usize, side: Real, ordered: bool) -> (Fields<DVec2>, Neighbours<DVec2>) {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut f = Fields::<DVec2>::default();
    f.resize(n);
    let mut pos: Vec<DVec2> = (0..n)
        .map(|_| DVec2::new(rng.random_range(0.0..side), rng.random_range(0.0..side)))
        .collect();
    if ordered {
        pos.sort_by(|a, b| (a.y.floor(), a.x).partial_cmp(&(b.y.floor(), b.x)).unwrap());
    }
    for i in 0..n {
        f.pos[i] = pos[i];
        f.vel[i] = DVec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        f.mass[i] = rng.random_range(0.5..1.5);
        f.rho[i] = rng.random_range(900.0..1100.0);
        f.h[i] = rng.random_range(0.6..1.8);
    }
    f.pressure = (0..n).map(|_| rng.random_range(-1.0..3.0)).collect();
    let mut nb = Neighbours::new(0.2);
    nb.rebuild(&f.pos, &f.h);
    (f, nb)
}

fn cloud(n: usize) -> (Fields<DVec2>, Neighbours<DVec2>) {
    cloud_in(n, 10.0, false)
}

/// Pass 1 and pass 2 of the dual-support sweep (and the fused continuity sum) against a
/// direct evaluation pair by pair in the same order: bitwise equal.
#[test]
fn row_sweep_equals_pairwise_reference_bitwise() {
    let (f, nb) = cloud(400);
    assert_sweep_matches_pairwise(&f, &nb);
}

/// The same with several blocks and particles in space order, so that pass 2 runs both
/// behind pass 1 inside a block and, for particles with owners in another block, after it.
#[test]
fn blocked_wavefront_sweep_equals_pairwise_reference_bitwise() {
    let n = 3 * MIN_BLOCK + 77;
    let (f, nb) = cloud_in(n, 55.0, true);
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
    assert_sweep_matches_pairwise(&f, &nb);
}

fn assert_sweep_matches_pairwise(f: &Fields<DVec2>, nb: &Neighbours<DVec2>) {
    let kernel = Kernel::new(KernelKind::CubicSpline, 2);
    let ctx = SweepCtx {
        fields: f,
        neighbours: nb,
        kernel: &kernel,
        formulation: Formulation::DualSupport,
    };
    let terms: Vec<Arc<dyn PairTerm<DVec2>>> = vec![Arc::new(Probe), Arc::new(Probe)];
    let mut buf = SweepBuffers::<DVec2> {
        with_density_rate: true,
        ..Default::default()
    };
    // a first sweep of the particles moved (other pairs inside h) leaves its reactions in
    // the reused slot buffer: the sweep under test must not read any of them
    let mut moved = f.clone();
    for (k, x) in moved.pos.iter_mut().enumerate() {
        *x += DVec2::new(0.31, -0.17) * ((k % 7) as Real - 3.0);
    }
    let warm = SweepCtx {
        fields: &moved,
        ..ctx
    };
    evaluate(&warm, &terms, &mut buf);
    evaluate(&ctx, &terms, &mut buf);
    let n = f.len();
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
                fields: f,
            };
            let mut out = PairOut::default();
            for t in &terms {
                t.interact(&pair, &mut out);
            }
            fo += out.force;
            po += out.power_i;
            reaction[j].push((i, out.force, out.power_j));
        });
        force[i] = fo;
        power[i] = po;
        let cont = crate::passes::own_support_continuity(f, nb.support.row(i), i, &kernel);
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
