//! `dualsph probe RUN_DIR`: the scene's probes sampled over a finished run's snapshots (the
//! files its `snapshots.csv` lists, CSV or `.vtp`), as the live probes sample the running
//! simulation (`dualsph_probes::evaluate`), into `OUT/probes.csv` and `OUT/probes_points.csv`
//! (`plot-probes OUT` draws them). The probes are the run's scene's, read from its
//! `run.json` (its text and `--set`), or another scene's (`--scene`: the run's scene with
//! probes added after the run).

use super::exit::{self, Failure};
use super::{SetArgs, load, require_file};
use crate::gridded::{field, read_particles};
use dualsph_core::plugin::Registry;
use dualsph_fluid::prelude::*;
use dualsph_probes::{ProbeState, ProbedParticles, Quantity};
use dualsph_scene::Scene;
use std::path::{Path, PathBuf};

/// The default output directory of `probe` inside the run's directory.
pub(crate) const DEFAULT_OUT: &str = "snapshot_probes";

/// Runs `dualsph probe`: returns the probes file written and the number of snapshots read.
pub(crate) fn probe_command(
    dir: &Path,
    scene: Option<&Path>,
    out: Option<PathBuf>,
    set: &SetArgs,
    registry: &Registry,
) -> Result<(PathBuf, usize), Failure> {
    let scene = match scene {
        Some(path) => {
            let s = load(path, registry, set)?;
            describes_the_run(dir, path, &s, registry)?;
            s
        }
        None => recorded_scene(dir, registry, set)?,
    };
    let list = dir.join(dualsph_io::SNAPSHOT_INDEX_FILE);
    require_file(&list)?;
    let snapshots = read_index(&list)?;
    let out = out.unwrap_or_else(|| dir.join(DEFAULT_OUT));
    crate::with_dimension!(scene.dimension, V => {
        sample_snapshots::<V>(&scene, dir, &snapshots, &out)
    })
    .map(|()| (out.join(dualsph_probes::PROBES_FILE), snapshots.len()))
}

/// The scene of the run in `dir`: its `run.json`'s text, parsed with its `--set` (and any
/// given now) against the scene's own path, so files it names resolve as they did.
fn recorded_scene(dir: &Path, registry: &Registry, set: &SetArgs) -> Result<Scene, Failure> {
    let record = dir.join("run.json");
    require_file(&record)?;
    let invalid =
        |m: String| Failure::new(exit::INVALID_INPUT, format!("{}: {m}", record.display()));
    let text = dualsph_io::read_input_text(&record, dualsph_io::SCENE_FILE_LIMIT)
        .map_err(|e| Failure::new(exit::IO, format!("{}: {e}", record.display())))?;
    let json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| invalid(format!("not a run record: {e}")))?;
    let field = |k: &str| json.get(k).and_then(|v| v.as_str()).map(str::to_string);
    let (Some(path), Some(scene_text)) = (field("scene_path"), field("scene_text")) else {
        return Err(invalid("names no scene (scene_path, scene_text)".into()));
    };
    let base = field("working_directory").map_or_else(PathBuf::new, PathBuf::from);
    let path = base.join(path);
    let recorded = json.pointer("/settings/set").and_then(|s| s.as_array());
    let mut overrides = Vec::new();
    for given in recorded.into_iter().flatten().filter_map(|v| v.as_str()) {
        let o: dualsph_scene::Override = given
            .parse()
            .map_err(|e: String| invalid(format!("its --set {given}: {e}")))?;
        overrides.push(o);
    }
    overrides.extend(set.set.iter().cloned());
    let scene = Scene::parse_overridden(&scene_text, &path, registry, &overrides)
        .map_err(|e| invalid(format!("its scene: {e}")))?;
    scene
        .validate(&path)
        .map_err(|e| invalid(format!("its scene: {e}")))?;
    Ok(scene)
}

/// Refuses a `--scene` that does not describe the run in `dir`: the rule is the run's
/// scene fingerprint ([`crate::checkpoint::fingerprint`]: name, dimension, domain, kernel,
/// formulation, bodies, generators, plugins and integrator) with the `Probes` plugins left
/// out of both sides; `end_time`, `max_steps`, `output` and `health` may differ. An unrelated
/// scene's probes read the snapshots of another flow, and wrote readings of nothing.
fn describes_the_run(
    dir: &Path,
    path: &Path,
    scene: &Scene,
    registry: &Registry,
) -> Result<(), Failure> {
    let run = recorded_scene(dir, registry, &SetArgs::default())?;
    let of = |s: &Scene| crate::checkpoint::fingerprint_of(s, |name| name != "Probes");
    if of(&run) == of(scene) {
        return Ok(());
    }
    Err(Failure::new(
        exit::INVALID_INPUT,
        format!(
            "{}: the scene does not describe the run in {} (the run's scene is `{}`, {}-D with \
             {} generators and {} plugins; this is `{}`, {}-D with {} generators and {} \
             plugins): --scene must be the run's scene, its --set included, with probes added \
             or changed; only its Probes, end_time, max_steps, output and health may differ",
            path.display(),
            dir.display(),
            run.name,
            run.dimension,
            run.particles.len(),
            run.plugins.len(),
            scene.name,
            scene.dimension,
            scene.particles.len(),
            scene.plugins.len(),
        ),
    ))
}

/// `(step, t, file)` of every snapshot `snapshots.csv` lists.
fn read_index(path: &Path) -> Result<Vec<(u64, Real, String)>, Failure> {
    let text = dualsph_io::read_input_text(path, dualsph_io::INPUT_FILE_LIMIT)
        .map_err(|e| Failure::new(exit::IO, format!("{}: {e}", path.display())))?;
    let bad = |line: usize| {
        Failure::new(
            exit::INVALID_INPUT,
            format!("{}:{line}: expected `step,t,file`", path.display()),
        )
    };
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate().skip(1) {
        let mut f = line.splitn(3, ',');
        let (Some(step), Some(t), Some(file)) = (f.next(), f.next(), f.next()) else {
            return Err(bad(k + 1));
        };
        let step = step.trim().parse().map_err(|_| bad(k + 1))?;
        let t = t.trim().parse().map_err(|_| bad(k + 1))?;
        out.push((step, t, file.trim().to_string()));
    }
    Ok(out)
}

/// Samples the probes of `scene` in each snapshot and writes the probe files to `out`.
fn sample_snapshots<V: Vector>(
    scene: &Scene,
    dir: &Path,
    snapshots: &[(u64, Real, String)],
    out: &Path,
) -> Result<(), Failure> {
    let invalid = |m: String| Failure::new(exit::INVALID_INPUT, m);
    let sim = crate::build_sim::<V>(scene).map_err(|e| invalid(e.to_string()))?;
    let Some(state) = sim.world.get_resource::<ProbeState<V>>() else {
        return Err(invalid(format!(
            "the scene `{}` has no Probes plugin: nothing to sample",
            scene.name
        )));
    };
    let kernel = sim.world.resource::<KernelRes>().0;
    let domain = *sim.world.resource::<Domain<V>>();
    let mut rows = Vec::with_capacity(snapshots.len());
    for (step, t, file) in snapshots {
        let path = dir.join(file);
        require_file(&path)?;
        let at = |m: String| invalid(format!("{}: {m}", path.display()));
        let table = read_particles(scene, &path).map_err(at)?;
        let (particles, values) = probed(&table, state).map_err(at)?;
        rows.push((
            *step,
            *t,
            dualsph_probes::evaluate(state, kernel, &domain, &particles, &values),
        ));
    }
    dualsph_probes::write_files(out, state, &rows).map_err(|m| Failure::new(exit::IO, m))
}

/// The particles of `table` the probes sample (their bodies') and each sampled quantity's
/// values of them.
#[allow(clippy::type_complexity)]
fn probed<V: Vector>(
    table: &dualsph_io::ParticleTable,
    state: &ProbeState<V>,
) -> Result<(ProbedParticles<V>, Vec<(Quantity, Vec<Real>)>), String> {
    let d = V::DIM;
    let col = |name: &str| {
        field::column(table, name, d)
            .map(|c| c.values.clone())
            .map_err(|e| e.to_string())
    };
    let bodies = col("body")?;
    let keep: Vec<bool> = bodies
        .iter()
        .map(|&b| state.sampled.get(b as usize).copied().unwrap_or(false))
        .collect();
    // the rows of the sampled bodies (`side` true) or of the others
    let rows = |v: &[Real], w: usize, side: bool| -> Vec<Real> {
        v.chunks_exact(w)
            .zip(&keep)
            .filter(|(_, k)| **k == side)
            .flat_map(|(r, _)| r.iter().copied())
            .collect()
    };
    let kept = |v: Vec<Real>, w: usize| rows(&v, w, true);
    let points = |v: &[Real]| -> Vec<V> {
        v.chunks_exact(3)
            .map(|p| V::from_slice(&p[..d]).unwrap_or_else(V::zero))
            .collect()
    };
    let (position, mass, h) = (col("position")?, col("mass")?, col("smoothing_length")?);
    let particles = ProbedParticles {
        pos: points(&rows(&position, 3, true)),
        mass: rows(&mass, 1, true),
        rho: kept(col("density")?, 1),
        h: rows(&h, 1, true),
        others: (
            points(&rows(&position, 3, false)),
            rows(&mass, 1, false),
            rows(&h, 1, false),
        ),
    };
    let mut values = Vec::new();
    for q in state.quantities() {
        let v = field::values(table, q, d).map_err(|e| e.to_string())?;
        values.push((q.clone(), kept(v, 1)));
    }
    Ok((particles, values))
}
