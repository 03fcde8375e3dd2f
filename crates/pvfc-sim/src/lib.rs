//! # pvfc-sim
//!
//! The simulation library of Passive Velocity Field Control, in layers through which the data
//! of a run flows one way: the controllers of robots known at run time (crate
//! `pvfc-control`, re-exported here as [`urdf`], [`model`] and [`error`]); contact with the
//! world ([`contact`]); scenarios as plain data, the
//! paper's presets, and the one builder that makes a scenario's system ([`scenario`]); the
//! closed loop and its runs ([`run`]); what a run leaves and what is measured on it
//! ([`trace`]); MCAP logs ([`log`]); studies over many runs ([`study`]).
//! `docs/architecture.md` draws the layers.
//!
//! It has no command line and draws no figures: the `pvfc` command (crate `pvfc-cli`) and the
//! Python wheel (`pvfc-py`) are built on it.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod contact;
pub mod log;
pub mod plant;
pub mod run;
pub mod scenario;
pub mod study;
pub mod trace;

pub use pvfc_control::{dof_dispatch, dof_enum, on_joints, with_dof};
pub use pvfc_control::{error, model, urdf};

pub use error::{Result, SimError};
pub use run::integrate::{ClosedLoop, Derivative, Evaluation};
pub use run::{run_scenario, simulate, simulate_timed};
pub use scenario::Scenario;
pub use trace::{ContactTrace, Trace};
