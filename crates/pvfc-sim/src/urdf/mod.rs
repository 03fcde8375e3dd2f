//! Robots from URDF files (urdf-rs), with the checks urdf-rs does not make: any serial chain
//! ([`chain`]) and the paper's planar two-link arm in closed form ([`scara`]).

pub mod chain;
pub mod collision;
pub mod scara;

pub use chain::{ChainDescription, JointDescription, JointLimits};
pub use collision::{CollisionGeometry, LinkCollision};
pub use scara::{scara_from_urdf, scara_from_urdf_str};

use crate::error::SimError;
use std::path::Path;

/// A [`SimError::Urdf`] naming the file and the element at fault.
pub(crate) fn err(path: &Path, element: impl Into<String>, message: impl Into<String>) -> SimError {
    SimError::Urdf {
        path: path.to_path_buf(),
        element: element.into(),
        message: message.into(),
    }
}
