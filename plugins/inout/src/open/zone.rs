//! The geometry of a buffer zone: an axis-aligned box, the axis and sense of the flow through
//! it, its open plane (the face it shares with the fluid) and its depth.

use dualsph_core::math::{Real, Vector};

/// A buffer zone `[min, max]` with the flow along `sign · e_axis`.
///
/// For an inflow the open plane is the downstream face and the zone lies upstream of it; for
/// an outflow the open plane is the upstream face and the zone lies downstream. Either way a
/// point's *depth* `d = sign · (x_axis − plane)` is negative upstream of the plane and positive
/// downstream, so an inflow's buffer holds `−L ≤ d < 0` and an outflow's `0 ≤ d ≤ L`, with
/// `L = max_axis − min_axis` the zone's depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Zone<V: Vector> {
    /// Lower corner.
    pub min: V,
    /// Upper corner.
    pub max: V,
    /// The axis of the flow.
    pub axis: usize,
    /// +1 when the flow goes towards +axis, −1 towards −axis.
    pub sign: Real,
    /// The coordinate of the open plane on `axis`.
    pub plane: Real,
    /// The axes on which the domain is periodic, as the domain's period had them when the
    /// boundary was built (the domain does not change over a run): read by the profile
    /// ([`super::Profile`]), which has no access to the neighbour lists' period.
    pub periodic: [bool; 3],
}

impl<V: Vector> Zone<V> {
    /// The zone of the box `[min, max]` with the flow along `direction` (an axis, ±e_k); the
    /// open plane is the downstream face for an inflow, the upstream face for an outflow.
    pub fn new(min: V, max: V, axis: usize, sign: Real, inflow: bool) -> Self {
        let downstream = if sign > 0.0 { max } else { min };
        let upstream = if sign > 0.0 { min } else { max };
        let plane = if inflow { downstream } else { upstream }.get(axis);
        Zone {
            min,
            max,
            axis,
            sign,
            plane,
            periodic: [false; 3],
        }
    }

    /// The zone in a domain periodic on `axes`: a profile across the flow is uniform along a
    /// periodic axis ([`super::Profile`]).
    pub fn with_periodic(mut self, axes: [bool; 3]) -> Self {
        self.periodic = axes;
        self
    }

    /// The depth `L` of the zone along the flow.
    pub fn depth(&self) -> Real {
        self.max.get(self.axis) - self.min.get(self.axis)
    }

    /// `d = sign · (x_axis − plane)` (see the type's docs).
    pub fn depth_of(&self, x: V) -> Real {
        self.sign * (x.get(self.axis) - self.plane)
    }

    /// True when `x` lies within the zone's cross-section (faces included) on every axis but
    /// the flow's.
    pub fn in_section(&self, x: V) -> bool {
        (0..V::DIM)
            .filter(|&k| k != self.axis)
            .all(|k| x.get(k) >= self.min.get(k) && x.get(k) <= self.max.get(k))
    }

    /// The flow's unit vector `sign · e_axis`.
    pub fn normal(&self) -> V {
        let mut n = V::zero();
        n.set(self.axis, self.sign);
        n
    }

    /// The mirror image of `x` in the open plane: `x − 2 d n`.
    pub fn mirror(&self, x: V) -> V {
        x - self.normal() * (2.0 * self.depth_of(x))
    }

    /// The fraction `s_k = (x_k − min_k)/(max_k − min_k)` of the cross-section on axis `k`.
    pub fn fraction(&self, x: V, k: usize) -> Real {
        (x.get(k) - self.min.get(k)) / (self.max.get(k) - self.min.get(k))
    }
}

/// The axis and sense of an axis-aligned direction (`[1, 0]`, `[0, 0, -1]`), or the message
/// for one that is not.
pub fn axis_of(direction: &[Real], d: usize) -> Result<(usize, Real), String> {
    let nonzero: Vec<usize> = (0..direction.len())
        .filter(|&k| direction[k] != 0.0)
        .collect();
    match nonzero[..] {
        [k] if direction.len() == d && direction[k].abs() == 1.0 => Ok((k, direction[k])),
        _ => Err(format!(
            "direction: expected a unit vector along an axis with {d} components (such as \
             [1.0{}]), got {direction:?}",
            ", 0.0".repeat(d.saturating_sub(1))
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn depth_and_mirror_follow_the_flow() {
        let inflow = Zone::new(DVec2::new(-0.2, 0.0), DVec2::ZERO.with_y(1.0), 0, 1.0, true);
        assert_eq!((inflow.plane, inflow.depth()), (0.0, 0.2));
        assert_eq!(inflow.depth_of(DVec2::new(-0.05, 0.5)), -0.05);
        assert_eq!(inflow.mirror(DVec2::new(-0.05, 0.5)), DVec2::new(0.05, 0.5));
        let outflow = Zone::new(DVec2::new(1.0, 0.0), DVec2::new(1.2, 1.0), 0, 1.0, false);
        assert_eq!(outflow.plane, 1.0);
        assert!((outflow.depth_of(DVec2::new(1.05, 0.5)) - 0.05).abs() < 1e-15);
        // a flow towards −x: the inflow's plane is its lower face
        let back = Zone::new(DVec2::new(1.0, 0.0), DVec2::new(1.2, 1.0), 0, -1.0, true);
        assert_eq!(back.plane, 1.0);
        assert!((back.depth_of(DVec2::new(1.1, 0.0)) + 0.1).abs() < 1e-15);
        assert!(back.in_section(DVec2::new(5.0, 1.0)) && !back.in_section(DVec2::new(1.1, 1.1)));
    }

    #[test]
    fn a_direction_must_be_an_axis() {
        assert_eq!(axis_of(&[0.0, -1.0], 2), Ok((1, -1.0)));
        for bad in [
            &[0.6, 0.8][..],
            &[1.0],
            &[0.0, 0.0],
            &[2.0, 0.0],
            &[f64::NAN, 0.0],
        ] {
            let e = axis_of(bad, 2).unwrap_err();
            assert!(e.starts_with("direction:"), "{e}");
        }
    }
}
