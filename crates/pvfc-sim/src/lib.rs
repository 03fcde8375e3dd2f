//! # pvfc-sim
//!
//! The simulation library of Passive Velocity Field Control: plants with friction
//! ([`friction`]), arms from URDF ([`urdf`]), the closed loop and its integrators
//! ([`integrate`]), scenarios as data ([`scenario`], [`presets`]), runs ([`simulate`]), traces
//! ([`trace`]), metrics ([`metrics`]), contact ([`contact`]) and MCAP logs ([`log`]).
//!
//! It has no command line and draws no figures: the `pvfc` command (crate `pvfc-cli`) and the
//! Python wheel (`pvfc-py`) are built on it.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod arm;
pub mod cartesian;
pub mod chain_run;
pub mod contact;
pub mod error;
pub mod friction;
pub mod integrate;
pub mod log;
pub mod metrics;
pub mod preset_id;
pub mod presets;
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
