//! Particle generation: lattice points of each generator, in a deterministic order.

use crate::lattice::{Lattice, Velocity};
use crate::particle::ParticleSpec;
use crate::schema::{BodySettings, Generator};
use crate::shapes;

/// The most particles a scene may generate (checked from an estimate before generating).
pub const MAX_PARTICLES: usize = 50_000_000;

/// Component `k` of `v`, NaN when missing (so malformed input never panics and never passes
/// a comparison).
fn comp(v: &[f64], k: usize) -> f64 {
    v.get(k).copied().unwrap_or(f64::NAN)
}

/// The box whose lattice the generator samples: the block itself, or the disk's bounding box.
pub(crate) fn lattice_box(g: &Generator, d: usize) -> ([f64; 3], [f64; 3]) {
    let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
    for k in 0..d.min(3) {
        match g {
            Generator::Block(b) => {
                lo[k] = comp(&b.min, k);
                hi[k] = comp(&b.max, k);
            }
            Generator::Disk(c) => {
                lo[k] = comp(&c.center, k) - c.radius;
                hi[k] = comp(&c.center, k) + c.radius;
            }
            Generator::Shape(s) => return s.shape.geometry(d).bounds(),
            Generator::File(_) => {}
        }
    }
    (lo, hi)
}

/// Per-axis lattice index ranges `[start, end)`: the whole box lattice (`round(L/Δx)` points
/// per axis), narrowed to the clip box when there is one. Unused axes have the range `[0, 1)`.
fn index_ranges(g: &Generator, d: usize) -> [(f64, f64); 3] {
    let c = g.common();
    let dx = c.spacing;
    let (lo, hi) = lattice_box(g, d);
    let mut r = [(0.0, 1.0); 3];
    for k in 0..d.min(3) {
        let n = ((hi[k] - lo[k]) / dx).round().max(0.0);
        let (mut a, mut b) = (0.0_f64, n);
        if let Some(clip) = c.clip {
            // Offsets lie in [0.25, 0.75]: keep every index whose point could be in the clip box.
            a = a.max(((comp(&clip.min, k) - lo[k]) / dx - 0.75).floor());
            b = b.min(((comp(&clip.max, k) - lo[k]) / dx - 0.25).floor() + 1.0);
        }
        r[k] = (a, b.max(a));
    }
    r
}

/// An upper estimate of how many particles `g` generates, computed without generating;
/// infinite when the spacing or geometry is not usable.
pub(crate) fn estimate_count(g: &Generator, d: usize) -> f64 {
    let dx = g.spacing();
    if !(dx > 0.0 && dx.is_finite() && (1..=3).contains(&d)) {
        return f64::INFINITY;
    }
    match g {
        Generator::Shape(s) => return shapes::estimate_count(s, d),
        Generator::File(f) => return f.particles().len() as f64,
        _ => {}
    }
    let n: f64 = index_ranges(g, d).iter().map(|(a, b)| b - a).product();
    if n.is_nan() {
        return f64::INFINITY;
    }
    match g {
        Generator::Block(_) | Generator::Shape(_) | Generator::File(_) => n,
        // The lattice of the bounding box, times the ball's share of it (plus a margin of a
        // surface layer), but never more than the box itself.
        Generator::Disk(_) => {
            let share = [1.0, std::f64::consts::PI / 4.0, std::f64::consts::PI / 6.0][d - 1];
            (n * share * 1.1).min(n)
        }
    }
}

/// Lattice offset (in units of Δx) of axis `k` for the point with index `idx`.
fn offset(lattice: Lattice, d: usize, k: usize, idx: [usize; 3]) -> f64 {
    let stagger = |parity: usize| if parity.is_multiple_of(2) { 0.25 } else { 0.75 };
    match (lattice, d) {
        (Lattice::Staggered, 2) if k == 0 => stagger(idx[1]),
        (Lattice::Staggered, 3) if k < 2 => stagger(idx[2]),
        _ => 0.5,
    }
}

/// The positions `g` generates, in lexicographic index order (axis 0 slowest). Empty when the
/// estimate exceeds [`MAX_PARTICLES`] or the spacing is unusable.
pub(crate) fn positions(g: &Generator, d: usize) -> Vec<[f64; 3]> {
    let est = estimate_count(g, d);
    if est.is_nan() || est > MAX_PARTICLES as f64 {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(est as usize);
    for_each_position(g, d, |p| out.push(p));
    out
}

/// Calls `f` with every position `g` generates, in the order of [`positions`], without
/// storing them (nothing when the estimate exceeds [`MAX_PARTICLES`] or the spacing is
/// unusable): the validator's checks need O(1) memory per generator.
pub(crate) fn for_each_position(g: &Generator, d: usize, mut f: impl FnMut([f64; 3])) {
    let est = estimate_count(g, d);
    if est.is_nan() || est > MAX_PARTICLES as f64 {
        return;
    }
    let disk = match g {
        Generator::Shape(s) => return shapes::for_each_position(s, d, f),
        Generator::File(file) => return file.particles().rows().for_each(|r| f(r.pos())),
        Generator::Disk(disk) => {
            let centre: Vec<f64> = (0..d).map(|k| comp(&disk.center, k)).collect();
            Some((centre, disk.radius * disk.radius * (1.0 + 1e-12)))
        }
        Generator::Block(_) => None,
    };
    let c = g.common();
    let cuts: Vec<_> = c.cut.iter().map(|r| r.geometry(d)).collect();
    let dx = c.spacing;
    let (lo, _) = lattice_box(g, d);
    let amplitude = match g {
        Generator::Block(b) => b.jitter,
        _ => 0.0,
    };
    let ranges = index_ranges(g, d).map(|(a, b)| (a as usize, b as usize));
    for i0 in ranges[0].0..ranges[0].1 {
        for i1 in ranges[1].0..ranges[1].1 {
            for i2 in ranges[2].0..ranges[2].1 {
                let idx = [i0, i1, i2];
                let mut p = [0.0; 3];
                for k in 0..d {
                    p[k] = lo[k] + (idx[k] as f64 + offset(c.lattice, d, k, idx)) * dx;
                }
                if amplitude > 0.0 {
                    for (k, x) in p.iter_mut().enumerate().take(d) {
                        *x += amplitude * dx * jitter(idx, k);
                    }
                }
                if let Some((centre, r2)) = &disk {
                    let dist2: f64 = (0..d).map(|k| (p[k] - centre[k]).powi(2)).sum();
                    if dist2.is_nan() || dist2 > *r2 {
                        continue;
                    }
                }
                if c.clip.is_some_and(|b| !b.contains(&p, d)) {
                    continue;
                }
                if cuts.iter().any(|b| b.contains(&p)) {
                    continue;
                }
                f(p);
            }
        }
    }
}

/// A number in `[−1, 1)` fixed by a lattice index and an axis: SplitMix64 (Steele, Lea &
/// Flood 2014, *Fast splittable pseudorandom number generators*, OOPSLA) of the index's
/// three components and the axis. Written out rather than taken from a crate so that a scene
/// file gives the same particles in every version of the engine (a generator crate is free
/// to change its sequence between versions).
pub fn jitter(idx: [usize; 3], axis: usize) -> f64 {
    let mut z = (idx[0] as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add((idx[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        .wrapping_add((idx[2] as u64).wrapping_mul(0x1656_67B1_9E37_79F9))
        .wrapping_add(axis as u64);
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Velocity of a particle at `p`.
fn velocity(v: Option<&Velocity>, p: &[f64; 3], d: usize) -> [f64; 3] {
    let mut out = [0.0; 3];
    match v {
        None => {}
        Some(Velocity::Uniform(u)) => {
            for k in 0..d {
                out[k] = u.get(k).copied().unwrap_or(0.0);
            }
        }
        Some(Velocity::Linear(g)) => {
            for a in 0..d {
                let row = g.get(a).map(Vec::as_slice).unwrap_or(&[]);
                out[a] = (0..d)
                    .map(|b| row.get(b).copied().unwrap_or(0.0) * p[b])
                    .sum();
            }
        }
        Some(Velocity::TaylorGreen { speed, wavelength }) => {
            let k = 2.0 * std::f64::consts::PI / wavelength;
            let ((sx, cx), (sy, cy)) = (libm::sincos(k * p[0]), libm::sincos(k * p[1]));
            out[0] = speed * sx * cy;
            out[1] = -speed * cx * sy;
        }
    }
    out
}

/// The particles of generator number `index`.
/// `body` is the index of the generator's body.
pub(crate) fn particles(g: &Generator, generator: u32, body: u16, d: usize) -> Vec<ParticleSpec> {
    if let Generator::File(f) = g {
        return f.specs(generator, body);
    }
    let c = g.common();
    let dx = c.spacing;
    let mass = c.density * dx.powi(d as i32);
    positions(g, d)
        .into_iter()
        .map(|pos| ParticleSpec {
            pos,
            vel: velocity(c.velocity, &pos, d),
            mass,
            density: c.density,
            h: c.h_factor * dx,
            internal_energy: c.internal_energy,
            body,
            generator,
        })
        .collect()
}

/// All particles of all generators, in order, each with the index of its body in `bodies`
/// (0 for a generator without a known body). Empty for an unusable dimension or when the
/// estimated total exceeds [`MAX_PARTICLES`].
pub(crate) fn generate_all(
    generators: &[Generator],
    bodies: &[BodySettings],
    d: usize,
) -> Vec<ParticleSpec> {
    if !(1..=3).contains(&d) {
        return Vec::new();
    }
    let total: f64 = generators.iter().map(|g| estimate_count(g, d)).sum();
    if total.is_nan() || total > MAX_PARTICLES as f64 {
        return Vec::new();
    }
    generators
        .iter()
        .enumerate()
        .flat_map(|(i, g)| {
            let name = g.common().body;
            let body = name.and_then(|n| bodies.iter().position(|b| b.name == n));
            particles(g, i as u32, body.unwrap_or(0) as u16, d)
        })
        .collect()
}
