//! # pvfc-sim
//!
//! Closed-loop simulation of Passive Velocity Field Control: a plant (a
//! [`MechanicalSystem`](pvfc_core::mechanics::MechanicalSystem)) driven by a
//! [`Controller`](pvfc_core::controller::Controller), with an environment force, integrated
//! with a fixed-step Runge–Kutta–Munthe-Kaas scheme that keeps the configuration on its group.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod integrate;

pub use integrate::{ClosedLoop, Derivative};
