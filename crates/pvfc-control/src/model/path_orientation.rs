//! The tool's orientation along a closed tool path: held at one rotation, given at the
//! corners of a polyline (`[contour.cartesian] orientations`, a path in SE(3)), or the path's
//! own frame (`[contour.cartesian] tool_frame`). Between two corners it turns at a constant
//! rate (slerp) with the arc length along the path, from the point of the path closest to one
//! corner (its rounding's midpoint; the corner itself when sharp) to the next. The path's
//! frame has its x along the path's direction and its z against the part's surface normal,
//! turned by a lead and a tilt angle ([`PathFrame`]). The same rule gives the inverse
//! kinematics' orientations at the samples and the task-space field's `R_d(τ)` with its rates.

use crate::model::tool_path::ToolPath;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
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

/// The tool's frame along a path, for a tool that works the part's surface as it goes
/// (deburring an edge, gluing, polishing):
///
/// `R(s) = F(s) · R_y(lead) · R_x(tilt)`, `F(s) = [x(s), z × x(s), z]`,
///
/// with `z = −n` against the surface normal `n` (the tool's axis into the part) and `x(s)` the
/// path's unit tangent `t(s)` with its component along `n` removed (the direction of travel
/// in the surface). `lead` turns the tool's axis towards the direction of travel, `tilt` then
/// about that direction (right-handed). `F` turns about `z` only, at the rate
/// `ω = x × dx/ds` (rad/m) of the tangent's turning in the surface: on an arc of radius `ρ` in
/// the surface, `1/ρ`. A path whose direction jumps (a sharp corner) would jump the tool's
/// orientation with it and is refused, as is a path whose direction passes along `n`.
#[derive(Clone, Debug, PartialEq)]
pub struct PathFrame {
    path: ToolPath,
    /// The tool's axis `z = −n` in the base frame.
    axis: Vector3<f64>,
    /// `R_y(lead) R_x(tilt)`.
    offset: Matrix3<f64>,
}

impl PathFrame {
    /// The frame along `path` against the surface normal `normal` (base frame; any non-zero
    /// length), turned by `lead` and `tilt` (rad). Errors name what is wrong: a normal or an
    /// angle that is not finite, a zero normal, a sharp corner (where, and by how much the
    /// direction turns), a direction along the normal (where).
    pub fn new(
        path: &ToolPath,
        normal: Vector3<f64>,
        lead: f64,
        tilt: f64,
    ) -> Result<Self, String> {
        let norm = normal.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(format!(
                "tool_frame.normal: a finite, non-zero vector, got [{}, {}, {}]",
                normal.x, normal.y, normal.z
            ));
        }
        if !(lead.is_finite() && tilt.is_finite()) {
            return Err(format!(
                "tool_frame: lead and tilt finite (rad), got {lead} and {tilt}"
            ));
        }
        let axis = -normal / norm;
        let length = path.length();
        // The direction may not jump where one piece meets the next.
        let starts = path.piece_starts();
        for &s in &starts[..starts.len() - 1] {
            let before = path.tangent((s - 1e-9 * length).rem_euclid(length));
            let after = path.tangent(s);
            let turn = before.angle(&after);
            if turn > 1e-3 {
                let p = path.point(s);
                return Err(format!(
                    "tool_frame: the path turns sharply by {:.1}° at ({:.4}, {:.4}, {:.4}) m, {:.4} m along it: the tool's frame would jump there (round the corner: corner_radius > 0, arcs tangent to their neighbours, or G64 P in a part program)",
                    turn.to_degrees(),
                    p.x,
                    p.y,
                    p.z,
                    s
                ));
            }
        }
        // Nor run along the normal (the direction in the surface is then undefined).
        let steps = 64 * (starts.len() - 1).max(1);
        for k in 0..steps {
            let s = length * k as f64 / steps as f64;
            let t = path.tangent(s);
            if t.cross(&axis).norm() < 1e-3 {
                let p = path.point(s);
                return Err(format!(
                    "tool_frame: the path runs along the surface normal at ({:.4}, {:.4}, {:.4}) m, {:.4} m along it: no direction of travel in the surface",
                    p.x, p.y, p.z, s
                ));
            }
        }
        let offset = Rotation3::from_axis_angle(&Vector3::y_axis(), lead)
            * Rotation3::from_axis_angle(&Vector3::x_axis(), tilt);
        Ok(PathFrame {
            path: path.clone(),
            axis,
            offset: offset.into_inner(),
        })
    }

    /// The rotation at arc length `s` (m, modulo the length) and its body rate per metre of
    /// arc length.
    pub fn at(&self, s: f64) -> (Matrix3<f64>, Vector3<f64>) {
        let (_, t, c) = self.path.frame(s);
        let z = self.axis;
        let p = t - z * t.dot(&z);
        let m = p.norm();
        let x = p / m;
        let dp = c - z * c.dot(&z);
        let dx = (dp - x * x.dot(&dp)) / m;
        let frame = Matrix3::from_columns(&[x, z.cross(&x), z]);
        let omega = x.cross(&dx);
        let r = frame * self.offset;
        (r, r.transpose() * omega)
    }
}

/// How the tool's orientation follows a path's arc length: slerped between corners, or the
/// path's own frame.
#[derive(Clone, Debug, PartialEq)]
pub enum OrientationLaw {
    /// The orientations at a polyline's corners ([`CornerOrientations`]).
    Corners(CornerOrientations),
    /// The path's frame against the part's surface ([`PathFrame`]).
    Frame(PathFrame),
}

impl OrientationLaw {
    /// The rotation at arc length `s` (m, modulo the path's length) and its body rate per
    /// metre of arc length.
    pub fn at(&self, s: f64) -> (Matrix3<f64>, Vector3<f64>) {
        match self {
            OrientationLaw::Corners(c) => c.at(s),
            OrientationLaw::Frame(f) => f.at(s),
        }
    }

    /// The path's length (m).
    pub fn length(&self) -> f64 {
        match self {
            OrientationLaw::Corners(c) => c.length,
            OrientationLaw::Frame(f) => f.path.length(),
        }
    }
}

/// The tool's orientation along a path as a contour `R_d(τ)` on SO(3), one pass every
/// `period` of `τ` (the task-space field's orientation).
#[derive(Clone, Debug, PartialEq)]
pub enum PathOrientation {
    /// One orientation held along the whole path.
    Held(So3<f64>),
    /// The orientation along the path ([`OrientationLaw`]), traced with it at constant
    /// speed.
    Along {
        /// How the orientation follows the arc length.
        law: OrientationLaw,
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
            PathOrientation::Along { law, period } => {
                let speed = law.length() / period;
                let (r, rate) = law.at(tau * speed);
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
            PathOrientation::Along { period, .. } => Some(*period),
        }
    }
}
