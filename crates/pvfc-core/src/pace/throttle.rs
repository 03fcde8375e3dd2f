//! The pace throttled on the drives' torque margin: the pace the field asks for, scaled on
//! line by how much of its limits the drive is using.
//!
//! A pace profile ([`super::drive_limits`]) is planned in advance from the model: the
//! friction the controller compensates, the inertia it believes. A plant with more friction
//! or heavier links leaves less torque than planned, the field then asks for more than the
//! drives give, and the error grows before self-pacing answers it. The throttle reads the
//! margin the controller measures at every step, the largest share of a limit the command
//! uses before the drive clamps it, `u = max_i |T_i|/L_i`, and scales the field's pace by
//! `s ∈ [floor, 1]`:
//!
//! `V_I = s σ(τ) λ₁(U)`, and the feed-forward of `V_G` with it,
//!
//! where `s` follows, with time constant `T_s`, the target `min(1, (1 − u)/(1 − u₀))` for a
//! threshold `u₀`: 1 while every torque is below `u₀` of its limit, 0 at the limit. It is the
//! rule by which the scaled joint-trajectory controllers of UR and ros2_control slow a
//! trajectory's time, here applied to the field rather than to a clock.
//!
//! The scale is a parameter of the field, held over each period: the coupling stays
//! workless whatever it is (`q̇_aᵀT = 0` for any field), so the energy balance of eq. (9), the
//! passive controller's storage and Proposition 1 are untouched. On the contour at energy
//! level `β`, `τ̇ = β s σ(τ)`: the robot's share of `κ_a` goes to the flywheel as it slows,
//! and comes back when the margin returns. (The field's rate `V̄̇` does not include `ṡ`: `s`
//! changes by at most `dt/T_s` of its range per period, and a rate that is off costs
//! tracking, never passivity.)

use super::PaceProfile;
use crate::error::{Error, ErrorKind, Result};
use crate::Real;

/// The throttle's rule and its state: the scale `s` and how it follows the torque margin
/// (module documentation).
///
/// ```
/// use pvfc_core::pace::PaceThrottle;
/// let mut t = PaceThrottle::<f64>::new(0.8, 0.05, 0.05).unwrap();
/// // Below the threshold the pace is the field's own.
/// t.update(0.5, 1e-3);
/// assert_eq!(t.scale(), 1.0);
/// // At the limit for a second (twenty time constants) it falls to its floor.
/// for _ in 0..1000 {
///     t.update(1.0, 1e-3);
/// }
/// assert!((t.scale() - 0.05).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PaceThrottle<T: Real> {
    threshold: T,
    time_constant: T,
    floor: T,
    scale: T,
}

impl<T: Real> PaceThrottle<T> {
    /// The throttle that slows the pace above `threshold ∈ [0, 1)` of a limit, with the time
    /// constant `time_constant > 0` (s), never below `floor ∈ (0, 1]`; it starts at `s = 1`.
    pub fn new(threshold: T, time_constant: T, floor: T) -> Result<Self> {
        if !(threshold.is_finite() && time_constant.is_finite() && floor.is_finite()) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "PaceThrottle: threshold, time constant and floor must be finite",
            ));
        }
        if !(threshold >= T::zero() && threshold < T::one()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PaceThrottle: the threshold must be in [0, 1)",
            ));
        }
        if time_constant <= T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PaceThrottle: the time constant must be > 0",
            ));
        }
        if !(floor > T::zero() && floor <= T::one()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PaceThrottle: the floor must be in (0, 1]",
            ));
        }
        Ok(PaceThrottle {
            threshold,
            time_constant,
            floor,
            scale: T::one(),
        })
    }

    /// The scale `s` of the pace.
    pub fn scale(&self) -> T {
        self.scale
    }

    /// The threshold `u₀`.
    pub fn threshold(&self) -> T {
        self.threshold
    }

    /// The time constant `T_s` (s).
    pub fn time_constant(&self) -> T {
        self.time_constant
    }

    /// The least scale.
    pub fn floor(&self) -> T {
        self.floor
    }

    /// The target of the scale when the command uses `share` of a limit at most:
    /// `min(1, (1 − u)/(1 − u₀))`, at least 0 (a non-finite share counts as at the limit).
    pub fn target(&self, share: T) -> T {
        let t = (T::one() - share) / (T::one() - self.threshold);
        if t >= T::one() {
            T::one()
        } else if t > T::zero() {
            t
        } else {
            // Also a NaN share: slow down rather than speed up on a reading that is not one.
            T::zero()
        }
    }

    /// The scale after a period `dt` whose command used `share` of a limit at most:
    /// `s + (target − s)(1 − e^{−dt/T_s})`, within `[floor, 1]`. The throttle is unchanged.
    pub fn next(&self, share: T, dt: T) -> T {
        let blend = T::one() - (-(dt / self.time_constant)).exp_fast();
        let s = self.scale + (self.target(share) - self.scale) * blend;
        if s < self.floor {
            self.floor
        } else if s > T::one() {
            T::one()
        } else {
            s
        }
    }

    /// Advances the scale over `dt` ([`next`](Self::next)) and returns it.
    pub fn update(&mut self, share: T, dt: T) -> T {
        self.scale = self.next(share, dt);
        self.scale
    }

    /// Sets the scale (clamped to `[floor, 1]`; a NaN leaves it unchanged).
    pub fn set_scale(&mut self, scale: T) {
        if scale < self.floor {
            self.scale = self.floor;
        } else if scale > T::one() {
            self.scale = T::one();
        } else if scale.is_finite() {
            self.scale = scale;
        }
    }
}

/// A pace profile `P` scaled on line by `s ∈ (0, 1]`: `(s σ(τ), s dσ/dτ)`. The lever of a
/// [`PaceThrottle`]: [`PaceProfile::set_scale`] sets `s`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Throttled<T: Real, P> {
    profile: P,
    scale: T,
}

impl<T: Real, P> Throttled<T, P> {
    /// `profile` at the scale 1.
    pub fn new(profile: P) -> Self {
        Throttled {
            profile,
            scale: T::one(),
        }
    }

    /// The profile before scaling.
    pub fn profile(&self) -> &P {
        &self.profile
    }

    /// The profile before scaling, to replace it on line (between steps).
    pub fn profile_mut(&mut self) -> &mut P {
        &mut self.profile
    }

    /// The scale `s`.
    pub fn scale(&self) -> T {
        self.scale
    }
}

impl<T: Real, P: PaceProfile<T>> PaceProfile<T> for Throttled<T, P> {
    #[inline]
    fn pace(&self, tau: T) -> (T, T) {
        let (sigma, dsigma) = self.profile.pace(tau);
        (sigma * self.scale, dsigma * self.scale)
    }

    fn learn(&mut self, tau: T, share: T, dt: T, rule: &crate::pace::PaceLearning<T>) -> bool {
        self.profile.learn(tau, share, dt, rule)
    }

    fn set_caps(&mut self, caps: &[T]) -> bool {
        self.profile.set_caps(caps)
    }

    /// Sets `s` when it is finite and in `(0, 1]`; `false` (and `s` unchanged) otherwise.
    fn set_scale(&mut self, scale: T) -> bool {
        if scale.is_finite() && scale > T::zero() && scale <= T::one() {
            self.scale = scale;
            true
        } else {
            false
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;
    use crate::pace::{PaceTable, UniformPace};

    #[test]
    fn the_scale_follows_the_margin_down_and_back_up() {
        let mut t = PaceThrottle::<f64>::new(0.8, 0.05, 0.02).unwrap();
        // Half-way between the threshold and the limit for a second: the target 0.5.
        for _ in 0..1000 {
            t.update(0.9, 1e-3);
        }
        assert!((t.scale() - 0.5).abs() < 1e-6, "{}", t.scale());
        // Below the threshold again: back to 1 within a second, monotonically.
        let mut last = t.scale();
        for _ in 0..1000 {
            let s = t.update(0.3, 1e-3);
            assert!(s >= last);
            last = s;
        }
        assert!((t.scale() - 1.0).abs() < 1e-8);
        // One step from 1 at the limit: s = e^{−dt/T_s}.
        let fresh = PaceThrottle::<f64>::new(0.8, 0.05, 0.02).unwrap();
        let s = fresh.next(1.0, 1e-3);
        assert!((s - (-0.02f64).exp()).abs() < 1e-15);
        // A NaN share slows down, a share above 1 is the limit.
        assert!(t.next(f64::NAN, 1e-3) < 1.0);
        assert_eq!(t.target(1.7), 0.0);
    }

    #[test]
    fn bad_settings_are_named() {
        assert!(PaceThrottle::<f64>::new(1.0, 0.05, 0.1).is_err());
        assert!(PaceThrottle::new(-0.1, 0.05, 0.1).is_err());
        assert!(PaceThrottle::new(0.8, 0.0, 0.1).is_err());
        assert!(PaceThrottle::new(0.8, 0.05, 0.0).is_err());
        assert!(PaceThrottle::new(0.8, 0.05, 1.5).is_err());
        let e = PaceThrottle::new(0.8, f64::NAN, 0.1).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::NonFinite);
    }

    #[test]
    fn a_throttled_profile_scales_the_pace_and_its_derivative() {
        let table = PaceTable::<f64, 8>::new(&[1.0, 0.5, 0.25, 0.5], 4.0).unwrap();
        let mut p = Throttled::new(table);
        assert!(p.set_scale(0.4));
        for tau in [0.0, 0.7, 1.9, 3.3] {
            let (s, ds) = p.pace(tau);
            let (s0, ds0) = table.pace(tau);
            assert!((s - 0.4 * s0).abs() < 1e-15 && (ds - 0.4 * ds0).abs() < 1e-15);
        }
        assert!(!p.set_scale(0.0) && !p.set_scale(f64::NAN) && !p.set_scale(1.5));
        assert_eq!(p.scale(), 0.4);
        // A profile that is not throttled has no scale to set.
        assert!(!PaceProfile::<f64>::set_scale(&mut UniformPace, 0.5));
    }
}
