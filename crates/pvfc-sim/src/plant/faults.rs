//! Faults the simulated loop meets (`[[faults]]`): what the encoders, the controller's clock,
//! the drive and the world do to a run. The passive controller's supervision
//! (`[controller.passive.supervision]`) detects what it can of them; the run's audit says
//! whether any energy was created meanwhile.
//!
//! Each event acts over `[at, at + duration)` (a `duration` of 0: the first sample at or
//! after `at`):
//!
//! | `kind` | what happens | `joint` | `size` |
//! |---|---|---|---|
//! | `encoder_spike` | the joint's reading is off by `size` | yes | offset (rad, m) |
//! | `encoder_freeze` | the joint's reading keeps its value of the window's first sample | yes | — |
//! | `non_finite` | the joint's reading is NaN | yes | — |
//! | `jitter` | each period is drawn uniformly in `period = [min, max]` (s; within half to a hundred nominal periods) | — | — |
//! | `missed_period` | the samples in the window do not happen: the drive holds its torque | — | — |
//! | `dropped_command` | the drive keeps the torque it had | — | — |
//! | `late_command` | the drive applies the command of the sample before | — | — |
//! | `torque_limit` | the drive clamps to `size` × `[controller.passive] torque_limit` | — | factor |
//! | `impact` | a torque `size` on the joint, from the world (its work is the environment's) | yes | N·m, N |
//!
//! The drive reports the torque it applied to the controller at every sample of a run with
//! faults (real drives report their current). Only `impact` acts on the baselines' runs: the
//! trackers have no supervision, and the other faults are the passive controller's to survive.

use crate::error::{Result, SimError};
use nalgebra::SVector;
use serde::{Deserialize, Serialize};

/// What a fault event does (the module's table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FaultKind {
    /// The joint's reading is off by `size`.
    EncoderSpike,
    /// The joint's reading keeps its value of the window's first sample.
    EncoderFreeze,
    /// The joint's reading is NaN.
    NonFinite,
    /// Each period is drawn uniformly in `period`.
    Jitter,
    /// The samples in the window do not happen.
    MissedPeriod,
    /// The drive keeps the torque it had.
    DroppedCommand,
    /// The drive applies the command of the sample before.
    LateCommand,
    /// The drive clamps to `size` × the controller's torque limits.
    TorqueLimit,
    /// A torque `size` on the joint, from the world.
    Impact,
}

/// One fault of a run (`[[faults]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaultEvent {
    /// What happens.
    pub kind: FaultKind,
    /// When it begins (s, ≥ 0).
    pub at: f64,
    /// How long it lasts (s, ≥ 0; 0: one sample).
    #[serde(default)]
    pub duration: f64,
    /// The joint it acts on (0-based): the encoder faults and `impact`.
    #[serde(default)]
    pub joint: usize,
    /// The spike's offset, the torque limits' factor, the impact's torque.
    #[serde(default)]
    pub size: f64,
    /// `jitter`: the shortest and the longest period (s).
    #[serde(default, skip_serializing_if = "is_unset")]
    pub period: (f64, f64),
}

fn is_unset(p: &(f64, f64)) -> bool {
    *p == (0.0, 0.0)
}

impl FaultEvent {
    /// Checks the event for a `dof`-joint robot whose drive has torque limits or not, in a
    /// loop of nominal period `dt` (a jitter's periods must lie within `[dt/2, 100 dt]`: the
    /// run's size is checked from the nominal period); the error names the event (its index
    /// in `[[faults]]`) and the key.
    pub fn validate(&self, index: usize, dof: usize, limited: bool, dt: f64) -> Result<()> {
        let bad = |what: String| Err(SimError::Setting(format!("faults[{index}].{what}")));
        if !(self.at.is_finite() && self.at >= 0.0) {
            return bad(format!("at: {} (finite and ≥ 0, s)", self.at));
        }
        if !(self.duration.is_finite() && self.duration >= 0.0) {
            return bad(format!("duration: {} (finite and ≥ 0, s)", self.duration));
        }
        if !self.size.is_finite() {
            return bad(format!("size: {} is not finite", self.size));
        }
        let per_joint = matches!(
            self.kind,
            FaultKind::EncoderSpike
                | FaultKind::EncoderFreeze
                | FaultKind::NonFinite
                | FaultKind::Impact
        );
        if per_joint && self.joint >= dof {
            return bad(format!("joint: {} for a {dof}-joint robot", self.joint));
        }
        match self.kind {
            FaultKind::Jitter => {
                let (lo, hi) = self.period;
                let fits = lo.is_finite() && hi.is_finite() && lo <= hi;
                if !(fits && lo >= 0.5 * dt && hi <= 100.0 * dt) {
                    return bad(format!(
                        "period: [{lo}, {hi}] (jitter: min ≤ max, within [{}, {}] s: half to a hundred nominal periods)",
                        0.5 * dt,
                        100.0 * dt
                    ));
                }
            }
            FaultKind::TorqueLimit => {
                if !limited {
                    return bad("kind: torque_limit needs [controller.passive] torque_limit".into());
                }
                if self.size <= 0.0 {
                    return bad(format!("size: {} (a factor > 0)", self.size));
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// Whether the event acts at time `t` of a loop of period `dt` (with a millionth of a
    /// period's slack: a clock that adds its periods up is off the grid by rounding).
    fn active(&self, t: f64, dt: f64) -> bool {
        let slack = 1e-6 * dt;
        t >= self.at - slack && t < self.at + self.duration.max(dt) - slack
    }
}

/// The torque of the impacts acting at time `t` on an `N`-joint robot (zero without one).
pub(crate) fn impact_torque<const N: usize>(
    faults: &[FaultEvent],
    t: f64,
    dt: f64,
) -> SVector<f64, N> {
    let mut u = SVector::zeros();
    for e in faults {
        if e.kind == FaultKind::Impact && e.active(t, dt) && e.joint < N {
            u[e.joint] += e.size;
        }
    }
    u
}

/// The faults of one run as it goes: the encoders' frozen values, the drive's last torques.
#[derive(Clone, Debug)]
pub(crate) struct FaultState<'a, const N: usize> {
    faults: &'a [FaultEvent],
    dt: f64,
    frozen: Vec<Option<f64>>,
    last_command: SVector<f64, N>,
    applied: SVector<f64, N>,
}

impl<'a, const N: usize> FaultState<'a, N> {
    /// The faults of a loop of nominal period `dt`.
    pub(crate) fn new(faults: &'a [FaultEvent], dt: f64) -> Self {
        FaultState {
            faults,
            dt,
            frozen: vec![None; faults.len()],
            last_command: SVector::zeros(),
            applied: SVector::zeros(),
        }
    }

    /// Whether the run has any fault.
    pub(crate) fn any(&self) -> bool {
        !self.faults.is_empty()
    }

    /// The torque the drive applied over the last period.
    pub(crate) fn applied(&self) -> &SVector<f64, N> {
        &self.applied
    }

    /// The encoders' reading at time `t`: `x` (the measured coordinates) as the sensor faults
    /// acting leave it.
    pub(crate) fn reading(&mut self, t: f64, x: &mut SVector<f64, N>) {
        for (i, e) in self.faults.iter().enumerate() {
            if !e.active(t, self.dt) || e.joint >= N {
                self.frozen[i] = None;
                continue;
            }
            match e.kind {
                FaultKind::EncoderSpike => x[e.joint] += e.size,
                FaultKind::NonFinite => x[e.joint] = f64::NAN,
                FaultKind::EncoderFreeze => x[e.joint] = *self.frozen[i].get_or_insert(x[e.joint]),
                _ => {}
            }
        }
    }

    /// The period that follows the sample at time `t` (the `k`-th): drawn in a jitter's
    /// range, and lengthened by every sample that a missed-period window swallows.
    pub(crate) fn period(&self, k: usize, t: f64) -> f64 {
        let mut p = self.dt;
        for (i, e) in self.faults.iter().enumerate() {
            if e.kind == FaultKind::Jitter && e.active(t, self.dt) {
                let (lo, hi) = e.period;
                p = lo + (hi - lo) * unit(i as u64, k as u64);
            }
        }
        let missed = |t: f64| {
            self.faults
                .iter()
                .any(|e| e.kind == FaultKind::MissedPeriod && e.active(t, self.dt))
        };
        // At most a second of samples swallowed at once (a longer window is several).
        let mut n = 0;
        while missed(t + p) && n < 1_000_000 {
            p += self.dt;
            n += 1;
        }
        p
    }

    /// Whether the clock is anything but the nominal one (jitter, missed periods).
    pub(crate) fn timing(&self) -> bool {
        self.faults
            .iter()
            .any(|e| matches!(e.kind, FaultKind::Jitter | FaultKind::MissedPeriod))
    }

    /// The torque the drive applies over the period from `t`, given the controller's
    /// `command` and its torque `limits`: the command, or what the drive faults make of it.
    pub(crate) fn drive(
        &mut self,
        t: f64,
        command: &SVector<f64, N>,
        limits: Option<&[f64]>,
    ) -> SVector<f64, N> {
        let mut u = *command;
        for e in self.faults.iter().filter(|e| e.active(t, self.dt)) {
            match e.kind {
                FaultKind::DroppedCommand => u = self.applied,
                FaultKind::LateCommand => u = self.last_command,
                FaultKind::TorqueLimit => {
                    if let Some(l) = limits {
                        for (x, l) in u.iter_mut().zip(l) {
                            *x = x.clamp(-l * e.size, l * e.size);
                        }
                    }
                }
                _ => {}
            }
        }
        self.last_command = *command;
        self.applied = u;
        u
    }
}

/// A number in `[0, 1)` from two integers (SplitMix64's finaliser): the jitter's draws are
/// the same on every machine and every run.
fn unit(a: u64, b: u64) -> f64 {
    let mut z = a
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(b)
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;
    use nalgebra::Vector2;

    fn event(kind: FaultKind, at: f64, duration: f64) -> FaultEvent {
        FaultEvent {
            kind,
            at,
            duration,
            joint: 1,
            size: 0.5,
            period: (5e-4, 3e-3),
        }
    }

    #[test]
    fn sensor_faults_change_the_reading_in_their_window() {
        let f = [
            event(FaultKind::EncoderSpike, 0.010, 0.0),
            event(FaultKind::EncoderFreeze, 0.020, 0.003),
        ];
        let mut s = FaultState::<2>::new(&f, 1e-3);
        let mut x = Vector2::new(1.0, 2.0);
        s.reading(0.0095, &mut x);
        assert_eq!(x, Vector2::new(1.0, 2.0));
        s.reading(0.010, &mut x);
        assert_eq!(x, Vector2::new(1.0, 2.5));
        let mut y = Vector2::new(1.0, 2.0);
        s.reading(0.011, &mut y);
        assert_eq!(
            y,
            Vector2::new(1.0, 2.0),
            "a spike of duration 0 lasts one sample"
        );
        for (t, v) in [(0.020, 3.0), (0.021, 3.1), (0.022, 3.2)] {
            let mut z = Vector2::new(0.0, v);
            s.reading(t, &mut z);
            assert_eq!(z[1], 3.0, "frozen at t = {t}");
        }
        let mut z = Vector2::new(0.0, 3.3);
        s.reading(0.023, &mut z);
        assert_eq!(z[1], 3.3);
    }

    #[test]
    fn periods_jitter_in_range_and_missed_samples_lengthen_them() {
        let f = [event(FaultKind::Jitter, 0.0, 1.0)];
        let s = FaultState::<2>::new(&f, 1e-3);
        let draws: Vec<f64> = (0..1000).map(|k| s.period(k, k as f64 * 1e-3)).collect();
        assert!(draws.iter().all(|p| (5e-4..=3e-3).contains(p)));
        let mean = draws.iter().sum::<f64>() / 1000.0;
        assert!((mean - 1.75e-3).abs() < 1e-4, "mean period {mean}");
        let f = [event(FaultKind::MissedPeriod, 0.0105, 0.002)];
        let s = FaultState::<2>::new(&f, 1e-3);
        // The samples at 11 and 12 ms are missed: the period from 10 ms lasts 3 ms.
        assert!((s.period(10, 0.010) - 3e-3).abs() < 1e-15);
        assert_eq!(s.period(20, 0.020), 1e-3);
    }

    #[test]
    fn the_drive_drops_delays_and_clamps() {
        let f = [
            event(FaultKind::DroppedCommand, 0.002, 0.0),
            event(FaultKind::LateCommand, 0.004, 0.0),
            event(FaultKind::TorqueLimit, 0.006, 0.0),
        ];
        let mut s = FaultState::<2>::new(&f, 1e-3);
        let c = |k: f64| Vector2::new(k, -k);
        let limits = [4.0, 4.0];
        let applied: Vec<_> = (0..8)
            .map(|k| s.drive(k as f64 * 1e-3, &c(k as f64), Some(&limits)))
            .collect();
        assert_eq!(applied[2], c(1.0), "dropped: the torque it had");
        assert_eq!(applied[4], c(3.0), "late: the command before");
        assert_eq!(applied[6], Vector2::new(2.0, -2.0), "clamped to 0.5 × 4");
        assert_eq!(applied[7], c(7.0));
    }

    #[test]
    fn bad_events_are_named() {
        let mut e = event(FaultKind::EncoderSpike, 0.0, 0.0);
        e.joint = 2;
        let msg = e.validate(3, 2, true, 1e-3).unwrap_err().to_string();
        assert!(msg.contains("faults[3].joint"), "{msg}");
        let mut e = event(FaultKind::Jitter, 0.0, 0.0);
        e.period = (3e-3, 1e-3);
        assert!(e
            .validate(0, 2, true, 1e-3)
            .unwrap_err()
            .to_string()
            .contains("faults[0].period"));
        e.period = (1e-9, 1e-3);
        assert!(e
            .validate(0, 2, true, 1e-3)
            .unwrap_err()
            .to_string()
            .contains("half to a hundred"));
        let e = event(FaultKind::TorqueLimit, 0.0, 0.0);
        assert!(e
            .validate(0, 2, false, 1e-3)
            .unwrap_err()
            .to_string()
            .contains("torque_limit"));
        let e = event(FaultKind::EncoderSpike, f64::NAN, 0.0);
        assert!(e
            .validate(0, 2, true, 1e-3)
            .unwrap_err()
            .to_string()
            .contains("faults[0].at"));
    }
}
