//! Semantic checks of a parsed scene; the first problem found is reported.

use crate::Scene;
use crate::checks::{Check, ordered, positive, vector};
use crate::error::Problem;
use crate::generate::{self, MAX_PARTICLES};
use crate::lattice::{BoxRegion, Velocity};
use crate::schema::Generator;
use crate::shapes;
use dualsph_core::plugin::{Role, SceneInfo};

mod close;
mod overlap;
mod support;

use overlap::{fmt_point, overlaps};

fn boxes(field: &str, b: &BoxRegion, d: usize) -> Check {
    vector(&format!("{field}.min"), &b.min, d)?;
    vector(&format!("{field}.max"), &b.max, d)
}

fn generator(i: usize, g: &Generator, d: usize) -> Check {
    let f = |name: &str| format!("particles[{i}].{name}");
    match g {
        Generator::File(file) => return crate::particles_file::check(i, file, d),
        Generator::Block(b) => {
            vector(&f("min"), &b.min, d)?;
            vector(&f("max"), &b.max, d)?;
            ordered(&f("max"), &b.min, &b.max)?;
            if !(0.0..=0.25).contains(&b.jitter) {
                return Err(Problem::new(
                    f("jitter"),
                    format!(
                        "expected a fraction of the spacing in [0, 0.25], got {}",
                        b.jitter
                    ),
                ));
            }
        }
        Generator::Disk(c) => {
            vector(&f("center"), &c.center, d)?;
            positive(&f("radius"), c.radius)?;
        }
        Generator::Shape(s) => shapes::check_shape(&f("shape"), &s.shape, d)?,
    }
    let c = g.common();
    positive(&f("spacing"), c.spacing)?;
    positive(&f("density"), c.density)?;
    positive(&f("h_factor"), c.h_factor)?;
    if let Some(clip) = c.clip {
        boxes(&f("clip"), clip, d)?;
        ordered(&f("clip.max"), &clip.min, &clip.max)?;
    }
    for (j, cut) in c.cut.iter().enumerate() {
        shapes::check_region(&f(&format!("cut[{j}]")), cut, d)?;
    }
    match c.velocity {
        None => {}
        Some(Velocity::Uniform(v)) => vector(&f("velocity"), v, d)?,
        Some(Velocity::Linear(rows)) => {
            if rows.len() != d {
                return Err(Problem::new(
                    f("velocity"),
                    format!(
                        "expected a {d}x{d} matrix (one row per axis) for dimension {d}, got {} rows",
                        rows.len()
                    ),
                ));
            }
            for (r, row) in rows.iter().enumerate() {
                vector(&f(&format!("velocity[{r}]")), row, d)?;
            }
        }
        Some(Velocity::TaylorGreen { speed, wavelength }) => {
            if d != 2 {
                return Err(Problem::new(
                    f("velocity"),
                    format!("TaylorGreen is a 2-D vortex, the scene has dimension {d}"),
                ));
            }
            if !speed.is_finite() {
                return Err(Problem::new(
                    f("velocity.speed"),
                    format!("must be finite, got {speed}"),
                ));
            }
            positive(&f("velocity.wavelength"), *wavelength)?;
        }
    }
    if !(c.internal_energy.is_finite() && c.internal_energy >= 0.0) {
        return Err(Problem::new(
            f("internal_energy"),
            format!("must be a finite number >= 0, got {}", c.internal_energy),
        ));
    }
    Ok(())
}

/// One periodic flag per axis, and every support fitting its period: a pair must meet one
/// image only, so `2 h (1 + skin) < L` on each periodic axis for the largest generated h.
fn periodic(s: &Scene) -> Check {
    let (d, p) = (s.dimension, &s.domain.periodic);
    if p.is_empty() {
        return Ok(());
    }
    if p.len() != d {
        return Err(Problem::new(
            "domain.periodic",
            format!("expected {d} flags (one per axis), got {}", p.len()),
        ));
    }
    let reach = s
        .particles
        .iter()
        .map(|g| g.common().h_factor * g.spacing() * (1.0 + s.neighbours.skin))
        .fold(0.0, f64::max);
    for k in (0..d).filter(|&k| p[k]) {
        let l = s.domain.max[k] - s.domain.min[k];
        if 2.0 * reach >= l {
            return Err(Problem::new(
                "domain.periodic",
                format!(
                    "axis {k} is periodic with length {l}, which must exceed twice the largest \
                     search radius h (1 + skin) = {reach}"
                ),
            ));
        }
    }
    Ok(())
}

/// Everything that can be checked without generating particles.
fn settings(s: &Scene) -> Check {
    let d = s.dimension;
    if !(1..=3).contains(&d) {
        return Err(Problem::new(
            "dimension",
            format!("must be 1, 2 or 3, got {d}"),
        ));
    }
    vector("domain.min", &s.domain.min, d)?;
    vector("domain.max", &s.domain.max, d)?;
    ordered("domain.max", &s.domain.min, &s.domain.max)?;
    periodic(s)?;
    if !s.kernel.supports_dimension(d) {
        return Err(Problem::new(
            "kernel",
            format!(
                "{:?} cannot be normalised in {d}-D (its radial integral diverges at r = 0); \
                 choose another kernel",
                s.kernel
            ),
        ));
    }
    let skin = s.neighbours.skin;
    if !(skin.is_finite() && skin >= 0.0) {
        return Err(Problem::new(
            "neighbours.skin",
            format!("must be a finite number >= 0, got {skin}"),
        ));
    }
    if s.particles.is_empty() {
        return Err(Problem::new(
            "particles",
            "the scene has no particle generators",
        ));
    }
    for (i, g) in s.particles.iter().enumerate() {
        generator(i, g, d)?;
        if let Generator::Shape(shape) = g {
            let domain = (&s.domain.min[..], &s.domain.max[..]);
            shapes::check_generator(i, shape, d, domain)?;
        }
    }
    let info = SceneInfo {
        dimension: d,
        bodies: s.body_list().into_iter().map(|b| b.name).collect(),
        domain: (s.domain.min.clone(), s.domain.max.clone()),
        max_steps: s.max_steps,
    };
    for section in [Some(&s.integrator), s.health.as_ref()]
        .into_iter()
        .flatten()
    {
        section
            .validate(&info)
            .map_err(|p| Problem::new(p.field, p.message))?;
    }
    positive("end_time", s.end_time)?;
    if s.max_steps == Some(0) {
        return Err(Problem::new("max_steps", "must be at least 1 (or None)"));
    }
    s.output.check()?;
    bodies(s)?;
    for (i, p) in s.plugins.iter().enumerate() {
        p.validate(&info)
            .map_err(|m| Problem::new(format!("plugins[{i}] ({})", p.name()), m))?;
    }
    for role in [Role::Integrator, Role::Diagnostics] {
        one_of_role(s, role)?;
    }
    Ok(())
}

/// At most one plugin of an exclusive role (an integrator, the diagnostics); the problem
/// names the first two.
pub(crate) fn one_of_role(s: &Scene, role: Role) -> Check {
    let mut found = s
        .plugins
        .iter()
        .enumerate()
        .filter(|(_, p)| p.role() == role);
    if let (Some((i, a)), Some((j, b))) = (found.next(), found.next()) {
        let what = match role {
            Role::Integrator => "integrators",
            _ => "diagnostics plugins",
        };
        return Err(Problem::new(
            format!("plugins[{j}] ({})", b.name()),
            format!(
                "two {what} in one scene, {} (plugins[{i}]) and {}: keep one",
                a.name(),
                b.name()
            ),
        ));
    }
    Ok(())
}

/// Whether `c` may be part of a body name: letters, digits, `_`, `-` and `.`.
fn body_name_char(c: char) -> bool {
    c.is_alphanumeric() || matches!(c, '_' | '-' | '.')
}

/// A body name is not empty and made of [`body_name_char`]s only: the name heads columns of
/// `diagnostics.csv` (`mass[water]`) and `bodies.csv`, where a comma, a quote, a bracket, a
/// blank or a line break would break the row (the run failed when it wrote the file).
fn body_name(i: usize, name: &str) -> Check {
    let field = format!("bodies[{i}].name");
    if name.is_empty() {
        return Err(Problem::new(field, "must not be empty"));
    }
    match name.chars().find(|&c| !body_name_char(c)) {
        None => Ok(()),
        Some(c) => Err(Problem::new(
            field,
            format!(
                "{name:?} holds {c:?}: a body name is made of letters, digits, `_`, `-` and `.` \
                 (it heads columns of diagnostics.csv)"
            ),
        )),
    }
}

/// Every declared body that is not a fluid (a fixed or a moved one) has particles from some
/// generator, unless its kind is filled during the run (an open boundary's buffer): nothing
/// else adds any later (an inlet fills fluid bodies only), so an empty one
/// is a body named in a generator's stead by mistake, or a generator's `body` forgotten.
fn solid_bodies_have_particles(s: &Scene) -> Check {
    let single = s.bodies.len() == 1;
    for (i, b) in s.bodies.iter().enumerate() {
        let filled = s.particles.iter().any(|g| match g.common().body {
            Some(name) => name == b.name,
            None => single,
        });
        if !b.kind.is_fluid() && !b.kind.filled_during_run() && !filled {
            return Err(Problem::new(
                format!("bodies[{i}]"),
                format!(
                    "the body `{}` is not a fluid and no generator gives it particles (set a \
                     generator's `body: \"{}\"`, or remove the body)",
                    b.name, b.name
                ),
            ));
        }
    }
    Ok(())
}

/// Body names are unique and not empty, at most `u16::MAX + 1` of them; every generator
/// names a declared body, or leaves it out when there is one body.
fn bodies(s: &Scene) -> Check {
    let names: Vec<&str> = s.bodies.iter().map(|b| b.name.as_str()).collect();
    if names.len() > usize::from(u16::MAX) + 1 {
        return Err(Problem::new(
            "bodies",
            format!("{} bodies, at most 65536", names.len()),
        ));
    }
    for (i, name) in names.iter().enumerate() {
        body_name(i, name)?;
        if names[..i].contains(name) {
            return Err(Problem::new(
                format!("bodies[{i}].name"),
                format!("the body `{name}` is declared twice"),
            ));
        }
    }
    for (i, g) in s.particles.iter().enumerate() {
        match g.common().body {
            Some(b) if !names.is_empty() && !names.contains(&b) => {
                return Err(Problem::new(
                    format!("particles[{i}].body"),
                    format!(
                        "no body named `{b}`; the scene's bodies are {}",
                        names.join(", ")
                    ),
                ));
            }
            Some(b) if names.is_empty() => {
                return Err(Problem::new(
                    format!("particles[{i}].body"),
                    format!("`{b}` names a body, but the scene declares no `bodies`"),
                ));
            }
            None if names.len() > 1 => {
                return Err(Problem::new(
                    format!("particles[{i}].body"),
                    format!(
                        "the scene has {} bodies: say which this generator's particles belong to",
                        names.len()
                    ),
                ));
            }
            _ => {}
        }
    }
    let info = SceneInfo {
        dimension: s.dimension,
        bodies: names.iter().map(|n| n.to_string()).collect(),
        domain: (s.domain.min.clone(), s.domain.max.clone()),
        max_steps: s.max_steps,
    };
    for (i, b) in s.bodies.iter().enumerate() {
        b.kind.validate(&info).map_err(|p| {
            let at = format!("bodies[{i}].kind");
            let field = if p.field.is_empty() {
                at
            } else {
                format!("{at}.{}", p.field)
            };
            Problem::new(field, p.message)
        })?;
        if let Some(c) = &b.moment_about {
            let at = format!("bodies[{i}].moment_about");
            if b.kind.is_fluid() {
                return Err(Problem::new(
                    at,
                    "a fluid body has no load to take a moment of: give it to a fixed or \
                     prescribed body",
                ));
            }
            vector(&at, c, s.dimension)?;
            moment_arm_bounded(&at, c, s)?;
        }
    }
    solid_bodies_have_particles(s)
}

/// How far outside the domain (in domain diagonals from its centre) a moment may be taken:
/// farther, the arms times the forces lose every digit of the moment, or overflow.
const MAX_MOMENT_ARM: f64 = 1e3;

/// `c` lies within [`MAX_MOMENT_ARM`] domain diagonals of the domain's centre.
fn moment_arm_bounded(at: &str, c: &[f64], s: &Scene) -> Check {
    let d = s.dimension.min(c.len());
    let (min, max) = (&s.domain.min, &s.domain.max);
    let diagonal = (0..d)
        .map(|k| (max[k] - min[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    // the largest offset along an axis: squares of far points would overflow
    let off = (0..d)
        .map(|k| (c[k] - 0.5 * (min[k] + max[k])).abs())
        .fold(0.0, f64::max);
    if off.is_finite() && off <= MAX_MOMENT_ARM * diagonal {
        return Ok(());
    }
    Err(Problem::new(
        at,
        format!(
            "{off:e} from the domain's centre along an axis, more than {MAX_MOMENT_ARM:e} \
             domain diagonals ({diagonal}): the moment's arms would swamp its digits or overflow"
        ),
    ))
}

/// A cap on the particle count: the number and why it is what it is (empty for the fixed
/// [`MAX_PARTICLES`]; e.g. " (the memory available for a run)" for a machine-derived cap).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limit<'a> {
    pub max: usize,
    pub why: &'a str,
}

/// The particle-count guard, evaluated before anything is generated.
fn count_guard(s: &Scene, limit: Limit) -> Check {
    let d = s.dimension;
    let counts: Vec<f64> = s
        .particles
        .iter()
        .map(|g| generate::estimate_count(g, d))
        .collect();
    let total: f64 = counts.iter().sum();
    let max = limit.max.min(MAX_PARTICLES);
    if total <= max as f64 {
        return Ok(());
    }
    let (worst, n) = counts.iter().enumerate().fold(
        (0, 0.0),
        |acc, (i, &n)| if n > acc.1 { (i, n) } else { acc },
    );
    Err(Problem::new(
        "particles",
        format!(
            "the generators would create about {total:.3e} particles, more than the limit of \
             {max}{}; the largest is particles[{worst}] with about {n:.3e} (increase its spacing)",
            if max < MAX_PARTICLES { limit.why } else { "" }
        ),
    ))
}

/// Runs every check in order and returns the first problem. The particles are streamed, not
/// stored: per generator its count, the first particle outside the domain and its bounding box.
pub(crate) fn validate(s: &Scene, limit: Limit) -> Check {
    settings(s)?;
    count_guard(s, limit)?;
    let d = s.dimension;
    let (min, max) = (&s.domain.min, &s.domain.max);
    let mut bounds = Vec::with_capacity(s.particles.len());
    let mut outside: Option<(usize, [f64; 3])> = None;
    for (i, g) in s.particles.iter().enumerate() {
        let (mut count, mut lo, mut hi) = (0usize, [f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut first_out = None;
        generate::for_each_position(g, d, |p| {
            count += 1;
            for k in 0..d {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
            if first_out.is_none() && (0..d).any(|k| p[k] < min[k] || p[k] > max[k]) {
                first_out = Some(p);
            }
        });
        if count == 0 {
            return Err(Problem::new(
                format!("particles[{i}]"),
                format!(
                    "particles[{i}] generates no particles (check its size, spacing, clip and cut)"
                ),
            ));
        }
        if outside.is_none() {
            outside = first_out.map(|p| (i, p));
        }
        bounds.push((lo, hi));
    }
    if let Some((i, x)) = outside {
        return Err(Problem::new(
            format!("particles[{i}]"),
            format!(
                "particles[{i}] generates a particle at {} outside the domain {:?}..{:?}",
                fmt_point(&x, d),
                min,
                max
            ),
        ));
    }
    overlaps(s, &bounds)?;
    close::across_periodic_faces(s)?;
    close::coincident_in_files(s)?;
    support::enough_neighbours(s)
}
