//! Studies: sweeps and Monte Carlo runs over any scenario key. A [`spec::StudySpec`] names a
//! base scenario and axes over its keys by their dotted paths (`controller.self_pacing`,
//! `plant.friction.coulomb[1]`), as lists, ranges or random draws from a seed
//! ([`sample`]); [`spec::StudySpec::runs`] expands it into one validated scenario per run,
//! so that a bad key or value is an error naming it before anything runs.

pub mod sample;
pub mod spec;
