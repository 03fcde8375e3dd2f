//! The tool's orientation along a closed tool path: held at one rotation, or given at the
//! corners of a polyline (`[contour.cartesian] orientations`, a path in SE(3)). Between two
//! corners it turns at a constant rate (slerp) with the arc length along the path, from the
//! point of the path closest to one corner (its rounding's midpoint; the corner itself when
//! sharp) to the next. The same rule gives the inverse kinematics' orientations at the samples
//! and the task-space field's `R_d(τ)` with its rates.

use crate::model::tool_path::ToolPath;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use pvfc_core::contour::{Contour, ContourSample};
use pvfc_core::lie::So3;

/// The orientation at given corners of a path, as the arc length is travelled.
#[derive(Clone, Debug, PartialEq)]
pub struct CornerOrientations {
    /// The arc length of each corner's closest point of the path, in path order from the
    /// smallest.
    along: Vec<f64>,
    /// The rotation at each corner, in the same order.
    rotations: Vec<UnitQuaternion<f64>>,
    /// The body rotation vector from each corner to the next (`log(R_iᵀ R_{i+1})`).
    turns: Vec<Vector3<f64>>,
    /// The path's length.
    length: f64,
}

impl CornerOrientations {
    /// The orientations `rotations` at `corners` of `path` (one each, in the path's order).
    /// Two neighbours half a turn apart are an error naming them (there are two equally short
    /// ways between them).
    pub fn new(
        path: &ToolPath,
        corners: &[Vector3<f64>],
        rotations: &[UnitQuaternion<f64>],
    ) -> Result<Self, String> {
        let n = corners.len();
        if n < 2 || rotations.len() != n {
            return Err(format!(
                "orientations: one per point ({n}), at least two, got {}",
                rotations.len()
            ));
        }
        let mut order: Vec<(f64, usize)> = corners
            .iter()
            .enumerate()
            .map(|(i, c)| (path.closest(c).along, i))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut turns = Vec::with_capacity(n);
        for k in 0..n {
            let (i, j) = (order[k].1, order[(k + 1) % n].1);
            let (a, b) = (rotations[i], rotations[j]);
            if a.coords.dot(&b.coords).abs() < 1e-6 {
                return Err(format!(
                    "orientations: points {i} and {j} differ by half a turn (no unique way between them)"
                ));
            }
            turns.push((a.inverse() * b).scaled_axis());
        }
        Ok(CornerOrientations {
            along: order.iter().map(|o| o.0).collect(),
            rotations: order.iter().map(|o| rotations[o.1]).collect(),
            turns,
            length: path.length(),
        })
    }

    /// The rotation at arc length `s` (m, modulo the length) and its body rate per metre of
    /// arc length.
    pub fn at(&self, s: f64) -> (Matrix3<f64>, Vector3<f64>) {
        let n = self.along.len();
        let s = s.rem_euclid(self.length);
        // The corner at or before s (the last one, wrapping, if s is before the first).
        let k = match self.along.partition_point(|&a| a <= s) {
            0 => n - 1,
            k => k - 1,
        };
        let span = (self.along[(k + 1) % n] - self.along[k]).rem_euclid(self.length);
        let span = if span > 0.0 { span } else { self.length };
        let frac = (s - self.along[k]).rem_euclid(self.length) / span;
        let r = self.rotations[k] * UnitQuaternion::from_scaled_axis(self.turns[k] * frac);
        (r.to_rotation_matrix().into_inner(), self.turns[k] / span)
    }
}

/// The tool's orientation along a path as a contour `R_d(τ)` on SO(3), one pass every
/// `period` of `τ` (the task-space field's orientation).
#[derive(Clone, Debug, PartialEq)]
pub enum PathOrientation {
    /// One orientation held along the whole path.
    Held(So3<f64>),
    /// The orientations at the corners, traced with the path at constant speed.
    Corners {
        /// The orientations.
        corners: CornerOrientations,
        /// `τ` per pass.
        period: f64,
    },
}

impl Contour<f64, So3<f64>, 3> for PathOrientation {
    fn sample(&self, tau: f64) -> ContourSample<f64, So3<f64>, 3> {
        match self {
            PathOrientation::Held(r) => ContourSample {
                point: *r,
                velocity: Vector3::zeros(),
                acceleration: Vector3::zeros(),
            },
            PathOrientation::Corners { corners, period } => {
                let speed = corners.length / period;
                let (r, rate) = corners.at(tau * speed);
                ContourSample {
                    point: So3::from_matrix_unchecked(r),
                    velocity: rate * speed,
                    acceleration: Vector3::zeros(),
                }
            }
        }
    }

    fn period(&self) -> Option<f64> {
        match self {
            PathOrientation::Held(_) => None,
            PathOrientation::Corners { period, .. } => Some(*period),
        }
    }
}
