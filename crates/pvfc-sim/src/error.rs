//! The error type of pvfc-sim.

use std::path::PathBuf;

/// What can go wrong in a simulation, a scenario file, a URDF, a log or a figure.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// The control law or a model rejected a state or a parameter.
    #[error(transparent)]
    Core(#[from] pvfc_core::Error),
    /// A scenario file is malformed; the message names the field and the line.
    #[error("scenario {path}: {message}")]
    Scenario {
        /// The file.
        path: PathBuf,
        /// What is wrong, where (from the TOML parser, with line and column).
        message: String,
    },
    /// A URDF is malformed or is not a planar two-revolute chain; names the element.
    #[error("URDF {path}: {element}: {message}")]
    Urdf {
        /// The file.
        path: PathBuf,
        /// The offending element (`link NAME`, `joint NAME`, `robot`).
        element: String,
        /// What is wrong.
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Writing or reading an MCAP log failed.
    #[error("MCAP log: {0}")]
    Mcap(String),
    /// Drawing a figure failed.
    #[error("figure {path}: {message}")]
    Plot {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A simulation setting is invalid.
    #[error("invalid setting: {0}")]
    Setting(String),
}

/// The result type of pvfc-sim.
pub type Result<T> = std::result::Result<T, SimError>;

impl SimError {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        SimError::Io {
            path: path.into(),
            source,
        }
    }
}
