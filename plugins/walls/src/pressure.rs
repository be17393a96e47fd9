//! `WallPressure(bodies: [..])`: the particles of fixed and prescribed bodies (walls,
//! obstacles, pistons) take the pressure of the fluid next to them, extrapolated as in the
//! generalised wall boundary condition of Adami, Hu & Adams (2012), *A generalized wall
//! boundary condition for smoothed particle hydrodynamics*, J. Comput. Phys. 231, 7057,
//! Eq. 27:
//!
//! `p_w = [Σ_f p_f W_wf + (g − a_w)·Σ_f ρ_f r_wf W_wf] / Σ_f W_wf`, `r_wf = x_w − x_f`,
//!
//! over the fluid particles f within the larger of the two supports, `|r_wf| < max(h_w, h_f)`,
//! with `W_wf = W(r_wf, max(h_w, h_f))`, where `a_w` is the wall's acceleration (its law's,
//! zero for a fixed body) and `g` the scene's gravity. Where wall and fluid share one h this is
//! Adami et al.'s sum over the wall particle's support. Where they do not, a wall particle
//! takes its value from every fluid particle that sees it (its dual-support) as well as from
//! those it sees: a fine wall next to coarse fluid has wall particles deeper than their own h
//! from the fluid, which the coarse fluid's supports hold, and which would otherwise keep `ρ0`
//! and show the fluid a wall without pressure. The wall particle's density is then the equation
//! of state's at `p_w` (Eq. 28), so the pressure term reads a consistent `p/ρ²` on both sides
//! of every fluid–wall pair. A wall particle with no fluid within either support takes `ρ0`
//! (and the pressure the equation gives there). With `no_suction: true` a negative `p_w` is read
//! as zero before the density is taken from it.
//!
//! The fluid–wall pair forces are the ordinary pair terms of the sweep: each pair's reaction
//! lands on the wall particle through its dual-support, so the load on a body is the exact sum
//! of the reactions (conservation of fluid + walls to round-off), and the walls may have their
//! own h. Without this plugin, wall particles evolve their density by the continuity equation
//! like the fluid (the dynamic boundary of Crespo, Gómez-Gesteira & Dalrymple 2007); with it,
//! their density and pressure are set from the fluid every step, after the equation of state.

use crate::WallBodies;
use crate::velocity::{ViscousWall, ViscousWallMode, wall_offset};
use dualsph_core::bevy_ecs::prelude::*;
use dualsph_core::bodies::Anchor;
use dualsph_core::bodies::DriveBodies;
use dualsph_core::bodies::{Bodies, DrivenBodies, WallVelocityOffset, motion_acceleration};
use dualsph_core::chunks::DENSE;
use dualsph_core::columns::ColumnSpec;
use dualsph_core::neighbours::Neighbours;
use dualsph_fluid::prelude::*;
use dualsph_fluid::{BodyEos, EquationOfState};
use dualsph_gravity::GravityAccel;
use dualsph_sweep::Support;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Wall particles take the pressure extrapolated from the fluid (module docs).
#[derive(Debug, Clone, Default, Deserialize, Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WallPressure {
    /// The bodies treated so, by name; empty (the default) means every fixed or prescribed
    /// body.
    #[serde(default)]
    pub bodies: Vec<String>,
    /// The velocity the wall particles show the viscous terms: `Own` (the default),
    /// `NoSlip` or `FreeSlip` ([`crate::velocity`]).
    #[serde(default)]
    pub viscous: ViscousWall,
    /// Read a negative extrapolated pressure as zero (default false): a wall then never pulls
    /// the fluid towards it, which keeps a thin jet or a surge front with suction from being
    /// drawn into the wall.
    #[serde(default)]
    pub no_suction: bool,
}

/// Whether the walls read a negative extrapolated pressure as zero
/// ([`WallPressure::no_suction`]).
#[derive(Resource, Clone, Copy, Debug)]
pub struct NoSuction(pub bool);

/// The density each wall particle was given this step, by row: put back after the
/// integrator's corrector ([`keep_wall_density`]), which would otherwise have advanced it by
/// the continuity equation, so that the state (and what snapshots show) is the wall's
/// extrapolated density.
#[derive(Resource, Clone, Debug, Default)]
pub struct WallDensity(pub Vec<(usize, Real)>);

/// What a wall particle's extrapolation reads of the others, by row.
struct Fluid<'a, V: Vector> {
    rho: &'a [Density],
    p: &'a [Pressure],
    vel: &'a [Velocity<V>],
    body: &'a [BodyId],
    walls: &'a [bool],
}

/// The sums of one wall particle over the fluid within either support (module docs;
/// [`crate::velocity`] for the velocity's).
struct Sums<V: Vector> {
    /// `Σ_f p_f W_wf`.
    p: Real,
    /// `Σ_f ρ_f r_wf W_wf`.
    rho_r: V,
    /// `Σ_f W_wf`.
    w: Real,
    /// `Σ_f v_f W_wf`, when the viscous terms need the wall's velocity (else zero).
    v: V,
}

/// [`Sums`] of wall particle i in one walk over its neighbours, the fluid's only (the other
/// wall particles cost an index test); the velocity's only when `velocity` is true.
#[inline]
fn sums<V: Vector>(
    support: &Support<'_, V>,
    f: &Fluid<'_, V>,
    i: usize,
    velocity: bool,
) -> Sums<V> {
    let mut s = Sums {
        p: 0.0,
        rho_r: V::zero(),
        w: 0.0,
        v: V::zero(),
    };
    let fluid = |j: usize| !f.walls[f.body[j].0 as usize];
    support.for_each_within_either(i, fluid, |j, rij, w| {
        s.p += f.p[j].0 * w;
        s.rho_r += rij * (f.rho[j].0 * w);
        s.w += w;
        if velocity {
            s.v += f.vel[j].0 * w;
        }
    });
    s
}

/// Everything one wall particle's extrapolated state is computed from (module docs).
struct Extrapolation<'a, V: Vector> {
    support: Support<'a, V>,
    fluid: Fluid<'a, V>,
    laws: &'a BodyEos,
    driven: &'a DrivenBodies,
    anchor: &'a [Anchor<V>],
    /// Gravity.
    g: V,
    /// The time the walls' accelerations are taken at (the end of the step).
    t: Real,
    mode: ViscousWall,
    no_suction: bool,
}

impl<V: Vector> Extrapolation<'_, V> {
    /// The state of wall particle i: `p_w` (Eq. 27, read as zero below zero with
    /// `no_suction`), the density the equation of state gives at it (Eq. 28) and its sound
    /// speed, and the velocity offset of the viscous wall model (Eq. 22–23).
    fn state(&self, i: usize) -> WallState<V> {
        let f = &self.fluid;
        let b = f.body[i].0 as usize;
        let eos = self.laws.0[b].as_ref();
        let a_w = self.driven.0[b].as_deref().map_or(V::zero(), |m| {
            motion_acceleration(m, self.anchor[i].0, self.t)
        });
        let velocity = self.mode != ViscousWall::Own;
        let s = sums(&self.support, f, i, velocity);
        let rho_w = if s.w > 0.0 {
            let p_w = (s.p + (self.g - a_w).dot(s.rho_r)) / s.w;
            let p_w = if self.no_suction { p_w.max(0.0) } else { p_w };
            eos.density_at(p_w).unwrap_or(f.rho[i].0)
        } else {
            eos.reference_density().unwrap_or(f.rho[i].0)
        };
        let (p_w, c_w) = eos.eval(rho_w, 0.0);
        let v_f = (s.w > 0.0).then(|| s.v * (1.0 / s.w));
        (i, rho_w, p_w, c_w, wall_offset(self.mode, f.vel[i].0, v_f))
    }
}

/// What [`wall_pressure`] sets on one wall particle: its row, density, pressure, sound speed
/// and the velocity offset it shows the viscous terms.
type WallState<V> = (usize, Real, Real, Real, V);

/// Sets every wall particle's pressure, density and sound speed (module docs) and, with a
/// viscous wall model, its [`WallVelocityOffset`] ([`crate::velocity`]), in `Eos` after the
/// equation of state: one walk over each wall particle's neighbours.
#[allow(clippy::too_many_arguments)] // one system, its resources
#[inline(never)] // a frame of its own in profiles
pub fn wall_pressure<V: Vector>(
    walls: Res<WallBodies>,
    laws: Res<BodyEos>,
    gravity: Option<Res<GravityAccel<V>>>,
    driven: Res<DrivenBodies>,
    clock: Res<SimClock>,
    kernel: Res<KernelRes>,
    nb: Res<Neighbours<V>>,
    formulation: Res<Formulation>,
    viscous: Option<Res<ViscousWallMode>>,
    no_suction: Res<NoSuction>,
    mut kept: ResMut<WallDensity>,
    mut q: Query<(
        &Position<V>,
        &SmoothingLength,
        &BodyId,
        &Anchor<V>,
        &Velocity<V>,
        &mut Density,
        &mut Pressure,
        &mut SoundSpeed,
    )>,
    mut offsets: Query<&mut WallVelocityOffset<V>>,
) {
    let Some((pos, h, body, anchor, vel, mut rho, mut p, mut c)) =
        dualsph_core::store::single_table(q.contiguous_iter_mut().expect(DENSE))
    else {
        return;
    };
    // the engine reads no change ticks (`dualsph_core::chunks`); a write through the
    // change-detecting slice would mark every row at each wall particle
    let (rho, p, c) = (
        rho.bypass_change_detection(),
        p.bypass_change_detection(),
        c.bypass_change_detection(),
    );
    let mode = viscous.map_or(ViscousWall::Own, |m| m.0);
    let velocity = mode != ViscousWall::Own;
    let walls_now = Extrapolation {
        support: Support {
            pos,
            h,
            neighbours: &nb,
            kernel: &kernel.0,
            formulation: *formulation,
        },
        fluid: Fluid {
            rho,
            p,
            vel,
            body,
            walls: &walls.0,
        },
        laws: &laws,
        driven: &driven,
        anchor,
        g: gravity.map_or(V::zero(), |g| g.0),
        t: clock.t + clock.dt,
        mode,
        no_suction: no_suction.0,
    };
    let set: Vec<WallState<V>> = (0..pos.len())
        .into_par_iter()
        .with_min_len(256)
        .filter(|&i| walls.0[body[i].0 as usize])
        .map(|i| walls_now.state(i))
        .collect();
    kept.0.clear();
    for &(i, rho_w, p_w, c_w, _) in &set {
        (rho[i].0, p[i].0, c[i].0) = (rho_w, p_w, c_w);
        kept.0.push((i, rho_w));
    }
    if velocity
        && let Some(mut offset) =
            dualsph_core::store::single_table(offsets.contiguous_iter_mut().expect(DENSE))
    {
        let offset = offset.bypass_change_detection();
        for (i, .., delta) in set {
            offset[i].0 = delta;
        }
    }
}

/// Puts back the wall particles' densities of this step (see [`WallDensity`]), after the
/// integrator's corrector and the bodies' drive.
pub fn keep_wall_density(kept: Res<WallDensity>, mut q: Query<&mut Density>) {
    let Some(mut rho) = dualsph_core::store::single_table(q.contiguous_iter_mut().expect(DENSE))
    else {
        return;
    };
    let rho = rho.bypass_change_detection();
    for &(i, rho_w) in &kept.0 {
        rho[i].0 = rho_w;
    }
}

impl SimPlugin for WallPressure {
    const NAME: &'static str = "WallPressure";
    const SUMMARY: &'static str =
        "wall particles take the pressure extrapolated from the fluid (Adami, Hu & Adams 2012)";

    fn validate(&self, info: &SceneInfo) -> Result<(), String> {
        for (k, b) in self.bodies.iter().enumerate() {
            info.check_body(&format!("bodies[{k}]"), b)?;
        }
        Ok(())
    }

    fn build<V: Vector>(&self, sim: &mut Sim<V>) -> Result<(), SimError> {
        sim.require::<EquationOfState>("WallPressure needs an equation of state (TaitEos)");
        let bodies = sim.world.resource::<Bodies>();
        let mut walls = Vec::with_capacity(bodies.0.len());
        for b in &bodies.0 {
            let driven = !b.is_fluid();
            let named = if self.bodies.is_empty() {
                driven
            } else {
                self.bodies.contains(&b.name)
            };
            if named && !driven {
                return Err(SimError::Build(format!(
                    "WallPressure: body `{}` is a fluid; name fixed or prescribed bodies",
                    b.name
                )));
            }
            walls.push(named && driven);
        }
        if !walls.iter().any(|&w| w) {
            return Err(SimError::Build(
                "WallPressure: the scene has no fixed or prescribed body".into(),
            ));
        }
        sim.world.insert_resource(WallBodies(walls));
        sim.world.init_resource::<WallDensity>();
        sim.world.insert_resource(NoSuction(self.no_suction));
        sim.add_system(
            StepSet::Correct,
            "keep_wall_density (the extrapolated density, not the integrated one)",
            keep_wall_density,
        )
        .after::<DriveBodies>();
        if self.viscous != ViscousWall::Own {
            let spec = ColumnSpec::scratch("wall_velocity_offset");
            sim.add_column(spec, |_| WallVelocityOffset(V::zero()))?;
            sim.world.insert_resource(ViscousWallMode(self.viscous));
        }
        sim.add_system(
            StepSet::Eos,
            "wall_pressure (Adami et al. 2012, Eq. 22-23, 27-28)",
            wall_pressure::<V>,
        )
        .after::<EquationOfState>();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualsph_core::bodies::{Bodies, Body, install_bodies};
    use glam::DVec2;

    /// A floor of two wall rows under five rows of water at density `rho` (no gravity), with
    /// the walls' pressure extrapolated (`no_suction` as given), after the initial evaluation:
    /// the wall particles' (pressure, density) and the water's pressure.
    fn floor_under(rho: Real, no_suction: bool) -> (Vec<(Real, Real)>, Real) {
        let dx = 0.1;
        let mut sim = Sim::<DVec2>::new(SimConfig {
            kernel: KernelKind::CubicSpline,
            formulation: Formulation::DualSupport,
            domain: Domain::closed(DVec2::splat(-1.0), DVec2::splat(2.0)),
            skin: 0.0,
            skin_rule: SkinRule::Fixed,
            time_stepping: TimeStepping::Fixed(1e-4),
        });
        let particle = |i: usize, j: usize, body: u16| ParticleInit {
            pos: DVec2::new(i as Real * dx, j as Real * dx - 0.15),
            vel: DVec2::ZERO,
            mass: rho * dx * dx,
            density: rho,
            // both wall rows within reach of the water
            h: 2.5 * dx,
            internal_energy: 0.0,
            body,
        };
        let parts: Vec<_> = (0..10)
            .flat_map(|i| (0..7).map(move |j| particle(i, j, u16::from(j >= 2))))
            .collect();
        sim.spawn_particles(&parts).unwrap();
        let bodies = Bodies(vec![Body::fixed("floor"), Body::fluid("water")]);
        install_bodies(&mut sim, bodies).unwrap();
        let integrator: &dyn PluginConfig = &dualsph_integrator::LeapfrogPC::default();
        sim.build_plugin(integrator).unwrap();
        let eos = dualsph_eos::TaitEos {
            rho0: 1000.0,
            gamma: 7.0,
            c0: Some(10.0.into()),
            p0: None,
            min_pressure: None,
            cavitation: false,
            background: 0.0,
            materials: Vec::new(),
        };
        sim.build_plugin(&eos).unwrap();
        let walls = WallPressure {
            no_suction,
            ..WallPressure::default()
        };
        sim.build_plugin(&walls).unwrap();
        sim.initialize().unwrap();
        let mut q = sim.world.query::<(&BodyId, &Pressure, &Density)>();
        let rows: Vec<_> = q
            .iter(&sim.world)
            .map(|(b, p, r)| (b.0, p.0, r.0))
            .collect();
        let wall = rows
            .iter()
            .filter(|r| r.0 == 0)
            .map(|r| (r.1, r.2))
            .collect();
        (wall, rows.iter().find(|r| r.0 == 1).unwrap().1)
    }

    /// Water in tension (ρ = 990 < ρ0): the walls take its pressure (a uniform field is
    /// extrapolated exactly), unless they read suction as zero, when they hold ρ0 and p = 0;
    /// in compression (ρ = 1010) both read the water's pressure.
    #[test]
    fn walls_without_suction_do_not_pull_the_water() {
        let (walls, p_water) = floor_under(990.0, false);
        assert!(p_water < 0.0);
        let wet = |w: &[(Real, Real)]| w.iter().filter(|x| x.1 != 1000.0 || x.0 != 0.0).count();
        for &(p, _) in &walls {
            assert!(
                (p - p_water).abs() < 1e-9 * p_water.abs(),
                "{p} vs {p_water}"
            );
        }
        let (walls, _) = floor_under(990.0, true);
        assert_eq!(wet(&walls), 0, "{walls:?}");
        let (pressed, p_water) = floor_under(1010.0, false);
        let (held, _) = floor_under(1010.0, true);
        assert!(p_water > 0.0);
        assert_eq!(pressed, held);
    }
}
