//! Refusing a scene whose simulation would not fit in memory, before anything is built.
//!
//! The scene validator caps the particle count ([`dualsph_scene::MAX_PARTICLES`]) whatever the
//! machine; this guard compares an estimate of the run's peak memory with what the machine has
//! available (`MemAvailable` in `/proc/meminfo`; no check where that cannot be read).

use dualsph_core::prelude::SimError;

/// Estimated peak bytes per particle by dimension (index = dimension): 3-D is the measured
/// 4,557 bytes of docs/performance.md (~51 candidates per particle); 1-D and 2-D scale the
/// neighbour-list part down with their fewer neighbours.
pub const BYTES_PER_PARTICLE: [u64; 4] = [0, 1_500, 3_000, 4_600];

/// Estimated peak memory of a run with `n` particles in `dim` dimensions.
pub fn memory_needed(dim: usize, n: usize) -> u64 {
    BYTES_PER_PARTICLE[dim.clamp(1, 3)].saturating_mul(n as u64)
}

/// `MemAvailable` of `/proc/meminfo` in bytes, if it can be read.
pub fn memory_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// The most particles of a `dim`-dimensional scene that fit in `available` bytes, and the
/// reason to print with it (`usize::MAX` and "" when the memory is unknown).
pub fn particle_limit(dim: usize, available: Option<u64>) -> (usize, String) {
    match available {
        Some(have) => {
            let per = BYTES_PER_PARTICLE[dim.clamp(1, 3)];
            let n = usize::try_from(have / per).unwrap_or(usize::MAX);
            let why = format!(
                " (what fits in the {:.1} GB of memory available at ~{per} bytes per particle)",
                have as f64 / 1e9
            );
            (n, why)
        }
        None => (usize::MAX, String::new()),
    }
}

/// An error when `n` particles in `dim` dimensions need more than `available` bytes.
pub fn check_memory(dim: usize, n: usize, available: Option<u64>) -> Result<(), SimError> {
    let need = memory_needed(dim, n);
    match available {
        Some(have) if need > have => Err(SimError::Build(format!(
            "{n} particles in {dim}-D need about {:.1} GB of memory (~{} bytes per particle), \
             more than the {:.1} GB available; increase the spacing",
            need as f64 / 1e9,
            BYTES_PER_PARTICLE[dim.clamp(1, 3)],
            have as f64 / 1e9
        ))),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_does_not_fit_and_accepts_what_does() {
        let gb = 1_000_000_000;
        assert!(check_memory(3, 1_000_000, Some(8 * gb)).is_ok());
        let e = check_memory(3, 10_000_000, Some(8 * gb)).unwrap_err();
        assert!(e.to_string().contains("46.0 GB"), "{e}");
        assert!(check_memory(2, usize::MAX, None).is_ok());
        assert_eq!(memory_needed(2, usize::MAX), u64::MAX);
        assert_eq!(particle_limit(3, Some(4_600_000)).0, 1000);
        assert_eq!(particle_limit(3, None).0, usize::MAX);
    }
}
