//! A pose written in a scenario file, Python or C: `{ xyz = [...], rpy = [...] }`, URDF's
//! convention (a translation in m, then roll, pitch, yaw in rad about the fixed x, y, z axes).
//! A part's frame in the base frame (`[contour.cartesian] part`) and the tool centre point on
//! the tip link (`[plant] tcp`) are given so.

use crate::error::{Result, SimError};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pvfc_core::mechanics::Pose;
use serde::{Deserialize, Serialize};

/// `{ xyz = [...], rpy = [...] }`: a frame's pose in another (both default to zeros).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PoseSpec {
    /// The frame's origin (m).
    pub xyz: [f64; 3],
    /// Its orientation: roll, pitch, yaw (rad), about the fixed x, y, z axes.
    pub rpy: [f64; 3],
}

impl PoseSpec {
    /// The pose as an isometry, or an error naming `key` when a number is not finite.
    pub fn isometry(&self, key: &str) -> Result<Isometry3<f64>> {
        self.check(key)?;
        let [r, p, y] = self.rpy;
        Ok(Isometry3::from_parts(
            Translation3::from(Vector3::from(self.xyz)),
            UnitQuaternion::from_euler_angles(r, p, y),
        ))
    }

    /// The pose as the core's [`Pose`] (the same rotation, built as the URDF reader builds a
    /// joint's origin), or an error naming `key` when a number is not finite.
    pub fn pose(&self, key: &str) -> Result<Pose<f64>> {
        self.check(key)?;
        Ok(Pose::from_xyz_rpy(self.xyz, self.rpy))
    }

    fn check(&self, key: &str) -> Result<()> {
        match self.xyz.iter().chain(&self.rpy).all(|x| x.is_finite()) {
            true => Ok(()),
            false => Err(SimError::Setting(format!(
                "{key}: xyz and rpy must be finite, got xyz = {:?}, rpy = {:?}",
                self.xyz, self.rpy
            ))),
        }
    }
}
