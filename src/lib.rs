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

pub use pvfc_control as control;
pub use pvfc_core as core;
pub use pvfc_core::prelude;
pub use pvfc_sim as sim;

/// The Rust snippets of the README and of the user's manual (`docs/src`), compiled and run as
/// doctests, so that every snippet a user copies builds.
#[cfg(doctest)]
mod manual {
    #[doc = include_str!("../README.md")]
    struct Readme;
    #[doc = include_str!("../docs/src/reference/crates.md")]
    struct Crates;
    #[doc = include_str!("../docs/src/guide/digital-controller.md")]
    struct DigitalController;
    #[doc = include_str!("../docs/src/guide/studies.md")]
    struct Studies;
    #[doc = include_str!("../docs/src/guide/obstacles.md")]
    struct Obstacles;
    #[doc = include_str!("../docs/src/guide/drive-limits.md")]
    struct DriveLimits;
    #[doc = include_str!("../docs/src/guide/faults.md")]
    struct Faults;
}
