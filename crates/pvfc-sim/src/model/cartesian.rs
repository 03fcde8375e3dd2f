//! Tool paths given in Cartesian space (`[contour.cartesian]`): a closed curve of the tool's
//! position in the robot's base frame (a polyline with rounded corners, a circle or ellipse in any
//! plane, or the points of a CSV file), turned into joint waypoints by inverse kinematics
//! along the path. The joint contour is then the periodic spline through those waypoints
//! (`[contour] spacing`), as for a contour given in joint space.
//!
//! Why a joint-space contour and not a task-space field pulled back through the Jacobian:
//! the field, the navigation function and the coupling stay exactly those of the joint-space
//! arms (passivity is a property of the coupling and is untouched either way), the spline
//! gives `ξ_d` and `dξ_d/dτ` in closed form, and the inverse kinematics is done once, where
//! its failures (unreachable points, singularities, limits, branch jumps) can be reported by
//! waypoint before anything runs. The price is that the tool follows the Cartesian path only
//! at the waypoints and through the joint spline in between (the distance is reported).

use crate::error::{Result, SimError, WaypointProblem};
use crate::model::robot::Robot;
use crate::with_dof;
use nalgebra::{SVector, Vector3};
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
    /// How many joint waypoints the path is sampled into (equal arc length; 4 to 32).
    pub samples: usize,
    /// The joint posture the inverse kinematics starts from at the first waypoint.
    pub seed: Vec<f64>,
    /// Hold the tool's orientation at the seed's (else it is free).
    pub fixed_orientation: bool,
    /// The tool's orientation at each of `points` (roll, pitch, yaw in the base frame, URDF's
    /// convention), for a path in SE(3): between two corners the orientation turns at
    /// constant rate (slerp) with the position's progress along the sharp polyline. Empty:
    /// position only (with `fixed_orientation` or free).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub orientations: Vec<[f64; 3]>,
    /// A rest posture for redundant arms (7 joints): each inverse-kinematics iteration pulls
    /// towards it in the null space of the task, with `rest_gain`.
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
}

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
    /// The path sampled at `samples` points of equal arc length, starting at its first point.
    pub fn sample(&self, base_dir: &Path) -> Result<Vec<Vector3<f64>>> {
        if !(4..=MAX_SAMPLES).contains(&self.samples) {
            return Err(bad(format!("samples: 4 to {MAX_SAMPLES}")));
        }
        Ok(resample(&self.polyline(base_dir)?, self.samples))
    }

    /// The path as a dense closed polyline (m, base frame).
    pub fn polyline(&self, base_dir: &Path) -> Result<Vec<Vector3<f64>>> {
        Ok(match (&self.circle, &self.csv, self.points.is_empty()) {
            (Some(c), None, true) => circle(c)?,
            (None, Some(f), true) => polyline(&read_csv(&base_dir.join(f))?, self.corner_radius)?,
            (None, None, false) => polyline(
                &self
                    .points
                    .iter()
                    .map(|p| Vector3::from(*p))
                    .collect::<Vec<_>>(),
                self.corner_radius,
            )?,
            _ => return Err(bad("give exactly one of points, circle or csv")),
        })
    }

    /// The joint waypoints of the path for `robot`: inverse kinematics at every sample,
    /// warm-started from the previous one (the first from `seed`), each checked for reach,
    /// manipulability, joint limits and jumps; errors name the waypoint.
    pub fn joint_waypoints(&self, robot: &Robot, base_dir: &Path) -> Result<Vec<Vec<f64>>> {
        let points = self.sample(base_dir)?;
        with_dof!(robot.dof(), N => {
            let chain = SerialChain::<f64, N>::try_from(robot.model())?;
            self.solve::<N>(robot, &chain, &points)
        }, otherwise Err(bad("the robot has more joints than pvfc supports")))
    }

    fn solve<const N: usize>(
        &self,
        robot: &Robot,
        chain: &SerialChain<f64, N>,
        points: &[Vector3<f64>],
    ) -> Result<Vec<Vec<f64>>> {
        if self.seed.len() != N || !self.seed.iter().all(|x| x.is_finite()) {
            return Err(bad(format!("seed: {N} finite joint coordinates")));
        }
        let max_jump = self.max_jump.unwrap_or(0.6);
        let min_w = self.min_manipulability.unwrap_or(1e-4);
        let seed = SVector::<f64, N>::from_column_slice(&self.seed);
        let rotation = chain.tool_pose(&seed).rotation;
        let rest = match &self.rest {
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
        let orientations = self.sampled_orientations(points)?;
        if orientations.is_some() && self.fixed_orientation {
            return Err(bad("give orientations or fixed_orientation, not both"));
        }
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
        Ok(out.iter().map(|q| q.as_slice().to_vec()).collect())
    }
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
    /// The distance (m) of every tool position in `tool` to the path (its dense polyline).
    pub fn distances(&self, base_dir: &Path, tool: &[Vector3<f64>]) -> Result<Vec<f64>> {
        Ok(distances_to(&self.polyline(base_dir)?, tool))
    }

    /// The distance of every tool position in `tool` to the path, summarised.
    pub fn path_error(&self, base_dir: &Path, tool: &[Vector3<f64>]) -> Result<PathError> {
        let dense = self.polyline(base_dir)?;
        let d = distances_to(&dense, tool);
        let (worst, max) =
            d.iter().enumerate().fold(
                (0, 0.0f64),
                |(wi, wm), (i, x)| if *x > wm { (i, *x) } else { (wi, wm) },
            );
        // Where along the path: the arc length to the worst sample's closest path point.
        let n = dense.len();
        let (mut along, mut length, mut best) = (0.0, 0.0, f64::INFINITY);
        for i in 0..n {
            let (a, b) = (&dense[i], &dense[(i + 1) % n]);
            let segment = (b - a).norm();
            if let Some(p) = tool.get(worst) {
                let (t, dist) = closest_on_segment(p, a, b);
                if dist < best {
                    best = dist;
                    along = length + t * segment;
                }
            }
            length += segment;
        }
        Ok(PathError {
            mean: d.iter().sum::<f64>() / d.len().max(1) as f64,
            max,
            worst,
            along,
            length,
        })
    }
}

impl CartesianSpec {
    /// The tool's orientation at each sampled point of a path with `orientations`: the
    /// points' sharp polygon segment closest to the sample, and the slerp between its two
    /// corners' orientations at the sample's fraction along it. `None` without orientations.
    pub fn sampled_orientations(
        &self,
        samples: &[Vector3<f64>],
    ) -> Result<Option<Vec<nalgebra::Matrix3<f64>>>> {
        if self.orientations.is_empty() {
            return Ok(None);
        }
        let n = self.points.len();
        if self.orientations.len() != n || n == 0 {
            return Err(bad(format!(
                "orientations: one (roll, pitch, yaw) per point ({n}); only with points"
            )));
        }
        if !self.orientations.iter().flatten().all(|x| x.is_finite()) {
            return Err(bad("orientations must be finite"));
        }
        let corner = |i: usize| Vector3::from(self.points[i % n]);
        let rot = |i: usize| {
            let [r, p, y] = self.orientations[i % n];
            nalgebra::UnitQuaternion::from_euler_angles(r, p, y)
        };
        samples
            .iter()
            .map(|x| {
                let (i, t, _) = (0..n)
                    .map(|i| {
                        let (t, d) = closest_on_segment(x, &corner(i), &corner(i + 1));
                        (i, t, d)
                    })
                    .fold((0, 0.0, f64::INFINITY), |a, b| if b.2 < a.2 { b } else { a });
                // The shorter way round; half a turn (quaternions orthogonal) has two
                // equally short ways and is an error.
                let (a, b) = (rot(i), rot(i + 1));
                let half_turn = || {
                    bad(format!(
                        "orientations: points {i} and {} differ by half a turn (no unique way between them)",
                        (i + 1) % n
                    ))
                };
                if a.coords.dot(&b.coords).abs() < 1e-6 {
                    return Err(half_turn());
                }
                a.try_slerp(&b, t, 1e-9)
                    .map(|q| q.to_rotation_matrix().into_inner())
                    .ok_or_else(half_turn)
            })
            .collect::<Result<Vec<_>>>()
            .map(Some)
    }
}

/// The distance of every point of `tool` to the closed polyline `dense`.
fn distances_to(dense: &[Vector3<f64>], tool: &[Vector3<f64>]) -> Vec<f64> {
    let n = dense.len();
    let dist = |p: &Vector3<f64>| {
        (0..n)
            .map(|i| segment_distance(p, &dense[i], &dense[(i + 1) % n]))
            .fold(f64::INFINITY, f64::min)
    };
    tool.iter().map(dist).collect()
}

/// The distance from `p` to the segment `ab`.
fn segment_distance(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    closest_on_segment(p, a, b).1
}

/// The closest point of segment `ab` to `p`, as its fraction `t ∈ [0, 1]` along `ab`, and the
/// distance to it.
fn closest_on_segment(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> (f64, f64) {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (t, (p - (a + ab * t)).norm())
}

/// A dense closed polyline of the circle or ellipse (256 points, equal angles).
fn circle(c: &CircleSpec) -> Result<Vec<Vector3<f64>>> {
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
    Ok((0..256)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 256.0;
            match c.semi_minor {
                None => center + (u * a.cos() + w * a.sin()) * c.radius,
                Some(b) => center + u * (a.cos() * c.radius) + w * (a.sin() * b),
            }
        })
        .collect())
}

/// A dense closed polyline through `corners`, each corner rounded by a circular arc of
/// `radius` (the tangent length clipped to half the shorter neighbouring segment).
fn polyline(corners: &[Vector3<f64>], radius: f64) -> Result<Vec<Vector3<f64>>> {
    let n = corners.len();
    if n < 3 {
        return Err(bad("points: at least 3"));
    }
    let finite = corners.iter().all(|p| p.iter().all(|x| x.is_finite()));
    if !(finite && radius.is_finite() && radius >= 0.0) {
        return Err(bad("points and corner_radius must be finite (radius ≥ 0)"));
    }
    let mut out = Vec::new();
    for i in 0..n {
        let (prev, here, next) = (corners[(i + n - 1) % n], corners[i], corners[(i + 1) % n]);
        let (la, lb) = ((here - prev).norm(), (next - here).norm());
        if la == 0.0 || lb == 0.0 {
            return Err(bad(format!("points: point {i} repeats its neighbour")));
        }
        let (a, b) = ((here - prev) / la, (next - here) / lb);
        let turn = a.dot(&b).clamp(-1.0, 1.0).acos();
        let tangent = (radius * (turn / 2.0).tan()).min(0.5 * la.min(lb));
        if radius == 0.0 || turn < 1e-6 || tangent <= 0.0 {
            out.push(here);
            continue;
        }
        // The arc from here − a·t to here + b·t, tangent to both segments.
        let (start, end) = (here - a * tangent, here + b * tangent);
        let r = tangent / (turn / 2.0).tan();
        let inward = (b - a).normalize();
        let center = here + inward * (r / (turn / 2.0).cos());
        let s0 = start - center;
        let axis = s0.cross(&(end - center));
        let axis = if axis.norm() > 0.0 {
            axis.normalize()
        } else {
            a.cross(&b).normalize()
        };
        for k in 0..=16 {
            let ang = turn * k as f64 / 16.0;
            let rot =
                nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_unchecked(axis), ang);
            out.push(center + rot * s0);
        }
    }
    // Densify the straight pieces.
    let mut dense = Vec::with_capacity(out.len() * 8);
    for i in 0..out.len() {
        let (p, q) = (out[i], out[(i + 1) % out.len()]);
        for k in 0..8 {
            dense.push(p + (q - p) * (k as f64 / 8.0));
        }
    }
    Ok(dense)
}

/// `m` points at equal arc length along the closed polyline `dense`, from its first point.
fn resample(dense: &[Vector3<f64>], m: usize) -> Vec<Vector3<f64>> {
    let n = dense.len();
    let mut cum = Vec::with_capacity(n + 1);
    cum.push(0.0);
    for i in 0..n {
        let d = (dense[(i + 1) % n] - dense[i]).norm();
        cum.push(cum[i] + d);
    }
    let total = cum[n];
    let mut out = Vec::with_capacity(m);
    let mut seg = 0;
    for k in 0..m {
        let s = total * k as f64 / m as f64;
        while seg + 1 < n && cum[seg + 1] < s {
            seg += 1;
        }
        let len = cum[seg + 1] - cum[seg];
        let f = if len > 0.0 { (s - cum[seg]) / len } else { 0.0 };
        out.push(dense[seg] + (dense[(seg + 1) % n] - dense[seg]) * f);
    }
    out
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
