//! `[[operator]]`: an operator's commands to the drive by time (start at a nominal speed,
//! change it, stop), the commands a motor controller takes over its serial line
//! (`pvfc_link::Command`). A passive drive with commands starts stopped (the safe torque,
//! the controller not stepped) and applies each at the first control period at or after its
//! time, one a period, in the order given; the host of a drive in the loop (`pvfc hil`) sends
//! each in that period's frame.

use crate::error::{Result, SimError};
use pvfc_link::Command;
use serde::{Deserialize, Serialize};

/// One command of `[[operator]]`: exactly one of `start`, `speed` and `stop`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatorCommand {
    /// When (s, ≥ 0): applied at the first control period at or after it.
    pub at: f64,
    /// Run the controller at the nominal speed `r` of eq. (36).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<f64>,
    /// Change the nominal speed `r`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// The safe torque (zero) from this period on, the controller not stepped.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub stop: bool,
}

impl OperatorCommand {
    /// The command on the line, checked: `at` finite and ≥ 0, `r` finite and ≥ 0, exactly one
    /// command. `index` names it in the error (`operator[index]`).
    pub fn command(&self, index: usize) -> Result<Command> {
        let bad = |what: String| Err(SimError::Setting(format!("operator[{index}]: {what}")));
        if !(self.at.is_finite() && self.at >= 0.0) {
            return bad(format!("at = {}: a time, finite and ≥ 0", self.at));
        }
        let speed = |r: f64| {
            if r.is_finite() && r >= 0.0 && r <= f64::from(f32::MAX) {
                Ok(r as f32)
            } else {
                Err(SimError::Setting(format!(
                    "operator[{index}]: the nominal speed r = {r}: finite and ≥ 0"
                )))
            }
        };
        match (self.start, self.speed, self.stop) {
            (Some(r), None, false) => Ok(Command::Start(speed(r)?)),
            (None, Some(r), false) => Ok(Command::Speed(speed(r)?)),
            (None, None, true) => Ok(Command::Stop),
            _ => bad("exactly one of start = r, speed = r, stop = true".into()),
        }
    }
}

/// The operator's commands due by control period, and the setpoint they build.
#[derive(Clone, Debug, PartialEq)]
pub struct Operator {
    /// `(period, command)`, by period.
    commands: Vec<(u64, Command)>,
    next: usize,
    /// Whether the controller runs, and at which nominal speed.
    running: bool,
    speed: f64,
}

impl Operator {
    /// The schedule of scenario `s`'s `[[operator]]` on its control period.
    pub fn of(s: &crate::scenario::Scenario) -> Result<Option<Operator>> {
        Self::new(&s.operator, 1.0 / s.controller.rate)
    }

    /// The schedule of `commands` on a loop of period `dt` (s); `None` without commands (the
    /// drive runs from the start).
    pub fn new(commands: &[OperatorCommand], dt: f64) -> Result<Option<Operator>> {
        if commands.is_empty() {
            return Ok(None);
        }
        let mut due = Vec::with_capacity(commands.len());
        for (i, c) in commands.iter().enumerate() {
            let command = c.command(i)?;
            // The first period at or after `at` (a period's time rounds within 1e-9 of it).
            let period = (c.at / dt - 1e-9).ceil().max(0.0) as u64;
            due.push((period, command));
        }
        due.sort_by_key(|(p, _)| *p);
        Ok(Some(Operator {
            commands: due,
            next: 0,
            running: false,
            speed: 0.0,
        }))
    }

    /// The command sent at control period `k` (one a period: of two due at once, the second
    /// goes at the next period), applied to the setpoint.
    pub fn due(&mut self, k: u64) -> Option<Command> {
        let (at, command) = *self.commands.get(self.next)?;
        if at > k {
            return None;
        }
        self.next += 1;
        match command {
            Command::Start(r) => {
                self.running = true;
                self.speed = f64::from(r);
            }
            Command::Speed(r) => self.speed = f64::from(r),
            Command::Stop => self.running = false,
        }
        Some(command)
    }

    /// Whether the controller runs.
    pub fn running(&self) -> bool {
        self.running
    }

    /// The nominal speed `r` asked for.
    pub fn speed(&self) -> f64 {
        self.speed
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;

    fn at(at: f64) -> OperatorCommand {
        OperatorCommand {
            at,
            ..Default::default()
        }
    }

    #[test]
    fn commands_come_at_their_periods_one_a_period_and_build_the_setpoint() {
        let cmds = [
            OperatorCommand {
                start: Some(1.0),
                ..at(0.2)
            },
            OperatorCommand {
                speed: Some(2.0),
                ..at(0.2)
            },
            OperatorCommand {
                stop: true,
                ..at(0.0105)
            },
        ];
        let mut op = Operator::new(&cmds, 1e-3).unwrap().unwrap();
        assert!(!op.running());
        let sent: Vec<(u64, Command)> =
            (0..400).filter_map(|k| op.due(k).map(|c| (k, c))).collect();
        assert_eq!(
            sent,
            [
                (11, Command::Stop),
                (200, Command::Start(1.0)),
                (201, Command::Speed(2.0))
            ]
        );
        assert!(op.running() && op.speed() == 2.0);
        assert!(Operator::new(&[], 1e-3).unwrap().is_none());
    }

    #[test]
    fn a_bad_command_is_named() {
        let both = OperatorCommand {
            start: Some(1.0),
            stop: true,
            ..at(0.0)
        };
        let e = Operator::new(&[both], 1e-3).unwrap_err().to_string();
        assert!(
            e.contains("operator[0]") && e.contains("exactly one"),
            "{e}"
        );
        let nan = OperatorCommand {
            speed: Some(f64::NAN),
            ..at(1.0)
        };
        let e = Operator::new(&[at(0.0), nan.clone()], 1e-3)
            .unwrap_err()
            .to_string();
        assert!(e.contains("operator[0]"), "{e}");
        let e = nan.command(1).unwrap_err().to_string();
        assert!(e.contains("operator[1]") && e.contains("NaN"), "{e}");
        let late = OperatorCommand {
            stop: true,
            ..at(f64::INFINITY)
        };
        assert!(late
            .command(0)
            .unwrap_err()
            .to_string()
            .contains("at = inf"));
    }
}
