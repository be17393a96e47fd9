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
//! two, exactly, whatever the h field. It moves no momentum (no force). It is a term of the
//! force sweep ([`DiffusionTerm`]): `D_ij` is evaluated once per pair, and the reaction reaches
//! j through its dual-support like every other sum of the sweep, in a fixed order.
//!
//! **Under gravity** (`hydrostatic: true`) the term diffuses the density's departure from
//! hydrostatics instead, `ψ_ij = 2[(ρ_j − ρ_i) − ρ^H_ji]` with the hydrostatic difference
//! `ρ^H_ji = ρ0 [(1 + ρ0 |g| z_ij / p0)^{1/γ} − 1]`, `z_ij = (x_i − x_j)·(−ĝ)` the height of i
//! above j, and ρ0, p0, γ the owner's Tait parameters (Fourtakas, Domínguez, Vacondio &
//! Rogers (2019), Local uniform stencil (LUST) boundary condition for arbitrary 3-D
//! boundaries in parallel smoothed particle hydrodynamics (SPH) models, Comput. Fluids 190,
//! 346–361, the density diffusion of DualSPHysics). Molteni's term alone diffuses the
//! hydrostatic density gradient wherever the support is truncated (the free surface, a wall)
//! and a fluid at rest loses its hydrostatic pressure; the corrected term vanishes on it.
//!
//! Only pairs of two fluid particles diffuse: a particle of a fixed or prescribed body (a wall
//! of particles) neither gives nor takes density, since its density is the wall model's (set
//! from the fluid by `WallPressure`, or its own continuity equation), and mass diffused into a
//! wall would leave the fluid.

use dualsph_core::bevy_ecs::prelude::Resource;
use dualsph_core::bodies::Bodies;
use dualsph_core::lanes::LaneVec;
use dualsph_eos::Eos;
use dualsph_fluid::BodyEos;
use dualsph_fluid::DensityIntegration;
use dualsph_fluid::EquationOfState;
use dualsph_fluid::prelude::*;
use dualsph_gravity::GravityAccel;
use serde::{Deserialize, Serialize};

/// Present once the diffusion term is in the force sweep.
#[derive(Resource, Default)]
struct DiffusionOn;

/// δ-SPH density diffusion settings.
#[derive(Debug, Clone, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DensityDiffusion {
    /// δ (dimensionless), on the classical smoothing length h/2 (Molteni & Colagrossi, Antuono et al.: 0.1).
    #[serde(default = "default_delta")]
    pub delta: Real,
    /// Diffuse the departure from hydrostatics (module docs); needs `Gravity` and `TaitEos`
    /// listed before.
    #[serde(default)]
    pub hydrostatic: bool,
}

fn default_delta() -> Real {
    0.1
}

/// The diffusion as a pair term of the force sweep: `D_ij V_j` to `dρ_i/dt`, `−D_ij V_i` to
/// `dρ_j/dt` ([`Reaction::Separate`]).
#[derive(Debug, Clone)]
pub struct DiffusionTerm {
    /// δ.
    pub delta: Real,
    /// Whether each body, by [`BodyId`], is a fluid (diffuses); `None` when every body is.
    pub fluid: Option<Vec<bool>>,
    /// The hydrostatic correction, when asked for.
    pub hydrostatic: Option<Hydrostatic>,
}

/// What the hydrostatic correction needs: the unit vector up (`−ĝ`), `|g|`, and each body's
/// Tait `(ρ0, p0, 1/γ)`.
#[derive(Debug, Clone)]
pub struct Hydrostatic {
    /// `−g/|g|` (3-D embedding).
    pub up: [Real; 3],
    /// `|g|`.
    pub g: Real,
    /// `(ρ0, p0, 1/γ)` by [`BodyId`].
    pub tait: Vec<(Real, Real, Real)>,
}

/// [`DiffusionTerm`] bound for a sweep.
#[derive(Clone, Copy, Debug)]
pub struct BoundDiffusion<'w> {
    delta: Real,
    sound: &'w [SoundSpeed],
    /// The particles' bodies and which bodies diffuse, when some do not.
    fluid: Option<(&'w [BodyId], &'w [bool])>,
    /// The hydrostatic correction and the particles' bodies.
    hydrostatic: Option<(&'w [BodyId], &'w Hydrostatic)>,
}

impl<V: Vector> PairTerm<V> for DiffusionTerm {
    type Bound<'w> = BoundDiffusion<'w>;

    fn name(&self) -> &str {
        "density_diffusion (delta-SPH, Molteni & Colagrossi 2009)"
    }

    fn bind<'w>(&'w self, b: &mut Binder<'_, 'w, V>) -> Result<BoundDiffusion<'w>, String> {
        b.density_rate(Reaction::Separate)?;
        let fluid = match &self.fluid {
            Some(f) => Some((b.require::<BodyId>()?, f.as_slice())),
            None => None,
        };
        let hydrostatic = match &self.hydrostatic {
            Some(h) => Some((b.require::<BodyId>()?, h)),
            None => None,
        };
        Ok(BoundDiffusion {
            delta: self.delta,
            sound: b.require()?,
            fluid,
            hydrostatic,
        })
    }
}

impl<V: Vector> BoundTerm<V> for BoundDiffusion<'_> {
    type Owner = ();

    #[inline(always)]
    fn owner(&self, _: usize) {}

    /// `D_ij = δ (h_i/2) c̄_ij (ρ_j − ρ_i) (−∂W/∂r)/r` (module docs); zero at `r = 0`.
    #[inline(always)]
    fn interact<T: Lanes>(&self, _: &(), p: &PairLanes<'_, T, V>, out: &mut Out<'_, T>) {
        let (d, i) = (p.data(), p.i());
        let c = T::splat(0.5) * (T::splat(self.sound[i].0) + p.gather(self.sound, |c| c.0));
        // the owner's half of ψ_ij = 2(ρ_j − ρ_i)
        let mut half_psi = p.rho_j() - T::splat(d.rho[i].0);
        if let Some((body, h)) = self.hydrostatic {
            let (rho0, p0, inv_gamma) = h.tait[body[i].0 as usize];
            let up = V::from_slice(&h.up[..V::DIM]).unwrap_or_else(V::zero);
            let z = p.rij().dot::<V>(LaneVec::splat(up));
            let k = rho0 * h.g / p0;
            // (1 + k z)^{1/γ} as exp(ln(1 + k z)/γ): the libm crate's `pow` costs three times
            // its `log1p` and `exp` together, and here it is evaluated for every pair
            let rho_h =
                T::from_fn(|l| rho0 * (libm::exp(inv_gamma * libm::log1p(k * z.lane(l))) - 1.0));
            half_psi = half_psi - rho_h;
        }
        let mut coef = T::splat(self.delta * 0.5 * d.h[i].0) * c * half_psi * (-p.grad_factor());
        if let Some((body, fluid)) = self.fluid {
            let both = |b: &BodyId| if fluid[b.0 as usize] { 1.0 } else { 0.0 };
            coef = coef * T::splat(both(&body[i])) * p.gather(body, both);
        }
        let v_j = p.m_j() / p.rho_j();
        out.add_density_rate(coef * v_j);
        out.react_density_rate(-(coef * T::splat(d.volume(i))));
    }
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

    /// Adds the diffusion term to the force sweep, whose density-rate sum it joins.
    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require::<DensityIntegration>(
            "DensityDiffusion diffuses the integrated density: add ContinuityDensity",
        );
        sim.require::<EquationOfState>(
            "DensityDiffusion needs the sound speed: add an equation of state",
        );
        if !sim.enable::<DiffusionOn>() {
            return Err(SimError::Build("DensityDiffusion is listed twice".into()));
        }
        let kinds = &sim.world.resource::<Bodies>().0;
        let fluid: Vec<bool> = kinds.iter().map(|b| b.is_fluid()).collect();
        let fluid = (!fluid.iter().all(|&f| f)).then_some(fluid);
        let hydrostatic = if self.hydrostatic {
            Some(hydrostatic_setup::<V>(sim)?)
        } else {
            None
        };
        sim.add_pair_term(DiffusionTerm {
            delta: self.delta,
            fluid,
            hydrostatic,
        });
        Ok(())
    }
}

/// The hydrostatic correction's parameters, from the gravity and the equation of state built
/// before this plugin.
fn hydrostatic_setup<V: Vector>(sim: &Sim<V>) -> Result<Hydrostatic, SimError> {
    let need = "DensityDiffusion(hydrostatic: true) needs Gravity and TaitEos listed before it";
    let g = sim
        .world
        .get_resource::<GravityAccel<V>>()
        .ok_or_else(|| SimError::Build(need.into()))?
        .0;
    let laws = sim
        .world
        .get_resource::<BodyEos>()
        .ok_or_else(|| SimError::Build(need.into()))?;
    let tait = (0..laws.0.len())
        .map(|b| match laws.law_as::<Eos>(b).copied() {
            None => Err(SimError::Build(need.into())),
            Some(e) => Ok(e),
        })
        .map(|e| match e? {
            Eos::Tait {
                rho0, gamma, p0, ..
            } => Ok((rho0, p0, 1.0 / gamma)),
            Eos::Ideal { .. } => Err(SimError::Build(need.into())),
        })
        .collect::<Result<_, _>>()?;
    let gn = g.length();
    if gn <= 0.0 {
        return Err(SimError::Build(
            "DensityDiffusion(hydrostatic: true): gravity is zero".into(),
        ));
    }
    Ok(Hydrostatic {
        up: (g * (-1.0 / gn)).to_xyz(),
        g: gn,
        tait,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::bevy_ecs::prelude::*;
    use dualsph_core::glam::DVec2;
    use dualsph_core::neighbours::Neighbours;
    use dualsph_core::store::{Cloud, insert_column};
    use dualsph_sweep::{DynPairTerm, SweepBuffers, evaluate};
    use std::sync::Arc;

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
        insert_column(&mut world, |_| DensityRate::default());
        (world, nb)
    }

    /// Every particle's diffusion rate, from a dual-support sweep of the term alone.
    fn diffusion_rates(
        world: &World,
        nb: &Neighbours<DVec2>,
        k: &Kernel,
        delta: Real,
    ) -> Vec<Real> {
        let terms: Vec<Arc<dyn DynPairTerm<DVec2>>> = vec![Arc::new(DiffusionTerm {
            delta,
            fluid: None,
            hydrostatic: None,
        })];
        let data = ParticleData::of(world).unwrap();
        let ctx = SweepCtx::new(data, nb, k, Formulation::DualSupport);
        let mut buf = SweepBuffers::default();
        evaluate(&ctx, &terms, &mut buf).unwrap();
        (0..data.len())
            .map(|i| buf.sum_of::<DensityRate>(i).unwrap()[0])
            .collect()
    }

    #[test]
    fn two_lanes_equal_one_lane_bitwise() {
        dualsph_fluid::checks::check_lanes_2d(&DiffusionTerm {
            delta: 0.1,
            fluid: None,
            hydrostatic: None,
        })
        .unwrap();
    }

    #[test]
    fn exchanges_mass_exactly_for_any_h_field() {
        let (world, nb) = cloud(
            20,
            0.05,
            |x| 1000.0 + 30.0 * libm::sin(7.0 * x.x) * libm::cos(5.0 * x.y),
            |x| 1.0 + 0.8 * x.x, // h varies by 1.8 across the cloud: one-sided pairs
        );
        let k = Kernel::new(KernelKind::CubicSpline, 2);
        let rates = diffusion_rates(&world, &nb, &k, 0.1);
        let d = ParticleData::<DVec2>::of(&world).unwrap();
        let exchanged: Real = (0..d.len()).map(|i| d.volume(i) * rates[i]).sum();
        let scale: Real = (0..d.len()).map(|i| (d.volume(i) * rates[i]).abs()).sum();
        assert!(scale > 0.0);
        assert!(
            exchanged.abs() <= 1e-13 * scale,
            "Σ V dρ/dt = {exchanged:e} (scale {scale:e})"
        );
        // a uniform density is left alone
        let (world, nb) = cloud(10, 0.05, |_| 1000.0, |x| 1.0 + x.x);
        assert!(
            diffusion_rates(&world, &nb, &k, 0.1)
                .iter()
                .all(|&r| r == 0.0)
        );
    }

    #[test]
    fn is_delta_h_c_times_the_laplacian_of_a_smooth_density() {
        // ρ = ρ0 + a cos(κx), c = 100 + 10x: with the pair-averaged c̄ the sum is Brookshaw's
        // (1985) form of ∇·(c∇ρ) = −κ² a cos(κx) c − 10 κ a sin(κx), so in the interior
        // dρ/dt = δ (h/2) ∇·(c∇ρ) to O(Δx²)
        let (n, dx, a, kappa) = (40, 0.025, 5.0, std::f64::consts::PI);
        let (world, nb) = cloud(n, dx, |x| 1000.0 + a * libm::cos(kappa * x.x), |_| 1.0);
        let k = Kernel::new(KernelKind::CubicSpline, 2);
        let rates = diffusion_rates(&world, &nb, &k, 0.1);
        let d = ParticleData::<DVec2>::of(&world).unwrap();
        let sound: &[SoundSpeed] = d.column().unwrap();
        let (mut err, mut norm) = (0.0, 0.0);
        for i in 0..d.len() {
            let x = d.pos[i].0;
            let inside = (0.2..=0.8).contains(&x.x) && (0.2..=0.8).contains(&x.y);
            if inside {
                let div = -kappa * kappa * a * libm::cos(kappa * x.x) * sound[i].0
                    - 10.0 * kappa * a * libm::sin(kappa * x.x);
                let exact = 0.1 * 0.5 * d.h[i].0 * div;
                err += (rates[i] - exact).abs();
                norm += exact.abs();
            }
        }
        assert!(err / norm < 0.03, "relative L1 error {}", err / norm);
    }

    #[test]
    fn refuses_a_meaningless_delta() {
        let info = SceneInfo::of_dimension(2);
        assert!(
            SimPlugin::validate(
                &DensityDiffusion {
                    delta: 0.1,
                    hydrostatic: false
                },
                &info
            )
            .is_ok()
        );
        for bad in [0.0, -0.1, 2.0, Real::NAN] {
            assert!(
                SimPlugin::validate(
                    &DensityDiffusion {
                        delta: bad,
                        hydrostatic: false
                    },
                    &info
                )
                .is_err()
            );
        }
    }
}
