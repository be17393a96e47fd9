//! What `Probes::validate` refuses: every field named, before anything is built.

use crate::{MAX_GAUGE_SAMPLES, MAX_SENSOR_REACH, MAX_TABLE_VALUES, Probe, Probes};
use dualsph_core::math::Real;
use dualsph_core::plugin::SceneInfo;

/// The settings' checks ([`dualsph_core::plugin::SimPlugin::validate`]).
pub(crate) fn probes(p: &Probes, info: &SceneInfo) -> Result<(), String> {
    if p.every == 0 {
        return Err("every: must be at least 1".into());
    }
    if !(p.min_shepard.is_finite() && (0.0..1.0).contains(&p.min_shepard)) {
        return Err(format!(
            "min_shepard: must be in [0, 1), got {}",
            p.min_shepard
        ));
    }
    if p.probes.is_empty() {
        return Err("probes: the list is empty".into());
    }
    check_table(p, info.max_steps)?;
    for (k, b) in p.bodies.iter().enumerate() {
        info.check_body(&format!("bodies[{k}]"), b)?;
    }
    let mut names: Vec<&str> = Vec::new();
    for (i, probe) in p.probes.iter().enumerate() {
        let f = |s: &str| format!("probes[{i}].{s}");
        let name = check_probe(probe, &f, info)?;
        check_name(&f("name"), name)?;
        if names.contains(&name) {
            return Err(format!("{}: duplicate probe name {name:?}", f("name")));
        }
        names.push(name);
    }
    Ok(())
}

/// A table of `p`'s columns sampled every `p.every` steps over up to `max_steps` steps fits
/// in [`MAX_TABLE_VALUES`] (nothing to check without `max_steps`: a run stops at the bound).
fn check_table(p: &Probes, max_steps: Option<u64>) -> Result<(), String> {
    let Some(steps) = max_steps else {
        return Ok(());
    };
    let values = p.column_count().saturating_mul(steps / p.every + 2);
    if values > MAX_TABLE_VALUES {
        return Err(format!(
            "every: {} columns sampled every {} steps over up to {steps} steps (max_steps) \
             make {values:.3e} values, more than the table's {MAX_TABLE_VALUES:.0e}; sample \
             less often or fewer points",
            p.column_count(),
            p.every
        ));
    }
    Ok(())
}

/// One probe's settings (`f` names its fields); its name.
fn check_probe<'a>(
    probe: &'a Probe,
    f: &dyn Fn(&str) -> String,
    info: &SceneInfo,
) -> Result<&'a str, String> {
    let d = info.dimension;
    Ok(match probe {
        Probe::Point { name, at, .. } => {
            check_vec(&f("at"), at, d)?;
            check_inside(&f("at"), at, info)?;
            name
        }
        Probe::Line {
            name,
            start,
            end,
            n,
            ..
        } => {
            check_points(&f, (start, end, *n), info)?;
            name
        }
        Probe::Sensor {
            name,
            start,
            end,
            n,
            floor,
            clip,
            reach,
            ..
        } => {
            check_points(&f, (start, end, *n), info)?;
            if floor.is_some_and(|x| !x.is_finite()) {
                return Err(format!("{}: must be finite", f("floor")));
            }
            if clip.is_some_and(|x| !x.is_finite()) {
                return Err(format!("{}: must be finite", f("clip")));
            }
            if let Some(r) = reach
                && !(r.is_finite() && (0.1..=MAX_SENSOR_REACH).contains(r))
            {
                return Err(format!(
                    "{}: must be in [0.1, {MAX_SENSOR_REACH}], got {r}",
                    f("reach")
                ));
            }
            name
        }
        Probe::WaterHeight {
            name,
            at,
            threshold,
            dy,
        } => {
            check_gauge(f, at, *threshold, *dy, info)?;
            name
        }
    })
}

/// A water-height gauge's settings (`f` names its fields).
fn check_gauge(
    f: &dyn Fn(&str) -> String,
    at: &[Real],
    threshold: Option<Real>,
    dy: Option<Real>,
    info: &SceneInfo,
) -> Result<(), String> {
    let d = info.dimension;
    if d < 2 {
        return Err(format!(
            "{}: a water-height gauge needs dimension 2 or 3",
            f("")
        ));
    }
    check_vec(&f("at"), at, d - 1)?;
    check_inside(&f("at"), at, info)?;
    if let Some(t) = threshold
        && !(t.is_finite() && t > 0.0 && t < 1.0)
    {
        return Err(format!("{}: must be in (0, 1), got {t}", f("threshold")));
    }
    if let Some(dy) = dy
        && !(dy.is_finite() && dy > 0.0)
    {
        return Err(format!("{}: must be > 0, got {dy}", f("dy")));
    }
    // every reading walks the domain's height in steps of dy
    let height = info.domain.1[d - 1] - info.domain.0[d - 1];
    if let Some(dy) = dy
        && height.is_finite()
        && height / dy > MAX_GAUGE_SAMPLES
    {
        return Err(format!(
            "{}: {dy} takes {:.3e} samples over the domain's height {height} \
                 per reading, more than {MAX_GAUGE_SAMPLES:e}",
            f("dy"),
            height / dy
        ));
    }
    Ok(())
}

/// The point `x` lies in the scene's domain; the error names the field.
fn check_inside(field: &str, x: &[Real], info: &SceneInfo) -> Result<(), String> {
    if info.in_domain(x) {
        return Ok(());
    }
    Err(format!(
        "{field}: {x:?} is outside the domain [{:?}, {:?}]",
        info.domain.0, info.domain.1
    ))
}

fn check_name(field: &str, name: &str) -> Result<(), String> {
    let bad = |c: char| c.is_whitespace() || ",\"[]".contains(c);
    if name.is_empty() || name.chars().any(bad) {
        return Err(format!(
            "{field}: name {name:?} must be non-empty without spaces, commas, quotes or brackets"
        ));
    }
    Ok(())
}

/// `n` equally spaced points from `start` to `end` (a line or a sensor): both ends of the
/// scene's dimension and in the domain, 2 ≤ n ≤ 10,000; `f` names a field of the probe.
fn check_points(
    f: &dyn Fn(&str) -> String,
    (start, end, n): (&[Real], &[Real], usize),
    info: &SceneInfo,
) -> Result<(), String> {
    let d = info.dimension;
    check_vec(&f("start"), start, d)?;
    check_vec(&f("end"), end, d)?;
    check_inside(&f("start"), start, info)?;
    check_inside(&f("end"), end, info)?;
    if !(2..=10_000).contains(&n) {
        return Err(format!("{}: must be between 2 and 10000, got {n}", f("n")));
    }
    Ok(())
}

fn check_vec(field: &str, v: &[Real], d: usize) -> Result<(), String> {
    if v.len() != d {
        return Err(format!("{field}: expected {d} components, got {}", v.len()));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(format!("{field}: components must be finite"));
    }
    Ok(())
}
