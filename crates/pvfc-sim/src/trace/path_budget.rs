//! The error budget of a tool path: how far the contour itself is from the Cartesian path
//! (geometry), and how far the tool was from it in a run (tracking), split into the error
//! along the surface the path lies on and the offset normal to it.

use crate::error::Result;
use crate::model::cartesian::{ContourGeometry, PathError};
use crate::model::robot::Robot;
use crate::scenario::Scenario;
use crate::trace::Trace;
use nalgebra::Vector3;

/// Mean, 95th percentile and largest of a set of distances (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    /// The mean.
    pub mean: f64,
    /// The 95th percentile (nearest rank).
    pub p95: f64,
    /// The largest.
    pub max: f64,
}

impl Spread {
    /// The spread of `x` (zeros when empty).
    pub fn of(x: &[f64]) -> Self {
        if x.is_empty() {
            return Spread::default();
        }
        let mut sorted = x.to_vec();
        sorted.sort_by(f64::total_cmp);
        let rank = ((0.95 * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
        Spread {
            mean: x.iter().sum::<f64>() / x.len() as f64,
            p95: sorted[rank - 1],
            max: sorted[sorted.len() - 1],
        }
    }
}

/// The offset of the tool normal to the path's plane (m, signed along
/// [`ToolPath::normal`](crate::model::tool_path::ToolPath::normal)): in contact, the press-in
/// (or lift-off) that the force asks for, not an error along the path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalOffset {
    /// The mean offset.
    pub mean: f64,
    /// The smallest offset.
    pub min: f64,
    /// The largest offset.
    pub max: f64,
    /// The unit normal it is measured along.
    pub normal: Vector3<f64>,
}

/// The error budget of a run on a Cartesian path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathBudget {
    /// Geometry: the joint contour's own distance to the path; `None` when the controller
    /// follows the exact path (the task-space field, `[contour.cartesian.task]`).
    pub geometry: Option<ContourGeometry>,
    /// Tracking: the tool's 3-D distance to the path over the steady passes (every complete
    /// pass after the first; the last pass if there is only one), where the largest was.
    pub distance: PathError,
    /// The 3-D distance's spread.
    pub spread: Spread,
    /// The distance in the path's plane, i.e. along the surface the path lies on (`None` for a
    /// path that is not planar).
    pub surface: Option<Spread>,
    /// The offset normal to the path's plane (`None` for a path that is not planar).
    pub normal: Option<NormalOffset>,
    /// The time of the largest distance (s).
    pub when: f64,
    /// The tool's mean speed along the path (m/s): the progress of its closest point.
    pub speed: f64,
    /// The tool's mean speed (m/s): the length it travelled over the time.
    pub tool_speed: f64,
    /// The times (s) the tracking figures are taken over.
    pub window: (f64, f64),
}

/// The samples of the steady passes: `τ` from the start of the second pass the trace began in
/// to the end of the last complete pass; the last complete pass if that is empty. `None` if
/// the trace does not cover a pass.
pub fn steady_passes(trace: &Trace, period: f64) -> Option<std::ops::Range<usize>> {
    let (first, end) = (*trace.tau.first()?, *trace.tau.last()?);
    let last = (end / period).floor();
    let lo = ((first / period).floor() + 1.0).min(last - 1.0);
    if lo < (first / period).floor() {
        return None;
    }
    let start = trace.tau.iter().position(|&t| t >= lo * period)?;
    let stop = trace.tau.iter().position(|&t| t >= last * period)?;
    (stop > start).then_some(start..stop + 1)
}

/// The error budget of the run `t` of scenario `s` on `robot`; `None` for a contour not given
/// in Cartesian space or a run shorter than a pass.
pub fn path_budget(s: &Scenario, robot: &Robot, t: &Trace) -> Result<Option<PathBudget>> {
    let Some(c) = s.contour.cartesian() else {
        return Ok(None);
    };
    let Some(range) = steady_passes(t, s.period()) else {
        return Ok(None);
    };
    let path = c.path(&s.base_dir)?;
    // The task-space field follows the exact path; the timed tracker, the joint contour.
    let geometry = match c.task {
        Some(_) if !t.is_timed() => None,
        _ => Some(c.joint_path(robot, &s.base_dir)?.geometry),
    };
    let tool =
        t.q.rows(range.clone())
            .map(|q| robot.tool_pose(q).map(|(_, p)| p))
            .collect::<Result<Vec<_>>>()?;
    let closest: Vec<_> = tool.iter().map(|p| path.closest(p)).collect();
    let d: Vec<f64> = closest.iter().map(|c| c.distance).collect();
    let distance = PathError::of(&closest, path.length());
    let length = path.length();
    let (surface, normal) = match path.normal() {
        None => (None, None),
        Some(n) => {
            let off: Vec<f64> = tool
                .iter()
                .zip(&closest)
                .map(|(p, c)| (p - c.point).dot(&n))
                .collect();
            let lateral: Vec<f64> = tool
                .iter()
                .zip(&closest)
                .zip(&off)
                .map(|((p, c), o)| (p - c.point - n * *o).norm())
                .collect();
            (
                Some(Spread::of(&lateral)),
                Some(NormalOffset {
                    mean: off.iter().sum::<f64>() / off.len().max(1) as f64,
                    min: off.iter().cloned().fold(f64::INFINITY, f64::min),
                    max: off.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
                    normal: n,
                }),
            )
        }
    };
    // Progress along the path, each step wrapped into (−L/2, L/2].
    let progress: f64 = closest
        .windows(2)
        .map(|w| {
            let ds = w[1].along - w[0].along;
            ds - length * (ds / length).round()
        })
        .sum();
    let travelled: f64 = tool.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let (t0, t1) = (t.t[range.start], t.t[range.end - 1]);
    let duration = (t1 - t0).max(f64::MIN_POSITIVE);
    Ok(Some(PathBudget {
        geometry,
        distance,
        spread: Spread::of(&d),
        surface,
        normal,
        when: t.t[range.start + distance.worst],
        speed: progress / duration,
        tool_speed: travelled / duration,
        window: (t0, t1),
    }))
}

impl std::fmt::Display for PathBudget {
    /// One line in millimetres: geometry, then tracking along the surface, normal offset and
    /// in 3-D, then the speed.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mm = |x: f64| x * 1e3;
        match &self.geometry {
            Some(g) => {
                write!(
                    f,
                    "geometry: {} samples, contour {:.4} mm from the path at most (mean {:.4} mm)",
                    g.samples,
                    mm(g.max),
                    mm(g.mean)
                )?;
                if let Some(a) = g.max_angle {
                    write!(f, ", orientation {:.3} mrad at most", a * 1e3)?;
                }
            }
            None => write!(f, "geometry: the exact path (task-space field)")?,
        }
        write!(
            f,
            "; tracking over t = {:.1}–{:.1} s: ",
            self.window.0, self.window.1
        )?;
        if let Some(s) = &self.surface {
            write!(
                f,
                "along the surface mean {:.3} / p95 {:.3} / max {:.3} mm, ",
                mm(s.mean),
                mm(s.p95),
                mm(s.max)
            )?;
        }
        if let Some(n) = &self.normal {
            write!(
                f,
                "normal offset {:+.3} mm ({:+.3}…{:+.3}), ",
                mm(n.mean),
                mm(n.min),
                mm(n.max)
            )?;
        }
        write!(
            f,
            "3-D mean {:.3} / p95 {:.3} / max {:.3} mm ({:.0} mm along the {:.0} mm path at t = {:.2} s); speed along the path {:.0} mm/s",
            mm(self.spread.mean),
            mm(self.spread.p95),
            mm(self.spread.max),
            mm(self.distance.along),
            mm(self.distance.length),
            self.when,
            mm(self.speed)
        )
    }
}
