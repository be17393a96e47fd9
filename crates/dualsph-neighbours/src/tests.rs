//! Tests of the neighbour lists: both indexes against brute force and each other.

use super::*;
use dualsph_math::Vec1;
use glam::{DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn cloud<V: Vector>(n: usize, seed: u64) -> (Vec<V>, Vec<Real>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = libm::pow(n as Real, 1.0 / V::DIM as Real);
    let pos = (0..n)
        .map(|_| {
            let mut v = V::zero();
            for k in 0..V::DIM {
                v.set(k, rng.random_range(0.0..side));
            }
            v
        })
        .collect();
    // h varies by a factor 8 between particles
    let h = (0..n).map(|_| rng.random_range(0.4..3.2)).collect();
    (pos, h)
}

fn check_dim<V: Vector>() {
    let (pos, h) = cloud::<V>(700, 7 + V::DIM as u64);
    let mut nb = Neighbours::<V>::new(0.0);
    nb.rebuild(&pos, &h);
    let exact = brute_force_support(&pos, &h);
    assert_eq!(
        nb.support,
        exact,
        "{}-D support lists differ from brute force",
        V::DIM
    );
    // dual-support = transpose, checked against its definition H'_j = { i : j ∈ H_i }
    let mut asymmetric = 0;
    for j in 0..pos.len() {
        let expect: Vec<u32> = (0..pos.len())
            .filter(|&i| i != j && (pos[i] - pos[j]).length_squared() <= h[i] * h[i])
            .map(|i| i as u32)
            .collect();
        assert_eq!(nb.dual.row(j), &expect[..]);
        for (k, &i) in nb.dual.row(j).iter().enumerate() {
            let slot = nb.dual_slot[nb.dual.offsets[j] as usize + k] as usize;
            assert_eq!(nb.support.indices[slot] as usize, j);
            assert!(nb.support.slots(i as usize).contains(&slot));
            if !nb.support.row(j).contains(&i) {
                asymmetric += 1; // j ∈ H_i but i ∉ H_j
            }
        }
    }
    assert!(
        asymmetric > 50,
        "test cloud must contain one-sided pairs ({asymmetric})"
    );
}

#[test]
fn support_lists_match_brute_force_1d_2d_3d() {
    check_dim::<Vec1>();
    check_dim::<DVec2>();
    check_dim::<DVec3>();
}

#[test]
fn skin_lists_stay_supersets_until_rebuild_rule_fires() {
    let (mut pos, h) = cloud::<DVec2>(500, 3);
    let mut nb = Neighbours::<DVec2>::new(0.2);
    nb.rebuild(&pos, &h);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut rebuilt = 0;
    for _ in 0..40 {
        for p in &mut pos {
            *p += DVec2::new(rng.random_range(-0.01..0.01), rng.random_range(-0.01..0.01));
        }
        if nb.update(&pos, &h) {
            rebuilt += 1;
        }
        let exact = brute_force_support(&pos, &h);
        for i in 0..pos.len() {
            for j in exact.row(i) {
                assert!(nb.support.row(i).contains(j), "pair ({i},{j}) missing");
            }
        }
    }
    assert!((1..40).contains(&rebuilt), "rebuilt {rebuilt} times");
    nb.dirty = true;
    assert!(nb.needs_rebuild(&pos));
}

/// With h changing between builds (grown or shrunk by up to 4 % a step, as a smoothing-length
/// update every step does), the lists are kept while the slack allows and stay supersets of
/// the exact supports at every step; an h that outgrows its build radius forces a rebuild.
#[test]
fn lists_follow_h_changes_within_the_slack() {
    let (mut pos, mut h) = cloud::<DVec2>(500, 9);
    let mut nb = Neighbours::<DVec2>::new(0.3);
    nb.rebuild(&pos, &h);
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let (mut kept, mut rebuilt) = (0, 0);
    for _ in 0..40 {
        for (p, hi) in pos.iter_mut().zip(&mut h) {
            *p += DVec2::new(rng.random_range(-2e-3..2e-3), rng.random_range(-2e-3..2e-3));
            *hi *= rng.random_range(0.96..1.04);
        }
        nb.h_changed(&h);
        match nb.update(&pos, &h) {
            true => rebuilt += 1,
            false => kept += 1,
        }
        let exact = brute_force_support(&pos, &h);
        for i in 0..pos.len() {
            for j in exact.row(i) {
                assert!(nb.support.row(i).contains(j), "pair ({i},{j}) missing");
            }
        }
    }
    assert!(kept > 0 && rebuilt > 0, "kept {kept}, rebuilt {rebuilt}");
    // one h past its build radius: a rebuild whatever the motion
    nb.rebuild(&pos, &h);
    assert!(!nb.needs_rebuild(&pos));
    h[7] = nb.build_radii[7] * 1.001;
    nb.h_changed(&h);
    assert!(nb.dirty && nb.needs_rebuild(&pos));
    // an h that is not a number, too
    nb.rebuild(&pos, &h);
    h[3] = Real::NAN;
    nb.h_changed(&h);
    assert!(nb.needs_rebuild(&pos));
    // and lists built with it are rebuilt at the next step, not kept
    nb.rebuild(&pos, &h);
    assert!(nb.needs_rebuild(&pos));
}

/// A tuned skin follows the motion (small while the particles creep, larger while they run)
/// and its lists stay supersets of the exact supports at every step.
#[test]
fn tuned_skin_follows_the_motion_and_lists_stay_supersets() {
    let (mut pos, h) = cloud::<DVec2>(400, 5);
    let mut nb = Neighbours::<DVec2>::with_rule(0.3, SkinRule::Tuned);
    nb.update(&pos, &h);
    assert_eq!(
        (nb.builds, nb.skin),
        (1, 0.3),
        "the first build uses the given skin"
    );
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut skins = Vec::new();
    for (steps, speed) in [(60, 1e-4), (60, 2e-2), (60, 1e-4)] {
        let builds = nb.builds;
        for _ in 0..steps {
            for p in &mut pos {
                *p += DVec2::new(
                    rng.random_range(-speed..speed),
                    rng.random_range(-speed..speed),
                );
            }
            nb.update(&pos, &h);
            let exact = brute_force_support(&pos, &h);
            for i in 0..pos.len() {
                for j in exact.row(i) {
                    assert!(nb.support.row(i).contains(j), "pair ({i},{j}) missing");
                }
            }
        }
        assert!(nb.builds > builds, "no build while moving at {speed}");
        skins.push(nb.skin);
    }
    // creeping: an early rebuild replaced 0.3 by a thin skin; running: thicker; creeping again
    assert!(
        skins[0] < 0.05 && skins[1] > 2.0 * skins[0] && skins[2] < skins[1],
        "{skins:?}"
    );
}

#[test]
fn lattice_with_many_equal_coordinates() {
    // k-d trees can choke on many identical coordinates: a square lattice has them.
    let pos: Vec<DVec2> = (0..80)
        .flat_map(|a| (0..80).map(move |b| DVec2::new(a as Real * 0.1, b as Real * 0.1)))
        .collect();
    let h = vec![0.15; pos.len()];
    let mut nb = Neighbours::<DVec2>::new(0.0);
    nb.rebuild(&pos, &h);
    assert_eq!(nb.support, brute_force_support(&pos, &h));
    assert_eq!(nb.support.row(81).len(), 8);
}

/// The three searches on one input: kiddo, the grid forced, brute force; returns the grid's.
fn all_agree<V: Vector>(pos: &[V], radii: &[Real], what: &str) -> Csr {
    let exact = brute_force_support(pos, radii);
    let kd = kd_radius_csr(pos, radii);
    assert_eq!(
        kd,
        exact,
        "{}-D {what}: kiddo differs from brute force",
        V::DIM
    );
    for cpr in [1.0, 2.0, 3.0] {
        let plan = GridPlan::new(pos, radii, cpr).expect("finite input has a grid");
        let grid = plan.radius_csr(pos, radii);
        assert_eq!(grid, exact, "{}-D {what}: grid ({cpr}/r) differs", V::DIM);
    }
    let (grid, used) = radius_csr(pos, radii, NeighbourIndex::CellGrid);
    assert_eq!(used, NeighbourIndex::CellGrid);
    assert_eq!(grid, exact);
    grid
}

fn uniform_h<V: Vector>(n: usize, seed: u64) -> (Vec<V>, Vec<Real>) {
    let (pos, _) = cloud::<V>(n, seed);
    let h = vec![1.7; n];
    (pos, h)
}

#[test]
fn grid_matches_kiddo_and_brute_force_on_random_clouds() {
    fn dim<V: Vector>() {
        let (pos, h) = cloud::<V>(900, 31 + V::DIM as u64);
        all_agree(&pos, &h, "h varying by 8");
        let (pos, h) = uniform_h::<V>(900, 41 + V::DIM as u64);
        all_agree(&pos, &h, "uniform h");
        // far from the origin: cell coordinates lose low bits
        let shift: Vec<V> = pos
            .iter()
            .map(|&p| {
                let mut s = V::zero();
                for k in 0..V::DIM {
                    s.set(k, 1.0e6 + 3.0 * k as Real);
                }
                p + s
            })
            .collect();
        all_agree(&shift, &h, "shifted by 1e6");
        // negative radii: the test squares them
        let neg: Vec<Real> = h.iter().map(|r| -r).collect();
        all_agree(&pos, &neg, "negative radii");
    }
    dim::<Vec1>();
    dim::<DVec2>();
    dim::<DVec3>();
}

#[test]
fn lattice_at_exact_radius_boundary() {
    // spacing 0.1, radius 0.2 (and 0.1·√2): distances land on the radius up to rounding, so
    // inclusion is decided by the last bit of the shared test
    let pos2: Vec<DVec2> = (0..40)
        .flat_map(|a| (0..40).map(move |b| DVec2::new(a as Real * 0.1, b as Real * 0.1)))
        .collect();
    let pos3: Vec<DVec3> = (0..12)
        .flat_map(|a| {
            (0..12).flat_map(move |b| {
                (0..12).map(move |c| DVec3::new(a as Real * 0.1, b as Real * 0.1, c as Real * 0.1))
            })
        })
        .collect();
    let pos1: Vec<Vec1> = (0..500).map(|a| Vec1(a as Real * 0.1)).collect();
    for r in [0.2, 0.1, 0.1 * 2f64.sqrt(), 0.3, 0.15] {
        let g = all_agree(&pos2, &vec![r; pos2.len()], "2-D lattice");
        all_agree(&pos3, &vec![r; pos3.len()], "3-D lattice");
        all_agree(&pos1, &vec![r; pos1.len()], "1-D lattice");
        if r == 0.2 {
            // (0.1·k)² sums that round to exactly 0.04 are in, the others out: same as kiddo
            assert!(g.row(81).len() >= 8);
        }
    }
    // mixed radii on the lattice, h ratio 4
    let radii: Vec<Real> = (0..pos2.len()).map(|i| [0.1, 0.2, 0.4][i % 3]).collect();
    all_agree(&pos2, &radii, "2-D lattice, mixed radii");
}

#[test]
fn odd_inputs_never_panic_and_stay_exact() {
    // empty and single point
    for index in [
        NeighbourIndex::Auto,
        NeighbourIndex::CellGrid,
        NeighbourIndex::KdTree,
    ] {
        let (c, _) = radius_csr::<DVec2>(&[], &[], index);
        assert_eq!(c.rows(), 0);
        assert_eq!(c.offsets, vec![0]);
        let (c, _) = radius_csr(&[DVec3::ONE], &[1.0], index);
        assert_eq!((c.rows(), c.indices.len()), (1, 0));
    }
    // all points at one position, with a radius and with zero radius
    let same = vec![DVec2::new(0.3, -7.0); 200];
    let g = all_agree(&same, &vec![0.5; 200], "one position");
    assert_eq!(g.row(5).len(), 199);
    all_agree(&same, &vec![0.0; 200], "one position, radius 0");
    // zero, tiny and subnormal radii on a cloud with some duplicated points
    let (mut pos, _) = cloud::<DVec3>(400, 5);
    for k in 0..50 {
        pos[k + 300] = pos[k];
    }
    for r in [0.0, 1e-300, 5e-324, 1e-9] {
        all_agree(&pos, &vec![r; pos.len()], "tiny radius");
    }
    // a huge range with a tiny radius: the grid must coarsen (budget), Auto must pick kiddo
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let spread: Vec<DVec2> = (0..500)
        .map(|k| {
            let c = if k % 2 == 0 { 0.0 } else { 1e12 };
            DVec2::new(c + rng.random_range(0.0..1.0), rng.random_range(0.0..1e9))
        })
        .collect();
    let radii = vec![1e-3; spread.len()];
    let plan = GridPlan::auto(&spread, &radii).unwrap();
    assert!(plan.coarsening > 1.0 && plan.cells() <= 4 * 500 + 64);
    assert!(!auto_uses_grid(&plan));
    all_agree(&spread, &radii, "huge range, tiny radius");
    assert_eq!(
        radius_csr(&spread, &radii, NeighbourIndex::Auto).1,
        NeighbourIndex::KdTree
    );
    // two dense clusters far apart (the coarsened grid puts each in one cell)
    let clusters: Vec<DVec3> = (0..400)
        .map(|k| {
            let off = if k < 200 { 0.0 } else { 1e15 };
            DVec3::new(off + (k % 7) as Real, (k % 5) as Real, (k % 3) as Real)
        })
        .collect();
    all_agree(&clusters, &vec![1.5; 400], "two far clusters");
    // coordinates of huge magnitude whose extent overflows: no grid, kiddo
    let huge = vec![DVec2::new(-1e308, 0.0), DVec2::new(1e308, 1.0), DVec2::ZERO];
    assert!(GridPlan::new(&huge, &[1.0; 3], 1.0).is_none());
    let (c, used) = radius_csr(&huge, &[1.0; 3], NeighbourIndex::CellGrid);
    assert_eq!(
        (c, used),
        (
            brute_force_support(&huge, &[1.0; 3]),
            NeighbourIndex::KdTree
        )
    );
}

#[test]
fn non_finite_input_goes_to_kiddo_without_panic() {
    let (mut pos, h) = uniform_h::<DVec2>(300, 17);
    pos[3] = DVec2::new(Real::NAN, 1.0);
    pos[10] = DVec2::new(Real::INFINITY, 2.0);
    pos[11] = DVec2::new(1.0, Real::NEG_INFINITY);
    for index in [
        NeighbourIndex::Auto,
        NeighbourIndex::CellGrid,
        NeighbourIndex::KdTree,
    ] {
        let (c, used) = radius_csr(&pos, &h, index);
        assert_eq!(used, NeighbourIndex::KdTree);
        assert_eq!(c.rows(), pos.len());
        for i in 0..pos.len() {
            assert!(c.row(i).windows(2).all(|w| w[0] < w[1]));
            if [3, 10, 11].contains(&i) {
                assert!(c.row(i).is_empty(), "non-finite point {i} has neighbours");
            }
        }
        let finite: Vec<usize> = (0..pos.len())
            .filter(|i| ![3, 10, 11].contains(i))
            .collect();
        let exact = brute_force_support(&pos, &h);
        for &i in &finite {
            assert_eq!(c.row(i), exact.row(i), "row {i}");
        }
    }
    // non-finite radii
    let (pos, mut h) = uniform_h::<DVec3>(300, 19);
    h[4] = Real::NAN;
    h[8] = Real::INFINITY;
    assert!(GridPlan::new(&pos, &h, 1.0).is_none());
    let (c, used) = radius_csr(&pos, &h, NeighbourIndex::CellGrid);
    assert_eq!(used, NeighbourIndex::KdTree);
    assert_eq!(c.row(4).len(), 0);
    assert_eq!(c.row(8).len(), pos.len() - 1);
}

#[test]
fn same_lists_on_one_and_two_threads() {
    let (pos, h) = cloud::<DVec3>(6000, 23);
    let (pos2, h2) = uniform_h::<DVec2>(9000, 29);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let mut a = Neighbours::<DVec3>::new(0.1);
            a.index = NeighbourIndex::CellGrid;
            a.rebuild(&pos, &h);
            let mut b = Neighbours::<DVec2>::new(0.1);
            b.rebuild(&pos2, &h2);
            assert_eq!(b.used_index, Some(NeighbourIndex::CellGrid));
            (
                a.support,
                a.dual,
                a.dual_slot,
                b.support,
                b.dual,
                b.dual_slot,
            )
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn every_index_gives_the_same_lists_and_auto_chooses_by_rule() {
    fn lists<V: Vector>(pos: &[V], h: &[Real], index: NeighbourIndex) -> Neighbours<V> {
        let mut nb = Neighbours::<V>::new(0.15);
        nb.index = index;
        nb.rebuild(pos, h);
        nb
    }
    let (pos, h) = uniform_h::<DVec2>(2000, 3);
    // h varying by 2 and 8 (within the bound), and by 10 (beyond it)
    let h2: Vec<Real> = h
        .iter()
        .enumerate()
        .map(|(i, &x)| x * [1.0, 2.0][i % 2])
        .collect();
    let (_, h8) = cloud::<DVec2>(2000, 3);
    let h10: Vec<Real> = h
        .iter()
        .enumerate()
        .map(|(i, &x)| x * [0.2, 2.0][i % 2])
        .collect();
    assert!(
        h8.iter().fold(0.0, |a: Real, &b| a.max(b))
            <= 8.0 * h8.iter().fold(9.0, |a: Real, &b| a.min(b))
    );
    for (hs, auto) in [
        (&h, NeighbourIndex::CellGrid),
        (&h2, NeighbourIndex::CellGrid),
        (&h8, NeighbourIndex::CellGrid),
        (&h10, NeighbourIndex::KdTree),
    ] {
        let kd = lists(&pos, hs, NeighbourIndex::KdTree);
        let grid = lists(&pos, hs, NeighbourIndex::CellGrid);
        let a = lists(&pos, hs, NeighbourIndex::Auto);
        assert_eq!(kd.used_index, Some(NeighbourIndex::KdTree));
        assert_eq!(grid.used_index, Some(NeighbourIndex::CellGrid));
        assert_eq!(a.used_index, Some(auto));
        for nb in [&grid, &a] {
            assert_eq!(nb.support, kd.support);
            assert_eq!(nb.dual, kd.dual);
            assert_eq!(nb.dual_slot, kd.dual_slot);
        }
    }
    assert_eq!(Neighbours::<DVec2>::new(0.1).index, NeighbourIndex::Auto);
}

#[test]
fn parallel_transpose_equals_serial() {
    // large enough for the parallel path (>= 2^16 entries), rows of varied order
    let (pos, h) = cloud::<DVec3>(6000, 41);
    let (csr, _) = radius_csr(&pos, &h, NeighbourIndex::KdTree);
    assert!(csr.indices.len() >= 1 << 16);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| csr.transpose_with_slots())
    };
    let serial = on(1);
    assert_eq!(on(2), serial);
    assert_eq!(on(3), serial);
    let (t, slots) = serial;
    for j in 0..t.rows() {
        assert!(t.row(j).windows(2).all(|w| w[0] < w[1]));
        for (k, &i) in t.row(j).iter().enumerate() {
            let s = slots[t.offsets[j] as usize + k] as usize;
            assert_eq!(csr.indices[s] as usize, j);
            assert!(csr.slots(i as usize).contains(&s));
        }
    }
}

/// Across a period: the lists of both indexes equal brute force over the nearest images
/// (points given outside the box too, as after a step), on every mix of periodic axes, in
/// 1-, 2- and 3-D; the minimum image is odd, `image(−d) = −image(d)`, bit for bit.
fn check_periodic<V: Vector>(axes: [bool; 3]) {
    let (mut pos, h) = cloud::<V>(600, 40 + V::DIM as u64);
    let side = libm::pow(600.0 as Real, 1.0 / V::DIM as Real);
    let mut max = V::zero();
    (0..V::DIM).for_each(|k| max.set(k, side));
    let period = Period::new(V::zero(), max, axes).unwrap();
    // a few points a little outside the box on a periodic axis, as the predictor leaves them
    for (i, p) in pos.iter_mut().enumerate().step_by(37) {
        for k in (0..V::DIM).filter(|&k| axes[k]) {
            p.set(k, p.get(k) + if i % 2 == 0 { side } else { -side } * 1e-3);
        }
    }
    let exact: Vec<Vec<u32>> = (0..pos.len())
        .map(|i| {
            (0..pos.len())
                .filter(|&j| {
                    j != i && period.image(pos[i] - pos[j]).length_squared() <= h[i] * h[i]
                })
                .map(|j| j as u32)
                .collect()
        })
        .collect();
    let exact = Csr::from_rows(exact);
    let crossing = (0..pos.len())
        .flat_map(|i| exact.row(i).iter().map(move |&j| (i, j as usize)))
        .filter(|&(i, j)| period.image(pos[i] - pos[j]) != pos[i] - pos[j])
        .count();
    assert!(crossing >= 5, "{crossing} pairs across the period");
    for index in [NeighbourIndex::CellGrid, NeighbourIndex::KdTree] {
        let (c, used) = periodic_radius_csr(&pos, &h, index, &period);
        assert_eq!(used, index);
        assert_eq!(c, exact, "{}-D {axes:?} {index:?}", V::DIM);
    }
    for (i, &j) in exact.indices.iter().enumerate().take(500) {
        let d = pos[i % pos.len()] - pos[j as usize];
        assert_eq!(period.image(-d), -period.image(d));
    }
}

#[test]
fn periodic_lists_are_brute_force_over_the_nearest_images() {
    check_periodic::<Vec1>([true, false, false]);
    check_periodic::<DVec2>([true, false, false]);
    check_periodic::<DVec2>([false, true, false]);
    check_periodic::<DVec2>([true, true, false]);
    check_periodic::<DVec3>([true, true, true]);
    check_periodic::<DVec3>([false, true, true]);
}

/// A wrapped point lies in `[lo, lo + L)`, a whole number of periods from where it was.
#[test]
fn wrapping_lands_in_the_box_by_whole_periods() {
    let p = Period::new(
        DVec2::new(-1.0, 0.0),
        DVec2::new(2.0, 1.0),
        [true, false, false],
    )
    .unwrap();
    for x in [-1.0, 2.0, 2.0 + 1e-17, -1.0 - 1e-17, 7.3, -9.9, 0.5] {
        let w = p.wrap(DVec2::new(x, 5.0));
        assert!((-1.0..2.0).contains(&w.x), "{x} -> {}", w.x);
        assert_eq!(w.y, 5.0);
        let periods = (x - w.x) / 3.0;
        assert!((periods - periods.round()).abs() < 1e-12, "{x} -> {}", w.x);
    }
    assert_eq!(
        Period::<DVec2>::new(DVec2::ZERO, DVec2::ONE, [false; 3]),
        None
    );
}

/// The nearest point within a reach is the brute-force least distance (bitwise), in 1-, 2-
/// and 3-D, for reaches that find none, a few and every point.
fn nearest_within_is_brute_force<V: Vector>() {
    let (points, _) = cloud::<V>(300, 40 + V::DIM as u64);
    let (queries, _) = cloud::<V>(200, 50 + V::DIM as u64);
    let tree = kd::KdTree::new(&points);
    for reach in [0.05, 0.7, 2.0, 1e3] {
        for &q in &queries {
            let exact = points
                .iter()
                .map(|&p| (q - p).length_squared())
                .filter(|&d2| d2 <= reach * reach)
                .fold(Real::INFINITY, Real::min)
                .sqrt();
            let found = tree.nearest_within(q, reach);
            assert_eq!(
                found.to_bits(),
                exact.to_bits(),
                "{}-D reach {reach}",
                V::DIM
            );
        }
    }
}

#[test]
fn nearest_within_matches_brute_force_1d_2d_3d() {
    nearest_within_is_brute_force::<Vec1>();
    nearest_within_is_brute_force::<DVec2>();
    nearest_within_is_brute_force::<DVec3>();
}
