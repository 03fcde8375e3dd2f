//! Tool paths given in Cartesian space (`[contour.cartesian]`): a closed curve of the tool's
//! position in the robot's base frame or a part's frame (a polyline with rounded corners, a
//! circle or ellipse in any plane, the points of a CSV file, or a part program's cutting
//! moves), turned into joint waypoints by inverse kinematics
//! along the path. The joint contour is then the periodic spline through those waypoints
//! (`[contour] spacing`), as for a contour given in joint space.
//!
//! Why a joint-space contour by default: the field, the navigation function and the coupling
//! stay exactly those of the joint-space arms, the spline gives `ξ_d` and `dξ_d/dτ` in closed
//! form, and the inverse kinematics is done once, where its failures (unreachable points,
//! singularities, limits, branch jumps) can be reported by waypoint before anything runs. The
//! price is that the tool follows the Cartesian path through the joint spline between
//! waypoints (the distance is reported, and the adaptive sampling bounds it). With
//! `[contour.cartesian.task]` ([`TaskSpec`]) the controller follows the exact path instead,
//! with the task-space field ([`crate::model::arm_field`]).

use crate::error::{Result, SimError, WaypointProblem};
use crate::model::arm::JointContourSpec;
use crate::model::arm_field::{TaskFieldSpec, TaskOrientation};
use crate::model::feeds::FeedProfile;
use crate::model::gcode::PartProgram;
use crate::model::path_orientation::{CornerOrientations, OrientationLaw, PathFrame};
pub use crate::model::pose::PoseSpec;
use crate::model::robot::Robot;
use crate::model::tool_path::{Closest, ToolPath};
use crate::with_dof;
use nalgebra::{SVector, Vector3};
use pvfc_core::contour::Contour;
use pvfc_core::mechanics::{IkSettings, IkTarget, SerialChain};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The most waypoints a Cartesian path is sampled into (the joint spline's capacity).
pub const MAX_SAMPLES: usize = super::MAX_WAYPOINTS;

/// `[contour.cartesian]`: a closed tool path and how to turn it into joint waypoints.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CartesianSpec {
    /// The corners of a closed polyline (m, base frame); the last joins the first.
    pub points: Vec<[f64; 3]>,
    /// The radius the polyline's corners are rounded to (m; 0: sharp).
    pub corner_radius: f64,
    /// A circle instead of points.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub circle: Option<CircleSpec>,
    /// A CSV file of points `x,y,z` (one per line, a header allowed) instead of `points`,
    /// relative to the scenario file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub csv: Option<PathBuf>,
    /// A part program (G-code) whose cutting moves are the path (lines and arcs, exactly;
    /// see [`gcode`](crate::model::gcode) for what it reads), relative to the scenario file,
    /// instead of `points`, `circle` or `csv`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gcode: Option<PathBuf>,
    /// The workpiece's pose in the base frame, when the path is given in the part's frame:
    /// `points`, `circle`, `csv` or `gcode`, and the corners' `orientations`, are then
    /// placed by it. Default: the base frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part: Option<PoseSpec>,
    /// How many joint waypoints the path is sampled into (equal arc length; 4 to
    /// [`MAX_SAMPLES`]); 0: as many as it takes for the joint contour to stay within
    /// `tolerance` of the path, and where [`MAX_SAMPLES`] of equal arc length are not enough,
    /// that many placed by the joints' motion (each interval an equal share of the path's length
    /// and of the joints' travel, half each).
    pub samples: usize,
    /// The largest distance (m) allowed between the path and the joint contour's tool
    /// position (its forward kinematics) when `samples` is 0; default 10 µm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// The joint posture the inverse kinematics starts from at the first waypoint.
    pub seed: Vec<f64>,
    /// Hold the tool's orientation at the seed's (else it is free).
    pub fixed_orientation: bool,
    /// The tool's orientation at each of `points` (roll, pitch, yaw in the base frame, URDF's
    /// convention), for a path in SE(3): between the path's points closest to two
    /// neighbouring corners the orientation turns at constant rate (slerp) with the arc length
    /// ([`CornerOrientations`]). Empty: position only (with `fixed_orientation` or free).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub orientations: Vec<[f64; 3]>,
    /// `[contour.cartesian.tool_frame]`: the tool's axis held to the path's own frame (its
    /// z against the part's surface normal, leaning by a lead angle towards the direction of
    /// travel and by a tilt across it; [`PathFrame`]), the roll about the axis free (a
    /// five-dimensional task: a spindle, a deburring cone, a nozzle), instead of
    /// `orientations` or `fixed_orientation`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool_frame: Option<ToolFrameSpec>,
    /// A rest posture for redundant tasks (more joints than the path fixes coordinates: 3 for
    /// a position, 6 with an orientation): each inverse-kinematics iteration pulls towards it
    /// in the null space of the task, with `rest_gain`. Default for a redundant task: the
    /// seed (the waypoints then lie on one smooth branch).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rest: Option<Vec<f64>>,
    /// The gain (0 to 1) of the pull towards `rest`; default 0.1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rest_gain: Option<f64>,
    /// The largest joint change between neighbouring waypoints (rad or m) before it counts as
    /// a jump to another branch of the inverse kinematics; default 0.6.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_jump: Option<f64>,
    /// The smallest manipulability accepted; default 1e-4.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_manipulability: Option<f64>,
    /// `[contour.cartesian.task]`: follow the path with the task-space field (the tool's
    /// error to the exact path, pulled back through the Jacobian) instead of the joint
    /// contour through the waypoints. The waypoints are still solved: the timed tracker and
    /// the figures use them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub task: Option<TaskSpec>,
    /// One pass's period in `τ` with adaptive sampling (`samples = 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period: Option<f64>,
    /// `τ` between waypoints with fixed `samples` (the period is `spacing × samples`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
}

/// `[contour.cartesian.task]`: the task-space field's gains (every key has a default, so
/// `task = {}` chooses the field with them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TaskSpec {
    /// `k` of the position's navigation function `U = ½ k |e|²` (1/s); default
    /// [`DEFAULT_TASK_STIFFNESS`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// `k_R` of the orientation's `U_R = k_R (1 − cos θ)` (1/s), with `fixed_orientation` or
    /// `orientations`; default: `stiffness`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orientation_stiffness: Option<f64>,
    /// The damping `μ` of the Jacobian's inverse `Jᵀ(J Jᵀ + μ² I)⁻¹` (m): near a singularity
    /// the field stays below `|w|/(2μ)`; default [`DEFAULT_TASK_DAMPING`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// The gain (1/s) of the pull towards `rest` (default: the seed) in the task's null
    /// space, for arms with more joints than the task has coordinates; default 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rest_gain: Option<f64>,
    /// The distance `ℓ` (m) at which the position's navigation function saturates: the
    /// pseudo-Huber `kℓ²(√(1 + |e|²/ℓ²) − 1)`, whose pull stays below `kℓ`; none: `½k|e|²`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub saturation: Option<f64>,
}

/// `[contour.cartesian.tool_frame]`: the tool's frame along the path ([`PathFrame`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ToolFrameSpec {
    /// The part's surface normal, pointing out of the part towards the tool, in the part's
    /// frame (`contour.cartesian.part`; the base frame without one); default `[0, 0, 1]`, the
    /// part's top face. The tool's z axis points against it, into the part.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal: Option<[f64; 3]>,
    /// The lead angle (rad): the tool's axis turned about its y axis, towards the direction
    /// of travel.
    pub lead: f64,
    /// The tilt angle (rad): then turned about the direction of travel (right-handed).
    pub tilt: f64,
}

/// The task-space field's default stiffness `k` (1/s).
pub const DEFAULT_TASK_STIFFNESS: f64 = 4.0;

/// The task-space field's default damping `μ` (m).
pub const DEFAULT_TASK_DAMPING: f64 = 0.01;

/// A circle of the tool path, or an ellipse (with `semi_minor`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CircleSpec {
    /// Centre (m, base frame).
    pub center: [f64; 3],
    /// Radius (m, > 0); an ellipse's semi-axis along `major_axis`.
    pub radius: f64,
    /// The normal of its plane (the direction it turns about, right-handed).
    pub normal: [f64; 3],
    /// An ellipse's other semi-axis (m, > 0), across `major_axis` in the plane.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub semi_minor: Option<f64>,
    /// The direction of the `radius` semi-axis (projected onto the plane; default: any),
    /// where the path starts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub major_axis: Option<[f64; 3]>,
}

fn bad(what: impl Into<String>) -> SimError {
    SimError::Setting(format!("contour.cartesian: {}", what.into()))
}

impl CartesianSpec {
    /// The path sampled at `samples` points of equal arc length, starting at its first point
    /// (with `samples = 0`, at the number the adaptive sampling starts from).
    pub fn sample(&self, base_dir: &Path) -> Result<Vec<Vector3<f64>>> {
        Ok(self.path(base_dir)?.sample(self.first_count()?))
    }

    /// The number of samples fixed by the spec, or the adaptive sampling's first.
    fn first_count(&self) -> Result<usize> {
        match self.samples {
            0 => Ok(ADAPTIVE_START),
            n if (4..=MAX_SAMPLES).contains(&n) => Ok(n),
            _ => Err(bad(format!("samples: 4 to {MAX_SAMPLES}, or 0 (adaptive)"))),
        }
    }

    /// The tolerance of the adaptive sampling (m).
    pub fn tolerance(&self) -> Result<f64> {
        match self.tolerance {
            None => Ok(DEFAULT_TOLERANCE),
            Some(t) if t.is_finite() && t > 0.0 => Ok(t),
            Some(t) => Err(bad(format!("tolerance: a length > 0 (m), got {t}"))),
        }
    }

    /// The path's exact geometry (m, base frame).
    pub fn path(&self, base_dir: &Path) -> Result<ToolPath> {
        finite(self.path_unchecked(base_dir)?)
    }

    /// The speed asked for along the path by a part program's feeds (`gcode` with F words),
    /// in the base frame: each cutting move's F on its stretch, a move without F at
    /// `fallback` (the scenario's `controller.pace.speed`); `None` for a path without feeds.
    pub fn feeds(&self, base_dir: &Path, fallback: Option<f64>) -> Result<Option<FeedProfile>> {
        let Some(f) = &self.gcode else {
            return Ok(None);
        };
        let file = base_dir.join(f);
        let (program, named) = read_program(&file)?;
        let path = finite(self.placed(program.tool_path().map_err(named)?)?)?;
        FeedProfile::from_program(&program, path, fallback)
    }

    /// A path given in the part's frame, placed in the base frame by `part`.
    fn placed(&self, in_part: ToolPath) -> Result<ToolPath> {
        match &self.part {
            Some(part) => Ok(in_part.transformed(&part.isometry("contour.cartesian.part")?)),
            None => Ok(in_part),
        }
    }

    fn path_unchecked(&self, base_dir: &Path) -> Result<ToolPath> {
        let corners = |p: &[[f64; 3]]| p.iter().map(|p| Vector3::from(*p)).collect::<Vec<_>>();
        let given = [
            !self.points.is_empty(),
            self.circle.is_some(),
            self.csv.is_some(),
            self.gcode.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(bad("give exactly one of points, circle, csv or gcode"));
        }
        let in_part = if let Some(c) = &self.circle {
            circle(c)?
        } else if let Some(f) = &self.csv {
            ToolPath::rounded_polygon(&read_csv(&base_dir.join(f))?, self.corner_radius)
                .map_err(bad)?
        } else if let Some(f) = &self.gcode {
            part_program(&base_dir.join(f))?
        } else {
            ToolPath::rounded_polygon(&corners(&self.points), self.corner_radius).map_err(bad)?
        };
        self.placed(in_part)
    }

    /// The task-space field's settings for `robot`, when the path has a
    /// `[contour.cartesian.task]` table: the exact path, the gains, the orientation (the
    /// seed's tool orientation held, with `fixed_orientation`; the corners' along the path,
    /// with `orientations`) and the rest posture (`rest`, or
    /// the seed for an arm with more joints than the task has coordinates).
    pub fn task_field(&self, robot: &Robot, base_dir: &Path) -> Result<Option<TaskFieldSpec>> {
        let Some(t) = &self.task else {
            return Ok(None);
        };
        let positive = |x: Option<f64>, default: f64, key: &str| match x.unwrap_or(default) {
            v if v.is_finite() && v > 0.0 => Ok(v),
            v => Err(bad(format!("task.{key}: finite and > 0, got {v}"))),
        };
        let stiffness = positive(t.stiffness, DEFAULT_TASK_STIFFNESS, "stiffness")?;
        let turn = positive(t.orientation_stiffness, stiffness, "orientation_stiffness")?;
        let damping = positive(t.damping, DEFAULT_TASK_DAMPING, "damping")?;
        let gain = positive(t.rest_gain, 1.0, "rest_gain")?;
        let saturation = match t.saturation {
            None => None,
            Some(l) => Some(positive(Some(l), l, "saturation")?),
        };
        let n = robot.dof();
        if self.seed.len() != n || !self.seed.iter().all(|x| x.is_finite()) {
            return Err(bad(format!("seed: {n} finite joint coordinates")));
        }
        let path = self.path(base_dir)?;
        let orientation = match self.orientation_law_on(&path)? {
            _ if self.fixed_orientation => {
                Some((TaskOrientation::Held(robot.tool_pose(&self.seed)?.0), turn))
            }
            Some(law @ OrientationLaw::Frame(_)) => Some((TaskOrientation::Axis(law), turn)),
            Some(law) => Some((TaskOrientation::Along(law), turn)),
            None => None,
        };
        let dims = match &orientation {
            None => 3,
            Some((TaskOrientation::Axis(_), _)) => 5,
            Some(_) => 6,
        };
        let rest = match &self.rest {
            Some(r) if r.len() == n && r.iter().all(|x| x.is_finite()) => Some((r.clone(), gain)),
            Some(_) => return Err(bad(format!("rest: {n} finite joint coordinates"))),
            None if n > dims => Some((self.seed.clone(), gain)),
            None => None,
        };
        Ok(Some(TaskFieldSpec {
            path,
            stiffness,
            damping,
            saturation,
            orientation,
            rest,
        }))
    }

    /// The period of one pass in `τ`: `spacing × samples` with fixed samples, `period` with
    /// adaptive sampling (`None` if the one it needs is not set).
    pub fn period_in_tau(&self) -> Option<f64> {
        match (self.samples, self.spacing) {
            (0, _) => self.period,
            (n, Some(h)) => Some(h * n as f64),
            (_, None) => None,
        }
    }

    /// The joint contour of the path for `robot`: the periodic spline through its joint
    /// waypoints, one every `spacing` of `τ` with fixed `samples`, and as many as the pass's
    /// `period` holds with adaptive sampling (`samples = 0`, where `spacing` must be `None`).
    pub fn joint_contour(&self, robot: &Robot, base_dir: &Path) -> Result<JointContourSpec> {
        let bad = |what: &str| Err(SimError::Setting(what.into()));
        match (self.samples, self.spacing, self.period) {
            (0, Some(_), _) => {
                return bad(
                    "contour.cartesian: with samples = 0 (adaptive) give the pass's period \
                     (contour.cartesian.period), not spacing",
                )
            }
            (0, None, None) => {
                return bad(
                    "contour.cartesian.period is needed with samples = 0 (adaptive sampling)",
                )
            }
            (1.., None, _) => return bad("contour.cartesian.spacing is needed with fixed samples"),
            _ => {}
        }
        let points = self.joint_waypoints(robot, base_dir)?;
        let spacing = match (self.spacing, self.period) {
            (Some(h), _) => h,
            (None, Some(p)) => p / points.len() as f64,
            (None, None) => return bad("contour.cartesian.period is needed"),
        };
        Ok(JointContourSpec::Waypoints { points, spacing })
    }

    /// The joint waypoints of the path for `robot` (those of [`joint_path`](Self::joint_path)).
    pub fn joint_waypoints(&self, robot: &Robot, base_dir: &Path) -> Result<Vec<Vec<f64>>> {
        Ok(self.joint_path(robot, base_dir)?.waypoints)
    }

    /// The joint waypoints of the path for `robot`, and how far the joint contour through
    /// them is from the path: inverse kinematics at every sample, warm-started from the
    /// previous one (the first from `seed`), each checked for reach, manipulability, joint
    /// limits and jumps (errors name the waypoint). With `samples = 0` the number of samples
    /// grows until the contour's tool position is within `tolerance` of the path everywhere
    /// (an error if [`MAX_SAMPLES`] are not enough).
    pub fn joint_path(&self, robot: &Robot, base_dir: &Path) -> Result<JointPath> {
        let path = self.path(base_dir)?;
        let tolerance = self.tolerance()?;
        let mut n = self.first_count()?;
        with_dof!(robot.dof(), N => {
            let chain = SerialChain::<f64, N>::try_from(robot.model())?;
            // The samples' arc lengths: evenly spaced, or, once MAX_SAMPLES evenly spaced are
            // not enough, placed by the joints' motion (at most PLACEMENTS times).
            let mut along: Vec<f64> = even(&path, n);
            let mut placements = 0;
            loop {
                let points: Vec<Vector3<f64>> = along.iter().map(|&s| path.point(s)).collect();
                let joints = self.solve::<N>(robot, &chain, &path, &points)?;
                let geometry = self.geometry::<N>(&chain, &path, &joints)?;
                if self.samples != 0 || geometry.max <= tolerance {
                    let waypoints = joints.iter().map(|q| q.as_slice().to_vec()).collect();
                    return Ok(JointPath { waypoints, geometry });
                }
                if n == MAX_SAMPLES && placements < PLACEMENTS {
                    along = by_joint_motion(&along, path.length(), &joints);
                    placements += 1;
                    continue;
                }
                if n == MAX_SAMPLES {
                    return Err(bad(format!(
                        "the joint contour stays {:.1} µm from the path with {MAX_SAMPLES} samples, more than the tolerance of {:.1} µm (raise tolerance)",
                        geometry.max * 1e6,
                        tolerance * 1e6
                    )));
                }
                // The largest distance falls as 1/n² where the path's curvature jumps (a
                // straight side meeting a rounded corner): aim there with 10 % to spare.
                let aim = (n as f64 * (geometry.max / tolerance).sqrt() * 1.1).ceil() as usize;
                n = aim.max(n + n / 4).min(MAX_SAMPLES);
                along = even(&path, n);
            }
        }, otherwise Err(bad("the robot has more joints than pvfc supports")))
    }

    /// How far the tool position of the joint contour through `waypoints` (forward kinematics
    /// at [`GEOMETRY_STEPS`] values of `τ` per waypoint) is from the path, and, for a path
    /// with an orientation, how far its orientation is from the path's.
    fn geometry<const N: usize>(
        &self,
        chain: &SerialChain<f64, N>,
        path: &ToolPath,
        waypoints: &[SVector<f64, N>],
    ) -> Result<ContourGeometry> {
        let spec = JointContourSpec::Waypoints {
            points: waypoints.iter().map(|q| q.as_slice().to_vec()).collect(),
            spacing: 1.0,
        };
        let contour = spec.build::<N>(chain.kinds())?;
        let m = waypoints.len() * GEOMETRY_STEPS;
        let poses: Vec<_> = (0..m)
            .map(|k| {
                let q = contour.sample(k as f64 / GEOMETRY_STEPS as f64).point;
                chain.tool_pose(q.coords())
            })
            .collect();
        let closest: Vec<_> = poses.iter().map(|p| path.closest(&p.translation)).collect();
        let law = self.orientation_law_on(path)?;
        let axis_only = matches!(law, Some(OrientationLaw::Frame(_)));
        let desired: Option<Vec<nalgebra::Matrix3<f64>>> = match (law, self.fixed_orientation) {
            (Some(law), _) => Some(closest.iter().map(|c| law.at(c.along).0).collect()),
            (None, true) => {
                let seed = SVector::<f64, N>::from_column_slice(&self.seed);
                Some(vec![chain.tool_pose(&seed).rotation; m])
            }
            (None, false) => None,
        };
        // The angle between the orientations, or between the axes for a tool frame.
        let angle = desired.map(|r| {
            poses
                .iter()
                .zip(&r)
                .map(|(p, r)| match axis_only {
                    true => p.rotation.column(2).angle(&r.column(2)),
                    false => {
                        let c = ((r.transpose() * p.rotation).trace() - 1.0) / 2.0;
                        c.clamp(-1.0, 1.0).acos()
                    }
                })
                .fold(0.0, f64::max)
        });
        Ok(ContourGeometry {
            samples: waypoints.len(),
            mean: closest.iter().map(|c| c.distance).sum::<f64>() / m as f64,
            max: closest.iter().map(|c| c.distance).fold(0.0, f64::max),
            max_angle: angle,
            length: path.length(),
        })
    }

    fn solve<const N: usize>(
        &self,
        robot: &Robot,
        chain: &SerialChain<f64, N>,
        path: &ToolPath,
        points: &[Vector3<f64>],
    ) -> Result<Vec<SVector<f64, N>>> {
        if self.seed.len() != N || !self.seed.iter().all(|x| x.is_finite()) {
            return Err(bad(format!("seed: {N} finite joint coordinates")));
        }
        let max_jump = self.max_jump.unwrap_or(0.6);
        let min_w = self.min_manipulability.unwrap_or(1e-4);
        let seed = SVector::<f64, N>::from_column_slice(&self.seed);
        let rotation = chain.tool_pose(&seed).rotation;
        let orientations = self.sampled_orientations_on(path, points)?;
        let axis_only = self.tool_frame.is_some();
        // A task of fewer coordinates than joints leaves a null space: without a rest posture
        // the solutions drift in it from waypoint to waypoint, and the joint contour through
        // them leaves the path between waypoints however many there are. The seed is then the
        // rest posture, so that the waypoints lie on one smooth branch.
        let task = match (&orientations, self.fixed_orientation) {
            (Some(_), _) if axis_only => 5,
            (Some(_), _) | (None, true) => 6,
            (None, false) => 3,
        };
        let rest = match &self.rest {
            None if N > task => Some((seed, self.rest_gain.unwrap_or(0.1))),
            None => None,
            Some(r) if r.len() == N && r.iter().all(|x| x.is_finite()) => {
                let gain = self.rest_gain.unwrap_or(0.1);
                if !(gain.is_finite() && gain > 0.0 && gain <= 1.0) {
                    return Err(bad("rest_gain: in (0, 1]"));
                }
                Some((SVector::<f64, N>::from_column_slice(r), gain))
            }
            Some(_) => return Err(bad(format!("rest: {N} finite joint coordinates"))),
        };
        let settings = IkSettings::<f64, N> {
            tolerance: 1e-7,
            max_iterations: 500,
            rest,
            ..IkSettings::default()
        };
        let names: Vec<&str> = robot
            .description()
            .joints
            .iter()
            .map(|j| j.name.as_str())
            .collect();
        let mut out: Vec<SVector<f64, N>> = Vec::with_capacity(points.len());
        let mut from = seed;
        for (index, p) in points.iter().enumerate() {
            let fail = |problem| SimError::Waypoint {
                index,
                point: [p.x, p.y, p.z],
                problem,
            };
            let target = match (&orientations, self.fixed_orientation) {
                (Some(r), _) if axis_only => IkTarget::Axis {
                    position: *p,
                    axis: r[index].column(2).into_owned(),
                },
                (Some(r), _) => IkTarget::Pose(pvfc_core::mechanics::Pose {
                    rotation: r[index],
                    translation: *p,
                }),
                (None, true) => IkTarget::Pose(pvfc_core::mechanics::Pose {
                    rotation,
                    translation: *p,
                }),
                (None, false) => IkTarget::Position(*p),
            };
            let q = chain
                .inverse_kinematics(&target, &from, &settings)
                .map_err(|e| fail(WaypointProblem::Unreachable(e.value().unwrap_or(f64::NAN))))?;
            let w = chain.manipulability(&q);
            if w < min_w {
                return Err(fail(WaypointProblem::Singular(w, min_w)));
            }
            for (i, j) in robot.description().joints.iter().enumerate() {
                if let (Some(lo), Some(hi)) = (j.limits.lower, j.limits.upper) {
                    if q[i] < lo || q[i] > hi {
                        return Err(fail(WaypointProblem::JointLimit {
                            joint: j.name.clone(),
                            value: q[i],
                            lower: lo,
                            upper: hi,
                        }));
                    }
                }
            }
            if let Some(prev) = out.last() {
                let d = q - prev;
                if d.amax() > max_jump {
                    return Err(fail(WaypointProblem::BranchJump {
                        joint: names.get(d.iamax()).unwrap_or(&"?").to_string(),
                        jump: d.amax(),
                        limit: max_jump,
                    }));
                }
            }
            out.push(q);
            from = q;
        }
        // The path is closed: the last waypoint must join the first without a jump.
        if let (Some(first), Some(last)) = (out.first(), out.last()) {
            let d = first - last;
            if d.amax() > max_jump {
                let p = points[0];
                return Err(SimError::Waypoint {
                    index: 0,
                    point: [p.x, p.y, p.z],
                    problem: WaypointProblem::BranchJump {
                        joint: names.get(d.iamax()).unwrap_or(&"?").to_string(),
                        jump: d.amax(),
                        limit: max_jump,
                    },
                });
            }
        }
        Ok(out)
    }
}

/// How many times the adaptive sampling places its samples by the joints' motion before it
/// gives up (each placement measured on the joints of the one before).
const PLACEMENTS: usize = 4;

/// `n` arc lengths evenly spaced along `path`, from its start.
fn even(path: &ToolPath, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| path.length() * k as f64 / n as f64)
        .collect()
}

/// The samples' arc lengths placed so that each interval of the closed path between two
/// samples has the same share of the path's length and of the joints' travel, half each: where
/// the joints move much for little of the path (the wrist turning the tool's axis round a tight
/// blend), the samples close up. `along` are the arc lengths the joints `q` were solved at
/// (increasing from 0, less than `length`); as many are returned, the first at 0.
fn by_joint_motion<const N: usize>(along: &[f64], length: f64, q: &[SVector<f64, N>]) -> Vec<f64> {
    let n = along.len();
    let next = |j: usize| if j + 1 < n { along[j + 1] } else { length };
    let travel: Vec<f64> = (0..n).map(|j| (q[(j + 1) % n] - q[j]).norm()).collect();
    let total: f64 = travel.iter().sum();
    let weight = |j: usize| {
        let share = (next(j) - along[j]) / length;
        if total > 0.0 {
            0.5 * share + 0.5 * travel[j] / total
        } else {
            share
        }
    };
    let mut out = Vec::with_capacity(n);
    let (mut j, mut before) = (0, 0.0);
    for k in 0..n {
        let aim = k as f64 / n as f64;
        while j + 1 < n && before + weight(j) < aim {
            before += weight(j);
            j += 1;
        }
        let w = weight(j);
        let f = if w > 0.0 {
            ((aim - before) / w).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(along[j] + f * (next(j) - along[j]));
    }
    out
}

/// The samples the adaptive sampling starts from.
const ADAPTIVE_START: usize = 32;

/// The default tolerance of the adaptive sampling: 10 µm.
pub const DEFAULT_TOLERANCE: f64 = 1e-5;

/// Values of `τ` per waypoint at which the joint contour's geometry is measured.
pub const GEOMETRY_STEPS: usize = 16;

/// The geometry part of a Cartesian path's error budget: how far the joint contour itself
/// (the forward kinematics of `x_d(τ)`) is from the path, before any tracking error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourGeometry {
    /// The number of joint waypoints.
    pub samples: usize,
    /// The mean distance (m) of the contour's tool position to the path.
    pub mean: f64,
    /// The largest distance (m).
    pub max: f64,
    /// The largest angle (rad) between the contour's tool orientation and the path's, for a
    /// path with an orientation (`orientations` or `fixed_orientation`); between the tool's
    /// axis and the path's, with a `tool_frame`.
    pub max_angle: Option<f64>,
    /// The path's length (m).
    pub length: f64,
}

/// A Cartesian path turned into joint waypoints, with its geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct JointPath {
    /// The joint waypoints, one row of joint coordinates each.
    pub waypoints: Vec<Vec<f64>>,
    /// How far the joint contour through them is from the path.
    pub geometry: ContourGeometry,
}

/// How closely a run's tool followed the Cartesian path: the distance from the tool to the
/// path (m), mean and largest over the samples given, and where the largest was.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathError {
    /// Mean distance (m).
    pub mean: f64,
    /// Largest distance (m).
    pub max: f64,
    /// The sample of the largest distance.
    pub worst: usize,
    /// Where along the path that happens: the arc length (m) from the path's first point to
    /// the path point closest to the worst sample.
    pub along: f64,
    /// The path's length (m, closed).
    pub length: f64,
}

impl CartesianSpec {
    /// The distance (m) of every tool position in `tool` to the path.
    pub fn distances(&self, base_dir: &Path, tool: &[Vector3<f64>]) -> Result<Vec<f64>> {
        let path = self.path(base_dir)?;
        Ok(tool.iter().map(|p| path.closest(p).distance).collect())
    }

    /// The distance of every tool position in `tool` to the path, summarised.
    pub fn path_error(&self, base_dir: &Path, tool: &[Vector3<f64>]) -> Result<PathError> {
        let path = self.path(base_dir)?;
        let closest: Vec<_> = tool.iter().map(|p| path.closest(p)).collect();
        Ok(PathError::of(&closest, path.length()))
    }
}

impl PathError {
    /// The summary of the closest path points `closest` of a run's tool positions, on a path
    /// of `length` (m).
    pub fn of(closest: &[Closest], length: f64) -> Self {
        let (worst, max) = closest
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |(wi, wm), (i, c)| {
                if c.distance > wm {
                    (i, c.distance)
                } else {
                    (wi, wm)
                }
            });
        PathError {
            mean: closest.iter().map(|c| c.distance).sum::<f64>() / closest.len().max(1) as f64,
            max,
            worst,
            along: closest.get(worst).map_or(0.0, |c| c.along),
            length,
        }
    }
}

impl CartesianSpec {
    /// The tool's orientation at each sampled point of a path with `orientations`
    /// ([`CornerOrientations`]: between the path's points closest to two neighbouring corners,
    /// the slerp of their orientations with the arc length) or a `tool_frame` ([`PathFrame`]).
    /// `None` without either. The path is read relative to the working directory.
    pub fn sampled_orientations(
        &self,
        samples: &[Vector3<f64>],
    ) -> Result<Option<Vec<nalgebra::Matrix3<f64>>>> {
        if self.orientations.is_empty() && self.tool_frame.is_none() {
            return Ok(None);
        }
        self.sampled_orientations_on(&self.path(Path::new("."))?, samples)
    }

    /// [`sampled_orientations`](Self::sampled_orientations) on the path already built.
    fn sampled_orientations_on(
        &self,
        path: &ToolPath,
        samples: &[Vector3<f64>],
    ) -> Result<Option<Vec<nalgebra::Matrix3<f64>>>> {
        Ok(self.orientation_law_on(path)?.map(|law| {
            samples
                .iter()
                .map(|x| law.at(path.closest(x).along).0)
                .collect()
        }))
    }

    /// How the tool's orientation follows `path`: the corners' `orientations`, the
    /// `tool_frame`, or neither (`None`; the orientation is then held with
    /// `fixed_orientation`, or free). An error for more than one of `orientations`,
    /// `tool_frame` and `fixed_orientation`.
    pub fn orientation_law_on(&self, path: &ToolPath) -> Result<Option<OrientationLaw>> {
        let given = [
            !self.orientations.is_empty(),
            self.tool_frame.is_some(),
            self.fixed_orientation,
        ];
        if given.iter().filter(|g| **g).count() > 1 {
            return Err(bad(
                "give one of orientations, tool_frame and fixed_orientation, not more",
            ));
        }
        if let Some(f) = &self.tool_frame {
            let rotation = match &self.part {
                Some(part) => part.isometry("contour.cartesian.part")?.rotation,
                None => nalgebra::UnitQuaternion::identity(),
            };
            let normal = rotation * Vector3::from(f.normal.unwrap_or([0.0, 0.0, 1.0]));
            let frame = PathFrame::new(path, normal, f.lead, f.tilt).map_err(bad)?;
            return Ok(Some(OrientationLaw::Frame(frame)));
        }
        if self.orientations.is_empty() {
            return Ok(None);
        }
        Ok(Some(OrientationLaw::Corners(
            self.corner_orientations_on(path)?,
        )))
    }

    /// The orientations at the corners, for a path with `orientations` (checked: one per
    /// point, finite, no half turn between neighbours).
    pub fn corner_orientations(&self) -> Result<CornerOrientations> {
        self.corner_orientations_on(&self.path(Path::new("."))?)
    }

    /// [`corner_orientations`](Self::corner_orientations) on the path already built.
    fn corner_orientations_on(&self, path: &ToolPath) -> Result<CornerOrientations> {
        let n = self.points.len();
        if self.orientations.len() != n || n == 0 {
            return Err(bad(format!(
                "orientations: one (roll, pitch, yaw) per point ({n}); only with points"
            )));
        }
        if !self.orientations.iter().flatten().all(|x| x.is_finite()) {
            return Err(bad("orientations must be finite"));
        }
        // Given in the part's frame: placed in the base frame as the path is.
        let part = match &self.part {
            Some(part) => part.isometry("contour.cartesian.part")?,
            None => nalgebra::Isometry3::identity(),
        };
        let corners: Vec<Vector3<f64>> = self
            .points
            .iter()
            .map(|p| part.transform_point(&(*p).into()).coords)
            .collect();
        let rotations: Vec<_> = self
            .orientations
            .iter()
            .map(|[r, p, y]| {
                part.rotation * nalgebra::UnitQuaternion::from_euler_angles(*r, *p, *y)
            })
            .collect();
        CornerOrientations::new(path, &corners, &rotations).map_err(bad)
    }
}

/// `path`, or an error when its geometry overflows.
fn finite(path: ToolPath) -> Result<ToolPath> {
    match path.is_finite() {
        true => Ok(path),
        false => Err(bad(
            "the path's geometry overflows (its length or a point is not a finite number): coordinates, radii and axes of a tool path are metres, far below 1e150",
        )),
    }
}

/// The closed path of a part program's cutting moves (in the part's frame).
fn part_program(file: &Path) -> Result<ToolPath> {
    let (program, named) = read_program(file)?;
    program.tool_path().map_err(named)
}

/// A part program read from `file`, and what names its errors by the file.
fn read_program(
    file: &Path,
) -> Result<(
    PartProgram,
    impl Fn(crate::model::gcode::ProgramError) -> SimError + '_,
)> {
    let text = std::fs::read_to_string(file).map_err(|e| SimError::Io {
        path: file.to_path_buf(),
        source: e,
    })?;
    let named = |e: crate::model::gcode::ProgramError| SimError::PartProgram {
        path: file.to_path_buf(),
        line: e.line,
        column: e.column,
        message: e.message,
    };
    Ok((PartProgram::parse(&text).map_err(named)?, named))
}

/// The circle or ellipse.
fn circle(c: &CircleSpec) -> Result<ToolPath> {
    let n = Vector3::from(c.normal);
    let positive = |x: f64| x.is_finite() && x > 0.0;
    let valid = positive(c.radius)
        && c.semi_minor.is_none_or(positive)
        && n.norm() > 0.0
        && c.center.iter().all(|x| x.is_finite());
    if !valid {
        return Err(bad(
            "circle: finite centre, radius > 0 (and semi_minor > 0), non-zero normal",
        ));
    }
    let n = n.normalize();
    let u = match c.major_axis {
        None => {
            let helper = if n.x.abs() < 0.9 {
                Vector3::x()
            } else {
                Vector3::y()
            };
            n.cross(&helper).normalize()
        }
        Some(m) => {
            let m = Vector3::from(m);
            let in_plane = m - n * n.dot(&m);
            if !(in_plane.iter().all(|x| x.is_finite()) && in_plane.norm() > 1e-9 * m.norm()) {
                return Err(bad("circle.major_axis: finite, and not along the normal"));
            }
            in_plane.normalize()
        }
    };
    let w = n.cross(&u);
    let center = Vector3::from(c.center);
    let b = c.semi_minor.unwrap_or(c.radius);
    Ok(ToolPath::ellipse(center, u * c.radius, w * b))
}

/// Points `x,y,z` from a CSV file (a first line that is not numbers is a header).
fn read_csv(path: &Path) -> Result<Vec<Vector3<f64>>> {
    let text = std::fs::read_to_string(path).map_err(|e| SimError::io(path, e))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let v: std::result::Result<Vec<f64>, _> =
            line.split(',').map(|x| x.trim().parse::<f64>()).collect();
        match v {
            Ok(v) if v.len() == 3 => out.push(Vector3::new(v[0], v[1], v[2])),
            Err(_) if i == 0 => continue,
            _ => {
                return Err(bad(format!(
                    "{}: line {}: expected x,y,z",
                    path.display(),
                    i + 1
                )))
            }
        }
    }
    Ok(out)
}
