//! # pvfc-control
//!
//! Passive Velocity Field Control for robots whose number of joints is known at run time,
//! between the const-generic core (`pvfc-core`) and the simulator (`pvfc-sim`): URDF files
//! ([`urdf`]), robot models, joint contours, tool paths and their inverse kinematics, the arm
//! controllers, the passive controller and the pace along a contour ([`model`]), the
//! obstacles a field keeps an arm away from ([`obstacles`]), and their errors ([`error`]).
//! The C ABI (`pvfc-c`) depends on it alone; it links no simulator, contact engine or log
//! format.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod error;
pub mod model;
pub mod obstacles;
pub mod urdf;

pub use error::{Result, SimError};
