//! Refusing a scene whose simulation would not fit in memory, before anything is built.
//!
//! The scene validator caps the particle count ([`dualsph_scene::MAX_PARTICLES`]) whatever the
//! machine; this guard compares an estimate of the run's peak memory with what the machine has
//! available (`MemAvailable` in `/proc/meminfo`; no check where that cannot be read).

use dualsph_core::prelude::SimError;
use dualsph_core::sim::SimClock;
use dualsph_scene::Scene;

/// Bytes per particle besides its neighbour lists, by dimension (index = dimension): the
/// columns, the archetype tables of the set-up and the search grid. With
/// [`BYTES_PER_CANDIDATE`] at the usual `h_factor` 2 and skin 0.15 this gives 1.5 / 3.0 /
/// 4.6 kB in 1-/2-/3-D, above the measured peak of 2,581 bytes per particle of a 3-D run of
/// 10^6 particles with ~51 candidates each (docs/performance.md, "Memory").
pub const BASE_BYTES: [u64; 4] = [0, 1_350, 2_470, 2_970];

/// Bytes per candidate pair of the neighbour lists and the sweep: support, dual support and
/// the dual entries' slots (12), the sweep's route (4), the reaction records of pairs across
/// blocks, and the rows of the build (docs/performance.md, "Memory"); rounded up.
pub const BYTES_PER_CANDIDATE: f64 = 32.0;

/// The candidate neighbours of a particle on a lattice of its own spacing whose support is
/// `h_factor` spacings, searched to `h (1 + skin)`: the lattice points in that ball (segment,
/// disk), `ω_d (h_factor (1 + skin))^d` with `ω = 2, π, 4π/3`.
pub fn candidates(dim: usize, h_factor: f64, skin: f64) -> f64 {
    let r = h_factor * (1.0 + skin.max(0.0));
    match dim {
        1 => 2.0 * r,
        2 => std::f64::consts::PI * r * r,
        _ => 4.0 / 3.0 * std::f64::consts::PI * r * r * r,
    }
}

/// The largest finite `h_factor` of the scene's generators (0 without one).
fn largest_h_factor(scene: &Scene) -> f64 {
    scene
        .particles
        .iter()
        .map(|g| g.h_factor())
        .filter(|h| h.is_finite())
        .fold(0.0, f64::max)
}

/// Estimated peak bytes per particle of `scene`: [`BASE_BYTES`] and the neighbour lists of its
/// largest `h_factor` ([`candidates`] × [`BYTES_PER_CANDIDATE`]).
pub fn bytes_per_particle(scene: &Scene) -> u64 {
    let dim = scene.dimension.clamp(1, 3);
    let lists =
        BYTES_PER_CANDIDATE * candidates(dim, largest_h_factor(scene), scene.neighbours.skin);
    // a float beyond u64 saturates, as the memory it stands for is beyond any machine
    BASE_BYTES[dim].saturating_add(lists.ceil() as u64)
}

/// Estimated peak memory of a run of `scene` with `n` particles.
pub fn memory_needed(scene: &Scene, n: usize) -> u64 {
    bytes_per_particle(scene).saturating_mul(n as u64)
}

/// The environment variable that caps the memory a run may use (bytes): on a machine shared
/// with others, or in a container whose limit `/proc/meminfo` does not show.
pub const MEMORY_LIMIT_VAR: &str = "DUALSPH_MEMORY_LIMIT";

/// The memory a run may use, in bytes: `MemAvailable` of `/proc/meminfo`, or
/// [`MEMORY_LIMIT_VAR`] when that is set to a whole number of bytes and is smaller; `None`
/// when neither can be read.
pub fn memory_available() -> Option<u64> {
    let limit = std::env::var(MEMORY_LIMIT_VAR)
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok());
    let available = mem_available();
    match (limit, available) {
        (Some(l), Some(a)) => Some(l.min(a)),
        (l, a) => l.or(a),
    }
}

/// `MemAvailable` of `/proc/meminfo` in bytes, if it can be read.
fn mem_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// The run-time side of [`check_memory`]: the memory available when the run started, and the
/// particle count last checked against it. Plugins that add particles (the refinement's
/// splits, inlets) can multiply the count far past what the scene generates, which no check
/// before the run bounds; the run then stops with what went wrong where, as a blow-up does,
/// instead of being killed for memory with its files left as they were.
#[derive(Clone, Debug)]
pub struct Budget {
    available: Option<u64>,
    start: usize,
    last: usize,
}

impl Budget {
    /// The budget of a run that starts with `n` particles and `available` bytes.
    pub fn new(available: Option<u64>, n: usize) -> Self {
        Budget {
            available,
            start: n,
            last: n,
        }
    }

    /// After a step: when the particle count `n` grew since the last check, an error if `n`
    /// particles of `scene` need more than the memory available at the start (naming the
    /// step and time of `clock`).
    pub fn after_step(
        &mut self,
        scene: &Scene,
        n: usize,
        clock: &SimClock,
    ) -> Result<(), SimError> {
        let grew = n > self.last;
        self.last = n;
        let Some(have) = self.available.filter(|_| grew) else {
            return Ok(());
        };
        let per = bytes_per_particle(scene);
        let need = per.saturating_mul(n as u64);
        if need <= have {
            return Ok(());
        }
        Err(SimError::BlowUp(format!(
            "step {}, t = {:.6e}: the particle count grew to {n} ({} at the start; \
             particles added by refinement splits or inlets), which needs about {} of memory \
             (~{per} bytes per particle), more than the {} available to the run; \
             stopped before memory runs out: coarsen the finest size or the regions, refine \
             less often, or stop the inlets earlier",
            clock.step,
            clock.t,
            self.start,
            megabytes(need),
            megabytes(have)
        )))
    }
}

/// `bytes` as megabytes, e.g. `4.80 MB`, `12000.00 MB`.
fn megabytes(bytes: u64) -> String {
    format!("{:.2} MB", bytes as f64 / 1e6)
}

/// The most particles of `scene` that fit in `available` bytes, and the reason to print with
/// it (`usize::MAX` and "" when the memory is unknown).
pub fn particle_limit(scene: &Scene, available: Option<u64>) -> (usize, String) {
    match available {
        Some(have) => {
            let per = bytes_per_particle(scene).max(1);
            let n = usize::try_from(have / per).unwrap_or(usize::MAX);
            let why = format!(
                " (what fits in the {:.1} GB of memory available at ~{per} bytes per particle, \
                 its neighbour lists included)",
                have as f64 / 1e9
            );
            (n, why)
        }
        None => (usize::MAX, String::new()),
    }
}

/// The most particles the scene's plugins add over its run (its inlets' layers).
pub fn particles_added(scene: &Scene) -> f64 {
    scene
        .plugins
        .iter()
        .map(|p| p.particles_added(scene.end_time, scene.dimension))
        .sum()
}

/// An error when `n` particles of `scene`, with those its plugins add over the run
/// ([`particles_added`]), need more than `available` bytes.
pub fn check_memory(scene: &Scene, n: usize, available: Option<u64>) -> Result<(), SimError> {
    let per = bytes_per_particle(scene);
    let added = particles_added(scene);
    // a float beyond u64 saturates, as the memory it stands for is beyond any machine
    let total = (n as u64).saturating_add(added.ceil() as u64);
    let need = per.saturating_mul(total);
    let (inlets, or_inlets) = if added > 0.0 {
        (
            format!(" ({n} at the start and up to {added:.3e} added by inlets over the run)"),
            ", or stop the inlets earlier (`until`)",
        )
    } else {
        (String::new(), "")
    };
    match available {
        Some(have) if need > have => Err(SimError::Build(format!(
            "{total} particles{inlets} in {}-D need about {:.1} GB of memory (~{per} bytes per \
             particle, of which the neighbour lists of h_factor up to {} take {}), more than the \
             {:.1} GB available; increase the spacing or lower the h_factor{or_inlets}",
            scene.dimension,
            need as f64 / 1e9,
            largest_h_factor(scene),
            per - BASE_BYTES[scene.dimension.clamp(1, 3)],
            have as f64 / 1e9
        ))),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(dim: usize, h_factor: f64) -> Scene {
        let (min, max) = match dim {
            2 => ("[0.0, 0.0]", "[1.0, 1.0]"),
            _ => ("[0.0, 0.0, 0.0]", "[1.0, 1.0, 1.0]"),
        };
        let text = format!(
            "Scene(name: \"m\", dimension: {dim}, domain: (min: {min}, max: {max}),
             kernel: WendlandC2, particles: [Block(min: {min}, max: {max}, spacing: 0.1,
             density: 1000.0, h_factor: {h_factor})], integrator: (dt: Fixed(1e-4)),
             end_time: 1.0)"
        );
        let path = std::path::Path::new("m.ron");
        Scene::parse_only(&text, path, &dualsph_builtin::default_registry()).unwrap()
    }

    #[test]
    fn the_budget_stops_a_growing_run_once_it_outgrows_the_memory() {
        let s = scene(2, 2.0); // 3,002 bytes per particle
        let at = |step| SimClock {
            step,
            t: 0.1 * step as f64,
            dt: 0.1,
            initializing: false,
            t_end: 1.0,
        };
        let mut b = Budget::new(Some(3_002_000), 100);
        assert!(b.after_step(&s, 400, &at(1)).is_ok());
        assert!(b.after_step(&s, 1000, &at(2)).is_ok());
        let e = b.after_step(&s, 1001, &at(3)).unwrap_err().to_string();
        assert!(
            e.contains("step 3") && e.contains("grew to 1001 (100 at the start"),
            "{e}"
        );
        // no growth, no check; an unknown memory never stops a run
        let mut b = Budget::new(Some(1), 100);
        assert!(b.after_step(&s, 100, &at(1)).is_ok());
        assert!(
            Budget::new(None, 1)
                .after_step(&s, usize::MAX, &at(1))
                .is_ok()
        );
    }

    #[test]
    fn the_usual_h_factor_gives_the_measured_figures_with_margin() {
        // 3-D, h_factor 2, skin 0.15: ~51 candidates, as measured (2,581 bytes at 10^6)
        assert!((candidates(3, 2.0, 0.15) - 50.97).abs() < 0.01);
        assert_eq!(bytes_per_particle(&scene(3, 2.0)), 4_601);
        assert_eq!(bytes_per_particle(&scene(2, 2.0)), 3_002);
        assert_eq!(candidates(1, 2.0, 0.15), 4.6);
    }

    #[test]
    fn a_wide_support_counts_its_neighbour_lists() {
        // h_factor 16 in 3-D: ~26,000 candidates, ~0.8 MB per particle
        let s = scene(3, 16.0);
        let per = bytes_per_particle(&s);
        assert!(per > 800_000 && per < 900_000, "{per}");
        let gb = 1_000_000_000;
        let e = check_memory(&s, 20_000, Some(8 * gb)).unwrap_err();
        assert!(e.to_string().contains("h_factor up to 16"), "{e}");
        assert!(check_memory(&scene(3, 2.0), 20_000, Some(8 * gb)).is_ok());
        assert!(check_memory(&s, usize::MAX, None).is_ok());
        assert_eq!(memory_needed(&s, usize::MAX), u64::MAX);
        assert_eq!(particle_limit(&scene(3, 2.0), Some(4_601_000)).0, 1000);
        assert_eq!(particle_limit(&s, None).0, usize::MAX);
    }
}
