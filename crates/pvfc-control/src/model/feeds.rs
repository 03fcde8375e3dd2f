//! The speed asked for along a tool path stretch by stretch: a part program's feeds (F), each
//! the tool's speed along its move's stretch of the path. The pace (`model::pace`) turns it
//! into the rates `τ̇(τ)` asked for, and its smooth profile changes speed between stretches
//! without exceeding either.

use crate::error::{Result, SimError};
use crate::model::gcode::PartProgram;
use crate::model::tool_path::ToolPath;
use nalgebra::Vector3;

/// The tool's speed asked for along a closed tool path, constant on each stretch.
#[derive(Clone, Debug, PartialEq)]
pub struct FeedProfile {
    path: ToolPath,
    /// The arc length at each stretch's end, increasing, the last the path's length.
    ends: Vec<f64>,
    /// The speed on each stretch (m/s), finite and > 0.
    speeds: Vec<f64>,
}

impl FeedProfile {
    /// The feeds of `program` along `path` (the program's path, placed in the base frame: one
    /// stretch per cutting move), a move without F at `fallback` (the scenario's speed);
    /// `None` when no move has a feed. Errors name the line of a move whose speed is
    /// unknown or not finite and > 0.
    pub fn from_program(
        program: &PartProgram,
        path: ToolPath,
        fallback: Option<f64>,
    ) -> Result<Option<Self>> {
        if program.moves.iter().all(|m| m.feed.is_none()) {
            return Ok(None);
        }
        let starts = path.piece_starts();
        if starts.len() != program.moves.len() + 1 {
            return Err(SimError::Setting(format!(
                "feeds: the path has {} pieces for {} cutting moves",
                starts.len() - 1,
                program.moves.len()
            )));
        }
        let speeds = program
            .moves
            .iter()
            .map(|m| match m.feed.or(fallback) {
                Some(v) if v.is_finite() && v > 0.0 => Ok(v),
                Some(v) => Err(SimError::Setting(format!(
                    "the move on line {}: its speed {v} m/s must be finite and > 0",
                    m.line
                ))),
                None => Err(SimError::Setting(format!(
                    "the move on line {} has no feed (F) and no speed is given for it (controller.pace.speed)",
                    m.line
                ))),
            })
            .collect::<Result<Vec<_>>>()?;
        let ends = starts[1..].to_vec();
        Ok(Some(FeedProfile { path, ends, speeds }))
    }

    /// The path the feeds are along.
    pub fn path(&self) -> &ToolPath {
        &self.path
    }

    /// Each stretch: where it starts and ends along the path (m) and its speed (m/s).
    pub fn stretches(&self) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
        let starts = std::iter::once(0.0).chain(self.ends.iter().copied());
        starts
            .zip(&self.ends)
            .zip(&self.speeds)
            .map(|((a, b), v)| (a, *b, *v))
    }

    /// The index of the stretch at arc length `along` (m; wrapped into one pass).
    pub fn stretch_at(&self, along: f64) -> usize {
        let s = along.rem_euclid(self.path.length());
        self.ends
            .partition_point(|e| *e <= s)
            .min(self.speeds.len() - 1)
    }

    /// The speed asked for at arc length `along` (m; wrapped into one pass).
    pub fn speed_along(&self, along: f64) -> f64 {
        self.speeds[self.stretch_at(along)]
    }

    /// The speed asked for where the tool is at `p`: that of the stretch of the path's point
    /// closest to `p`.
    pub fn speed_at(&self, p: &Vector3<f64>) -> f64 {
        self.speed_along(self.path.closest(p).along)
    }
}
