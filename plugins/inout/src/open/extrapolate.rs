//! Step 3 of the open boundaries' systems ([`super::systems`]): the values of the buffer
//! particles extrapolated from the fluid with zero gradient across the open plane, and the
//! buffer's pressure where the boundary prescribes one.

use super::impedance::Impedance;
use super::state::{Boundaries, Boundary, BufferState};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::neighbours::{KdTree, Neighbours, Period};
use dualsph_fluid::BodyEos;
use dualsph_fluid::prelude::*;

/// A fluid particle next to a buffer: position, velocity, mass, density.
type Near<V> = (V, V, Real, Real);

/// True when a particle of `body` at `x` is of boundary `b`'s fluid within `reach` of its open
/// plane on the fluid's side (and of its section, widened by `reach`).
fn is_near<V: Vector>(b: &Boundary<V>, reach: Real, body: u16, x: V) -> bool {
    let z = &b.zone;
    let d = z.depth_of(x);
    let side = match b.inflow {
        Some(_) => (0.0..=z.depth() + reach).contains(&d),
        None => d < 0.0 && d >= -(z.depth() + reach),
    };
    body == b.fluid
        && side
        && (0..V::DIM)
            .filter(|&k| k != z.axis)
            .all(|k| x.get(k) >= z.min.get(k) - reach && x.get(k) <= z.max.get(k) + reach)
}

/// The fluid next to one boundary, in the order of its keys (the particle's id, then its
/// image across the period), with a k-d tree over its positions.
struct Slab<V: Vector> {
    near: Vec<Near<V>>,
    tree: Option<KdTree>,
}

/// A slab's key of the `image`-th copy of particle `id` (0: the particle itself; at most 7
/// images in 3-D, three bits).
fn key(id: u32, image: usize) -> u64 {
    (u64::from(id) << 3) | image as u64
}

/// The fluid particles within `reach` of each boundary (as [`is_near`] decides), with their
/// images across the periodic faces within `reach` of them: on a periodic axis the fluid
/// next to a buffer continues across the period.
fn near_rows<V: Vector>(
    all: &Boundaries<V>,
    period: Option<&Period<V>>,
    reach: Real,
    particles: impl Iterator<Item = (u32, u16, Near<V>)>,
) -> Vec<Vec<(u64, Near<V>)>> {
    let mut rows: Vec<Vec<(u64, Near<V>)>> = vec![Vec::new(); all.list.len()];
    for (id, body, f) in particles {
        if !all.list.iter().any(|b| b.fluid == body) {
            continue;
        }
        let shifts = period.map_or_else(Vec::new, |p| p.image_shifts(f.0, reach));
        let copies = std::iter::once(f.0).chain(shifts.into_iter().map(|s| f.0 + s));
        for (image, x) in copies.enumerate() {
            for (k, b) in all.list.iter().enumerate() {
                if is_near(b, reach, body, x) {
                    rows[k].push((key(id, image), (x, f.1, f.2, f.3)));
                }
            }
        }
    }
    rows
}

impl<V: Vector> Slab<V> {
    fn new(mut rows: Vec<(u64, Near<V>)>) -> Self {
        rows.sort_unstable_by_key(|r| r.0);
        let near: Vec<Near<V>> = rows.into_iter().map(|r| r.1).collect();
        let points: Vec<V> = near.iter().map(|f| f.0).collect();
        let tree = (!points.is_empty()).then(|| KdTree::new(&points));
        Slab { near, tree }
    }

    /// The particles within `h` of `x` (and a hair beyond: the kernel is zero there), in key
    /// order, so that a sum over them adds its non-zero terms in the same order as a sum over
    /// the whole slab.
    fn within(&self, x: V, h: Real) -> Vec<Near<V>> {
        let Some(tree) = &self.tree else {
            return Vec::new();
        };
        let mut picked = Vec::new();
        tree.for_each_within(x, h, |i| picked.push(i));
        picked.sort_unstable();
        picked.iter().map(|&i| self.near[i as usize]).collect()
    }
}

/// The Shepard average of the velocity and the density of `near` at `x` with support `h`,
/// `φ(x) = Σ_f φ_f W_f V_f / Σ_f W_f V_f` ([Shepard 1968]; the density as `Σ_f m_f W_f /
/// Σ_f W_f V_f`), or `None` when no fluid particle is within `h` of `x`.
pub fn shepard<V: Vector>(kernel: &Kernel, near: &[Near<V>], x: V, h: Real) -> Option<(V, Real)> {
    let (mut s0, mut sv, mut sm) = (0.0, V::zero(), 0.0);
    for &(xf, vf, mf, rhof) in near {
        let w = kernel.w((x - xf).length(), h);
        if w > 0.0 {
            let wv = w * mf / rhof;
            s0 += wv;
            sv += vf * wv;
            sm += w * mf;
        }
    }
    (s0 > 0.0).then(|| (sv / s0, sm / s0))
}

/// The velocity and density at `x` from the linear fit to `near` weighted by `W_f V_f`
/// (the first-order moving least squares: `φ(x_f) ≈ a + b·(x_f − x)` minimising
/// `Σ_f W_f V_f (φ_f − a − b·(x_f − x))²`, which gives `a`, exact for a linear field however
/// the support is truncated — next to a wall the Shepard average leans towards the interior,
/// by a first-order error in the distance to the wall). Falls back to [`shepard`] where the
/// fit's matrix is singular (fewer than d + 1 particles in the support, or all on a line);
/// `None` when no fluid particle is within `h` of `x`.
pub fn linear_fit<V: Vector>(
    kernel: &Kernel,
    near: &[Near<V>],
    x: V,
    h: Real,
) -> Option<(V, Real)> {
    let d = V::DIM;
    let n = d + 1;
    // the normal equations M c = r for every field (d velocity components and the density)
    let mut m = [[0.0; 4]; 4];
    let mut rhs = [[0.0; 4]; 4];
    let mut any = false;
    for &(xf, vf, mf, rhof) in near {
        let w = kernel.w((x - xf).length(), h) * mf / rhof;
        if w <= 0.0 {
            continue;
        }
        any = true;
        let dx = xf - x;
        let basis: [Real; 4] = std::array::from_fn(|k| {
            if k == 0 {
                1.0
            } else if k <= d {
                dx.get(k - 1)
            } else {
                0.0
            }
        });
        let fields: [Real; 4] = std::array::from_fn(|k| {
            if k < d {
                vf.get(k)
            } else if k == d {
                rhof
            } else {
                0.0
            }
        });
        for i in 0..n {
            for j in 0..n {
                m[i][j] += w * basis[i] * basis[j];
            }
            for (f, value) in fields.iter().enumerate().take(n) {
                rhs[f][i] += w * basis[i] * value;
            }
        }
    }
    if !any {
        return None;
    }
    let Some(a) = solve_first(m, rhs, n) else {
        return shepard(kernel, near, x, h);
    };
    let mut v = V::zero();
    for k in 0..d {
        v.set(k, a[k]);
    }
    Some((v, a[d]))
}

/// The first unknown of `M c = r_f` for each right-hand side `r_f` (f < n), by Gaussian
/// elimination with partial pivoting; `None` for a (numerically) singular `M`.
fn solve_first(mut m: [[Real; 4]; 4], mut r: [[Real; 4]; 4], n: usize) -> Option<[Real; 4]> {
    let scale = (0..n).map(|i| m[i][i].abs()).fold(0.0, Real::max);
    for col in 0..n {
        let pivot = (col..n).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].abs() <= 1e-10 * scale {
            return None;
        }
        m.swap(col, pivot);
        for f in r.iter_mut().take(n) {
            f.swap(col, pivot);
        }
        for row in col + 1..n {
            let k = m[row][col] / m[col][col];
            for j in col..n {
                m[row][j] -= k * m[col][j];
            }
            for f in r.iter_mut().take(n) {
                f[row] -= k * f[col];
            }
        }
    }
    let mut first = [0.0; 4];
    for (f, out) in r.iter().take(n).zip(first.iter_mut()) {
        let mut c = [0.0; 4];
        for i in (0..n).rev() {
            let s: Real = (i + 1..n).map(|j| m[i][j] * c[j]).sum();
            c[i] = (f[i] - s) / m[i][i];
        }
        *out = c[0];
    }
    Some(first)
}

/// Step 3 of the systems' docs ([`super::systems`]).
#[inline(never)] // a frame of its own in profiles
pub fn extrapolate<V: Vector>(
    all: Res<Boundaries<V>>,
    kernel: Res<KernelRes>,
    nb: Res<Neighbours<V>>,
    eos: Option<Res<BodyEos>>,
    mut impedance: Option<ResMut<Impedance>>,
    mut q: Query<(
        &ParticleId,
        &BodyId,
        &Position<V>,
        &mut Velocity<V>,
        &Mass,
        &mut Density,
        &SmoothingLength,
        &mut BufferState<V>,
    )>,
) {
    let h_max = q.iter().map(|r| r.6.0).fold(0.0, Real::max);
    let fluid =
        (q.iter()).map(|(id, body, r, v, m, rho, ..)| (id.0, body.0, (r.0, v.0, m.0, rho.0)));
    let rows = near_rows(&all, nb.period.as_ref(), h_max, fluid);
    let slabs: Vec<Slab<V>> = rows.into_iter().map(Slab::new).collect();
    let laws: Vec<_> = (all.list.iter())
        .map(|b| (eos.as_ref()).and_then(|e| e.0.get(usize::from(b.fluid)).cloned()))
        .collect();
    // the fit at every buffer particle's mirror image, in the query's order, with its id
    let (ids, fits): (Vec<u32>, Vec<Option<(usize, V, Real)>>) = (q.iter())
        .map(|(id, body, r, .., h, _)| {
            let fit = all
                .of_body
                .get(usize::from(body.0))
                .copied()
                .flatten()
                .and_then(|k| {
                    let x = all.list[k].zone.mirror(r.0);
                    let (v, rho) = linear_fit(&kernel.0, &slabs[k].within(x, h.0), x, h.0)?;
                    Some((k, v, rho))
                });
            (id.0, fit)
        })
        .unzip();
    let pressures = buffer_pressures(&all, &laws, &fits, &ids, impedance.as_deref_mut());
    let densities: Vec<Option<Real>> = (pressures.iter().zip(&laws))
        .map(|(p, law)| p.and_then(|p| law.as_ref().and_then(|l| l.density_at(p))))
        .collect();
    for ((_, _, _, mut v, _, mut rho, _, mut st), fit) in q.iter_mut().zip(fits) {
        let Some((k, v_g, rho_g)) = fit else {
            continue;
        };
        st.rho = densities[k].unwrap_or(rho_g);
        rho.0 = st.rho;
        if all.list[k].inflow.is_none() {
            st.v = v_g;
            v.0 = v_g;
        }
    }
}

/// The pressure each boundary's buffer takes, if any: the prescribed one, or for a
/// non-reflecting outflow `p + ρc (U − Ū)` ([`super::impedance`]) with U the mean normal
/// velocity of the fits, summed in id order.
fn buffer_pressures<V: Vector>(
    all: &Boundaries<V>,
    laws: &[Option<std::sync::Arc<dyn dualsph_fluid::EosLaw>>],
    fits: &[Option<(usize, V, Real)>],
    ids: &[u32],
    impedance: Option<&mut Impedance>,
) -> Vec<Option<Real>> {
    let mut pressures: Vec<Option<Real>> = all.list.iter().map(|b| b.pressure).collect();
    let Some(impedance) = impedance else {
        return pressures;
    };
    let mut by_id: Vec<(u32, usize, Real)> = (ids.iter().zip(fits))
        .filter_map(|(id, f)| f.map(|(k, v, _)| (*id, k, v.dot(all.list[k].zone.normal()))))
        .collect();
    by_id.sort_unstable_by_key(|r| r.0);
    let mut sums = vec![(0.0, 0usize); all.list.len()];
    for (_, k, u) in by_id {
        sums[k].0 += u;
        sums[k].1 += 1;
    }
    for (k, b) in all.list.iter().enumerate() {
        let (Some(p), Some(_), Some(law)) = (b.pressure, b.non_reflecting, &laws[k]) else {
            continue;
        };
        let (Some(rho), true) = (law.density_at(p), sums[k].1 > 0) else {
            continue;
        };
        let z = rho * law.eval(rho, 0.0).1;
        let u = sums[k].0 / sums[k].1 as Real;
        pressures[k] = Some(impedance.0[k].pressure(p, z, u));
    }
    pressures
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn the_shepard_average_is_exact_for_a_uniform_field_and_empty_far_away() {
        let kernel = Kernel::new(KernelKind::WendlandC2, 2);
        let near: Vec<Near<DVec2>> = (0..25)
            .map(|k| {
                let x = DVec2::new((k % 5) as f64, (k / 5) as f64) * 0.01;
                (x, DVec2::new(0.3, -0.1), 1e-4 * 1003.0, 1003.0)
            })
            .collect();
        let (v, rho) = shepard(&kernel, &near, DVec2::new(0.013, 0.021), 0.03).unwrap();
        assert!((v - DVec2::new(0.3, -0.1)).length() < 1e-15, "{v}");
        assert!((rho - 1003.0).abs() < 1e-12, "{rho}");
        assert!(shepard(&kernel, &near, DVec2::new(1.0, 1.0), 0.03).is_none());
    }

    /// An outflow on x ∈ [1, 1.1] of a domain periodic on y ∈ [0, 1): the fluid next to its
    /// buffer continues across the period, so a mirror image by the face y = 0 has as many
    /// neighbours as one in the middle (without the images it would have about half).
    #[test]
    fn the_fluid_next_to_a_buffer_continues_across_the_period() {
        use super::super::zone::Zone;
        let zone = Zone::new(DVec2::new(1.0, 0.0), DVec2::new(1.1, 1.0), 0, 1.0, false);
        let all = Boundaries {
            list: vec![Boundary {
                zone: zone.with_periodic([false, true, false]),
                buffer: 2,
                fluid: 1,
                inflow: None,
                pressure: None,
                non_reflecting: None,
            }],
            of_body: vec![None, None, Some(0)],
        };
        let period = Period::new(DVec2::ZERO, DVec2::new(2.0, 1.0), [false, true, false]);
        let dx = 0.02;
        let fluid = (0..50 * 50).map(|k| {
            let x = DVec2::new(0.01 + (k % 50) as f64 * dx, 0.01 + (k / 50) as f64 * dx);
            (k as u32, 1, (x, DVec2::X, 1.0, 1.0))
        });
        let h = 0.055;
        let slab = Slab::new(near_rows(&all, period.as_ref(), h, fluid).remove(0));
        let count = |y| slab.within(DVec2::new(0.97, y), h).len();
        // points the lattice passes at the same offsets: in the middle, on the face y = 0
        // and a spacing below y = 1
        let (middle, by_face) = (count(0.5), count(0.0));
        assert!(middle > 10, "{middle}");
        assert_eq!(by_face, middle);
        assert_eq!(count(0.98), middle);
        // the images are where the period puts them: below the face y = 0
        assert!(
            slab.within(DVec2::new(0.97, 0.0), h)
                .iter()
                .any(|f| f.0.y < 0.0)
        );
    }

    /// A linear field sampled on one side of a wall: the fit gives it exactly at a point by
    /// the wall, where the Shepard average leans towards the interior.
    #[test]
    fn the_linear_fit_is_exact_for_a_linear_field_by_a_wall() {
        let kernel = Kernel::new(KernelKind::WendlandC2, 2);
        let field = |x: DVec2| DVec2::new(2.0 + 30.0 * x.y, -x.x);
        let near: Vec<Near<DVec2>> = (0..100)
            .map(|k| {
                let x = DVec2::new((k % 10) as f64 + 0.5, (k / 10) as f64 + 0.5) * 0.005;
                (x, field(x), 0.025, 1000.0 + 100.0 * x.y)
            })
            .collect();
        let at = DVec2::new(0.0225, 0.0025);
        let (v, rho) = linear_fit(&kernel, &near, at, 0.015).unwrap();
        assert!((v - field(at)).length() < 1e-12, "{v} vs {}", field(at));
        assert!((rho - (1000.0 + 100.0 * at.y)).abs() < 1e-9, "{rho}");
        let (v_s, _) = shepard(&kernel, &near, at, 0.015).unwrap();
        assert!((v_s - field(at)).x > 0.05, "Shepard leans inwards: {v_s}");
    }
}
