//! Particle generation in 1, 2 and 3 dimensions.

use super::*;
use crate::ParticleSpec;
use crate::generate::estimate_count;
use std::f64::consts::PI;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

fn of_group(ps: &[ParticleSpec], g: u32) -> Vec<ParticleSpec> {
    ps.iter().filter(|p| p.generator == g).copied().collect()
}

#[test]
fn staggered_block_count_mass_h_and_offsets() {
    let s = load(BASE).unwrap();
    let ps = s.generate();
    let block = of_group(&ps, 0);
    assert_eq!(block.len(), 20 * 10);
    assert!(
        ps[..200].iter().all(|p| p.generator == 0),
        "generators come in order"
    );
    let dx = 0.05;
    for p in &block {
        assert!(close(p.mass, 1000.0 * dx * dx) && close(p.h, 2.0 * dx) && p.density == 1000.0);
        assert_eq!((p.vel, p.internal_energy, p.pos[2]), ([0.0; 3], 0.0, 0.0));
        assert!(p.pos[0] > 0.0 && p.pos[0] < 1.0 && p.pos[1] > 0.0 && p.pos[1] < 0.5);
    }
    // Lexicographic order, axis 0 slowest: index = i * 10 + j.
    let at = |i: usize, j: usize| block[i * 10 + j].pos;
    assert!(close(at(0, 0)[0], 0.25 * dx) && close(at(0, 0)[1], 0.5 * dx));
    assert!(close(at(0, 1)[0], 0.75 * dx) && close(at(0, 1)[1], 1.5 * dx));
    assert!(close(at(19, 9)[0], 1.0 - 0.25 * dx) && close(at(19, 9)[1], 0.5 - 0.5 * dx));
    assert!(close(at(19, 8)[0], 1.0 - 0.75 * dx));
}

#[test]
fn square_lattice_is_cell_centred() {
    let text = edit(&[("lattice: Staggered", "lattice: Square")]);
    let block = of_group(&load(&text).unwrap().generate(), 0);
    assert_eq!(block.len(), 200);
    for (n, p) in block.iter().enumerate() {
        let (i, j) = (n / 10, n % 10);
        assert!(
            close(p.pos[0], (i as f64 + 0.5) * 0.05) && close(p.pos[1], (j as f64 + 0.5) * 0.05)
        );
    }
}

#[test]
fn disk_count_matches_area() {
    let text = edit(&[
        ("max: [4.0, 3.0]", "max: [6.0, 5.0]"),
        (
            "center: [3.0, 2.0], radius: 0.5, spacing: 0.05",
            "center: [4.0, 3.0], radius: 1.0, spacing: 0.02",
        ),
    ]);
    let s = load(&text).unwrap();
    let disk = of_group(&s.generate(), 1);
    let expected = PI * 1.0 / (0.02 * 0.02);
    let rel = (disk.len() as f64 - expected).abs() / expected;
    assert!(rel < 0.01, "{} vs {expected}", disk.len());
    assert!(
        disk.iter()
            .all(|p| libm::hypot(p.pos[0] - 4.0, p.pos[1] - 3.0) <= 1.0 + 1e-12)
    );
    assert!(close(disk[0].mass, 500.0 * 0.02 * 0.02) && close(disk[0].h, 1.5 * 0.02));
    assert!(estimate_count(&s.particles[1], 2) >= disk.len() as f64);
}

#[test]
fn linear_and_uniform_velocity() {
    let text = edit(&[
        (
            "h_factor: 2.0)",
            "h_factor: 2.0, velocity: Linear([[-100.0, 0.0], [0.5, 100.0]]))",
        ),
        (
            "h_factor: 1.5)",
            "h_factor: 1.5, velocity: Uniform([1.5, -2.0]))",
        ),
    ]);
    let ps = load(&text).unwrap().generate();
    for p in of_group(&ps, 0) {
        let [x, y, _] = p.pos;
        assert!(
            close(p.vel[0], -100.0 * x) && close(p.vel[1], 0.5 * x + 100.0 * y),
            "{p:?}"
        );
        assert_eq!(p.vel[2], 0.0);
    }
    assert!(of_group(&ps, 1).iter().all(|p| p.vel == [1.5, -2.0, 0.0]));
}

#[test]
fn bodies_energy_clip_and_cut() {
    let text = edit(&[
        (
            "    particles: [",
            "    bodies: [Body(name: \"wall\", kind: Fixed), Body(name: \"water\")],\n    particles: [",
        ),
        (
            "h_factor: 2.0)",
            "h_factor: 2.0, body: \"water\", internal_energy: 3.0, cut: [(min: [0.0, 0.0], max: [0.5, 0.5])])",
        ),
        (
            "h_factor: 1.5)",
            "h_factor: 1.5, body: \"wall\", clip: Some((min: [2.5, 1.5], max: [3.0, 2.5])))",
        ),
    ]);
    let s = load(&text).unwrap();
    let ps = s.generate();
    let block = of_group(&ps, 0);
    assert!(block.iter().all(|p| p.body == 1));
    assert!(of_group(&ps, 1).iter().all(|p| p.body == 0));
    assert_eq!(s.body_list()[0].kind.name(), "Fixed");
    assert_eq!(block.len(), 100, "the cut removes the left half");
    assert!(
        block
            .iter()
            .all(|p| p.pos[0] > 0.5 && p.internal_energy == 3.0)
    );
    let disk = of_group(&ps, 1);
    let full = of_group(&load(BASE).unwrap().generate(), 1);
    assert_eq!(disk.len(), full.iter().filter(|p| p.pos[0] <= 3.0).count());
    assert!(disk.iter().all(|p| p.pos[0] <= 3.0));
    assert_eq!(ps.len(), block.len() + disk.len());
}

#[test]
fn one_dimensional_scene() {
    let text = r#"Scene(
        name: "rod", dimension: 1,
        domain: (min: [0.0], max: [2.0]),
        kernel: WendlandC2, formulation: ConstantH,
        particles: [
            Block(min: [0.0], max: [1.0], spacing: 0.01, lattice: Staggered, density: 2.0, h_factor: 3.0),
            Disk(center: [1.5], radius: 0.25, spacing: 0.05, lattice: Square, density: 1.0, h_factor: 2.0, velocity: Linear([[2.0]])),
        ],
        integrator: (dt: Fixed(1e-3)), end_time: 0.1,
    )"#;
    let s = load(text).unwrap();
    let ps = s.generate();
    let rod = of_group(&ps, 0);
    assert_eq!(rod.len(), 100);
    for (i, p) in rod.iter().enumerate() {
        assert!(
            close(p.pos[0], (i as f64 + 0.5) * 0.01),
            "staggered = square in 1-D"
        );
        assert_eq!((p.pos[1], p.pos[2]), (0.0, 0.0));
        assert!(close(p.mass, 2.0 * 0.01) && close(p.h, 0.03));
    }
    let seg = of_group(&ps, 1);
    assert_eq!(seg.len(), 10);
    assert!(close(seg[0].pos[0], 1.275) && close(seg[0].vel[0], 2.0 * 1.275));
}

#[test]
fn three_dimensional_scene() {
    let text = r#"Scene(
        name: "cube", dimension: 3,
        domain: (min: [0.0, 0.0, 0.0], max: [2.0, 2.0, 2.0]),
        kernel: QuinticSpline, formulation: SingleSupport,
        particles: [
            Block(min: [0.0, 0.0, 0.0], max: [0.5, 0.4, 0.3], spacing: 0.1, lattice: Staggered, density: 1000.0, h_factor: 2.0),
            Disk(center: [1.4, 1.4, 1.4], radius: 0.5, spacing: 0.05, lattice: Square, density: 1.0, h_factor: 2.0),
        ],
        plugins: [Gravity(g: [0.0, 0.0, -9.81])],
        integrator: (dt: Adaptive()), end_time: 0.1,
    )"#;
    let s = load(text).unwrap();
    let ps = s.generate();
    let block = of_group(&ps, 0);
    assert_eq!(block.len(), 5 * 4 * 3);
    let dx = 0.1;
    for (n, p) in block.iter().enumerate() {
        let (i, j, k) = (n / 12, (n / 3) % 4, n % 3);
        let off = if k % 2 == 0 { 0.25 } else { 0.75 };
        assert!(close(p.pos[0], (i as f64 + off) * dx), "{n} {p:?}");
        assert!(close(p.pos[1], (j as f64 + off) * dx), "{n} {p:?}");
        assert!(close(p.pos[2], (k as f64 + 0.5) * dx), "{n} {p:?}");
        assert!(close(p.mass, 1000.0 * dx * dx * dx));
    }
    let ball = of_group(&ps, 1);
    let expected = 4.0 / 3.0 * PI * 0.125 / 0.05f64.powi(3);
    let rel = (ball.len() as f64 - expected).abs() / expected;
    assert!(rel < 0.02, "{} vs {expected}", ball.len());
    assert!(estimate_count(&s.particles[1], 3) >= ball.len() as f64);
}

#[test]
fn generation_is_deterministic() {
    let a = load(BASE).unwrap().generate();
    let b = load(BASE).unwrap().generate();
    assert_eq!(a, b);
}

#[test]
fn generate_never_panics_on_invalid_scenes() {
    for edits in [
        vec![("dimension: 2", "dimension: 7")],
        vec![(
            "spacing: 0.05, lattice: Staggered",
            "spacing: 0.0, lattice: Staggered",
        )],
        vec![(
            "spacing: 0.05, lattice: Staggered",
            "spacing: -1.0, lattice: Staggered",
        )],
        vec![("min: [0.0, 0.0], max: [1.0, 0.5]", "min: [0.0], max: []")],
        vec![(
            "h_factor: 2.0)",
            "h_factor: 2.0, velocity: Linear([[1.0], []]), clip: (min: [], max: [NaN]))",
        )],
        vec![("dimension: 2", "dimension: 3")],
    ] {
        let s = Scene::parse_only(&edit(&edits), path(), &registry()).unwrap();
        let _ = s.generate();
        assert!(s.validate(path()).is_err());
    }
}

/// `jitter` moves every point of a block by less than `jitter · Δx` along each axis, in a
/// pattern that is the same on every load, spread over the whole range (the mean offset near
/// 0, the largest near the bound), and the velocity is taken at the moved point; a jitter
/// outside [0, 0.25] is refused with the field named.
#[test]
fn a_jittered_block_moves_each_point_within_its_bound() {
    let scene = |jitter: &str| {
        format!(
            r#"Scene(
        name: "jitter", dimension: 2,
        domain: (min: [0.0, 0.0], max: [1.0, 1.0], periodic: [true, true]),
        kernel: WendlandC2, formulation: DualSupport,
        particles: [
            Block(min: [0.0, 0.0], max: [1.0, 1.0], spacing: 0.05, lattice: Square,
                  jitter: {jitter}, density: 1.0, h_factor: 3.0, velocity: Linear([[1.0, 0.0], [0.0, 2.0]])),
        ],
        integrator: (dt: Fixed(1e-3)), end_time: 0.1,
    )"#
        )
    };
    let plain = load(&scene("0.0")).unwrap().generate();
    let moved = load(&scene("0.2")).unwrap().generate();
    assert_eq!(moved, load(&scene("0.2")).unwrap().generate());
    assert_eq!(plain.len(), moved.len());
    let (mut largest, mut mean) = (0.0f64, [0.0; 2]);
    for (a, b) in plain.iter().zip(&moved) {
        for k in 0..2 {
            let off = (b.pos[k] - a.pos[k]) / 0.05;
            assert!(off.abs() < 0.2, "{a:?} {b:?}");
            largest = largest.max(off.abs());
            mean[k] += off / plain.len() as f64;
        }
        assert!(close(b.vel[0], b.pos[0]) && close(b.vel[1], 2.0 * b.pos[1]));
    }
    assert!(largest > 0.19, "{largest}");
    assert!(mean.iter().all(|m| m.abs() < 0.02), "{mean:?}");
    let err = load(&scene("0.3")).unwrap_err().to_string();
    assert!(err.contains("particles[0].jitter"), "{err}");
}
