//! # pvfc-cli
//!
//! The application built on the simulation library [`pvfc_sim`]: the `pvfc` command
//! (`src/main.rs`), the figures of a run ([`plot`]), studies run into tables and figures
//! ([`sweep`], [`study_plot`]), and the paper's reproduction: every
//! preset run ([`reproduce`]) and the numbers behind each claim of section V ([`report`]).
//!
//! Data flows one way: the library runs a scenario into a trace; this crate turns traces into
//! figures, claims and the summary table. Nothing in the library depends on it.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod body_plot;
pub mod canvas;
pub mod chain_plot;
#[cfg(unix)]
pub mod hil;
pub mod plot;
mod plot_digital;
pub mod report;
mod report_arms;
mod report_digital;
mod report_paths;
pub mod reproduce;
pub mod robustness;
pub mod runs;
mod satellite;
pub mod speed_sweep;
pub mod study_plot;
pub mod sweep;
