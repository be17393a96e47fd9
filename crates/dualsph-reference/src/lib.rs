//! Reference solutions the paper's benchmarks (§7 of Ren, Dai, Zhuang & Rabczuk, *Dual-support
//! Smoothed Particle Hydrodynamics*, preprint; RenDSSPH in docs/references.md) are graded
//! against, written independently of the engine so that a test compares the simulation with
//! something that is not itself:
//!
//! * [`riemann`]: the exact solution of the Riemann problem for an ideal gas (Sod tube, §7.2);
//! * [`heat`]: the erf profile of 1-D heat conduction between two half-bars (Eq. 7.1);
//! * [`mod@drop`]: the ODE of the free elliptical drop's semi-axes (Eq. 7.6);
//! * [`dam_break`]: the experimental water-front positions of Koshizuka & Oka (1996);
//! * [`sedov`]: the self-similar Sedov–Taylor point explosion in planar, cylindrical and
//!   spherical geometry (Sedov 1959; Kamm & Timmes 2007);
//! * [`poiseuille`]: the series solution of plane Poiseuille flow started from rest (Morris,
//!   Fox & Zhu 1997);
//! * [`cavity`]: the centreline velocities of the lid-driven cavity at Re = 100 (Ghia, Ghia &
//!   Shin 1982);
//! * [`wall_pressure`]: the dam-break wall pressure of Buchner (2002) and the δ-SPH results of
//!   Marrone et al. (2011) on the same sensor;
//! * [`cylinder`]: the DFG benchmarks of flow past a cylinder in a channel, 2D-1 and 2D-2
//!   (Schäfer & Turek 1996);
//! * [`norms`]: the error norms and interpolation used by the reports.
#![warn(missing_docs)]

pub mod cavity;
pub mod cylinder;
pub mod dam_break;
pub mod drop;
pub mod heat;
pub mod norms;
pub mod poiseuille;
pub mod riemann;
pub mod sedov;
pub mod wall_pressure;
