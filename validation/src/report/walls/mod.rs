//! Flows bounded by walls of particles, and the viscous flows that grade the viscous terms
//! next to them: water at rest in a tank ([`hydrostatic`]), plane Poiseuille flow
//! ([`poiseuille`]), the lid-driven cavity ([`cavity`]) and the periodic Taylor–Green vortex
//! ([`taylor_green`]), the pressure of a dam break on the far wall ([`wall_pressure`]), the
//! water front of the paper's dam-break Cases II and III ([`dam_break_fronts`]), the load
//! on a submerged obstacle read from an STL file in a 3-D tank ([`stl_tank`]) and the load
//! history of a 2-D dam break onto a step and a cylinder ([`dam_break_obstacle`]), and the
//! free-surface flows refined to two and four times their resolution ([`refinement`]). The walls are
//! layers of fixed particles whose pressure and viscous velocity are extrapolated from the
//! fluid (Adami, Hu & Adams 2012, *A generalized wall boundary condition for smoothed particle
//! hydrodynamics*, J. Comput. Phys. 231, 7057–7075, Eqs. 22–28). Where a wrong wall model is the failure the measure is meant to catch, the
//! section runs it too: the walls' density evolved by the continuity equation (the dynamic
//! boundary) in the tanks and the dam break onto obstacles, the walls' own velocity in the
//! viscous terms in the channel, the cavity and the dam breaks.
//!
//! Each module holds the measures its test in `validation/tests/` asserts on, so the report
//! and the test compute them once.

pub mod cavity;
pub mod dam_break_fronts;
pub mod dam_break_obstacle;
pub mod hydrostatic;
pub mod poiseuille;
pub mod refinement;
pub mod stl_tank;
pub mod taylor_green;
pub mod wall_pressure;

/// The force on body `body` in a diagnostics row (zero when the row has no load for it).
pub(crate) fn body_force(d: &dualsph_diagnostics::Diagnostics, body: usize) -> [f64; 3] {
    d.loads
        .iter()
        .find(|l| l.body == body)
        .map_or([0.0; 3], |l| l.force)
}

/// `"within"` when `ok`, else `"NOT within"`: a verdict computed from a comparison.
pub(crate) fn within(ok: bool) -> &'static str {
    if ok { "within" } else { "NOT within" }
}

/// The scene `file` as it is (no-slip walls), then with the walls' own velocity in the
/// viscous terms (`viscous: Own`): the wall model and the one the measure must tell apart.
pub(crate) fn no_slip_and_own(
    opts: &super::ReportOptions,
    file: &str,
) -> Result<Vec<super::CaseSpec>, super::ReportError> {
    use super::CaseSpec;
    Ok(vec![
        CaseSpec::new("no-slip walls (Adami et al. 2012)", opts.scene(file)?, None),
        CaseSpec::new(
            "walls at their own velocity",
            opts.scene_edited(file, "viscous: NoSlip", "viscous: Own")?,
            None,
        ),
    ])
}
