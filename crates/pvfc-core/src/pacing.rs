//! Self-pacing (section III-C): gains `λ₁, λ₂` of the velocity field as functions of `U(E)`.
//!
//! `λ₁` scales the feed-forward term (how fast `τ` progresses), `λ₂` the gradient term (how
//! hard the error is corrected). When the error is large, self-pacing slows `τ` down.

use crate::error::{Error, ErrorKind, Result};
use crate::Real;

/// The gains and their derivatives with respect to `U` (needed for the rate `V̇` of the field).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PacingGains<T: Real> {
    /// `λ₁(U)`.
    pub lambda1: T,
    /// `λ₂(U)`.
    pub lambda2: T,
    /// `dλ₁/dU`.
    pub dlambda1: T,
    /// `dλ₂/dU`.
    pub dlambda2: T,
    /// `∂λ₁/∂τ`: zero unless a pace profile scales `λ₁` along the contour
    /// ([`crate::pace::Paced`]).
    pub dlambda1_dtau: T,
}

/// A self-pacing strategy: positive bounded gains `λ₁(U, τ), λ₂(U)` (eq. 30's requirements
/// `λ̄₁ ≥ λ₁ > 0`, `λ̄₂ ≥ λ₂ ≥ ε > 0`).
///
/// The paper's gains depend on `U` alone (eq. 21). `λ₁` may also depend on the contour's
/// parameter `τ` (a pace profile along the contour, [`crate::pace::Paced`]): Proposition 1,
/// `E_*V = −λ₂ grad U`, holds for any `λ₁ > 0`, since the feed-forward term `λ₁ ξ_d` and
/// `V_I = λ₁` cancel in the error's push-forward (eq. 29) whatever `λ₁` is.
pub trait SelfPacing<T: Real> {
    /// `true` when `λ₁` depends on `τ` (`dlambda1_dtau` may be non-zero). `false` (the
    /// default) lets the field leave the `∂λ₁/∂τ · τ̇` term of its rate out entirely.
    const DEPENDS_ON_TAU: bool = false;

    /// The gains at the navigation-function value `U` and the contour parameter `τ`.
    fn gains(&self, u: T, tau: T) -> PacingGains<T>;

    /// Scales `λ₁` on line by `s ∈ (0, 1]` (a [`crate::pace::PaceThrottle`]'s lever), if the
    /// strategy has a scale ([`crate::pace::Paced`] with a [`crate::pace::Throttled`]
    /// profile): `true` when it did. The default refuses.
    fn set_pace_scale(&mut self, scale: T) -> bool {
        let _ = scale;
        false
    }

    /// Lets the pace learn from a step at `τ` whose command used `share` of a limit (a
    /// [`crate::pace::LearnedPace`] profile); `true` when it did. The default does not.
    fn learn_pace(&mut self, tau: T, share: T, dt: T, rule: &crate::pace::PaceLearning<T>) -> bool {
        let _ = (tau, share, dt, rule);
        false
    }

    /// Sets the ceilings of a learned pace's scales (a [`crate::pace::MissLearner`]'s caps);
    /// `true` when it did. The default has none.
    fn set_pace_caps(&mut self, caps: &[T]) -> bool {
        let _ = caps;
        false
    }
}

/// Eq. (21): `λ₁ = exp(−R U)`, `λ₂ = 2 − exp(−R U)`. `R = 0` turns self-pacing off
/// (`λ₁ = λ₂ = 1`). In `f32`, `λ₁` below `2⁻⁴⁰` is taken as 0 (the contour halts until the
/// error shrinks; [`crate::Real::PACING_FLOOR`] says why).
///
/// ```
/// use pvfc_core::pacing::{ExponentialPacing, SelfPacing};
/// let g = ExponentialPacing::new(100.0_f64).unwrap().gains(0.01, 0.0);
/// assert!((g.lambda1 - (-1.0_f64).exp()).abs() < 1e-15);
/// assert!((g.lambda1 + g.lambda2 - 2.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExponentialPacing<T: Real> {
    r: T,
}

impl<T: Real> ExponentialPacing<T> {
    /// Self-pacing with parameter `R ≥ 0`.
    pub fn new(r: T) -> Result<Self> {
        if !r.is_finite() {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "ExponentialPacing: R must be finite",
            ));
        }
        if r < T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "ExponentialPacing: R must be ≥ 0",
            ));
        }
        Ok(ExponentialPacing { r })
    }

    /// No self-pacing: `R = 0`.
    pub fn off() -> Self {
        ExponentialPacing { r: T::zero() }
    }

    /// The self-pacing parameter `R`.
    pub fn r(&self) -> T {
        self.r
    }
}

impl<T: Real> SelfPacing<T> for ExponentialPacing<T> {
    #[inline]
    fn gains(&self, u: T, _tau: T) -> PacingGains<T> {
        let l1 = (-self.r * u).exp_fast();
        // Below the scalar's floor, 0: its products would be subnormal (`Real::PACING_FLOOR`).
        let l1 = if l1 < T::PACING_FLOOR { T::zero() } else { l1 };
        let d1 = -self.r * l1;
        PacingGains {
            lambda1: l1,
            lambda2: T::one() + T::one() - l1,
            dlambda1: d1,
            dlambda2: -d1,
            dlambda1_dtau: T::zero(),
        }
    }
}

/// Constant gains: no self-pacing, with a chosen balance of progression and correction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantGains<T: Real> {
    lambda1: T,
    lambda2: T,
}

impl<T: Real> ConstantGains<T> {
    /// Gains `λ₁ > 0`, `λ₂ > 0`.
    pub fn new(lambda1: T, lambda2: T) -> Result<Self> {
        if !(lambda1.is_finite() && lambda2.is_finite()) {
            return Err(Error::new(ErrorKind::NonFinite, "ConstantGains"));
        }
        if lambda1 <= T::zero() || lambda2 <= T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "ConstantGains: λ₁ and λ₂ must be > 0",
            ));
        }
        Ok(ConstantGains { lambda1, lambda2 })
    }
}

impl<T: Real> SelfPacing<T> for ConstantGains<T> {
    #[inline]
    fn gains(&self, _u: T, _tau: T) -> PacingGains<T> {
        PacingGains {
            lambda1: self.lambda1,
            lambda2: self.lambda2,
            dlambda1: T::zero(),
            dlambda2: T::zero(),
            dlambda1_dtau: T::zero(),
        }
    }
}
