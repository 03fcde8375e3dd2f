//! Closed joint-space contours of an arm, as plain data (`JointContourSpec`) and built into
//! one of the core's contours for a run-time number of joints: a periodic spline through
//! waypoints, a Lissajous curve or an ellipse.

use super::waypoint_spline::WaypointSpline;
use super::{fixed, MAX_JOINTS, MAX_WAYPOINTS};
use crate::error::{Result, SimError};
use pvfc_core::contour::ContourSample;
use pvfc_core::prelude::*;
use serde::{Deserialize, Serialize};

fn setting(message: String) -> SimError {
    SimError::Setting(message)
}

/// A closed joint-space contour of an arm, as plain data (one entry per joint in every list,
/// checked against the robot when the controller is built). In a scenario file it is one
/// table named for its kind: `[contour.waypoints]`, `[contour.lissajous]`,
/// `[contour.ellipse]` (see `model::contour`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum JointContourSpec {
    /// A periodic C² spline through 3 to [`MAX_WAYPOINTS`] waypoints, one every `spacing` of
    /// `τ` (the period is `spacing × waypoints`).
    Waypoints {
        /// The waypoints, one row of joint coordinates each.
        points: Vec<Vec<f64>>,
        /// `τ` between waypoints.
        spacing: f64,
    },
    /// `x_i = c_i + a_i sin(2πτ/T_i + φ_i)`, closed with the common period `period`.
    Lissajous {
        /// Amplitudes `a_i` (rad or m).
        amplitude: Vec<f64>,
        /// Periods `T_i` in `τ`.
        periods: Vec<f64>,
        /// Phases `φ_i` (rad); zeros when empty or left out.
        #[serde(default)]
        phase: Vec<f64>,
        /// Offsets `c_i` (rad or m); zeros when empty or left out.
        #[serde(default)]
        offset: Vec<f64>,
        /// The common period in `τ` (a multiple of every `T_i`); `None`: not closed.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        period: Option<f64>,
    },
    /// `x_d(τ) = c + u cos(2πτ/T) + w sin(2πτ/T)`: an ellipse in joint space.
    Ellipse {
        /// The centre `c`.
        center: Vec<f64>,
        /// The conjugate semi-axis `u`.
        u: Vec<f64>,
        /// The conjugate semi-axis `w`.
        w: Vec<f64>,
        /// The period `T` in `τ`.
        period: f64,
    },
}

/// `x` as a vector of `N` entries, or zeros when empty.
fn or_zeros<const N: usize>(x: &[f64], name: &str) -> Result<nalgebra::SVector<f64, N>> {
    match x.is_empty() {
        true => Ok(nalgebra::SVector::zeros()),
        false => fixed::<N>(x, name),
    }
}

impl JointContourSpec {
    /// The kind's name, as its table is named (`[contour.lissajous]`).
    pub fn kind(&self) -> &'static str {
        match self {
            JointContourSpec::Waypoints { .. } => "waypoints",
            JointContourSpec::Lissajous { .. } => "lissajous",
            JointContourSpec::Ellipse { .. } => "ellipse",
        }
    }

    /// The Lissajous curve of `N` coordinates, if the contour is one (closed with its
    /// period if it has one).
    pub fn lissajous<const N: usize>(&self) -> Result<Option<Lissajous<f64, N>>> {
        let JointContourSpec::Lissajous {
            amplitude,
            periods,
            phase,
            offset,
            period,
        } = self
        else {
            return Ok(None);
        };
        let c = Lissajous::new(
            fixed::<N>(amplitude, "lissajous.amplitude")?,
            fixed::<N>(periods, "lissajous.periods")?,
            or_zeros::<N>(phase, "lissajous.phase")?,
            or_zeros::<N>(offset, "lissajous.offset")?,
        )?;
        Ok(Some(match period {
            Some(p) => c.with_period(*p)?,
            None => c,
        }))
    }

    /// The period in `τ` (`None` for a Lissajous curve declared without one).
    pub fn period(&self) -> Option<f64> {
        match self {
            JointContourSpec::Waypoints { points, spacing } => Some(spacing * points.len() as f64),
            JointContourSpec::Lissajous { period, .. } => *period,
            JointContourSpec::Ellipse { period, .. } => Some(*period),
        }
    }

    /// The contour of an `N`-joint chain with these joint kinds.
    pub fn build<const N: usize>(&self, kinds: [JointKind; N]) -> Result<JointContour<N>> {
        Ok(match self {
            JointContourSpec::Waypoints { points, spacing } => {
                if !(3..=MAX_WAYPOINTS).contains(&points.len()) {
                    return Err(setting(format!(
                        "waypoints: 3 to {MAX_WAYPOINTS} are needed, got {}",
                        points.len()
                    )));
                }
                let pts = points
                    .iter()
                    .enumerate()
                    .map(|(k, w)| {
                        Ok(JointSpace::new(
                            fixed::<N>(w, &format!("waypoint {k}"))?,
                            kinds,
                        ))
                    })
                    .collect::<Result<Vec<_>>>()?;
                JointContour::Spline(WaypointSpline::through(&pts, *spacing)?)
            }
            JointContourSpec::Lissajous { .. } => match self.lissajous::<N>()? {
                Some(c) => JointContour::Lissajous(c),
                None => return Err(setting("lissajous: not a Lissajous curve".into())),
            },
            JointContourSpec::Ellipse {
                center,
                u,
                w,
                period,
            } => JointContour::Ellipse(Ellipse::new(
                fixed::<N>(center, "ellipse.center")?,
                fixed::<N>(u, "ellipse.u")?,
                fixed::<N>(w, "ellipse.w")?,
                *period,
            )?),
        })
    }
}

/// The closed joint-space contour of an `N`-joint arm: one of the core's contours, chosen at
/// run time.
#[derive(Clone, Debug, PartialEq)]
pub enum JointContour<const N: usize> {
    /// A periodic C² spline through waypoints (on the heap: up to [`MAX_WAYPOINTS`] of them;
    /// evaluating it costs the same for any number).
    Spline(WaypointSpline<N>),
    /// A Lissajous curve.
    Lissajous(Lissajous<f64, N>),
    /// An ellipse.
    Ellipse(Ellipse<f64, N>),
}

impl<const N: usize> Contour<f64, JointSpace<f64, N>, N> for JointContour<N> {
    #[inline]
    fn sample(&self, tau: f64) -> ContourSample<f64, JointSpace<f64, N>, N> {
        match self {
            JointContour::Spline(c) => c.sample(tau),
            JointContour::Lissajous(c) => c.sample(tau),
            JointContour::Ellipse(c) => c.sample(tau),
        }
    }

    fn period(&self) -> Option<f64> {
        match self {
            JointContour::Spline(c) => c.period(),
            JointContour::Lissajous(c) => Contour::<f64, JointSpace<f64, N>, N>::period(c),
            JointContour::Ellipse(c) => Contour::<f64, JointSpace<f64, N>, N>::period(c),
        }
    }
}

impl JointContourSpec {
    /// The number of coordinates (the first waypoint's, or the lists' length).
    pub fn dim(&self) -> usize {
        match self {
            JointContourSpec::Waypoints { points, .. } => points.first().map_or(0, Vec::len),
            JointContourSpec::Lissajous { amplitude, .. } => amplitude.len(),
            JointContourSpec::Ellipse { center, .. } => center.len(),
        }
    }
}

crate::dof_enum! {
    /// A joint-space contour of 1 to [`MAX_JOINTS`] coordinates, built once, for callers whose
    /// dimension is known at run time only (the Python contours): sampled with every coordinate
    /// circular unless told otherwise.
    #[derive(Clone, Debug)]
    pub enum DynJointContour of JointContour
}

impl DynJointContour {
    /// Builds `spec` with the given joint kinds (`None`: every coordinate circular, as on the
    /// torus).
    pub fn new(spec: &JointContourSpec, kinds: Option<&[JointKind]>) -> Result<Self> {
        let n = spec.dim();
        if let Some(k) = kinds {
            if k.len() != n {
                return Err(setting(format!(
                    "contour: {n} coordinates for a {}-joint robot",
                    k.len()
                )));
            }
        }
        Ok(crate::with_dof!(n, N => {
            let mut ks = [JointKind::Circular; N];
            if let Some(k) = kinds {
                ks.copy_from_slice(k);
            }
            DynJointContour::from(spec.build::<N>(ks)?)
        }, otherwise {
            return Err(setting(format!(
                "contour: 1 to {MAX_JOINTS} coordinates are supported, got {n}"
            )));
        }))
    }

    /// The number of coordinates.
    pub fn dim(&self) -> usize {
        crate::on_joints!(DynJointContour, self, _c, N => N)
    }

    /// `x_d(τ)`, `dx_d/dτ` and `d²x_d/dτ²` (coordinates, with circular ones unwrapped as the
    /// contour gives them).
    pub fn sample(&self, tau: f64) -> [Vec<f64>; 3] {
        crate::on_joints!(DynJointContour, self, c, N => {
            let s = c.sample(tau);
            [
                s.point.coords().as_slice().to_vec(),
                s.velocity.as_slice().to_vec(),
                s.acceleration.as_slice().to_vec(),
            ]
        })
    }

    /// The period in `τ`.
    pub fn period(&self) -> Option<f64> {
        crate::on_joints!(DynJointContour, self, c, N => c.period())
    }
}
