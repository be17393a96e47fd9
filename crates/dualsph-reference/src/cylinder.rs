//! Flow past a circular cylinder in a channel: the DFG benchmarks 2D-1 (steady, Re = 20) and
//! 2D-2 (periodic, Re = 100) of Schäfer & Turek (1996), *Benchmark computations of laminar
//! flow around a cylinder*, in E. H. Hirschel (ed.), *Flow Simulation with High-Performance
//! Computers II*, Notes on Numerical Fluid Mechanics 52, Vieweg, pp. 547–566, §2.2 (the
//! definitions) and Table 4 (the intervals the participants' best results fall in, which the
//! authors give as the reference values). The same intervals are quoted by the benchmark's
//! maintained page (FeatFlow, TU Dortmund: "DFG flow around cylinder benchmark 2D-1/2D-2") and
//! by the validation data of the Musubi lattice-Boltzmann solver (`Re20_data.txt`,
//! `Re100_data.txt`: L_a, Δp and St).
//!
//! The set-up (§2.2): the channel `[0, 2.2] × [0, 0.41]` m, the cylinder of diameter
//! `D = 0.1` m centred at `(0.2, 0.2)` (off the channel's axis by 0.005 m, hence a small lift
//! at Re = 20), no-slip on the walls and the cylinder, ρ = 1 kg/m³, ν = 10⁻³ m²/s, the inflow
//! `u(0, y) = 4 U_m y (H − y)/H²`, `H = 0.41` m, with `U_m = 0.3` m/s (2D-1) or 1.5 m/s (2D-2);
//! the mean inflow speed `Ū = 2 U_m / 3`, `Re = Ū D / ν`. The coefficients
//! `c_D = 2 F_D / (ρ Ū² D)`, `c_L = 2 F_L / (ρ Ū² D)` (F the force on the cylinder per unit
//! depth, along and across the flow), `L_a = x_r − 0.25` the recirculation length behind the
//! cylinder (x_r the end of the region of reversed flow on the axis y = 0.2), `St = D f / Ū`
//! (f the frequency of the lift), `Δp = p(0.15, 0.2) − p(0.25, 0.2)`.

/// A reference interval `[lower, upper]`.
pub type Interval = (f64, f64);

/// The midpoint of an interval.
pub fn midpoint((lower, upper): Interval) -> f64 {
    0.5 * (lower + upper)
}

/// The benchmark's geometry and fluid (§2.2).
pub mod setup {
    /// Channel length (m).
    pub const LENGTH: f64 = 2.2;
    /// Channel height H (m).
    pub const HEIGHT: f64 = 0.41;
    /// Cylinder diameter D (m).
    pub const DIAMETER: f64 = 0.1;
    /// Cylinder centre (m).
    pub const CENTRE: [f64; 2] = [0.2, 0.2];
    /// Kinematic viscosity ν (m²/s).
    pub const NU: f64 = 1e-3;
    /// Density ρ (kg/m³).
    pub const RHO: f64 = 1.0;
    /// Peak inflow speed U_m of 2D-1 (m/s): Ū = 0.2 m/s, Re = 20.
    pub const U_MAX_2D1: f64 = 0.3;
    /// Peak inflow speed U_m of 2D-2 (m/s): Ū = 1 m/s, Re = 100.
    pub const U_MAX_2D2: f64 = 1.5;
}

/// 2D-1 (steady, Re = 20), Table 4: the drag coefficient c_D.
pub const DRAG_2D1: Interval = (5.5700, 5.5900);
/// 2D-1, Table 4: the lift coefficient c_L.
pub const LIFT_2D1: Interval = (0.0104, 0.0110);
/// 2D-1, Table 4: the recirculation length L_a (m).
pub const RECIRCULATION_2D1: Interval = (0.0842, 0.0852);
/// 2D-1, Table 4: the pressure difference Δp (Pa).
pub const PRESSURE_DROP_2D1: Interval = (0.1172, 0.1176);

/// 2D-2 (periodic, Re = 100), Table 4: the largest drag coefficient over a period.
pub const DRAG_MAX_2D2: Interval = (3.2200, 3.2400);
/// 2D-2, Table 4: the largest lift coefficient over a period.
pub const LIFT_MAX_2D2: Interval = (0.9900, 1.0100);
/// 2D-2, Table 4: the Strouhal number.
pub const STROUHAL_2D2: Interval = (0.2950, 0.3050);
/// 2D-2, Table 4: Δp at the end of the period that starts at the lift's largest value (Pa).
pub const PRESSURE_DROP_2D2: Interval = (2.4600, 2.5000);

/// The force coefficient `2 F / (ρ Ū² D)` of a force per unit depth F (N/m).
pub fn coefficient(force: f64, rho: f64, mean_speed: f64, diameter: f64) -> f64 {
    2.0 * force / (rho * mean_speed * mean_speed * diameter)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reynolds_numbers_are_the_benchmarks() {
        let re = |u_max: f64| (2.0 / 3.0) * u_max * setup::DIAMETER / setup::NU;
        assert!((re(setup::U_MAX_2D1) - 20.0).abs() < 1e-12);
        assert!((re(setup::U_MAX_2D2) - 100.0).abs() < 1e-12);
    }

    #[test]
    fn a_coefficient_scales_the_force_by_the_dynamic_pressure() {
        // 2D-1: ρ Ū² D / 2 = 1 · 0.04 · 0.1 / 2 = 0.002 N/m
        assert!((coefficient(0.002 * 5.58, 1.0, 0.2, 0.1) - 5.58).abs() < 1e-12);
        assert!((midpoint(DRAG_2D1) - 5.58).abs() < 1e-12);
    }
}
