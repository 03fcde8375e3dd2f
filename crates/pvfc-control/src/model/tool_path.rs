//! The exact geometry of a closed tool path: straight pieces, circular arcs (rounded corners,
//! circles) and ellipses, parameterised by arc length. It gives a point at any arc length
//! (what the inverse kinematics is sampled from) and the exact closest point of the path to
//! any point (what the tool's error is measured against), so that neither the samples nor the
//! measured distances carry a chord's error.

use nalgebra::{Isometry3, Unit, UnitQuaternion, Vector3};

/// One move of a path given move by move ([`ToolPath::from_segments`]), from where the move
/// before ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// A straight move to `to`.
    Line {
        /// Where it ends (m).
        to: Vector3<f64>,
    },
    /// A circular arc to `to` about `center`, turning right-handed about `axis` (a clockwise
    /// arc seen from the plane's normal turns about the negative normal).
    Arc {
        /// Where it ends (m).
        to: Vector3<f64>,
        /// The arc's centre (m).
        center: Vector3<f64>,
        /// The axis it turns about (right-handed).
        axis: Unit<Vector3<f64>>,
    },
}

/// Why a path given move by move cannot be built: the move (its index) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentError {
    /// The move's index in the list.
    pub index: usize,
    /// What is wrong with it.
    pub what: String,
}

/// One piece of a closed path.
#[derive(Clone, Debug, PartialEq)]
enum Piece {
    /// The segment from `a` to `b`.
    Line { a: Vector3<f64>, b: Vector3<f64> },
    /// The arc about `center` from `center + start`, turning by `angle` (rad, > 0) about
    /// `axis` (right-handed).
    Arc {
        center: Vector3<f64>,
        start: Vector3<f64>,
        axis: Unit<Vector3<f64>>,
        angle: f64,
    },
    /// The whole ellipse `center + u cos θ + w sin θ` (`u ⟂ w`), with its arc length tabulated
    /// at `TABLE + 1` equal steps of `θ`.
    Ellipse {
        center: Vector3<f64>,
        u: Vector3<f64>,
        w: Vector3<f64>,
        table: Vec<f64>,
    },
}

/// Steps of `θ` in an ellipse's arc-length table.
const TABLE: usize = 4096;

impl Piece {
    fn length(&self) -> f64 {
        match self {
            Piece::Line { a, b } => (b - a).norm(),
            Piece::Arc { start, angle, .. } => start.norm() * angle,
            Piece::Ellipse { table, .. } => table[TABLE],
        }
    }

    /// The point, the unit tangent and the curvature vector (`d²x/ds²`) at arc length
    /// `s ∈ [0, length]` along the piece.
    fn at(&self, s: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        match self {
            Piece::Line { a, b } => {
                let l = (b - a).norm();
                let t = (b - a) / l;
                // NaN-safe (a clamp panics on a NaN bound): a path is checked finite when built.
                (a + t * s.max(0.0).min(l), t, Vector3::zeros())
            }
            Piece::Arc {
                center,
                start,
                axis,
                ..
            } => {
                let radius = start.norm();
                let r = UnitQuaternion::from_axis_angle(axis, s / radius);
                let v = r * start;
                (
                    center + v,
                    axis.cross(&v).normalize(),
                    -v / (radius * radius),
                )
            }
            Piece::Ellipse {
                center,
                u,
                w,
                table,
                ..
            } => {
                let theta = ellipse_angle(table, u, w, s);
                let (sn, cs) = theta.sin_cos();
                // x' and x'' in θ; by arc length, d²x/ds² = (x'' − (x'·x''/|x'|²) x')/|x'|².
                let (d1, d2) = (w * cs - u * sn, -(u * cs + w * sn));
                let speed2 = d1.norm_squared();
                (
                    center + u * cs + w * sn,
                    d1 / speed2.sqrt(),
                    (d2 - d1 * (d1.dot(&d2) / speed2)) / speed2,
                )
            }
        }
    }

    /// The closest point of the piece to `p`: its arc length along the piece and the point.
    fn closest(&self, p: &Vector3<f64>) -> (f64, Vector3<f64>) {
        match self {
            Piece::Line { a, b } => {
                let ab = b - a;
                let l = ab.norm();
                let t = ((p - a).dot(&ab) / (l * l)).clamp(0.0, 1.0);
                (t * l, a + ab * t)
            }
            Piece::Arc {
                center,
                start,
                axis,
                angle,
            } => {
                let r = start.norm();
                let x = start / r;
                let y = axis.cross(&x);
                let d = p - center;
                let phi = d.dot(&y).atan2(d.dot(&x)).rem_euclid(std::f64::consts::TAU);
                let phi = if phi <= *angle {
                    phi
                } else {
                    // Outside the arc's angles: the nearer end (in angle, both ways round).
                    let past_end = phi - angle;
                    let before_start = std::f64::consts::TAU - phi;
                    if past_end < before_start {
                        *angle
                    } else {
                        0.0
                    }
                };
                (r * phi, self.at(r * phi).0)
            }
            Piece::Ellipse {
                center,
                u,
                w,
                table,
            } => {
                let d = p - center;
                // The best of 64 angles, then Newton on f(θ) = (x(θ) − p)·x'(θ).
                let at = |t: f64| center + u * t.cos() + w * t.sin();
                let mut theta = (0..64)
                    .map(|k| std::f64::consts::TAU * k as f64 / 64.0)
                    .min_by(|a, b| (at(*a) - p).norm().total_cmp(&(at(*b) - p).norm()))
                    .unwrap_or(0.0);
                for _ in 0..30 {
                    let (sn, cs) = theta.sin_cos();
                    let x = u * cs + w * sn - d;
                    let dx = w * cs - u * sn;
                    let ddx = -(u * cs + w * sn);
                    let f = x.dot(&dx);
                    let df = dx.dot(&dx) + x.dot(&ddx);
                    if df.abs() < f64::MIN_POSITIVE {
                        break;
                    }
                    let step = (f / df).clamp(-0.2, 0.2);
                    theta -= step;
                    if step.abs() < 1e-15 {
                        break;
                    }
                }
                let theta = theta.rem_euclid(std::f64::consts::TAU);
                (ellipse_length(table, u, w, theta), at(theta))
            }
        }
    }
}

/// The arc length of an ellipse from `θ = 0` to `theta ∈ [0, 2π)`: its table to the step
/// below, then Simpson's rule over the rest.
fn ellipse_length(table: &[f64], u: &Vector3<f64>, w: &Vector3<f64>, theta: f64) -> f64 {
    let step = std::f64::consts::TAU / TABLE as f64;
    let k = ((theta / step).floor() as usize).min(TABLE - 1);
    let t0 = k as f64 * step;
    let speed = |t: f64| (w * t.cos() - u * t.sin()).norm();
    let mid = 0.5 * (t0 + theta);
    table[k] + (theta - t0) / 6.0 * (speed(t0) + 4.0 * speed(mid) + speed(theta))
}

/// The angle `θ` of an ellipse at arc length `s`: the table's interval, then Newton on
/// `L(θ) = s` with `L' = |x'(θ)|`.
fn ellipse_angle(table: &[f64], u: &Vector3<f64>, w: &Vector3<f64>, s: f64) -> f64 {
    let s = s.max(0.0).min(table[TABLE]);
    let k = table.partition_point(|&x| x <= s).clamp(1, TABLE) - 1;
    let step = std::f64::consts::TAU / TABLE as f64;
    let frac = (s - table[k]) / (table[k + 1] - table[k]).max(f64::MIN_POSITIVE);
    let mut theta = (k as f64 + frac) * step;
    // Newton on the arc length (Simpson's rule within the step).
    let speed = |t: f64| (w * t.cos() - u * t.sin()).norm();
    for _ in 0..3 {
        let l = ellipse_length(table, u, w, theta.clamp(0.0, std::f64::consts::TAU));
        theta -= (l - s) / speed(theta).max(f64::MIN_POSITIVE);
    }
    theta
}

/// Where a point is closest to a path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// The arc length (m) from the path's start to the closest point.
    pub along: f64,
    /// The closest point of the path.
    pub point: Vector3<f64>,
    /// The distance (m).
    pub distance: f64,
}

/// A closed tool path with its exact geometry, parameterised by arc length from its start.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolPath {
    pieces: Vec<Piece>,
    /// Arc length at the start of each piece, and the total last.
    starts: Vec<f64>,
    /// The unit normal of the path's plane (Newell's normal: right-handed with the path's
    /// direction), `None` if the path is not planar.
    normal: Option<Vector3<f64>>,
}

/// The circular arc that rounds the corner `here` between the unit directions `a` (in) and
/// `b` (out), which turn by `turn` (rad), with tangents of length `tangent` along each: its
/// centre and the axis it turns about (right-handed). The arc runs from `here − a·tangent` to
/// `here + b·tangent`, its radius `tangent / tan(turn/2)`.
pub(crate) fn corner_arc(
    here: Vector3<f64>,
    a: Vector3<f64>,
    b: Vector3<f64>,
    turn: f64,
    tangent: f64,
) -> (Vector3<f64>, Unit<Vector3<f64>>) {
    let r = tangent / (turn / 2.0).tan();
    let center = here + (b - a).normalize() * (r / (turn / 2.0).cos());
    (center, Unit::new_normalize(a.cross(&b)))
}

/// The angle an arc turns right-handed about `axis` from `s` to `e` (both from its centre), in
/// (0, 2π]: an arc that ends where it starts (`closed`) is a whole circle.
pub(crate) fn arc_sweep(
    s: Vector3<f64>,
    e: Vector3<f64>,
    axis: &Vector3<f64>,
    closed: bool,
) -> f64 {
    let turn = s.cross(&e).dot(axis).atan2(s.dot(&e));
    if closed {
        std::f64::consts::TAU
    } else if turn <= 0.0 {
        turn + std::f64::consts::TAU
    } else {
        turn
    }
}

impl ToolPath {
    fn from_pieces(pieces: Vec<Piece>) -> Self {
        let mut starts = Vec::with_capacity(pieces.len() + 1);
        let mut s = 0.0;
        for p in &pieces {
            starts.push(s);
            s += p.length();
        }
        starts.push(s);
        let mut path = ToolPath {
            pieces,
            starts,
            normal: None,
        };
        path.normal = path.plane_normal();
        path
    }

    /// A closed polyline through `corners`, each corner rounded by a circular arc of `radius`
    /// (its tangent length clipped to half the shorter neighbouring side). The path starts at
    /// the first corner (or, if it is rounded, where its arc ends).
    pub fn rounded_polygon(corners: &[Vector3<f64>], radius: f64) -> Result<Self, String> {
        let n = corners.len();
        if n < 3 {
            return Err("points: at least 3".into());
        }
        let finite = corners.iter().all(|p| p.iter().all(|x| x.is_finite()));
        if !(finite && radius.is_finite() && radius >= 0.0) {
            return Err("points and corner_radius must be finite (radius ≥ 0)".into());
        }
        // Each corner: where its arc starts and ends (equal to the corner when sharp), and
        // the arc between.
        let mut ends = Vec::with_capacity(n);
        for i in 0..n {
            let (prev, here, next) = (corners[(i + n - 1) % n], corners[i], corners[(i + 1) % n]);
            let (la, lb) = ((here - prev).norm(), (next - here).norm());
            if la == 0.0 || lb == 0.0 {
                return Err(format!("points: point {i} repeats its neighbour"));
            }
            let (a, b) = ((here - prev) / la, (next - here) / lb);
            let turn = a.dot(&b).clamp(-1.0, 1.0).acos();
            let tangent = (radius * (turn / 2.0).tan()).min(0.5 * la.min(lb));
            if radius == 0.0 || turn < 1e-6 || tangent <= 0.0 || turn > std::f64::consts::PI - 1e-6
            {
                ends.push((here, here, None));
                continue;
            }
            let (start, end) = (here - a * tangent, here + b * tangent);
            let (center, axis) = corner_arc(here, a, b, turn, tangent);
            let arc = Piece::Arc {
                center,
                start: start - center,
                axis,
                angle: turn,
            };
            ends.push((start, end, Some(arc)));
        }
        // From the first corner's arc (where the path starts), then its side to the next.
        let mut pieces = Vec::with_capacity(2 * n);
        for i in 0..n {
            let (_, end, arc) = &ends[i];
            if let Some(arc) = arc {
                pieces.push(arc.clone());
            }
            let next_start = ends[(i + 1) % n].0;
            if (next_start - end).norm() > 0.0 {
                pieces.push(Piece::Line {
                    a: *end,
                    b: next_start,
                });
            }
        }
        Ok(Self::from_pieces(pieces))
    }

    /// The ellipse `center + u cos θ + w sin θ` (`u`, `w` perpendicular; a circle when of equal
    /// length), starting at `center + u`.
    pub fn ellipse(center: Vector3<f64>, u: Vector3<f64>, w: Vector3<f64>) -> Self {
        if (u.norm() - w.norm()).abs() <= 1e-12 * u.norm() {
            let axis = Unit::new_normalize(u.cross(&w));
            return Self::from_pieces(vec![Piece::Arc {
                center,
                start: u,
                axis,
                angle: std::f64::consts::TAU,
            }]);
        }
        // Arc length by Simpson's rule on each of TABLE steps.
        let speed = |t: f64| (w * t.cos() - u * t.sin()).norm();
        let step = std::f64::consts::TAU / TABLE as f64;
        let mut table = Vec::with_capacity(TABLE + 1);
        table.push(0.0);
        for k in 0..TABLE {
            let t0 = k as f64 * step;
            let l = step / 6.0 * (speed(t0) + 4.0 * speed(t0 + 0.5 * step) + speed(t0 + step));
            table.push(table[k] + l);
        }
        Self::from_pieces(vec![Piece::Ellipse {
            center,
            u,
            w,
            table,
        }])
    }

    /// A closed path given move by move from `start` (a part program's cutting moves, see
    /// [`gcode`](super::gcode)): each segment starts where the one before ended. An arc's
    /// radius at its end may differ from its radius at its start by `tolerance` (m; a part
    /// program's rounded centre); it is then drawn with its start radius, and the next move
    /// starts where it ends. The last move must end within `tolerance` of `start`.
    pub fn from_segments(
        start: Vector3<f64>,
        segments: &[Segment],
        tolerance: f64,
    ) -> Result<Self, SegmentError> {
        if segments.is_empty() {
            return Err(SegmentError {
                index: 0,
                what: "no move".into(),
            });
        }
        let mut pieces = Vec::with_capacity(segments.len());
        let mut at = start;
        for (index, segment) in segments.iter().enumerate() {
            let err = |what: String| SegmentError { index, what };
            match *segment {
                Segment::Line { to } => {
                    // The last line closes the path exactly.
                    let to = if index + 1 == segments.len() && (to - start).norm() <= tolerance {
                        start
                    } else {
                        to
                    };
                    if (to - at).norm() <= tolerance {
                        return Err(err("a straight move of zero length".into()));
                    }
                    pieces.push(Piece::Line { a: at, b: to });
                    at = to;
                }
                Segment::Arc { to, center, axis } => {
                    let (s, e) = (at - center, to - center);
                    let climb = (to - at).dot(&axis);
                    if climb.abs() > tolerance {
                        return Err(err(format!(
                            "a helical arc (it climbs {climb:.3e} m along its axis): only arcs in their plane are supported"
                        )));
                    }
                    if s.dot(&axis).abs() > tolerance {
                        return Err(err("the arc's centre is not in its plane".into()));
                    }
                    let (rs, re) = (s.norm(), e.norm());
                    if rs <= tolerance {
                        return Err(err("an arc of zero radius".into()));
                    }
                    if (rs - re).abs() > tolerance {
                        return Err(err(format!(
                            "the arc's radius is {rs:.6} m at its start and {re:.6} m at its end"
                        )));
                    }
                    let angle = arc_sweep(s, e, &axis, (to - at).norm() <= tolerance);
                    let piece = Piece::Arc {
                        center,
                        start: s,
                        axis,
                        angle,
                    };
                    at = piece.at(piece.length()).0;
                    pieces.push(piece);
                }
            }
        }
        let gap = (at - start).norm();
        if gap > tolerance {
            return Err(SegmentError {
                index: segments.len() - 1,
                what: format!("the path does not close: its last move ends {gap:.6} m from where the first starts"),
            });
        }
        let path = Self::from_pieces(pieces);
        match path.is_finite() {
            true => Ok(path),
            false => Err(SegmentError {
                index: 0,
                what: "the path's geometry overflows (not finite)".into(),
            }),
        }
    }

    /// The same path moved rigidly by `pose` (a part's path given in the part's frame, placed
    /// in the base frame).
    pub fn transformed(&self, pose: &Isometry3<f64>) -> Self {
        let (p, r) = (
            |x: &Vector3<f64>| pose.transform_point(&(*x).into()).coords,
            pose.rotation,
        );
        let pieces = self
            .pieces
            .iter()
            .map(|piece| match piece {
                Piece::Line { a, b } => Piece::Line { a: p(a), b: p(b) },
                Piece::Arc {
                    center,
                    start,
                    axis,
                    angle,
                } => Piece::Arc {
                    center: p(center),
                    start: r * start,
                    axis: Unit::new_unchecked(r * axis.into_inner()),
                    angle: *angle,
                },
                Piece::Ellipse {
                    center,
                    u,
                    w,
                    table,
                } => Piece::Ellipse {
                    center: p(center),
                    u: r * u,
                    w: r * w,
                    table: table.clone(),
                },
            })
            .collect();
        Self::from_pieces(pieces)
    }

    /// Whether every piece's points, directions and the length are finite numbers (a path of
    /// finite corners can overflow: corners 1e308 apart).
    pub fn is_finite(&self) -> bool {
        let v = |x: &Vector3<f64>| x.iter().all(|c| c.is_finite());
        let length = self.length();
        length.is_finite()
            && length > 0.0
            && self.pieces.iter().all(|p| match p {
                Piece::Line { a, b } => v(a) && v(b),
                Piece::Arc {
                    center,
                    start,
                    axis,
                    angle,
                } => v(center) && v(start) && v(axis) && angle.is_finite(),
                Piece::Ellipse {
                    center,
                    u,
                    w,
                    table,
                    ..
                } => v(center) && v(u) && v(w) && table.iter().all(|x| x.is_finite()),
            })
    }

    /// The arc length (m) at the start of each piece (a line, an arc), then the path's length:
    /// one more entry than there are pieces.
    pub fn piece_starts(&self) -> &[f64] {
        &self.starts
    }

    /// The path's length (m).
    pub fn length(&self) -> f64 {
        self.starts[self.pieces.len()]
    }

    /// The unit normal of the path's plane, right-handed with its direction; `None` if the
    /// path is not planar (within 1 µm).
    pub fn normal(&self) -> Option<Vector3<f64>> {
        self.normal
    }

    fn piece_at(&self, s: f64) -> (usize, f64) {
        let s = s.rem_euclid(self.length());
        let k = self
            .starts
            .partition_point(|&x| x <= s)
            .min(self.pieces.len())
            .max(1)
            - 1;
        (k, s - self.starts[k])
    }

    /// The point at arc length `s` (m, modulo the length) from the start.
    pub fn point(&self, s: f64) -> Vector3<f64> {
        let (k, r) = self.piece_at(s);
        self.pieces[k].at(r).0
    }

    /// The unit tangent at arc length `s`.
    pub fn tangent(&self, s: f64) -> Vector3<f64> {
        let (k, r) = self.piece_at(s);
        self.pieces[k].at(r).1
    }

    /// The point, unit tangent and curvature vector `d²x/ds²` at arc length `s`.
    pub fn frame(&self, s: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let (k, r) = self.piece_at(s);
        self.pieces[k].at(r)
    }

    /// `m` points at equal arc length, from the start.
    pub fn sample(&self, m: usize) -> Vec<Vector3<f64>> {
        (0..m)
            .map(|k| self.point(self.length() * k as f64 / m as f64))
            .collect()
    }

    /// The closest point of the path to `p`.
    pub fn closest(&self, p: &Vector3<f64>) -> Closest {
        let mut best = Closest {
            along: 0.0,
            point: self.point(0.0),
            distance: f64::INFINITY,
        };
        for (k, piece) in self.pieces.iter().enumerate() {
            let (s, q) = piece.closest(p);
            let d = (p - q).norm();
            if d < best.distance {
                best = Closest {
                    along: self.starts[k] + s,
                    point: q,
                    distance: d,
                };
            }
        }
        best
    }

    /// Newell's normal of points along the path, if every point lies within 1 µm of the plane.
    fn plane_normal(&self) -> Option<Vector3<f64>> {
        let pts = self.sample(256);
        let centroid = pts.iter().sum::<Vector3<f64>>() / pts.len() as f64;
        let mut n = Vector3::zeros();
        for i in 0..pts.len() {
            let (a, b) = (pts[i] - centroid, pts[(i + 1) % pts.len()] - centroid);
            n += a.cross(&b);
        }
        let n = n.try_normalize(f64::MIN_POSITIVE)?;
        let flat = self
            .pieces
            .iter()
            .flat_map(|p| {
                let l = p.length();
                (0..=8).map(move |k| p.at(l * k as f64 / 8.0).0)
            })
            .all(|p| (p - centroid).dot(&n).abs() < 1e-6);
        flat.then_some(n)
    }
}

/// A closed tool path as a contour on `ℝ³` for the task-space field: the exact path (no
/// samples, no spline) traced at constant speed, one pass every `period` of `τ`, so that
/// `p_d(τ)` is the point at arc length `s = τ L / period`, `p_d' = t L / period` and
/// `p_d'' = κ (L / period)²` (`t` the unit tangent, `κ` the curvature vector). The path is
/// C¹: its curvature jumps where a straight side meets an arc, so the field's rate jumps there
/// too (the coupling needs the rate, not its continuity). Evaluating it finds the piece by
/// bisection: it costs the same for any path and allocates nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct PathContour {
    path: ToolPath,
    period: f64,
}

impl PathContour {
    /// `path` traced once every `period` (> 0) of `τ`.
    pub fn new(path: ToolPath, period: f64) -> Result<Self, String> {
        if !(period.is_finite() && period > 0.0) {
            return Err(format!(
                "the pass's period must be finite and > 0, got {period}"
            ));
        }
        Ok(PathContour { path, period })
    }

    /// The path.
    pub fn path(&self) -> &ToolPath {
        &self.path
    }
}

impl pvfc_core::contour::Contour<f64, pvfc_core::lie::Rn<f64, 3>, 3> for PathContour {
    fn sample(
        &self,
        tau: f64,
    ) -> pvfc_core::contour::ContourSample<f64, pvfc_core::lie::Rn<f64, 3>, 3> {
        let speed = self.path.length() / self.period;
        let (p, t, k) = self.path.frame(tau * speed);
        pvfc_core::contour::ContourSample {
            point: pvfc_core::lie::Rn::new(p),
            velocity: t * speed,
            acceleration: k * (speed * speed),
        }
    }

    fn period(&self) -> Option<f64> {
        Some(self.period)
    }
}
