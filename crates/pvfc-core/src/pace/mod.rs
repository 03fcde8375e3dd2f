//! The pace along the contour: how fast the field moves `τ` at each point of the contour, on
//! top of self-pacing (section III-C).
//!
//! The paper's field moves `τ` at `V_I = λ₁(U)`, the same rate at every point of the contour
//! when the error is small. A drive that can follow the contour at that rate on a straight
//! stretch may not have the torque for it in a tight corner: the field then asks for more
//! than the motors give, the error grows, and self-pacing slows `τ` only *after* the error has
//! grown (stop-and-go). A **pace profile** `σ(τ) > 0` scales the feed-forward of the field
//! along the contour, `λ₁(U, τ) = σ(τ) λ₁(U)`:
//!
//! `V_G = σ(τ) λ₁(U) ξ_d(τ) − λ₂(U) Ad_{x_d⁻¹} grad U(E)`,  `V_I = σ(τ) λ₁(U)`,
//!
//! so the field slows down *before* a corner, by as much as the corner needs. It is still a
//! field on `G × I` (it depends on `τ`, a coordinate of the suspended system): the coupling
//! stays workless, the energy balance of eq. (9) and the passivity of the digital controller
//! are untouched, and Proposition 1 (`E_*V = −λ₂ grad U`) holds for any `σ > 0`, since the
//! feed-forward cancels in the error's push-forward whatever its scale. On the contour
//! (`U = 0`) at energy level `β`, `τ̇ = β σ(τ)`.
//!
//! [`drive_limits::drive_limited_rates`] computes the fastest `τ̇(τ)` the drives allow along
//! the contour (the time-optimal parameterisation's profile, with room kept for the
//! correction), [`PaceTable`] holds it as a smooth periodic `σ(τ)`, and [`Paced`] puts it into
//! any [`SelfPacing`].
//!
//! The plan is made with the controller's model; the plant may need more torque or less. On
//! line, the passive controller ([`crate::passive`]) adjusts it on the torque margin it
//! measures: a [`PaceThrottle`] scales the whole profile through a [`Throttled`] wrapper (the
//! scaled joint-trajectory controllers' rule), and on a closed contour a [`LearnedPace`]
//! learns, lap over lap, a scale for each stretch. Both are parameters of the field: the
//! coupling stays workless whatever they are.

pub mod drive_limits;
pub mod learned;
pub mod miss;
pub mod table;
pub mod throttle;

pub use drive_limits::{
    drive_limited_rates, drive_limited_rates_on_rows, drive_limited_rates_with_miss, DriveLimits,
    MotionRow,
};
pub use learned::{LearnedPace, PaceLearning};
pub use miss::MissLearner;
pub use table::PaceTable;
pub use throttle::{PaceThrottle, Throttled};

use crate::pacing::{PacingGains, SelfPacing};
use crate::Real;

/// A pace profile `σ(τ) > 0` along the contour and its derivative `dσ/dτ`.
pub trait PaceProfile<T: Real> {
    /// `(σ(τ), dσ/dτ)`.
    fn pace(&self, tau: T) -> (T, T);

    /// Scales the profile on line by `s ∈ (0, 1]` (a [`PaceThrottle`]'s lever), if it can:
    /// `true` when it did. The default has no scale and refuses.
    fn set_scale(&mut self, scale: T) -> bool {
        let _ = scale;
        false
    }

    /// Learns by `rule` from a step at `τ` whose command used `share` of a limit, over `dt`
    /// (a [`LearnedPace`]); `true` when it did. The default does not learn.
    fn learn(&mut self, tau: T, share: T, dt: T, rule: &crate::pace::PaceLearning<T>) -> bool {
        let _ = (tau, share, dt, rule);
        false
    }

    /// Sets the ceilings of a learned pace's scales at its knots (a [`MissLearner`]'s caps),
    /// if it has as many knots; `true` when it did. The default has none and refuses.
    fn set_caps(&mut self, caps: &[T]) -> bool {
        let _ = caps;
        false
    }
}

/// The paper's pace: `σ ≡ 1`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UniformPace;

impl<T: Real> PaceProfile<T> for UniformPace {
    #[inline]
    fn pace(&self, _tau: T) -> (T, T) {
        (T::one(), T::zero())
    }
}

/// No profile (`None`) is the uniform pace `σ ≡ 1`.
impl<T: Real, P: PaceProfile<T>> PaceProfile<T> for Option<P> {
    #[inline]
    fn pace(&self, tau: T) -> (T, T) {
        match self {
            Some(p) => p.pace(tau),
            None => (T::one(), T::zero()),
        }
    }

    #[inline]
    fn set_scale(&mut self, scale: T) -> bool {
        self.as_mut().is_some_and(|p| p.set_scale(scale))
    }

    fn learn(&mut self, tau: T, share: T, dt: T, rule: &crate::pace::PaceLearning<T>) -> bool {
        self.as_mut().is_some_and(|p| p.learn(tau, share, dt, rule))
    }

    fn set_caps(&mut self, caps: &[T]) -> bool {
        self.as_mut().is_some_and(|p| p.set_caps(caps))
    }
}

/// A self-pacing strategy `S` with a pace profile `P` along the contour:
/// `λ₁(U, τ) = σ(τ) λ₁(U)`, `λ₂(U)` unchanged (module documentation).
///
/// ```
/// use pvfc_core::pace::{Paced, PaceTable};
/// use pvfc_core::pacing::{ExponentialPacing, SelfPacing};
/// // Half the pace over the second half of a contour of period 4.
/// let table = PaceTable::<f64, 8>::new(&[1.0, 1.0, 0.5, 0.5], 4.0).unwrap();
/// let pacing = Paced::new(ExponentialPacing::new(100.0).unwrap(), table);
/// let g = pacing.gains(0.0, 2.5);
/// assert!((g.lambda1 - 0.5).abs() < 1e-15 && (g.lambda2 - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Paced<S, P> {
    pacing: S,
    profile: P,
}

impl<S, P> Paced<S, P> {
    /// `pacing`'s gains with `λ₁` scaled by `profile`.
    pub fn new(pacing: S, profile: P) -> Self {
        Paced { pacing, profile }
    }

    /// The self-pacing strategy.
    pub fn pacing(&self) -> &S {
        &self.pacing
    }

    /// The pace profile.
    pub fn profile(&self) -> &P {
        &self.profile
    }

    /// The pace profile, to replace it on line (between steps).
    pub fn profile_mut(&mut self) -> &mut P {
        &mut self.profile
    }
}

impl<T: Real, S: SelfPacing<T>, P: PaceProfile<T>> SelfPacing<T> for Paced<S, P> {
    const DEPENDS_ON_TAU: bool = true;

    #[inline]
    fn gains(&self, u: T, tau: T) -> PacingGains<T> {
        let g = self.pacing.gains(u, tau);
        let (sigma, dsigma) = self.profile.pace(tau);
        PacingGains {
            lambda1: sigma * g.lambda1,
            lambda2: g.lambda2,
            dlambda1: sigma * g.dlambda1,
            dlambda2: g.dlambda2,
            dlambda1_dtau: dsigma * g.lambda1 + sigma * g.dlambda1_dtau,
        }
    }

    #[inline]
    fn set_pace_scale(&mut self, scale: T) -> bool {
        self.profile.set_scale(scale)
    }

    fn learn_pace(&mut self, tau: T, share: T, dt: T, rule: &crate::pace::PaceLearning<T>) -> bool {
        self.profile.learn(tau, share, dt, rule)
    }

    fn set_pace_caps(&mut self, caps: &[T]) -> bool {
        self.profile.set_caps(caps)
    }
}
