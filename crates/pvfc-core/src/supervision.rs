//! What a reading can be: the bounds the [`PassiveController`](crate::passive::PassiveController)
//! checks every sample against, and the [`Fault`]s it reports when one is broken.
//!
//! A controller cannot tell a lying sensor from a moving robot in general, but it can tell
//! what no motion can produce:
//! - a reading (position, velocity, applied torque) that is NaN or infinite;
//! - a period that is not finite or outside `[min, max]` (a missed deadline, a stalled
//!   timer);
//! - a joint that moved further since the last good reading than its speed bound allows,
//!   `|Δq_i| > v̄_i e + δ_i` over the time `e` since that reading (`δ_i` the encoder's
//!   resolution): a spike, a jump, a wrapped counter;
//! - with an acceleration bound, a joint whose speed changed more than the bound allows,
//!   `|Δq_i − w_i e| > ā_i e (e + e_w)/2 + δ_i (1 + e/e_w)`, with `w_i` the speed of the last
//!   good increment (measured over `e_w`): a spike too small for the speed bound, or an
//!   encoder that stopped dead while its joint was moving;
//! - an encoder that stopped dead (its reading exactly unchanged where the acceleration bound
//!   says the joint could not have stopped) is **frozen**: the fault is latched until that
//!   joint's reading changes. A joint frozen while at rest cannot be told from one at rest.
//!
//! What the controller does about a fault is documented at
//! [`PassiveController::step`](crate::passive::PassiveController::step): the safe torque
//! (zero), the storage charged for what the last torque may have done unseen, and recovery at
//! the next good reading.

use crate::error::{Error, ErrorKind, Result};
use crate::lie::Tangent;
use crate::scalar::cast;
use crate::Real;

/// A fault the [`PassiveController`](crate::passive::PassiveController) detected at a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Fault {
    /// A measured position or velocity, or the applied torque, is NaN or infinite.
    NonFinite,
    /// The period is not finite, or outside the supervision's `[min, max]`.
    Period,
    /// The joint moved further since the last good reading than its speed bound allows (or
    /// its measured velocity is above the bound).
    Speed {
        /// The first joint (0-based) found at fault.
        joint: usize,
    },
    /// The joint's speed changed more than its acceleration bound allows.
    Acceleration {
        /// The first joint (0-based) found at fault.
        joint: usize,
    },
    /// The joint's encoder stopped dead while the joint was moving, and has not changed since.
    Frozen {
        /// The first joint (0-based) found at fault.
        joint: usize,
    },
}

impl Fault {
    /// A stable small number for logs and the C ABI: 1 non-finite, 2 period, 3 speed,
    /// 4 acceleration, 5 frozen (0 is "no fault" there).
    pub const fn code(&self) -> u8 {
        match self {
            Fault::NonFinite => 1,
            Fault::Period => 2,
            Fault::Speed { .. } => 3,
            Fault::Acceleration { .. } => 4,
            Fault::Frozen { .. } => 5,
        }
    }

    /// The joint the fault names, if it names one.
    pub const fn joint(&self) -> Option<usize> {
        match self {
            Fault::Speed { joint } | Fault::Acceleration { joint } | Fault::Frozen { joint } => {
                Some(*joint)
            }
            Fault::NonFinite | Fault::Period => None,
        }
    }

    /// A short, stable, human-readable name.
    pub const fn as_str(&self) -> &'static str {
        match self {
            Fault::NonFinite => "non-finite reading",
            Fault::Period => "period out of bounds",
            Fault::Speed { .. } => "reading beyond the speed bound",
            Fault::Acceleration { .. } => "reading beyond the acceleration bound",
            Fault::Frozen { .. } => "encoder frozen",
        }
    }
}

impl core::fmt::Display for Fault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.joint() {
            Some(j) => write!(f, "{} (joint {j})", self.as_str()),
            None => f.write_str(self.as_str()),
        }
    }
}

/// Whether a joint's reading is unchanged: its increment `dq` from a reading of coordinate
/// `q` is zero but for the rounding of the arithmetic that formed it (an encoder repeats its
/// count exactly; a reading composed from coordinates may differ in its last bits).
pub(crate) fn unchanged<T: Real>(dq: T, q: T) -> bool {
    dq.abs() <= T::default_epsilon() * cast::<T>(8.0) * (T::one() + q.abs())
}

/// The bounds a reading is checked against (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Supervision<T: Real, const D: usize> {
    max_speed: Tangent<T, D>,
    max_acceleration: Option<Tangent<T, D>>,
    period: (T, T),
}

fn invalid(context: &'static str) -> Error {
    Error::new(ErrorKind::InvalidParameter, context)
}

impl<T: Real, const D: usize> Supervision<T, D> {
    /// The speed bound `v̄_i` per joint (rad/s or m/s, each > 0, finite: the fastest the joint
    /// can move, with a margin) and the period's bounds `0 < min ≤ max` (s, finite).
    pub fn new(max_speed: Tangent<T, D>, min_period: T, max_period: T) -> Result<Self> {
        if !max_speed.iter().all(|v| v.is_finite() && *v > T::zero()) {
            return Err(invalid(
                "Supervision: every speed bound must be finite and > 0",
            ));
        }
        if !(min_period.is_finite()
            && max_period.is_finite()
            && min_period > T::zero()
            && min_period <= max_period)
        {
            return Err(invalid(
                "Supervision: the period's bounds must be finite with 0 < min ≤ max",
            ));
        }
        Ok(Supervision {
            max_speed,
            max_acceleration: None,
            period: (min_period, max_period),
        })
    }

    /// With an acceleration bound `ā_i` per joint (rad/s², m/s²; each > 0, finite: the most
    /// the drives, gravity and the contacts the task expects can give the joint, with a
    /// margin). Without one, only the speed bound is checked and no encoder is found frozen.
    pub fn with_max_acceleration(mut self, max_acceleration: Tangent<T, D>) -> Result<Self> {
        if !max_acceleration
            .iter()
            .all(|a| a.is_finite() && *a > T::zero())
        {
            return Err(invalid(
                "Supervision: every acceleration bound must be finite and > 0",
            ));
        }
        self.max_acceleration = Some(max_acceleration);
        Ok(self)
    }

    /// The speed bounds `v̄`.
    pub fn max_speed(&self) -> &Tangent<T, D> {
        &self.max_speed
    }

    /// The acceleration bounds `ā`, if any.
    pub fn max_acceleration(&self) -> Option<&Tangent<T, D>> {
        self.max_acceleration.as_ref()
    }

    /// The period's bounds `(min, max)`.
    pub fn period(&self) -> (T, T) {
        self.period
    }

    /// Whether the period `dt` is finite and within the bounds.
    pub fn period_ok(&self, dt: T) -> bool {
        dt.is_finite() && dt >= self.period.0 && dt <= self.period.1
    }

    /// The time a period counts for while faults are accumulated: `dt` if it is finite and
    /// positive, otherwise the longest period allowed.
    pub(crate) fn elapsed(&self, dt: T) -> T {
        if dt.is_finite() && dt > T::zero() {
            dt
        } else {
            self.period.1
        }
    }

    /// The first fault of an increment `dq` over `elapsed` since the last good reading `at`
    /// (its coordinates), with `rate` the last good increment's speed and the time it was
    /// measured over, and `delta` the encoders' resolution (module documentation). A joint
    /// whose reading is unchanged ([`unchanged`]) where the acceleration bound is broken is
    /// reported frozen.
    pub(crate) fn check_increment(
        &self,
        (dq, at): (&Tangent<T, D>, &Tangent<T, D>),
        elapsed: T,
        rate: Option<&(Tangent<T, D>, T)>,
        delta: Option<&Tangent<T, D>>,
    ) -> Option<Fault> {
        let half = cast::<T>(0.5);
        let resolution = |i: usize| delta.map_or(T::zero(), |d| d[i]);
        for i in 0..D {
            if dq[i].abs() > self.max_speed[i] * elapsed + resolution(i) {
                return Some(Fault::Speed { joint: i });
            }
        }
        if let (Some(a), Some((w, ew))) = (&self.max_acceleration, rate) {
            for i in 0..D {
                let bound = a[i] * elapsed * (elapsed + *ew) * half
                    + resolution(i) * (T::one() + elapsed / *ew);
                if (dq[i] - w[i] * elapsed).abs() > bound {
                    return Some(if unchanged(dq[i], at[i]) {
                        Fault::Frozen { joint: i }
                    } else {
                        Fault::Acceleration { joint: i }
                    });
                }
            }
        }
        None
    }

    /// The first joint whose measured velocity is above its speed bound.
    pub(crate) fn check_velocity(&self, v: &Tangent<T, D>) -> Option<Fault> {
        (0..D)
            .find(|&i| v[i].abs() > self.max_speed[i])
            .map(|joint| Fault::Speed { joint })
    }

    /// The most the held torque `u` can have done over `dt` unseen: joint by joint
    /// `|u_i| v̄_i dt` (J).
    pub(crate) fn unseen_work(&self, torque: &Tangent<T, D>, dt: T) -> T {
        torque
            .iter()
            .zip(self.max_speed.iter())
            .fold(T::zero(), |acc, (c, v)| acc + c.abs() * *v)
            * dt
    }

    /// The most the held torque `u` can have done over a period `dt` whose reading is
    /// unusable, beginning `since` after the last good reading, when the last good
    /// increment's speed `w_i` (measured over `e_w`) is known: the period's mean speed is
    /// within `ā_i (e_w/2 + since + dt/2)` of the increment's (the distance between the two
    /// intervals' midpoints, times the acceleration bound), and `w_i` within `δ_i/e_w` of the
    /// true mean, so joint by joint the work is at most
    /// `u_i w_i dt + |u_i| (ā_i dt (e_w/2 + since + dt/2) + δ_i dt/e_w)`, and at most
    /// `|u_i| v̄_i dt` ([`unseen_work`](Self::unseen_work)): the lesser, and not below zero
    /// (J). Without an acceleration bound or a rate, and for a joint whose reading stood
    /// still (`still`: its speed is not known), the speed bound's.
    pub(crate) fn unseen_work_after(
        &self,
        (torque, dt): (&Tangent<T, D>, T),
        since: T,
        rate: Option<&(Tangent<T, D>, T)>,
        delta: Option<&Tangent<T, D>>,
        still: impl Fn(usize) -> bool,
    ) -> T {
        let (Some(a), Some((w, ew))) = (&self.max_acceleration, rate) else {
            return self.unseen_work(torque, dt);
        };
        let half = cast::<T>(0.5);
        let reach = (*ew * half + since + dt * half) * dt;
        (0..D).fold(T::zero(), |acc, i| {
            let u = torque[i];
            let worst = u.abs() * self.max_speed[i] * dt;
            if still(i) {
                return acc + worst;
            }
            let count = delta.map_or(T::zero(), |d| d[i]) * dt / *ew;
            let estimate = u * w[i] * dt + u.abs() * (a[i] * reach + count);
            acc + estimate.min(worst).max(T::zero())
        })
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// The readings' coordinates (the frozen check's scale).
    const Z: Vector2<f64> = Vector2::new(0.0, 0.0);

    fn sup() -> Supervision<f64, 2> {
        Supervision::new(Vector2::new(2.0, 3.0), 5e-4, 3e-3)
            .unwrap()
            .with_max_acceleration(Vector2::new(100.0, 100.0))
            .unwrap()
    }

    #[test]
    fn bad_bounds_are_refused() {
        assert!(Supervision::new(Vector2::new(0.0, 1.0), 1e-3, 1e-3).is_err());
        assert!(Supervision::new(Vector2::new(f64::NAN, 1.0), 1e-3, 1e-3).is_err());
        assert!(Supervision::new(Vector2::new(1.0, 1.0), 2e-3, 1e-3).is_err());
        assert!(Supervision::new(Vector2::new(1.0, 1.0), 0.0, 1e-3).is_err());
        assert!(Supervision::new(Vector2::new(1.0, 1.0), 1e-3, f64::INFINITY).is_err());
        let s = Supervision::new(Vector2::new(1.0, 1.0), 1e-3, 1e-3).unwrap();
        assert!(s.with_max_acceleration(Vector2::new(1.0, -1.0)).is_err());
    }

    #[test]
    fn speed_bound_names_the_joint() {
        let s = sup();
        // 2 rad/s over 1 ms: 2 mrad is the most joint 0 can move.
        let ok = Vector2::new(1.99e-3, -2.99e-3);
        assert_eq!(s.check_increment((&ok, &Z), 1e-3, None, None), None);
        let bad = Vector2::new(1.0e-3, -3.01e-3);
        assert_eq!(
            s.check_increment((&bad, &Z), 1e-3, None, None),
            Some(Fault::Speed { joint: 1 })
        );
        // Over two periods twice the distance is possible.
        assert_eq!(s.check_increment((&bad, &Z), 2e-3, None, None), None);
        // The encoder's resolution widens the bound.
        let d = Vector2::new(0.0, 1e-4);
        assert_eq!(s.check_increment((&bad, &Z), 1e-3, None, Some(&d)), None);
    }

    #[test]
    fn acceleration_bound_tells_a_stop_from_a_freeze() {
        let s = sup();
        let rate = (Vector2::new(1.5, 0.0), 1e-3);
        // 100 rad/s² changes the speed by 0.1 rad/s in a millisecond.
        let smooth = Vector2::new(1.45e-3, 0.0);
        assert_eq!(
            s.check_increment((&smooth, &Z), 1e-3, Some(&rate), None),
            None
        );
        let jump = Vector2::new(1.2e-3, 0.0);
        assert_eq!(
            s.check_increment((&jump, &Z), 1e-3, Some(&rate), None),
            Some(Fault::Acceleration { joint: 0 })
        );
        let frozen = Vector2::new(0.0, 0.0);
        assert_eq!(
            s.check_increment((&frozen, &Z), 1e-3, Some(&rate), None),
            Some(Fault::Frozen { joint: 0 })
        );
        // After 30 ms at 100 rad/s² the joint could have stopped and come back.
        assert_eq!(
            s.check_increment((&frozen, &Z), 30e-3, Some(&rate), None),
            None
        );
    }

    #[test]
    fn codes_are_stable_and_distinct() {
        let all = [
            Fault::NonFinite,
            Fault::Period,
            Fault::Speed { joint: 0 },
            Fault::Acceleration { joint: 0 },
            Fault::Frozen { joint: 0 },
        ];
        for (i, f) in all.iter().enumerate() {
            assert_eq!(f.code() as usize, i + 1);
        }
        assert_eq!(Fault::Frozen { joint: 3 }.joint(), Some(3));
    }

    #[test]
    fn a_faulted_period_after_a_known_speed_is_charged_near_its_work() {
        let s = sup()
            .with_max_acceleration(Vector2::new(100.0, 100.0))
            .unwrap();
        let u = Vector2::new(-4.0, 1.0);
        let rate = (Vector2::new(-1.0, 0.5), 1e-3);
        let h = 1e-3;
        // Right after the last good reading: u·w h plus |u| ā h (e_w/2 + h/2) per joint.
        let w = s.unseen_work_after((&u, h), 0.0, Some(&rate), None, |_| false);
        let expected = (4.0 * 1.0 + 4.0 * 100.0 * 1e-3) * h + (0.5 + 100.0 * 1e-3) * h;
        assert!((w - expected).abs() < 1e-15, "{w} {expected}");
        assert!(w < 0.5 * s.unseen_work(&u, h));
        // Every true motion within the bounds does no more work than the charge: the speed at
        // the period's start anywhere the increment's mean allows (within `ā e_w/2` of it),
        // then the most acceleration along the torque; the worst is reached.
        let mut worst: f64 = 0.0;
        for side in [-1.0, -0.5, 0.0, 0.5, 1.0] {
            let mut work = 0.0;
            for j in 0..2 {
                let v0 = rate.0[j] + side * u[j].signum() * 100.0 * 0.5e-3;
                work += u[j] * (v0 * h + 0.5 * 100.0 * u[j].signum() * h * h);
            }
            assert!(work <= w + 1e-15, "{work} > {w}");
            worst = worst.max(work);
        }
        assert!((worst - w).abs() < 1e-15, "{worst} {w}");
        // Later, the reach grows; a still joint, or no rate, takes the speed bound's.
        assert!(s.unseen_work_after((&u, h), 5e-3, Some(&rate), None, |_| false) > w);
        let still = s.unseen_work_after((&u, h), 0.0, Some(&rate), None, |j| j == 0);
        assert!((still - (4.0 * 2.0 * h + (0.5 + 100.0 * 1e-3) * h)).abs() < 1e-15);
        assert_eq!(
            s.unseen_work_after((&u, h), 0.0, None, None, |_| false),
            s.unseen_work(&u, h)
        );
        // Never below zero: a torque against the motion is not a credit.
        let against = s.unseen_work_after((&-u, h), 0.0, Some(&rate), None, |_| false);
        assert_eq!(against, 0.0);
    }

    #[test]
    fn unseen_work_is_the_worst_case() {
        let s = sup();
        let w = s.unseen_work(&Vector2::new(-4.0, 1.0), 1e-3);
        assert!((w - (4.0 * 2.0 + 1.0 * 3.0) * 1e-3).abs() < 1e-15);
    }
}
