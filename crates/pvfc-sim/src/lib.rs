//! # pvfc-sim
//!
//! Closed-loop simulation of Passive Velocity Field Control: a plant (a
//! [`MechanicalSystem`](pvfc_core::mechanics::MechanicalSystem)) driven by a
//! [`Controller`](pvfc_core::controller::Controller), with an environment force, integrated
//! with a fixed-step Runge–Kutta–Munthe-Kaas scheme that keeps the configuration on its group.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod integrate;

pub use integrate::{ClosedLoop, Derivative, Evaluation};
