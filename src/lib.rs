//! # pvfc
//!
//! Passive Velocity Field Control (Li & Horowitz) for contour following. This umbrella crate
//! re-exports the `no_std` core ([`core`], also usable alone as `pvfc-core` on a
//! microcontroller) and the simulation crate ([`sim`]); it also holds the project's
//! cross-crate tests, benchmarks and examples.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub use pvfc_core as core;
pub use pvfc_core::prelude;
pub use pvfc_sim as sim;
