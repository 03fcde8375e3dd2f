//! The controller of a digital loop: it owns `τ`, `τ̇` and the flywheel speed.

use crate::augmented::{AugmentedState, AugmentedVector};
use crate::coupling::{CouplingOutput, FrictionCompensation, NominalSpeed, PvfcLaw};
use crate::error::{Error, ErrorKind, Result};
use crate::field::VelocityField;
use crate::lie::{LieGroup, Tangent};
use crate::mechanics::MechanicalSystem;
use crate::Real;

/// The controller's internal states (section III-B): `τ`, `τ̇` and the flywheel speed `q̇_F`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InternalState<T: Real> {
    /// Contour parameter `τ`.
    pub tau: T,
    /// Its rate `τ̇`.
    pub tau_dot: T,
    /// Flywheel speed `q̇_F`.
    pub flywheel_speed: T,
    /// Whole periods of the contour that `τ` has been wrapped by (the unwrapped parameter is
    /// `τ + laps·period`); stays 0 for contours without a period.
    pub laps: i64,
}

impl<T: Real> InternalState<T> {
    /// The unwrapped contour parameter `τ + laps·period`.
    pub fn unwrapped_tau(&self, period: Option<T>) -> T {
        match period {
            Some(p) => self.tau + p * crate::scalar::cast::<T>(self.laps as f64),
            None => self.tau,
        }
    }
}

/// The quantities a user logs or monitors at every step (section V's figures plot them).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Diagnostics<T: Real> {
    /// The contour error `U(E)`.
    pub potential: T,
    /// Self-pacing gain `λ₁` (the desired `τ̇` is `βλ₁`).
    pub lambda1: T,
    /// Self-pacing gain `λ₂`.
    pub lambda2: T,
    /// `β = √(κ_a/Ē)`: the speed along the field.
    pub beta: T,
    /// The augmented kinetic energy `κ_a` (eq. 5).
    pub kinetic_energy: T,
    /// The flywheel entry `V_F` of the augmented field (eq. 6).
    pub flywheel_field_speed: T,
    /// `Pᵀq̇_a`, the momentum along the field (`2Ēβ` on the field).
    pub momentum_along_field: T,
}

impl<T: Real> Diagnostics<T> {
    /// The Lyapunov function `W_β = ½‖q̇_a − βV_a‖²_a` of Remark 1 (eq. 12).
    pub fn velocity_field_error_energy(&self) -> T {
        crate::coupling::velocity_field_error_energy(
            self.kinetic_energy,
            self.beta,
            self.momentum_along_field,
        )
    }

    /// `μ ∈ [0, 1]` of eq. (13), `Ẇ_β = −4Ēγβμ W_β` without environment forces.
    pub fn convergence_factor(&self) -> T {
        crate::coupling::convergence_factor(self.kinetic_energy, self.velocity_field_error_energy())
    }
}

impl<T: Real, G, const D: usize> From<&CouplingOutput<T, G, D>> for Diagnostics<T> {
    fn from(o: &CouplingOutput<T, G, D>) -> Self {
        Diagnostics {
            potential: o.field.potential,
            lambda1: o.field.lambda1,
            lambda2: o.field.lambda2,
            beta: o.beta,
            kinetic_energy: o.kinetic_energy,
            flywheel_field_speed: o.field_velocity.flywheel,
            momentum_along_field: o.momentum_along_field,
        }
    }
}

/// What one control step returns (kept small: a microcontroller copies it every sample; the
/// full [`CouplingOutput`] is what [`Controller::evaluate`] returns).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOutput<T: Real, const D: usize> {
    /// The motor torques to apply: coupling + nominal speed + friction and gravity
    /// compensation.
    pub torque: Tangent<T, D>,
    /// The whole augmented torque (robot, `τ`, flywheel) that was applied.
    pub augmented_torque: AugmentedVector<T, D>,
    /// The internal states the torque was computed at (before the update).
    pub state: InternalState<T>,
    /// `U`, `λ₁`, `λ₂`, `β`, `κ_a`, `V_F` at the state the torque was computed at.
    pub diagnostics: Diagnostics<T>,
}

#[cfg(feature = "defmt")]
impl<T: Real + defmt::Format, const D: usize> defmt::Format for StepOutput<T, D> {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "StepOutput {{ torque: [");
        for (i, t) in self.torque.iter().enumerate() {
            if i > 0 {
                defmt::write!(f, ", ");
            }
            defmt::write!(f, "{}", t);
        }
        defmt::write!(
            f,
            "], state: {}, diagnostics: {} }}",
            self.state,
            self.diagnostics
        );
    }
}

/// PVFC for a sampled-data loop: a [`PvfcLaw`] plus the optional add-ons of section V and
/// the internal states.
///
/// [`step`](Self::step)`(q, q̇, dt)` evaluates the law at the measured `(q, q̇)` and the current
/// internal states, then advances the internal states over `dt` with the **semi-implicit
/// (symplectic) Euler** scheme, treating the torques as held over the sample:
/// `τ̇ ← τ̇ + dt·T_τ`, `τ ← τ + dt·τ̇(new)`, `q̇_F ← q̇_F + dt·T_F/M_F`.
/// For a periodic contour `τ` is then wrapped into `[0, period)` (counting
/// [`laps`](InternalState::laps)), so that an `f32` controller keeps its resolution in `τ`
/// over arbitrarily long runs. On any error the internal states are left as they were.
///
/// [`evaluate`](Self::evaluate) is the same law as a pure function of a full
/// [`AugmentedState`], for simulations that integrate the internal states themselves.
///
/// ```
/// use pvfc_core::prelude::*;
/// use nalgebra::Vector2;
/// let field = SuspendedField::new(
///     Lissajous::<f64, 2>::paper(),
///     TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
///     ExponentialPacing::new(100.0).unwrap(),
/// );
/// let flywheel = Flywheel::new(1.0, 50.0).unwrap();
/// let law = PvfcLaw::new(Scara::pelican(), field, flywheel, 0.05).unwrap();
/// let mut ctl = Controller::new(law).starting_at_rest(0.0);
/// let out = ctl.step(&Torus::new(Vector2::new(0.0, 0.0)), &Vector2::zeros(), 1e-3).unwrap();
/// assert!(out.torque.iter().all(|t| t.is_finite()));
/// // NaN in, an error out, nothing lost:
/// let before = *ctl.state();
/// assert!(ctl.step(&Torus::new(Vector2::new(f64::NAN, 0.0)), &Vector2::zeros(), 1e-3).is_err());
/// assert_eq!(*ctl.state(), before);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controller<T: Real, G, Sys, F, const D: usize> {
    law: PvfcLaw<T, G, Sys, F, D>,
    nominal: Option<NominalSpeed<T>>,
    friction: Option<FrictionCompensation<T, D>>,
    gravity_compensation: bool,
    state: InternalState<T>,
}

impl<T, G, Sys, F, const D: usize> Controller<T, G, Sys, F, D>
where
    T: Real,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    /// A controller with `τ = τ̇ = 0` and the flywheel at rest. With the robot at rest too,
    /// nothing would ever move: use [`starting_at_rest`](Self::starting_at_rest) or
    /// [`with_state`](Self::with_state).
    pub fn new(law: PvfcLaw<T, G, Sys, F, D>) -> Self {
        Controller {
            law,
            nominal: None,
            friction: None,
            gravity_compensation: false,
            state: InternalState {
                tau: T::zero(),
                tau_dot: T::zero(),
                flywheel_speed: T::zero(),
                laps: 0,
            },
        }
    }

    /// Starts at `τ₀` with `τ̇ = 0` and all the energy `Ē` in the flywheel,
    /// `q̇_F = √(2Ē/M_F)`: with the robot at rest, `β = 1`.
    pub fn starting_at_rest(mut self, tau0: T) -> Self {
        self.state = InternalState {
            tau: tau0,
            tau_dot: T::zero(),
            flywheel_speed: self.law.flywheel().speed_for_unit_beta(),
            laps: 0,
        };
        self
    }

    /// Sets the internal states.
    pub fn with_state(mut self, state: InternalState<T>) -> Self {
        self.state = state;
        self
    }

    /// Adds nominal-speed control (eq. 36).
    pub fn with_nominal_speed(mut self, nominal: NominalSpeed<T>) -> Self {
        self.nominal = Some(nominal);
        self
    }

    /// Adds friction compensation (eq. 35).
    pub fn with_friction_compensation(mut self, friction: FrictionCompensation<T, D>) -> Self {
        self.friction = Some(friction);
        self
    }

    /// Adds gravity compensation: `T = T_pvfc + g(q)` with the plant model's
    /// [`MechanicalSystem::gravity`] (nothing for a system without gravity,
    /// [`MechanicalSystem::HAS_GRAVITY`] `= false`, such as the horizontal SCARA).
    ///
    /// Why the loop stays passive: the plant is `M q̈ + C q̇ + g(q) = T + F_e`; with
    /// `T = T_a + g(q)` the gravity terms cancel and the closed loop is exactly the
    /// gravity-free one of Theorem 1, `M_a q̈_a + C_a q̇_a = T_a + F_e` with `q̇_aᵀT_a = 0`, so
    /// `d/dt κ_a = q̇ᵀF_e`. Gravity's work is cancelled as it is done, not stored in `κ_a`: the
    /// robot's potential energy is not part of the storage, and the bound on the energy
    /// the robot can give the environment is `κ_a`, as for the horizontal arm. (If the model's
    /// `g` differs from the plant's, the difference is an external force like `F_e`.)
    pub fn with_gravity_compensation(mut self) -> Self {
        self.gravity_compensation = true;
        self
    }

    /// The law.
    pub fn law(&self) -> &PvfcLaw<T, G, Sys, F, D> {
        &self.law
    }

    /// The internal states.
    pub fn state(&self) -> &InternalState<T> {
        &self.state
    }

    /// The nominal-speed add-on, to schedule `r` on line.
    pub fn nominal_speed_mut(&mut self) -> Option<&mut NominalSpeed<T>> {
        self.nominal.as_mut()
    }

    /// Advances the nominal speed's integral ([`NominalSpeed::with_integral`]) over a period
    /// `dt` from the speed along the field `Pᵀq̇_a/(2Ē)` of the step's `diagnostics`.
    pub(crate) fn integrate_nominal_speed(&mut self, diagnostics: &Diagnostics<T>, dt: T) {
        let e_bar = self.law.flywheel().energy();
        if let Some(n) = self.nominal.as_mut() {
            n.integrate(diagnostics.momentum_along_field / (e_bar + e_bar), dt);
        }
    }

    /// Scales the field's pace on line by `s ∈ (0, 1]` (between steps;
    /// [`PvfcLaw::set_pace_scale`]): `true` when the field took it.
    pub fn set_pace_scale(&mut self, scale: T) -> bool {
        self.law.set_pace_scale(scale)
    }

    /// Lets the field's pace learn from a step at `τ` ([`PvfcLaw::learn_pace`]).
    pub fn learn_pace(
        &mut self,
        tau: T,
        share: T,
        dt: T,
        rule: &crate::pace::PaceLearning<T>,
    ) -> bool {
        self.law.learn_pace(tau, share, dt, rule)
    }

    /// Bounds the suspended field's kinetic energy at `share × Ē` (between steps;
    /// [`PvfcLaw::set_field_energy_bound`]). On an error nothing changes.
    pub fn set_field_energy_bound(&mut self, share: T) -> Result<()> {
        self.law.set_field_energy_bound(share)
    }

    /// Sets the ceilings of the field's learned pace (a [`crate::pace::MissLearner`]'s caps;
    /// [`PvfcLaw::set_pace_caps`]); `true` when the field took them.
    pub fn set_pace_caps(&mut self, caps: &[T]) -> bool {
        self.law.set_pace_caps(caps)
    }

    /// The full augmented torque at a full augmented state (coupling + add-ons), and the
    /// coupling output: a pure function.
    pub fn evaluate(
        &self,
        s: &AugmentedState<T, G, D>,
    ) -> Result<(AugmentedVector<T, D>, CouplingOutput<T, G, D>)> {
        self.evaluate_then(s, |out| *out)
    }

    /// [`evaluate`](Self::evaluate) keeping only what `finish` takes of the coupling output.
    /// The output is large (the field's sample, the coupling's matrices): a caller that needs
    /// a few of its numbers at every evaluation (a simulator's integration stages) saves
    /// copying it out.
    #[inline(always)]
    pub fn evaluate_then<R>(
        &self,
        s: &AugmentedState<T, G, D>,
        finish: impl FnOnce(&CouplingOutput<T, G, D>) -> R,
    ) -> Result<(AugmentedVector<T, D>, R)> {
        if Sys::HAS_GRAVITY && self.gravity_compensation {
            return self.evaluate_compensated(s, finish);
        }
        let out = self.law.evaluate(s)?;
        Ok((self.add_ons(s, &out), finish(&out)))
    }

    /// What [`step`](Self::step) needs of the law: the total torque and the diagnostics. The
    /// law's large output stays in this function (moving it out cost the f32 SCARA step three
    /// `memcpy`s, ~210 instructions on a Cortex-M4, measured).
    #[inline(always)]
    fn torque_and_diagnostics(
        &self,
        s: &AugmentedState<T, G, D>,
    ) -> Result<(AugmentedVector<T, D>, Diagnostics<T>)> {
        if Sys::HAS_GRAVITY && self.gravity_compensation {
            return self.evaluate_compensated(s, |out| Diagnostics::from(out));
        }
        let out = self.law.evaluate(s)?;
        Ok((self.add_ons(s, &out), Diagnostics::from(&out)))
    }

    /// The coupling's torque, the add-ons' (nominal speed, friction and gravity compensation)
    /// and the diagnostics, for a sibling stepper ([`crate::passive`]); the law's large
    /// output stays in this function. The add-ons are computed on their own, not as the
    /// total less the coupling (which loses the coupling's low bits, and in `f32` cost the
    /// passive step a store-forwarding stall on x86, measured with perf).
    #[inline(always)]
    pub(crate) fn coupling_add_ons_diagnostics(
        &self,
        s: &AugmentedState<T, G, D>,
    ) -> Result<(AugmentedVector<T, D>, AugmentedVector<T, D>, Diagnostics<T>)> {
        if Sys::HAS_GRAVITY && self.gravity_compensation {
            let (total, (coupling, d)) =
                self.evaluate_compensated(s, |out| (out.torque, Diagnostics::from(out)))?;
            return Ok((coupling, total - coupling, d));
        }
        let out = self.law.evaluate(s)?;
        let add_ons = self.add_ons_onto(AugmentedVector::zeros(), s, &out);
        Ok((out.torque, add_ons, Diagnostics::from(&out)))
    }

    /// [`evaluate`](Self::evaluate) with gravity compensation: `g(q)` comes from the law's own
    /// pass over the model; `finish` takes what the caller needs of the law's output (the
    /// step only its diagnostics: returning the whole output cost a 6-joint f32 step ~400
    /// instructions of copies on a Cortex-M4, measured). Kept out of line so that the
    /// uncompensated step (the paper's horizontal SCARA) compiles as it did (inlined, it
    /// cost that step ~9 %, measured).
    #[inline(never)]
    fn evaluate_compensated<R>(
        &self,
        s: &AugmentedState<T, G, D>,
        finish: impl FnOnce(&CouplingOutput<T, G, D>) -> R,
    ) -> Result<(AugmentedVector<T, D>, R)> {
        let mut gravity = Tangent::zeros();
        let out = self.law.evaluate_with_gravity(s, &mut gravity)?;
        let mut total = self.add_ons(s, &out);
        total.robot += gravity;
        Ok((total, finish(&out)))
    }

    /// The coupling torque plus nominal speed and friction compensation.
    #[inline(always)]
    fn add_ons(
        &self,
        s: &AugmentedState<T, G, D>,
        out: &CouplingOutput<T, G, D>,
    ) -> AugmentedVector<T, D> {
        self.add_ons_onto(out.torque, s, out)
    }

    /// `base` plus the nominal speed (36) and friction compensation (35), added in that order.
    #[inline(always)]
    fn add_ons_onto(
        &self,
        mut base: AugmentedVector<T, D>,
        s: &AugmentedState<T, G, D>,
        out: &CouplingOutput<T, G, D>,
    ) -> AugmentedVector<T, D> {
        if let Some(n) = &self.nominal {
            base = base + n.torque(out, &s.velocity());
        }
        if let Some(f) = &self.friction {
            base.robot += f.torque(&s.v);
        }
        base
    }

    /// Wraps `τ` into `[0, period)` for a periodic contour, counting the laps: one period
    /// crossed is the usual case (no division, no floor); several at once (a huge `dt`) take
    /// one floor division in `T` (no f64 on an f32 target).
    #[inline(always)]
    pub(crate) fn wrap_tau(&self, mut tau: T, mut laps: i64) -> Result<(T, i64)> {
        let overflow = Error::new(
            ErrorKind::NonFinite,
            "Controller::step: the internal states overflowed (is dt far too large?)",
        );
        if let Some(period) = self.law.field().period() {
            if tau >= T::zero() && tau < period {
                // Within the period: the usual step.
                return Ok((tau, laps));
            }
            if tau >= period && tau < period + period {
                // One period crossed forwards, once a lap (no division, no floor).
                tau -= period;
                laps = laps.saturating_add(1);
            } else if tau < T::zero() && tau >= -period {
                tau += period;
                laps = laps.saturating_sub(1);
            } else {
                // Several periods at once (a huge dt): one floor division, in T (no f64 on an
                // f32 target).
                let k = (tau / period).floor();
                let whole = k.to_i64_checked().ok_or(overflow)?;
                if whole.unsigned_abs() >= 1_000_000_000_000_000 {
                    return Err(overflow);
                }
                tau -= k * period;
                laps = laps.saturating_add(whole);
            }
            if tau >= period || tau < T::zero() {
                // Rounding at the boundary of a period.
                tau = T::zero();
            }
        }
        Ok((tau, laps))
    }

    /// The internal states, to be set by a sibling stepper ([`crate::passive`]).
    pub(crate) fn state_mut(&mut self) -> &mut InternalState<T> {
        &mut self.state
    }

    /// One control step at the measured `(q, q̇)`; see the type's documentation.
    pub fn step(&mut self, q: &G, v: &Tangent<T, D>, dt: T) -> Result<StepOutput<T, D>> {
        if !(dt.is_finite() && dt > T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "Controller::step: dt must be finite and > 0",
            ));
        }
        let s = AugmentedState {
            q: *q,
            v: *v,
            tau: self.state.tau,
            tau_dot: self.state.tau_dot,
            flywheel_speed: self.state.flywheel_speed,
        };
        let (total, diagnostics) = self.torque_and_diagnostics(&s)?;
        if !total.is_finite() {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "Controller::step: torque overflowed",
            ));
        }
        let before = self.state;
        let tau_dot = before.tau_dot + total.tau * dt;
        let tau = before.tau + tau_dot * dt;
        let flywheel_speed =
            before.flywheel_speed + total.flywheel * dt * self.law.flywheel().inverse_inertia();
        let overflow = Error::new(
            ErrorKind::NonFinite,
            "Controller::step: the internal states overflowed (is dt far too large?)",
        );
        if !crate::scalar::all_finite([&tau, &tau_dot, &flywheel_speed]) {
            return Err(overflow);
        }
        let (tau, laps) = self.wrap_tau(tau, before.laps)?;
        self.state = InternalState {
            tau,
            tau_dot,
            flywheel_speed,
            laps,
        };
        self.integrate_nominal_speed(&diagnostics, dt);
        Ok(StepOutput {
            torque: total.robot,
            augmented_torque: total,
            state: before,
            diagnostics,
        })
    }
}

/// The paper's setting as one concrete type (the SCARA on a Lissajous contour, the torus
/// navigation function of eq. 17, exponential self-pacing), so that firmware can name the
/// controller it keeps in a `static` without spelling ten generic parameters:
/// `static CTL: Mutex<RefCell<Option<ScaraLissajousController<f32>>>>`.
pub type ScaraLissajousController<T> = Controller<
    T,
    crate::lie::Torus<T, 2>,
    crate::mechanics::Scara<T>,
    crate::field::SuspendedField<
        T,
        crate::lie::Torus<T, 2>,
        crate::contour::Lissajous<T, 2>,
        crate::navigation::TorusNavigation<T, 2>,
        crate::pacing::ExponentialPacing<T>,
        2,
    >,
    2,
>;

impl<T: Real> ScaraLissajousController<T> {
    /// The core example in any scalar: the Pelican SCARA (`Scara::pelican`) on the paper's
    /// Lissajous contour, the torus navigation function of eq. (17) with `h = (1, 1)`,
    /// exponential self-pacing `R = 100` (eq. 21), `Ē = 50`, `M_F = 1`, `γ = 0.05`, from rest at
    /// `τ = 0` with all of `Ē` in the flywheel, no add-ons (add them with the `with_*`
    /// builders). The same controller as `pvfc_sim::scenario::presets::pelican_example`'s.
    ///
    /// ```
    /// use pvfc_core::controller::ScaraLissajousController;
    /// let ctl = ScaraLissajousController::<f32>::pelican_example().unwrap();
    /// assert_eq!(ctl.state().tau_dot, 0.0);
    /// ```
    pub fn pelican_example() -> Result<Self> {
        use crate::contour::Lissajous;
        use crate::coupling::Flywheel;
        use crate::field::SuspendedField;
        use crate::mechanics::Scara;
        use crate::navigation::TorusNavigation;
        use crate::pacing::ExponentialPacing;
        use crate::scalar::cast;
        let field = SuspendedField::new(
            Lissajous::paper(),
            TorusNavigation::paper(nalgebra::Vector2::new(T::one(), T::one()))?,
            ExponentialPacing::new(cast(100.0))?,
        );
        let law = PvfcLaw::new(
            Scara::pelican(),
            field,
            Flywheel::new(T::one(), cast(50.0))?,
            cast(0.05),
        )?;
        Ok(Controller::new(law).starting_at_rest(T::zero()))
    }
}
