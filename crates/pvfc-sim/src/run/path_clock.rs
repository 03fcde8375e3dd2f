//! How a tracker's path time `τ` advances: at a fixed rate (the timed tracker of Fig. 1), or
//! scaled down while a commanded torque nears its limit (the speed-scaling tracker,
//! [`SpeedScaling`]).

use crate::error::{Result, SimError};
use crate::model::pace::PACE_KNOTS;
use crate::scenario::{BaselineSpec, Scenario};
use crate::trace::{SCALED_SUFFIX, TIMED_SUFFIX};
use pvfc_core::pace::{PaceProfile, PaceTable, PaceThrottle};

/// The clock of a scenario's tracker at `tau_rate`, and its trace's suffix: the timed
/// tracker's, or (`scaled`) the speed-scaling tracker's of `[baseline.speed_scaling]` (which
/// needs torque limits).
pub(crate) fn tracker_clock(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    scaled: bool,
) -> Result<(PathClock, &'static str)> {
    if !tau_rate.is_finite() {
        return Err(SimError::Setting("baseline: τ rate must be finite".into()));
    }
    if !scaled {
        return Ok((PathClock::fixed(s.initial.tau, tau_rate), TIMED_SUFFIX));
    }
    let c = b.speed_scaling.ok_or_else(|| {
        SimError::Setting("baseline.speed_scaling: not set for a speed-scaling tracker".into())
    })?;
    let throttle = c.throttle("baseline.speed_scaling")?;
    if b.torque_limit.is_empty() {
        return Err(SimError::Setting(
            "baseline.speed_scaling: the scaling needs the drives' limits (baseline.torque_limit)"
                .into(),
        ));
    }
    Ok((
        PathClock::scaled(s.initial.tau, tau_rate, throttle),
        SCALED_SUFFIX,
    ))
}

/// The path time of a tracker and its rates.
#[derive(Clone, Debug)]
pub(crate) struct PathClock {
    tau0: f64,
    rate: f64,
    /// The scaling `s` (the core's pace throttle: the same rule as PVFC's) and its last
    /// target (scaled clock only).
    scaling: Option<PaceThrottle<f64>>,
    target: f64,
    /// The rate's profile along the contour, `τ̇ = rate · σ(τ)` (a part program's feeds).
    profile: Option<Box<PaceTable<f64, PACE_KNOTS>>>,
    /// The path time reached (scaled or profiled clock).
    tau: f64,
}

impl PathClock {
    /// `τ = τ₀ + rate · t`.
    pub(crate) fn fixed(tau0: f64, rate: f64) -> Self {
        PathClock {
            tau0,
            rate,
            scaling: None,
            target: 1.0,
            profile: None,
            tau: tau0,
        }
    }

    /// `τ̇ = s · rate` with the scaling `s` of `scaling`, starting at `s = 1`.
    pub(crate) fn scaled(tau0: f64, rate: f64, scaling: PaceThrottle<f64>) -> Self {
        PathClock {
            scaling: Some(scaling),
            ..Self::fixed(tau0, rate)
        }
    }

    /// This clock at `τ̇ = level · σ(τ)` (times its scaling, if any) in place of its rate: a
    /// part program's feeds, `profile` the rates asked for ÷ `level`.
    pub(crate) fn following(self, profile: PaceTable<f64, PACE_KNOTS>, level: f64) -> Self {
        PathClock {
            rate: level,
            profile: Some(Box::new(profile)),
            ..self
        }
    }

    /// The scaling `s` and its rate `ṡ` towards its last target (1 and 0 unscaled).
    fn scale(&self) -> (f64, f64) {
        match &self.scaling {
            Some(c) => (c.scale(), (self.target - c.scale()) / c.time_constant()),
            None => (1.0, 0.0),
        }
    }

    /// `(τ, τ̇, τ̈)` at time `t` (a scaled or profiled clock: where its steps have brought
    /// it; `τ̈` from the scaling's rate towards its last target and the profile's slope).
    pub(crate) fn at(&self, t: f64) -> (f64, f64, f64) {
        match (&self.scaling, &self.profile) {
            (None, None) => (self.tau0 + self.rate * t, self.rate, 0.0),
            (Some(c), None) => (
                self.tau,
                self.rate * c.scale(),
                self.rate * (self.target - c.scale()) / c.time_constant(),
            ),
            (_, Some(p)) => {
                let (s, ds) = self.scale();
                let (sigma, dsigma) = p.pace(self.tau);
                let rate = self.rate * s * sigma;
                (self.tau, rate, self.rate * (ds * sigma + s * dsigma * rate))
            }
        }
    }

    /// Advances over `dt` after a command that used `share` of a limit at most
    /// (`max_i |T_i|/L_i`, before the drive clamps it).
    pub(crate) fn advance(&mut self, dt: f64, share: f64) {
        let s = match self.scaling.as_mut() {
            Some(c) => {
                self.target = c.target(share);
                c.update(share, dt)
            }
            None if self.profile.is_some() => 1.0,
            None => return,
        };
        match &self.profile {
            Some(p) => self.tau += self.rate * s * p.pace(self.tau).0 * dt,
            None => self.tau += self.rate * s * dt,
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;
    use crate::scenario::SpeedScaling;

    #[test]
    fn the_fixed_clock_is_tau0_plus_rate_t_whatever_the_torque() {
        let mut c = PathClock::fixed(0.5, 2.0);
        c.advance(1e-3, 5.0);
        assert_eq!(c.at(3.0), (6.5, 2.0, 0.0));
    }

    #[test]
    fn the_scaled_clock_slows_above_the_threshold_and_recovers_below_it() {
        let scaling = SpeedScaling::default(); // threshold 0.8, 50 ms, floor 0.02
        let mut c = PathClock::scaled(
            0.0,
            2.0,
            scaling.throttle("baseline.speed_scaling").unwrap(),
        );
        assert_eq!(c.at(0.0), (0.0, 2.0, 0.0));
        // Below the threshold: full rate, τ advances at 2.
        for _ in 0..100 {
            c.advance(1e-3, 0.5);
        }
        let (tau, rate, _) = c.at(0.1);
        assert!((tau - 0.2).abs() < 1e-12 && rate == 2.0);
        // At the limit for 0.5 s (ten time constants): the scaling falls to its floor, and
        // the path time nearly stops; τ̈ is negative on the way down.
        c.advance(1e-3, 1.0);
        assert!(c.at(0.0).2 < 0.0, "decelerating");
        for _ in 0..500 {
            c.advance(1e-3, 1.0);
        }
        let (_, rate, _) = c.at(0.0);
        assert!((rate - 2.0 * scaling.floor).abs() < 1e-9, "rate {rate}");
        // Half-way between threshold and limit: the target is 0.5.
        for _ in 0..1000 {
            c.advance(1e-3, 0.9);
        }
        assert!((c.at(0.0).1 - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bad_scaling_is_a_named_error() {
        for (s, what) in [
            (
                SpeedScaling {
                    threshold: 1.0,
                    ..Default::default()
                },
                "threshold",
            ),
            (
                SpeedScaling {
                    time_constant: 0.0,
                    ..Default::default()
                },
                "time_constant",
            ),
            (
                SpeedScaling {
                    floor: 0.0,
                    ..Default::default()
                },
                "floor",
            ),
        ] {
            let e = s.validate().unwrap_err().to_string();
            assert!(e.contains(what), "{e}");
        }
    }
}
