//! Studies: sweeps and Monte Carlo runs over any scenario key. A [`spec::StudySpec`] names a
//! base scenario, axes over its keys by their dotted paths (`controller.self_pacing`,
//! `plant.friction.coulomb[1]`), as lists, ranges or random draws from a seed ([`sample`]),
//! and the [`metrics`] to keep; [`spec::StudySpec::runs`] expands it into one validated
//! scenario per run, so that a bad key, value or metric is an error naming it before
//! anything runs. [`runner`] runs them in parallel into rows, [`table`] writes the rows as CSV
//! and reads them back to resume, [`arrow`] as an Arrow IPC file for pandas and Polars.

pub mod arrow;
pub mod metrics;
pub mod runner;
pub mod sample;
pub mod spec;
pub mod table;
