//! The tool's speed on each stretch of a part program's path against the feed (F) asked for
//! there: over the run's steady passes, the progress of the tool's closest point on the path
//! and the time it took, stretch by stretch.

use crate::error::Result;
use crate::model::robot::Robot;
use crate::scenario::Scenario;
use crate::trace::path_budget::steady_passes;
use crate::trace::Trace;

/// The speed on one stretch of the path (one cutting move of the program).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StretchSpeed {
    /// Where the stretch starts and ends along the path (m).
    pub span: (f64, f64),
    /// The speed asked for (m/s): the move's feed.
    pub asked: f64,
    /// The mean speed along the path over the stretch (m/s): its progress over its time.
    pub mean: f64,
    /// The median of the speed between samples on the stretch (m/s): the speed held there,
    /// less the changes of speed at its ends.
    pub median: f64,
}

impl StretchSpeed {
    /// The median speed over the speed asked for, less 1.
    pub fn error(&self) -> f64 {
        self.median / self.asked - 1.0
    }
}

/// The speed on each stretch of the run `t` of `s` (its robot `robot`), for a contour whose
/// part program has feeds; `None` otherwise, or for a run shorter than a pass. A stretch the
/// tool crossed between two samples has no speed of its own and is left out.
pub fn feed_speeds(s: &Scenario, robot: &Robot, t: &Trace) -> Result<Option<Vec<StretchSpeed>>> {
    let Some(c) = s.contour.cartesian() else {
        return Ok(None);
    };
    let fallback = s.controller.pace.as_ref().and_then(|p| p.speed);
    let Some(feeds) = c.feeds(&s.base_dir, fallback)? else {
        return Ok(None);
    };
    let Some(range) = steady_passes(t, s.period()) else {
        return Ok(None);
    };
    let path = feeds.path();
    let length = path.length();
    let along =
        t.q.rows(range.clone())
            .map(|q| robot.tool_pose(q).map(|(_, p)| path.closest(&p).along))
            .collect::<Result<Vec<_>>>()?;
    let stretches: Vec<_> = feeds.stretches().collect();
    let mut samples: Vec<Vec<(f64, f64)>> = vec![Vec::new(); stretches.len()];
    for (k, w) in along.windows(2).enumerate() {
        let ds = w[1] - w[0];
        let ds = ds - length * (ds / length).round();
        let dt = t.t[range.start + k + 1] - t.t[range.start + k];
        samples[feeds.stretch_at(w[0] + ds / 2.0)].push((ds, dt));
    }
    Ok(Some(
        stretches
            .iter()
            .zip(&samples)
            .filter(|(_, x)| x.len() >= 2)
            .map(|((a, b, v), x)| {
                let (ds, dt) = x
                    .iter()
                    .fold((0.0, 0.0), |(s, u), (ds, dt)| (s + ds, u + dt));
                let mut speeds: Vec<f64> = x.iter().map(|(ds, dt)| ds / dt).collect();
                speeds.sort_by(f64::total_cmp);
                StretchSpeed {
                    span: (*a, *b),
                    asked: *v,
                    mean: ds / dt,
                    median: speeds[speeds.len() / 2],
                }
            })
            .collect(),
    ))
}
