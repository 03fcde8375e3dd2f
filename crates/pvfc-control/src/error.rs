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
    /// A part program (G-code) cannot be followed; names the line and the column.
    #[error("part program {path}: line {line}, column {column}: {message}")]
    PartProgram {
        /// The file.
        path: PathBuf,
        /// The line (1-based).
        line: usize,
        /// The column of the word (1-based).
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A simulation setting is invalid.
    #[error("invalid setting: {0}")]
    Setting(String),
    /// The serial line to a drive in the loop failed (hardware in the loop): the line closed,
    /// a period went unanswered, or the drive answered with something else.
    #[error("hardware in the loop, period {period}: {message}")]
    Link {
        /// The control period (the frames' sequence number).
        period: u32,
        /// What happened.
        message: String,
    },
    /// A point of a Cartesian tool path cannot be turned into a joint posture.
    #[error("Cartesian path: waypoint {index} at ({:.4}, {:.4}, {:.4}) m: {problem}", point[0], point[1], point[2])]
    Waypoint {
        /// The waypoint's index along the sampled path (0 is the first).
        index: usize,
        /// Where it is, in the base frame (m).
        point: [f64; 3],
        /// What is wrong with it.
        problem: WaypointProblem,
    },
}

/// Why a Cartesian waypoint has no joint posture the contour can use.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum WaypointProblem {
    /// The inverse kinematics left the tool this far from the point (m).
    #[error("unreachable (the tool stays {0:.3e} m away)")]
    Unreachable(f64),
    /// The posture's manipulability is below the threshold.
    #[error("too close to a singularity (manipulability {0:.3e} below {1:.1e})")]
    Singular(f64, f64),
    /// A joint would leave its limits.
    #[error("joint {joint} at {value:.4} outside its limits [{lower:.4}, {upper:.4}]")]
    JointLimit {
        /// The joint's name.
        joint: String,
        /// Its coordinate (rad or m).
        value: f64,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A joint jumps between this waypoint and the previous one (another IK branch).
    #[error("branch jump: joint {joint} moves {jump:.3} rad from the previous waypoint (more than {limit})")]
    BranchJump {
        /// The joint's name.
        joint: String,
        /// The jump (rad or m).
        jump: f64,
        /// The largest accepted.
        limit: f64,
    },
}

/// The result type of pvfc-sim.
pub type Result<T> = std::result::Result<T, SimError>;

impl SimError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        SimError::Io {
            path: path.into(),
            source,
        }
    }
}
