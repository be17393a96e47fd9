//! Where the current run writes its files.
//!
//! The runner inserts [`RunOutputDir`] into the world before the first evaluation; a plugin
//! that writes files of its own (e.g. probes) looks for it and keeps its data in memory when
//! it is absent (a `Sim` driven from library code without an output directory).

use bevy_ecs::prelude::Resource;
use std::path::PathBuf;

/// The output directory of the run (absent when no run output is being written).
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct RunOutputDir(pub PathBuf);

/// The step count at which the run stops (the scene's `max_steps`), inserted by the runner
/// when there is one, so that samplers can record the last state as they do at `t_end`.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepLimit(pub u64);
