//! # pvfc-sim
//!
//! Closed-loop simulation of Passive Velocity Field Control and the paper's experiments:
//! plants with friction ([`friction`]), arms from URDF ([`urdf`]), the closed loop and its
//! integrators ([`integrate`]), scenarios as data ([`scenario`], [`presets`]), runs
//! ([`simulate`]), MCAP logs ([`log`]), the numbers behind the paper's claims ([`report`]) and
//! the figures ([`plot`]). The `pvfc` command line drives it all.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod arm;
pub mod cartesian;
pub mod chain_plot;
pub mod chain_run;
pub mod contact;
pub mod error;
pub mod friction;
pub mod integrate;
pub mod log;
pub mod metrics;
pub mod plot;
mod plot_digital;
pub mod preset_id;
pub mod presets;
pub mod report;
mod report_arms;
mod report_digital;
pub mod reproduce;
pub mod robot;
mod run_loop;
pub mod scenario;
pub mod series;
pub mod simulate;
mod stepper;
pub mod trace;
pub mod urdf;

pub use error::{Result, SimError};
pub use integrate::{ClosedLoop, Derivative, Evaluation};
