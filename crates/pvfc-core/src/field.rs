//! The suspended velocity field on `G × I` (eqs. 18 and 30), its rate, and the group error.

use crate::contour::{Contour, ContourSample};
use crate::lie::{LieGroup, Tangent};
use crate::mechanics::{ChainKinematics, SerialChain};
use crate::navigation::NavigationFunction;
use crate::obstacle::{NoObstacles, Obstacles, Potential};
use crate::pacing::{PacingGains, SelfPacing};
use crate::Real;
use core::marker::PhantomData;

/// Which group error the field is built on (section IV-B).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ErrorConvention {
    /// Eq. (24), the paper's choice: `E(q, τ) = q·x_d(τ)⁻¹`.
    #[default]
    Right,
    /// The left variant `E(q, τ) = x_d(τ)⁻¹·q`, which the paper mentions with "the formulae
    /// properly adjusted": `V_G = λ₁ Ad_{E⁻¹} ξ_d − λ₂ grad U(E)` in body coordinates.
    Left,
}

/// The group error `E(q, τ)` from `q` and `x_d(τ)` in the given convention.
#[inline]
pub fn group_error<T: Real, G: LieGroup<T, D>, const D: usize>(
    convention: ErrorConvention,
    q: &G,
    x_d: &G,
) -> G {
    match convention {
        ErrorConvention::Right => q.compose(&x_d.inverse()),
        ErrorConvention::Left => x_d.inverse().compose(q),
    }
}

/// Everything the coupling control needs of the field at one state of the suspended system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldSample<T: Real, G, const D: usize> {
    /// The contour at `τ`.
    pub contour: ContourSample<T, G, D>,
    /// The group error `E(q, τ)`.
    pub error: G,
    /// `U(E)`; around obstacles, its composition `φ` with their barrier.
    pub potential: T,
    /// `grad U(E)` in body coordinates at `E`.
    pub gradient: Tangent<T, D>,
    /// Self-pacing gain `λ₁`.
    pub lambda1: T,
    /// Self-pacing gain `λ₂`.
    pub lambda2: T,
    /// `V_G(q̄)` in body coordinates at `q`.
    pub velocity: Tangent<T, D>,
    /// `V_I(q̄) = λ₁`, the desired rate of `τ`.
    pub velocity_tau: T,
    /// `V̇_G = (∂V_G/∂q̄)·q̄̇` along the actual motion (analytic).
    pub rate: Tangent<T, D>,
    /// `V̇_I`.
    pub rate_tau: T,
    /// `ε`: the body velocity of the error, `Ė = E·ε̂`, along the actual motion.
    pub error_velocity: Tangent<T, D>,
}

/// The suspended velocity field of eq. (30) (eq. 18 on the torus) for a contour `x_d`,
/// a navigation function `U` and a self-pacing strategy `(λ₁, λ₂)`:
///
/// `V_G = λ₁ (L_E)_* (x_d)_* 1_τ − λ₂ (R_{x_d})_* grad U(E)`, `V_I = λ₁`.
///
/// In body coordinates (right error, eq. 24) this is
/// `V_G = λ₁ ξ_d(τ) − λ₂ Ad_{x_d⁻¹} grad U(E)`; on the torus, eq. (18):
/// `V_i = λ₁ x_d,i'(τ) − λ₂ h_i sin E_i`.
///
/// Its rate along a motion `q̄̇ = (v, τ̇)` is computed analytically
/// ([`evaluate`](Self::evaluate)), with `ε = Ad_{x_d}(v − τ̇ ξ_d)`, `λ̇ = λ'(U) dU·ε`,
/// `d/dt Ad_{x_d⁻¹} g = −τ̇ [ξ_d, Ad_{x_d⁻¹} g] + Ad_{x_d⁻¹} ġ`.
///
/// ```
/// use pvfc_core::prelude::*;
/// use nalgebra::Vector2;
/// let field = SuspendedField::new(
///     Lissajous::<f64, 2>::paper(),
///     TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
///     ExponentialPacing::new(100.0).unwrap(),
/// );
/// let q = Torus::new(Vector2::new(0.0, 1.5)); // on the contour at τ = 0
/// let s = field.evaluate(&q, &Vector2::zeros(), 0.0, 0.0);
/// assert!(s.potential.abs() < 1e-15 && (s.lambda1 - 1.0).abs() < 1e-15);
/// ```
///
/// **Obstacles** (Remark 3, [`crate::obstacle`]): [`with_obstacles`](Self::with_obstacles)
/// replaces `U` by its composition `φ` with the obstacles' barrier `β` (Rimon–Koditschek),
/// the gradient term by `grad_q φ` (speed-limited if asked), and scales the feed-forward and
/// `V_I` by `β`: `V_G = λ₁(φ) β ξ_d − λ₂(φ) grad_q φ`, `V_I = λ₁(φ) β`. Along this field
/// `φ̇ = λ₁ β ∂φ/∂β (dβ·ξ_d) − λ₂ ‖grad_q φ‖²`, negative near the surfaces (where `β → 0`),
/// so the obstacles' surfaces, `φ`'s highest level set, are never reached. Without obstacles
/// ([`NoObstacles`], the default) the field is eq. (30) exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SuspendedField<T, G, X, N, S, const D: usize, O = NoObstacles> {
    contour: X,
    navigation: N,
    pacing: S,
    convention: ErrorConvention,
    obstacles: O,
    _g: PhantomData<(T, G)>,
}

impl<T, G, X, N, S, const D: usize> SuspendedField<T, G, X, N, S, D>
where
    T: Real,
    G: LieGroup<T, D>,
    X: Contour<T, G, D>,
    N: NavigationFunction<T, G, D>,
    S: SelfPacing<T>,
{
    /// The field for the right error `E = q·x_d⁻¹` of eq. (24).
    pub fn new(contour: X, navigation: N, pacing: S) -> Self {
        SuspendedField {
            contour,
            navigation,
            pacing,
            convention: ErrorConvention::Right,
            obstacles: NoObstacles,
            _g: PhantomData,
        }
    }
}

impl<T, G, X, N, S, const D: usize, O> SuspendedField<T, G, X, N, S, D, O>
where
    T: Real,
    G: LieGroup<T, D>,
    X: Contour<T, G, D>,
    N: NavigationFunction<T, G, D>,
    S: SelfPacing<T>,
    O: Obstacles<T, G, D>,
{
    /// The same field around the obstacles `obstacles` (Remark 3).
    pub fn with_obstacles<P: Obstacles<T, G, D>>(
        self,
        obstacles: P,
    ) -> SuspendedField<T, G, X, N, S, D, P> {
        SuspendedField {
            contour: self.contour,
            navigation: self.navigation,
            pacing: self.pacing,
            convention: self.convention,
            obstacles,
            _g: PhantomData,
        }
    }

    /// The obstacles.
    pub fn obstacles(&self) -> &O {
        &self.obstacles
    }

    /// The same field on the other error convention.
    pub fn with_convention(mut self, convention: ErrorConvention) -> Self {
        self.convention = convention;
        self
    }

    /// The contour.
    pub fn contour(&self) -> &X {
        &self.contour
    }

    /// The navigation function.
    pub fn navigation(&self) -> &N {
        &self.navigation
    }

    /// The self-pacing strategy.
    pub fn pacing(&self) -> &S {
        &self.pacing
    }

    /// The error convention.
    pub fn convention(&self) -> ErrorConvention {
        self.convention
    }

    /// The group error `E(q, τ)`.
    #[inline]
    pub fn error(&self, q: &G, tau: T) -> G {
        group_error(self.convention, q, &self.contour.point(tau))
    }

    /// `E_* W` for a tangent vector `W = (W_G, W_I)` at `(q, τ)`, in body coordinates at `E`
    /// (Lemma 1, eq. 29): right error `Ad_{x_d}(W_G − W_I ξ_d)`; left `W_G − W_I Ad_{E⁻¹} ξ_d`.
    pub fn error_pushforward(&self, q: &G, tau: T, w: &Tangent<T, D>, w_tau: T) -> Tangent<T, D> {
        let c = self.contour.sample(tau);
        match self.convention {
            ErrorConvention::Right => c.point.adjoint_apply(&(w - c.velocity * w_tau)),
            ErrorConvention::Left => {
                let e = group_error(self.convention, q, &c.point);
                w - e.adjoint_inverse_apply(&c.velocity) * w_tau
            }
        }
    }

    /// The field `V̄(q, τ)` and its rate `V̄̇` along the motion `q̄̇ = (v, τ̇)`.
    #[inline]
    pub fn evaluate(&self, q: &G, v: &Tangent<T, D>, tau: T, tau_dot: T) -> FieldSample<T, G, D> {
        let c = self.contour.sample(tau);
        // The error, its body velocity ε, and the feed-forward direction (L_E)_*(x_d)_* 1_τ
        // written at q, which depend on the convention.
        let (e, eps, ff) = match self.convention {
            ErrorConvention::Right => (
                q.compose(&c.point.inverse()),
                c.point.adjoint_apply(&(v - c.velocity * tau_dot)),
                c.velocity,
            ),
            ErrorConvention::Left => {
                let e = c.point.inverse().compose(q);
                let ff = e.adjoint_inverse_apply(&c.velocity);
                (e, v - ff * tau_dot, ff)
            }
        };
        let nav = self.navigation.evaluate(&e, &eps);
        // The rate of the feed-forward term, and the gradient term (R_{x_d})_* grad U (right)
        // or grad U itself (left), with its rate.
        let (ff_dot, a, a_dot) = match self.convention {
            ErrorConvention::Right => {
                let a = c.point.adjoint_inverse_apply(&nav.gradient);
                let a_dot = c.point.adjoint_inverse_apply(&nav.gradient_rate)
                    - G::lie_bracket(&c.velocity, &a) * tau_dot;
                (c.acceleration * tau_dot, a, a_dot)
            }
            ErrorConvention::Left => {
                let ff_dot =
                    e.adjoint_inverse_apply(&c.acceleration) * tau_dot - G::lie_bracket(&eps, &ff);
                (ff_dot, nav.gradient, nav.gradient_rate)
            }
        };
        let Some((barrier, composition)) = self.obstacles.barrier(q, v) else {
            let g = self.pacing.gains(nav.value, tau);
            let l1_dot = pace_rate::<T, S>(&g, nav.value_rate, tau_dot);
            let l2_dot = g.dlambda2 * nav.value_rate;
            return FieldSample {
                velocity: ff * g.lambda1 - a * g.lambda2,
                rate: ff * l1_dot + ff_dot * g.lambda1 - a * l2_dot - a_dot * g.lambda2,
                velocity_tau: g.lambda1,
                rate_tau: l1_dot,
                contour: c,
                error: e,
                potential: nav.value,
                gradient: nav.gradient,
                lambda1: g.lambda1,
                lambda2: g.lambda2,
                error_velocity: eps,
            };
        };
        // Around obstacles: U composed with the barrier (RK), `a = grad_q U` (the adjoint is
        // orthogonal, or the identity on the vector groups obstacles live on).
        let potential = Potential {
            value: nav.value,
            value_rate: nav.value_rate,
            gradient: a,
            gradient_rate: a_dot,
        };
        let phi = composition.compose(&potential, &barrier, self.navigation.metric_weight());
        let g = self.pacing.gains(phi.value, tau);
        let l1_dot = pace_rate::<T, S>(&g, phi.value_rate, tau_dot);
        let l2_dot = g.dlambda2 * phi.value_rate;
        let feed = g.lambda1 * phi.feed;
        let feed_dot = l1_dot * phi.feed + g.lambda1 * phi.feed_rate;
        FieldSample {
            velocity: ff * feed - phi.gradient * g.lambda2,
            rate: ff * feed_dot + ff_dot * feed
                - phi.gradient * l2_dot
                - phi.gradient_rate * g.lambda2,
            velocity_tau: feed,
            rate_tau: feed_dot,
            contour: c,
            error: e,
            potential: phi.value,
            gradient: nav.gradient,
            lambda1: g.lambda1,
            lambda2: g.lambda2,
            error_velocity: eps,
        }
    }
}

/// `λ̇₁ = λ₁'(U) U̇ + ∂λ₁/∂τ τ̇`, the second term only for a pacing that depends on `τ`.
#[inline(always)]
pub(crate) fn pace_rate<T: Real, S: SelfPacing<T>>(g: &PacingGains<T>, u_dot: T, tau_dot: T) -> T {
    if S::DEPENDS_ON_TAU {
        g.dlambda1 * u_dot + g.dlambda1_dtau * tau_dot
    } else {
        g.dlambda1 * u_dot
    }
}

/// A velocity field on the suspended space `G × I`, with its rate: what the coupling control
/// of [`crate::coupling::PvfcLaw`] tracks. [`SuspendedField`] is the paper's; implement this
/// trait to plug in another design (it must give the exact rate, not a finite difference).
pub trait VelocityField<T: Real, G: LieGroup<T, D>, const D: usize> {
    /// `V̄(q, τ)` and `V̄̇` along `q̄̇ = (v, τ̇)`.
    fn sample(&self, q: &G, v: &Tangent<T, D>, tau: T, tau_dot: T) -> FieldSample<T, G, D>;

    /// `true` for a field computed from a serial chain's forward kinematics (the task-space
    /// field), which it can take from the caller
    /// ([`sample_with_kinematics`](Self::sample_with_kinematics)) when the plant model is the
    /// same chain: [`PvfcLaw`](crate::coupling::PvfcLaw) then computes them once per step for
    /// both. `false` (the default) leaves that path out of the law entirely.
    const USES_CHAIN_KINEMATICS: bool = false;

    /// The serial chain whose forward kinematics the field uses, if any (`None` by default).
    #[inline]
    fn serial_chain(&self) -> Option<&SerialChain<T, D>> {
        None
    }

    /// [`sample`](Self::sample) given the forward kinematics of
    /// [`serial_chain`](Self::serial_chain) (or of a chain with the
    /// [`same kinematics`](SerialChain::same_kinematics)) at `q`. The default ignores them.
    #[inline]
    fn sample_with_kinematics(
        &self,
        kinematics: &ChainKinematics<T, D>,
        q: &G,
        v: &Tangent<T, D>,
        tau: T,
        tau_dot: T,
    ) -> FieldSample<T, G, D> {
        let _ = kinematics;
        self.sample(q, v, tau, tau_dot)
    }

    /// The period of the field in `τ`, if it has one (a closed contour). The
    /// [`Controller`](crate::controller::Controller) wraps its `τ` into `[0, period)` so that
    /// `τ` keeps its resolution in `f32` however long the machine runs.
    fn period(&self) -> Option<T> {
        None
    }

    /// Scales the field's pace on line by `s ∈ (0, 1]`: `V_I = s σ(τ) λ₁(U)` and the
    /// feed-forward of `V_G` with it (the lever of a [`crate::pace::PaceThrottle`]; the
    /// coupling stays workless whatever the field). `true` when the field has such a scale
    /// and took `s`; the default has none.
    fn set_pace_scale(&mut self, scale: T) -> bool {
        let _ = scale;
        false
    }

    /// Lets the field's pace learn from a step at `τ` whose command used `share` of a limit
    /// over `dt`; `true` when it did. The default does not.
    fn learn_pace(&mut self, tau: T, share: T, dt: T, rule: &crate::pace::PaceLearning<T>) -> bool {
        let _ = (tau, share, dt, rule);
        false
    }

    /// Sets the ceilings of the field's learned pace (a [`crate::pace::MissLearner`]'s caps);
    /// `true` when it did. The default has none.
    fn set_pace_caps(&mut self, caps: &[T]) -> bool {
        let _ = caps;
        false
    }
}

impl<T, G, X, N, S, const D: usize, O> VelocityField<T, G, D>
    for SuspendedField<T, G, X, N, S, D, O>
where
    T: Real,
    G: LieGroup<T, D>,
    X: Contour<T, G, D>,
    N: NavigationFunction<T, G, D>,
    S: SelfPacing<T>,
    O: Obstacles<T, G, D>,
{
    #[inline]
    fn sample(&self, q: &G, v: &Tangent<T, D>, tau: T, tau_dot: T) -> FieldSample<T, G, D> {
        self.evaluate(q, v, tau, tau_dot)
    }

    #[inline]
    fn period(&self) -> Option<T> {
        self.contour.period()
    }

    fn set_pace_scale(&mut self, scale: T) -> bool {
        self.pacing.set_pace_scale(scale)
    }

    fn learn_pace(&mut self, tau: T, share: T, dt: T, rule: &crate::pace::PaceLearning<T>) -> bool {
        self.pacing.learn_pace(tau, share, dt, rule)
    }

    fn set_pace_caps(&mut self, caps: &[T]) -> bool {
        self.pacing.set_pace_caps(caps)
    }
}
