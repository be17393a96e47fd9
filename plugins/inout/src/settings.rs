//! Checks and geometry shared by the inlet and the outlet.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::BodyId;
use dualsph_core::components::{ParticleId, Position};
use dualsph_core::math::{Real, Vector};

/// Checks a box's corners: `d` finite components each, `min < max` on every axis; the error
/// names the field.
pub fn check_box(min: &[Real], max: &[Real], d: usize) -> Result<(), String> {
    for (name, v) in [("min", min), ("max", max)] {
        if v.len() != d || v.iter().any(|x| !x.is_finite()) {
            return Err(format!("{name}: expected {d} finite components, got {v:?}"));
        }
    }
    if let Some(k) = (0..d).find(|&k| min[k] >= max[k]) {
        return Err(format!(
            "max: must exceed min on every axis (axis {k}: {} <= {})",
            max[k], min[k]
        ));
    }
    Ok(())
}

/// The particle of `world` with the lowest id strictly inside the box `[min, max]` (by more
/// than a millionth of `spacing` on every axis, so that a body ending on the box's face is
/// not inside it): its id, position and body.
pub fn first_inside<V: Vector>(
    world: &mut World,
    min: V,
    max: V,
    spacing: Real,
) -> Option<(u32, V, u16)> {
    let eps = 1e-6 * spacing;
    let inside =
        |p: &V| (0..V::DIM).all(|k| p.get(k) > min.get(k) + eps && p.get(k) < max.get(k) - eps);
    let mut q = world.query::<(&ParticleId, &Position<V>, &BodyId)>();
    q.iter(world)
        .filter(|(_, p, _)| inside(&p.0))
        .map(|(id, p, b)| (id.0, p.0, b.0))
        .min_by_key(|(id, _, _)| *id)
}

/// The cell centres of a lattice of `spacing` over `[min, max]`: `round(extent/spacing)`
/// cells per axis (at least one), centred in the box; axis 0 varies fastest.
pub fn lattice<V: Vector>(min: V, max: V, spacing: Real) -> Vec<V> {
    let counts: Vec<usize> = (0..V::DIM)
        .map(|k| (((max.get(k) - min.get(k)) / spacing).round() as usize).max(1))
        .collect();
    let total: usize = counts.iter().product();
    (0..total)
        .map(|mut flat| {
            let mut p = V::zero();
            for (k, &c) in counts.iter().enumerate() {
                let i = flat % c;
                flat /= c;
                let centre = 0.5 * (min.get(k) + max.get(k));
                p.set(k, centre + (i as Real - 0.5 * (c as Real - 1.0)) * spacing);
            }
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn the_lattice_fills_the_box_at_its_spacing() {
        let pts = lattice(DVec2::new(0.0, 0.0), DVec2::new(0.1, 0.4), 0.1);
        assert_eq!(pts.len(), 4);
        for (k, p) in pts.iter().enumerate() {
            assert!((p.x - 0.05).abs() < 1e-15);
            assert!((p.y - (0.05 + 0.1 * k as Real)).abs() < 1e-15, "{p:?}");
        }
        // a box thinner than the spacing holds one cell on that axis
        assert_eq!(lattice(DVec2::ZERO, DVec2::new(0.01, 0.2), 0.1).len(), 2);
    }

    #[test]
    fn a_box_is_refused_with_the_field_named() {
        assert!(check_box(&[0.0, 0.0], &[1.0, 1.0], 2).is_ok());
        assert!(
            check_box(&[0.0], &[1.0, 1.0], 2)
                .unwrap_err()
                .starts_with("min:")
        );
        assert!(
            check_box(&[0.0, 0.0], &[1.0, f64::NAN], 2)
                .unwrap_err()
                .starts_with("max:")
        );
        assert!(
            check_box(&[0.0, 1.0], &[1.0, 1.0], 2)
                .unwrap_err()
                .contains("axis 1")
        );
    }
}
