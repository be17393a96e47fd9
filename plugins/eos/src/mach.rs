//! The check of a weakly compressible liquid's sound speed against the speeds its scene
//! implies: a Tait liquid is nearly incompressible only while the flow's Mach number stays
//! below about 0.1 (the density then varies by about 1 %, `Δρ/ρ ≈ Ma²`; Monaghan 1994,
//! *Simulating free surface flows with SPH*, J. Comput. Phys. 110, 399, §3), so `c0` should be
//! at least ten times the largest speed: the speed `√(2 g H)` the fluid reaches falling a
//! height `H` under gravity `g` (`H` the drop from its highest free surface to its lowest, or
//! to an empty floor beside it: a dam-break column falls its height, a tank at rest does not
//! fall; no fall where gravity lies along a periodic axis and drives a flow instead), and the
//! fastest initial particle, and the speeds plugins impose (an inlet's). Below that the run may still
//! work, or stall on its time step when the density runs away (warned, not refused).

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::Bodies;
use dualsph_fluid::BodyEos;
use dualsph_fluid::prelude::*;
use dualsph_fluid::speeds::SpeedScales;
use dualsph_gravity::GravityAccel;

/// The ratio `c0 / U_max` below which [`sound_speed_advice`] warns.
pub const MIN_SPEED_RATIO: Real = 10.0;

/// The largest speed the fluid's particles imply: `(speed, what)`, with `what` saying where it
/// comes from (the fall of the fluid under `g`, or the fastest initial particle).
pub fn implied_speed<V: Vector>(world: &mut World) -> Option<(Real, String)> {
    let fluid: Vec<bool> = world
        .resource::<Bodies>()
        .0
        .iter()
        .map(|b| b.is_fluid())
        .collect();
    let domain = *world.resource::<Domain<V>>();
    // gravity along a periodic axis drives a flow (Poiseuille's); the fluid does not fall
    let g = world
        .get_resource::<GravityAccel<V>>()
        .map(|g| g.0)
        .filter(|g| g.length() > 0.0)
        .filter(|g| (0..V::DIM).all(|k| !domain.periodic[k] || g.get(k) == 0.0));
    let mut q = world.query::<(&Position<V>, &Velocity<V>, &BodyId, &Mass, &Density)>();
    let mut fastest: Real = 0.0;
    let mut seen = Vec::new();
    for (r, v, b, m, rho) in q.iter(world) {
        let is_fluid = fluid.get(b.0 as usize).copied().unwrap_or(false);
        if is_fluid {
            fastest = fastest.max(v.0.length());
        }
        let size = dualsph_core::math::particle_size(V::DIM, m.0, rho.0);
        seen.push((r.0, is_fluid, size));
    }
    if !seen.iter().any(|s| s.1) {
        return None;
    }
    let fall = g.map(|g| (fall_height(&seen, g, &domain), g.length()));
    let imposed = world
        .get_resource::<SpeedScales>()
        .and_then(|s| s.0.iter().cloned().max_by(|a, b| a.0.total_cmp(&b.0)));
    let own = match fall {
        Some((h, g)) if (2.0 * g * h).sqrt() >= fastest && h > 0.0 => Some((
            (2.0 * g * h).sqrt(),
            format!(
                "√(2 g H) of the fluid's fall, H = {h:.4} m from its highest free surface to its \
                 lowest or to the floor beside it, under g = {g} m/s²"
            ),
        )),
        _ => Some((fastest, "the fastest initial fluid particle".to_string())),
    };
    match (own, imposed) {
        (Some(o), Some(i)) if i.0 > o.0 => Some(i),
        (own, _) => own,
    }
}

/// The height the fluid can fall under `g`: over columns of the domain along gravity (each
/// two fluid spacings wide), the drop from the highest fluid top to the lowest, where a column
/// with no fluid counts at the fluid's lowest level (an empty floor the water can run onto)
/// unless a wall stands in it (a non-fluid particle between that level and the fluid's
/// highest: a tank's lid above the water blocks no column) or, in a scene with
/// walls of particles, it holds no particle at all (outside the container). A tank at rest has a
/// level surface and no fall; a dam-break column falls its height. With gravity along no
/// single axis, the fluid's whole height.
fn fall_height<V: Vector>(seen: &[(V, bool, Real)], g: V, domain: &Domain<V>) -> Real {
    let d = V::DIM;
    let axes: Vec<usize> = (0..d).filter(|&k| g.get(k) != 0.0).collect();
    let up = |r: &V| -r.dot(g) / g.length();
    let fluid = || seen.iter().filter(|s| s.1);
    let low = fluid().map(|s| up(&s.0)).fold(Real::INFINITY, Real::min);
    let high = fluid()
        .map(|s| up(&s.0))
        .fold(Real::NEG_INFINITY, Real::max);
    let [a] = axes[..] else { return high - low };
    let across: Vec<usize> = (0..d).filter(|&k| k != a).collect();
    let width = 2.0 * fluid().map(|s| s.2).fold(0.0, Real::max);
    let count = |k: usize| {
        ((domain.max.get(k) - domain.min.get(k)) / width)
            .ceil()
            .max(1.0)
    };
    let cells_f: Vec<Real> = across.iter().map(|&k| count(k)).collect();
    // a grid past four million columns (or a degenerate spacing) is not worth it: the whole height
    if width.is_nan() || width <= 0.0 || cells_f.iter().product::<Real>() > (1 << 22) as Real {
        return high - low;
    }
    let cells: Vec<usize> = cells_f.iter().map(|&c| c as usize).collect();
    let total: usize = cells.iter().product();
    // per column: the fluid's top, and whether a wall stands in it within the fluid's heights
    let mut top = vec![Real::NEG_INFINITY; total];
    let mut wall = vec![false; total];
    // with walls of particles the container is theirs, and a column with no particle at all
    // lies outside it; without, the domain box is the container
    let walled = seen.iter().any(|s| !s.1);
    let mut empty = vec![walled; total];
    for (r, is_fluid, _) in seen {
        let mut c = 0;
        for (n, &k) in across.iter().enumerate() {
            let i = ((r.get(k) - domain.min.get(k)) / width).floor();
            c = c * cells[n] + (i.max(0.0) as usize).min(cells[n] - 1);
        }
        let h = up(r);
        empty[c] = false;
        if *is_fluid {
            top[c] = top[c].max(h);
        } else if h > low && h <= high {
            wall[c] = true;
        }
    }
    let levels = (0..total).filter_map(|c| match (top[c] > Real::NEG_INFINITY, wall[c]) {
        (true, _) => Some(top[c]),
        (false, false) if !empty[c] => Some(low),
        (false, _) => None,
    });
    let (lo, hi) = levels.fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), h| {
        (lo.min(h), hi.max(h))
    });
    (hi - lo).max(0.0)
}

/// A warning when a liquid's sound speed is below [`MIN_SPEED_RATIO`] times the largest speed
/// its scene implies (module docs); `None` otherwise.
pub fn sound_speed_advice<V: Vector>(world: &mut World) -> Option<String> {
    let c0 = {
        let laws = world.get_resource::<BodyEos>()?;
        let bodies = world.resource::<Bodies>();
        laws.0
            .iter()
            .enumerate()
            .filter(|(b, _)| bodies.0.get(*b).is_some_and(|body| body.is_fluid()))
            .filter_map(|(_, law)| law.reference_density().map(|rho0| law.eval(rho0, 0.0).1))
            .fold(Real::INFINITY, Real::min)
    };
    let (u, what) = implied_speed::<V>(world)?;
    if !(c0.is_finite() && u > 0.0) || c0 >= MIN_SPEED_RATIO * u {
        return None;
    }
    Some(format!(
        "TaitEos: c0 = {c0} m/s is below {MIN_SPEED_RATIO} times the largest speed the scene \
         implies, {u:.3} m/s ({what}): the Mach number reaches {:.2}, the density may vary by \
         more than 1 % and the run may stall; c0 ≥ {:.1} m/s keeps it below 0.1",
        u / c0,
        (MIN_SPEED_RATIO * u * 10.0).ceil() / 10.0
    ))
}
