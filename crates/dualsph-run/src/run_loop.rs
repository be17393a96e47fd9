//! The one run loop: a simulation stepped to its end, with observers.
//!
//! Every way of running a simulation — `dualsph run`, the validation report, the examples —
//! steps it through [`run_to_end`]. The loop owns the stop condition (the scene's end time or
//! `max_steps`, [`Sim::at_end`]) and the failure channel: a step that fails (the health
//! check's unphysical value, the fixed dt's CFL check, a stalled time step, a population or
//! refinement that cannot go on — each reported by its system through
//! [`StepFailure`](dualsph_core::sim::StepFailure)) is the step's own `Err`, which the loop
//! returns. What a run does besides stepping — diagnostics rows, snapshots, checkpoints, the
//! progress bar, a report's recording — is an [`Observer`] called after every step, in the
//! order given (the pattern of TrixiParticles.jl's callbacks and rapier's physics hooks).

use crate::error::{RunError, cpu_seconds};
use dualsph_fluid::prelude::*;
use std::time::Instant;

/// What an observer tells the loop after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Go on stepping.
    Continue,
    /// End the run here, as if it had reached its end ([`Observer::at_end`] is called).
    Stop,
}

/// Something the run loop calls after every step and once at the end.
pub trait Observer<V: Vector> {
    /// After every step that succeeded; an error ends the run with it.
    fn after_step(&mut self, sim: &mut Sim<V>) -> Result<Flow, RunError>;

    /// Once after the last step, when the run reached its end (or an observer stopped it).
    fn at_end(&mut self, _sim: &mut Sim<V>) -> Result<(), RunError> {
        Ok(())
    }
}

/// What the loop measured over its steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stepped {
    /// Steps taken by this call.
    pub steps: u64,
    /// The particle count summed over those steps.
    pub particle_steps: u64,
    /// Wall-clock seconds of the stepping.
    pub wall_seconds: f64,
    /// CPU seconds of the stepping (user + system, all threads).
    pub cpu_seconds: f64,
}

/// Steps `sim` until it reaches its end ([`Sim::at_end`]), calling every observer after every
/// step and, at the end, [`Observer::at_end`]. The first error — the step's failure
/// ([`RunError::Sim`]) or an observer's — ends the run and is returned; the state is then the
/// one the failing step left.
pub fn run_to_end<V: Vector>(
    sim: &mut Sim<V>,
    observers: &mut [&mut dyn Observer<V>],
) -> Result<Stepped, RunError> {
    let (wall0, cpu0) = (Instant::now(), cpu_seconds());
    let mut stepped = Stepped::default();
    'run: while !sim.at_end() {
        sim.step()?;
        stepped.steps += 1;
        stepped.particle_steps += sim.particle_count() as u64;
        for o in observers.iter_mut() {
            if o.after_step(sim)? == Flow::Stop {
                break 'run;
            }
        }
    }
    stepped.wall_seconds = wall0.elapsed().as_secs_f64();
    stepped.cpu_seconds = cpu_seconds() - cpu0;
    for o in observers.iter_mut() {
        o.at_end(sim)?;
    }
    Ok(stepped)
}

/// An observer from a closure called after every step (a recording that needs no end).
pub struct EveryStep<F>(pub F);

impl<V: Vector, F: FnMut(&mut Sim<V>) -> Result<Flow, RunError>> Observer<V> for EveryStep<F> {
    fn after_step(&mut self, sim: &mut Sim<V>) -> Result<Flow, RunError> {
        (self.0)(sim)
    }
}

#[cfg(test)]
mod tests;
