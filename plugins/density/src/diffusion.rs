//! `DensityDiffusion(delta)`: the δ-SPH density diffusion of Molteni & Colagrossi (2009),
//! written as a dual-support pair term so that it only moves mass between particles.
//!
//! With the continuity equation the density carries the acoustic noise of a weakly
//! compressible flow undamped: pressures oscillate around the physical field with amplitudes
//! of order ρ0 c0 |v|, and where they swing negative the particles are under tension and pair
//! up (the tensile instability) until a density goes negative. The diffusive term
//!
//! `dρ_i/dt += δ h c0 Σ_j ψ_ij (r_ji·∇_iW_ij)/|r_ij|² V_j`,  `ψ_ij = 2(ρ_j − ρ_i)`
//!
//! (Molteni, D. & Colagrossi, A. (2009), A simple procedure to improve the pressure
//! evaluation in hydrodynamic context using the SPH, Comput. Phys. Commun. 180, 861–872: the
//! diffusive term they add to the continuity equation; it is also the δ-SPH term of Antuono,
//! Colagrossi, Marrone & Molteni (2010), Comput. Phys. Commun. 181, 532–549, without its
//! renormalised-gradient correction, which matters only under gravity. Equation numbers are
//! not quoted: they would refer to neither DS-SPH paper.) The pair sum is Brookshaw's (1985)
//! SPH Laplacian, so the term is `δ (h/2) c0 ∇²ρ` to O(h²): it damps the noise at the particle
//! scale and leaves smooth fields almost alone (tested against the analytic Laplacian).
//!
//! Dual-support form: for each owner i and `j ∈ H_i` (with i's kernel, `r < h_i`) one number
//!
//! `D_ij = δ (h_i/2) c̄_ij · (ρ_j − ρ_i) · (−∂W/∂r(r_ij, h_i)) / r_ij`,  `c̄_ij = (c_i + c_j)/2`
//!
//! (`r_ji·∇_iW_ij = −r ∂W/∂r ≥ 0`; `h_i/2` is the classical smoothing length of a kernel whose
//! support radius is `h_i`, so δ means what it means in the references, 0.1 there) is
//! applied as `dρ_i/dt += D_ij V_j` and, as the reaction, `dρ_j/dt −= D_ij V_i`. Like the
//! owner's half of the pressure term, each owner contributes half of `ψ_ij = 2(ρ_j − ρ_i)`:
//! with equal h the pair is evaluated from both sides and the sum is the formula above. Then
//! `V_i dρ_i + V_j dρ_j = 0` for every pair: the term only exchanges `ρV = m` between the
//! two, exactly, whatever the h field. It moves no momentum (no force). The sum over i is
//! taken over `H_i` in ascending j and the reactions through the dual-support list in
//! ascending i (the same `D_ij` recomputed from the same inputs), so it is deterministic.

use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::chunks::DENSE;
use dualsph_core::neighbours::Neighbours;
use dualsph_core::prelude::*;
use dualsph_core::sim::KernelRes;
use dualsph_core::store::{CoreColumns, single_table};
use rayon::prelude::*;
use serde::Deserialize;

/// δ-SPH density diffusion settings.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DensityDiffusion {
    /// δ, on the classical smoothing length h/2 (Molteni & Colagrossi, Antuono et al.: 0.1).
    #[serde(default = "default_delta")]
    pub delta: Real,
}

fn default_delta() -> Real {
    0.1
}

/// δ as a resource for the system.
#[derive(Resource, Clone, Copy, Debug)]
pub struct DiffusionDelta(pub Real);

/// What the diffusion reads: the core columns and the sound speeds.
#[derive(Clone, Copy, Debug)]
pub struct DiffusionData<'a, V: Vector> {
    /// Positions, masses, densities, support radii.
    pub data: ParticleData<'a, V>,
    /// Sound speeds `c_i`.
    pub sound: &'a [SoundSpeed],
}

/// `D_ij` of the module docs for the owner i and `j ∈ H_i`; `None` outside `h_i` or at r = 0.
#[inline]
pub fn pair_coefficient<V: Vector>(
    f: &DiffusionData<'_, V>,
    k: &Kernel,
    delta: Real,
    i: usize,
    j: usize,
) -> Option<Real> {
    let d = &f.data;
    let hi = d.h[i].0;
    let r = (d.pos[i].0 - d.pos[j].0).length();
    if !(r > 0.0 && r < hi) {
        return None;
    }
    let c = 0.5 * (f.sound[i].0 + f.sound[j].0);
    // the owner's half of ψ_ij = 2(ρ_j − ρ_i)
    let half_psi = d.rho[j].0 - d.rho[i].0;
    Some(delta * 0.5 * hi * c * half_psi * (-k.dw_dr(r, hi)) / r)
}

/// The diffusion rate `dρ_i/dt` of particle i (its owner sum plus its reactions).
pub fn diffusion_rate<V: Vector>(
    f: &DiffusionData<'_, V>,
    nb: &Neighbours<V>,
    k: &Kernel,
    delta: Real,
    i: usize,
) -> Real {
    let mut s = 0.0;
    for &j in nb.support.row(i) {
        let j = j as usize;
        if let Some(d) = pair_coefficient(f, k, delta, i, j) {
            s += d * f.data.volume(j);
        }
    }
    // reactions: i is the neighbour j of every owner o with i ∈ H_o
    for &o in nb.dual.row(i) {
        let o = o as usize;
        if let Some(d) = pair_coefficient(f, k, delta, o, i) {
            s -= d * f.data.volume(o);
        }
    }
    s
}

/// Adds the diffusion rates to `DensityRate.rate` (after the continuity equation has set it).
#[inline(never)] // a frame of its own in profiles
pub fn density_diffusion<V: Vector>(
    nb: Res<Neighbours<V>>,
    kernel: Res<KernelRes>,
    delta: Res<DiffusionDelta>,
    mut q: Query<(CoreColumns<V>, &SoundSpeed, &mut DensityRate)>,
) {
    let tables = q.contiguous_iter_mut().expect(DENSE);
    let Some((core, sound, mut rates)) = single_table(tables) else {
        return;
    };
    let f = DiffusionData {
        data: ParticleData::from_columns(core),
        sound,
    };
    rates
        .par_iter_mut()
        .enumerate()
        .with_min_len(64)
        .for_each(|(i, r)| r.rate += diffusion_rate(&f, &nb, &kernel.0, delta.0, i));
}

impl SimPlugin for DensityDiffusion {
    const NAME: &'static str = "DensityDiffusion";
    const SUMMARY: &'static str =
        "delta-SPH density diffusion (Molteni & Colagrossi 2009), mass-exchanging pair form";

    fn validate(&self, _info: &SceneInfo) -> Result<(), String> {
        if self.delta.is_finite() && self.delta > 0.0 && self.delta <= 1.0 {
            Ok(())
        } else {
            Err(format!("delta must lie in (0, 1], got {}", self.delta))
        }
    }

    /// Adds the diffusion after whatever sets the density rate in the `Forces` set (the pair
    /// sweep, the continuity system), wherever the plugins stand in the scene's list.
    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require_feature(
            "density_integration",
            "DensityDiffusion diffuses the integrated density: add ContinuityDensity",
        );
        sim.require_feature(
            "eos",
            "DensityDiffusion needs the sound speed: add an equation of state",
        );
        sim.require_feature(
            "pair_sweep",
            "DensityDiffusion adds to the rates of a pair sweep: add PressureForce or another pair term",
        );
        if !sim.enable_feature("density_diffusion") {
            return Err(SimError::Build("DensityDiffusion is listed twice".into()));
        }
        sim.world.insert_resource(DiffusionDelta(self.delta));
        sim.add_system(
            StepSet::Forces,
            "density_diffusion (delta-SPH, Molteni & Colagrossi 2009)",
            density_diffusion::<V>,
        )
        .after("pair_sweep")
        .after("continuity");
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::glam::DVec2;
    use dualsph_core::store::{Cloud, insert_column};

    /// A square lattice of `n × n` particles, spacing dx, h = 2.6 dx (support radius), with
    /// density `rho(x)` and sound speed `c`; h scaled by `h_scale(x)` (variable h).
    fn cloud(
        n: usize,
        dx: Real,
        rho: impl Fn(DVec2) -> Real,
        h_scale: impl Fn(DVec2) -> Real,
    ) -> (World, Neighbours<DVec2>) {
        let mut c = Cloud::<DVec2>::new(n * n);
        let mut sound = vec![0.0; n * n];
        for a in 0..n {
            for b in 0..n {
                let i = a * n + b;
                let x = DVec2::new((a as Real + 0.5) * dx, (b as Real + 0.5) * dx);
                c.pos[i] = x;
                c.rho[i] = rho(x);
                c.mass[i] = 1000.0 * dx * dx;
                c.h[i] = 2.6 * dx * h_scale(x);
                sound[i] = 100.0 + 10.0 * x.x;
            }
        }
        let mut nb = Neighbours::new(0.1);
        nb.rebuild(&c.pos, &c.h);
        let mut world = c.spawn();
        insert_column(&mut world, |i| SoundSpeed(sound[i]));
        (world, nb)
    }

    /// The diffusion data of a cloud's world.
    fn data_of(world: &World) -> DiffusionData<'_, DVec2> {
        DiffusionData {
            data: ParticleData::of(world).unwrap(),
            sound: dualsph_core::store::column(world).unwrap(),
        }
    }

    /// Every particle's diffusion rate.
    fn diffusion_rates(
        f: &DiffusionData<'_, DVec2>,
        nb: &Neighbours<DVec2>,
        k: &Kernel,
        delta: Real,
    ) -> Vec<Real> {
        (0..f.data.len())
            .map(|i| diffusion_rate(f, nb, k, delta, i))
            .collect()
    }

    #[test]
    fn exchanges_mass_exactly_for_any_h_field() {
        let (world, nb) = cloud(
            20,
            0.05,
            |x| 1000.0 + 30.0 * (7.0 * x.x).sin() * (5.0 * x.y).cos(),
            |x| 1.0 + 0.8 * x.x, // h varies by 1.8 across the cloud: one-sided pairs
        );
        let k = Kernel::new(KernelKind::CubicSpline, 2);
        let f = data_of(&world);
        let rates = diffusion_rates(&f, &nb, &k, 0.1);
        let d = f.data;
        let exchanged: Real = (0..d.len()).map(|i| d.volume(i) * rates[i]).sum();
        let scale: Real = (0..d.len()).map(|i| (d.volume(i) * rates[i]).abs()).sum();
        assert!(scale > 0.0);
        assert!(
            exchanged.abs() <= 1e-13 * scale,
            "Σ V dρ/dt = {exchanged:e} (scale {scale:e})"
        );
        // a uniform density is left alone
        let (world, nb) = cloud(10, 0.05, |_| 1000.0, |x| 1.0 + x.x);
        let f = data_of(&world);
        assert!(diffusion_rates(&f, &nb, &k, 0.1).iter().all(|&r| r == 0.0));
    }

    #[test]
    fn is_delta_h_c_times_the_laplacian_of_a_smooth_density() {
        // ρ = ρ0 + a cos(κx), c = 100 + 10x: with the pair-averaged c̄ the sum is Brookshaw's
        // (1985) form of ∇·(c∇ρ) = −κ² a cos(κx) c − 10 κ a sin(κx), so in the interior
        // dρ/dt = δ (h/2) ∇·(c∇ρ) to O(Δx²)
        let (n, dx, a, kappa) = (40, 0.025, 5.0, std::f64::consts::PI);
        let (world, nb) = cloud(n, dx, |x| 1000.0 + a * (kappa * x.x).cos(), |_| 1.0);
        let k = Kernel::new(KernelKind::CubicSpline, 2);
        let f = data_of(&world);
        let rates = diffusion_rates(&f, &nb, &k, 0.1);
        let (mut err, mut norm) = (0.0, 0.0);
        for i in 0..f.data.len() {
            let x = f.data.pos[i].0;
            let inside = (0.2..=0.8).contains(&x.x) && (0.2..=0.8).contains(&x.y);
            if inside {
                let div = -kappa * kappa * a * (kappa * x.x).cos() * f.sound[i].0
                    - 10.0 * kappa * a * (kappa * x.x).sin();
                let exact = 0.1 * 0.5 * f.data.h[i].0 * div;
                err += (rates[i] - exact).abs();
                norm += exact.abs();
            }
        }
        assert!(err / norm < 0.03, "relative L1 error {}", err / norm);
    }

    #[test]
    fn refuses_a_meaningless_delta() {
        let info = SceneInfo::of_dimension(2);
        assert!(SimPlugin::validate(&DensityDiffusion { delta: 0.1 }, &info).is_ok());
        for bad in [0.0, -0.1, 2.0, Real::NAN] {
            assert!(SimPlugin::validate(&DensityDiffusion { delta: bad }, &info).is_err());
        }
    }
}
