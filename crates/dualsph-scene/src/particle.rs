//! One generated particle, what every generator yields.

/// One generated particle. Components beyond the scene dimension are 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParticleSpec {
    /// Position.
    pub pos: [f64; 3],
    /// Velocity.
    pub vel: [f64; 3],
    /// Mass `density · Δx^d` (the lattice cell volume times the density).
    pub mass: f64,
    /// Initial density.
    pub density: f64,
    /// Support radius `h_factor · Δx`.
    pub h: f64,
    /// Initial specific internal energy.
    pub internal_energy: f64,
    /// The index of its body in the scene's bodies (0 when the scene declares none).
    pub body: u16,
    /// The index of its generator in the scene's `particles`.
    pub generator: u32,
}
