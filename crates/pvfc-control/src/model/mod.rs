//! Robot models with a number of joints known at run time, over the const-generic core: a
//! serial chain read from a URDF ([`robot`], dispatched onto `SerialChain<N>` by
//! [`with_dof!`](crate::with_dof)), the PVFC controller of any chain and its joint-space
//! contours ([`arm`]), the contour spec of every kind ([`contour`]), the law at one state for any robot ([`evaluation`]), tool paths in Cartesian space and their inverse kinematics
//! ([`cartesian`]), part programs read into tool paths ([`gcode`]) and the pace along a contour ([`pace`]).

pub mod arm;
pub mod arm_field;
pub mod cartesian;
pub mod contour;
pub mod dispatch;
pub mod evaluation;
pub mod feeds;
pub mod gcode;
pub mod joint_contour;
pub mod miss_paced;
pub mod pace;
pub mod path_orientation;
pub mod pose;
pub mod robot;
pub mod tool_path;
pub mod waypoint_spline;

use crate::error::{Result, SimError};
use nalgebra::SVector;

/// The largest number of joints (and of contour coordinates) dispatched at run time.
pub use crate::urdf::chain::MAX_JOINTS;

/// The most waypoints a joint-space contour may have.
pub const MAX_WAYPOINTS: usize = 1024;

/// A per-joint list as a vector of the robot's dimension, or an error naming it.
pub fn fixed<const N: usize>(x: &[f64], name: &str) -> Result<SVector<f64, N>> {
    if x.len() != N {
        return Err(SimError::Setting(format!(
            "{name}: {} entries for a {N}-joint robot",
            x.len()
        )));
    }
    Ok(SVector::from_column_slice(x))
}
