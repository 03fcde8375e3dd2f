//! The fictitious flywheel (eqs. 4–6), the passive coupling control (eq. 7), and the
//! add-ons of section V: nominal speed (eq. 36) and friction compensation (eq. 35).

use crate::augmented::{AugmentedState, AugmentedVector};
use crate::error::{Error, ErrorKind, Result};
use crate::field::{FieldSample, VelocityField};
use crate::lie::{LieGroup, Tangent};
use crate::mechanics::MechanicalSystem;
use crate::scalar::cast;
use crate::Real;
use core::marker::PhantomData;
use nalgebra::{SMatrix, SVector};

/// The fictitious flywheel that augments the suspended system (eqs. 4–6): inertia `M_F` and
/// the energy level `Ē` of the augmented field, `½ V_aᵀ M_a V_a = Ē`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flywheel<T: Real> {
    inertia: T,
    energy: T,
    // Reciprocals precomputed for the control step: 2/M_F, 1/M_F, 1/(2Ē).
    two_over_inertia: T,
    inv_inertia: T,
    inv_two_energy: T,
}

impl<T: Real> Flywheel<T> {
    /// A flywheel of inertia `M_F > 0` for the energy level `Ē > 0`.
    pub fn new(inertia: T, energy: T) -> Result<Self> {
        for (x, what) in [
            (inertia, "Flywheel: inertia M_F must be finite and > 0"),
            (energy, "Flywheel: energy level Ē must be finite and > 0"),
        ] {
            if !x.is_finite() {
                return Err(Error::new(ErrorKind::NonFinite, what));
            }
            if x <= T::zero() {
                return Err(Error::new(ErrorKind::InvalidParameter, what));
            }
        }
        let two = cast::<T>(2.0);
        Ok(Flywheel {
            inertia,
            energy,
            two_over_inertia: two / inertia,
            inv_inertia: T::one() / inertia,
            inv_two_energy: T::one() / (two * energy),
        })
    }

    /// `M_F`.
    pub fn inertia(&self) -> T {
        self.inertia
    }

    /// `Ē`.
    pub fn energy(&self) -> T {
        self.energy
    }

    /// `1/M_F`.
    #[inline]
    pub fn inverse_inertia(&self) -> T {
        self.inv_inertia
    }

    /// The flywheel speed that gives the robot at rest `β = 1`: `√(2Ē/M_F)`
    /// (the manual's control law, `docs/src/reference/control-law.md` §5: with everything at rest nothing ever moves).
    pub fn speed_for_unit_beta(&self) -> T {
        (self.energy * cast::<T>(2.0) / self.inertia).sqrt_fast()
    }

    /// Eq. (6): `V_F = +√((2/M_F)(Ē − κ̄))` for the kinetic energy `κ̄ = ½ V̄ᵀM̄V̄` of the
    /// suspended field. `EnergyTooLow` when `κ̄ ≥ Ē` (never a NaN).
    #[inline]
    pub fn field_speed(&self, field_energy: T) -> Result<T> {
        let margin = self.energy - field_energy;
        if margin > T::zero() {
            Ok((margin * self.two_over_inertia).sqrt_fast())
        } else {
            Err(Error::new(
                ErrorKind::EnergyTooLow,
                "flywheel (eq. 6): Ē ≤ ½ V̄ᵀM̄V̄ at this state; raise Ē or bound the field",
            )
            .with_value(nalgebra::try_convert::<T, f64>(-margin).unwrap_or(f64::NAN)))
        }
    }
}

/// Everything computed by one evaluation of the coupling control.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CouplingOutput<T: Real, G, const D: usize> {
    /// `T_a = G q̇_a + γ R q̇_a` (eq. 7): robot torques, `T_τ = τ̈`, and `T_F = M_F q̈_F`.
    pub torque: AugmentedVector<T, D>,
    /// The augmented field `V_a = (V_G, V_I, V_F)`.
    pub field_velocity: AugmentedVector<T, D>,
    /// Desired momentum `P = M_a V_a`.
    pub desired_momentum: AugmentedVector<T, D>,
    /// Actual momentum `p = M_a q̇_a`.
    pub momentum: AugmentedVector<T, D>,
    /// `w = M_a V̇_a + C_a V_a`.
    pub w: AugmentedVector<T, D>,
    /// The augmented kinetic energy `κ_a = ½ q̇_aᵀ M_a q̇_a` (eq. 5).
    pub kinetic_energy: T,
    /// `β = √(κ_a / Ē)` (eq. 10, `γ > 0`).
    pub beta: T,
    /// The energy level `Ē`.
    pub energy_level: T,
    /// `Pᵀq̇_a = ⟨⟨V_a, q̇_a⟩⟩_a`, the momentum along the field: `2Ēβ` on the field.
    pub momentum_along_field: T,
    /// The factor `k ∈ (0, 1]` the suspended field was scaled by to stay within the law's
    /// bound on its kinetic energy ([`PvfcLaw::set_field_energy_bound`]); 1 within it or
    /// without a bound.
    pub field_scale: T,
    /// The field sample (error, `U`, `λ₁`, `λ₂`, ...).
    pub field: FieldSample<T, G, D>,
}

/// `W_β` of eq. (12), `½‖e_β‖²_a` with `e_β = q̇_a − βV_a`, from `κ_a`, `β` and `Pᵀq̇_a`: as
/// `½V_aᵀM_aV_a = Ē` (eq. 6) and `β²Ē = κ_a` (eq. 10), `W_β = κ_a − βPᵀq̇_a + β²Ē =
/// 2κ_a − βPᵀq̇_a` (its rounding is that of `κ_a`, about `1e-16 κ_a` in f64).
#[inline]
pub(crate) fn velocity_field_error_energy<T: Real>(kappa: T, beta: T, along: T) -> T {
    (kappa * cast::<T>(2.0) - beta * along).max(T::zero())
}

/// `μ` of eq. (13), `Ẇ_β = −4Ēγβμ W_β` without environment forces: `μ = ½(1 + Pᵀq̇_a/(2Ēβ))
/// = 1 − W_β/(4κ_a)`. With `F_e = 0`, `d(Pᵀq̇_a)/dt = γ((2Ēβ)² − (Pᵀq̇_a)²)` (the `G` term
/// cancels `q̇_aᵀw`), hence `Ẇ_β = −γ(2Ēβ + Pᵀq̇_a) W_β`: `μ ∈ [0, 1]` is nondecreasing, `0` only
/// at `q̇_a = −βV_a`, and `1` on the field, where `‖e_β‖_a` converges at the rate `2γβĒ`
/// (Remark 1). `0` at rest (`κ_a = 0`).
#[inline]
pub fn convergence_factor<T: Real>(kappa: T, w_beta: T) -> T {
    if kappa > T::zero() {
        T::one() - w_beta / (kappa * cast::<T>(4.0))
    } else {
        T::zero()
    }
}

impl<T: Real, G, const D: usize> CouplingOutput<T, G, D> {
    /// The Lyapunov function `W_β = ½‖q̇_a − βV_a‖²_a` of Remark 1 (eq. 12): the energy of the
    /// velocity-field tracking error.
    pub fn velocity_field_error_energy(&self) -> T {
        velocity_field_error_energy(self.kinetic_energy, self.beta, self.momentum_along_field)
    }

    /// `μ ∈ [0, 1]` of eq. (13), `Ẇ_β = −4Ēγβμ W_β` without environment forces.
    pub fn convergence_factor(&self) -> T {
        convergence_factor(self.kinetic_energy, self.velocity_field_error_energy())
    }

    /// The skew-symmetric matrices `G = (w Pᵀ − P wᵀ)/(2Ē)` and `R = P pᵀ − p Pᵀ` of eq. (7)
    /// as `A × A` matrices, `A = D + 2` (`DimensionMismatch` otherwise). The control step never
    /// forms them: it applies them as rank-two updates.
    pub fn coupling_matrices<const A: usize>(
        &self,
    ) -> Result<(SMatrix<T, A, A>, SMatrix<T, A, A>)> {
        let mismatch = || Error::new(ErrorKind::DimensionMismatch, "coupling_matrices: A ≠ D + 2");
        let wp = self
            .w
            .outer::<A>(&self.desired_momentum)
            .ok_or_else(mismatch)?;
        let pp = self
            .desired_momentum
            .outer::<A>(&self.momentum)
            .ok_or_else(mismatch)?;
        let g = (wp - wp.transpose()) / (self.energy_level * cast::<T>(2.0));
        Ok((g, pp - pp.transpose()))
    }
}

/// Passive velocity field control (eq. 7) of a mechanical system along a velocity field:
/// the flywheel augmentation and the coupling `T_a = G q̇_a + γ R q̇_a`, with
///
/// * `P = M_a V_a` (desired momentum), `p = M_a q̇_a` (actual momentum),
/// * `w = M_a V̇_a + C_a V_a`, with the flywheel entry `w_F = −V̄ᵀ(M̄ V̄̇ + C̄ V̄)/V_F`,
/// * `G = (w Pᵀ − P wᵀ)/(2Ē)`, `R = P pᵀ − p Pᵀ`, both skew-symmetric, so that
///   `q̇_aᵀ T_a = 0`: the control neither creates nor dissipates energy.
///
/// The suspended coordinate `τ` has unit inertia and no Coriolis terms (eq. 14).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PvfcLaw<T: Real, G, Sys, F, const D: usize> {
    system: Sys,
    field: F,
    flywheel: Flywheel<T>,
    gamma: T,
    /// The field and the model are on chains with the same kinematics: computed once per
    /// step for both.
    share_kinematics: bool,
    /// The most kinetic energy `κ̄` the suspended field may have (J): beyond it the field is
    /// scaled onto it ([`set_field_energy_bound`](Self::set_field_energy_bound)).
    field_cap: Option<T>,
    _g: PhantomData<G>,
}

impl<T, G, Sys, F, const D: usize> PvfcLaw<T, G, Sys, F, D>
where
    T: Real,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    /// The law for a plant model, a field, a flywheel and a feedback gain `γ ≥ 0`.
    pub fn new(system: Sys, field: F, flywheel: Flywheel<T>, gamma: T) -> Result<Self> {
        if !gamma.is_finite() {
            return Err(Error::new(ErrorKind::NonFinite, "PvfcLaw: γ"));
        }
        if gamma < T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PvfcLaw: γ must be ≥ 0 (Theorem 1 needs γβ > 0)",
            ));
        }
        let share_kinematics = F::USES_CHAIN_KINEMATICS
            && matches!(
                (system.serial_chain(), field.serial_chain()),
                (Some(model), Some(of_field)) if model.same_kinematics(of_field)
            );
        Ok(PvfcLaw {
            system,
            field,
            flywheel,
            gamma,
            share_kinematics,
            field_cap: None,
            _g: PhantomData,
        })
    }

    /// Bounds the suspended field's kinetic energy `κ̄ = ½V̄ᵀM̄V̄` at `share × Ē`
    /// (`0 < share < 1`): where the field would carry more (far from the contour, where the
    /// navigation function's pull grows, or on an arm thrown off it by a fault) it is scaled
    /// by `k = √(share Ē / κ̄)` onto that level, and its rate `w` with it (including the change
    /// of `k` along the motion). The flywheel keeps `(1 − share) Ē`, so eq. (6) holds at every
    /// state and the law never fails with `EnergyTooLow`; the coupling stays workless (its
    /// matrices are skew-symmetric whatever the field). Within the bound nothing changes, to
    /// the bit. The factor is reported as [`CouplingOutput::field_scale`]. On an error nothing
    /// changes. (A setter rather than a builder: an arm's law is large, and each move of it is
    /// a copy on the stack of an unoptimised build.)
    pub fn set_field_energy_bound(&mut self, share: T) -> Result<()> {
        self.field_cap = Some(field_energy_share(share)? * self.flywheel.energy);
        Ok(())
    }

    /// The bound on the suspended field's kinetic energy, as a share of `Ē`, if any
    /// ([`set_field_energy_bound`](Self::set_field_energy_bound)).
    pub fn field_energy_bound(&self) -> Option<T> {
        self.field_cap.map(|c| c / self.flywheel.energy)
    }

    /// The plant model.
    pub fn system(&self) -> &Sys {
        &self.system
    }

    /// The velocity field.
    pub fn field(&self) -> &F {
        &self.field
    }

    /// Scales the field's pace on line by `s ∈ (0, 1]` ([`VelocityField::set_pace_scale`];
    /// the coupling stays workless whatever the field): `true` when the field took it.
    pub fn set_pace_scale(&mut self, scale: T) -> bool {
        self.field.set_pace_scale(scale)
    }

    /// Lets the field's pace learn ([`VelocityField::learn_pace`]).
    pub fn learn_pace(
        &mut self,
        tau: T,
        share: T,
        dt: T,
        rule: &crate::pace::PaceLearning<T>,
    ) -> bool {
        self.field.learn_pace(tau, share, dt, rule)
    }

    /// Sets the ceilings of the field's learned pace ([`VelocityField::set_pace_caps`]).
    pub fn set_pace_caps(&mut self, caps: &[T]) -> bool {
        self.field.set_pace_caps(caps)
    }

    /// The flywheel.
    pub fn flywheel(&self) -> &Flywheel<T> {
        &self.flywheel
    }

    /// The feedback gain `γ`.
    pub fn gamma(&self) -> T {
        self.gamma
    }

    /// Whether the law computes a serial chain's forward kinematics once per step for the
    /// field and the model (a task-space field on the model's chain; see
    /// [`VelocityField::USES_CHAIN_KINEMATICS`]).
    pub fn shares_kinematics(&self) -> bool {
        self.share_kinematics
    }

    /// The augmented kinetic energy `κ_a` of a state (eq. 5).
    pub fn kinetic_energy(&self, s: &AugmentedState<T, G, D>) -> T {
        self.system.kinetic_energy(&s.q, &s.v)
            + (s.tau_dot * s.tau_dot + self.flywheel.inertia * s.flywheel_speed * s.flywheel_speed)
                * cast::<T>(0.5)
    }

    /// Evaluates the coupling control at a full augmented state: a pure function, no
    /// allocation. Errors: `NonFinite` for a NaN/∞ state, `EnergyTooLow` (eq. 6).
    #[inline]
    pub fn evaluate(&self, s: &AugmentedState<T, G, D>) -> Result<CouplingOutput<T, G, D>> {
        self.evaluate_using(s, None)
    }

    /// [`evaluate`](Self::evaluate), and the plant model's gravity torque `g(q)` (written to
    /// `gravity`) from the same pass over the model, for gravity compensation.
    #[inline]
    pub fn evaluate_with_gravity(
        &self,
        s: &AugmentedState<T, G, D>,
        gravity: &mut Tangent<T, D>,
    ) -> Result<CouplingOutput<T, G, D>> {
        self.evaluate_using(s, Some(gravity))
    }

    /// The law with the model's products from one [`MechanicalSystem::law_products`] (which
    /// also gives `g(q)` when `gravity` asks for it).
    #[inline(always)]
    fn evaluate_using(
        &self,
        s: &AugmentedState<T, G, D>,
        gravity: Option<&mut Tangent<T, D>>,
    ) -> Result<CouplingOutput<T, G, D>> {
        if !s.is_finite() {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "PvfcLaw::evaluate: state has NaN or infinite entries",
            ));
        }
        let half = cast::<T>(0.5);
        // A serial chain's forward kinematics, once for the field and the model when both
        // use them (a compile-time `None` for every other field).
        let kinematics = if F::USES_CHAIN_KINEMATICS && self.share_kinematics {
            self.system.chain_kinematics(&s.q)
        } else {
            None
        };
        let (fs, products) = match &kinematics {
            Some(k) => {
                let fs = self
                    .field
                    .sample_with_kinematics(k, &s.q, &s.v, s.tau, s.tau_dot);
                let products = self.system.law_products_with_kinematics(
                    k,
                    &s.q,
                    &s.v,
                    &fs.velocity,
                    &fs.rate,
                    gravity.is_some(),
                );
                (fs, products)
            }
            None => {
                let fs = self.field.sample(&s.q, &s.v, s.tau, s.tau_dot);
                let products =
                    self.system
                        .law_products(&s.q, &s.v, &fs.velocity, &fs.rate, gravity.is_some());
                (fs, products)
            }
        };
        if let Some(g) = gravity {
            *g = products.gravity;
        }
        let mut mv = products.field_momentum;
        let mut velocity = fs.velocity;
        let mut velocity_tau = fs.velocity_tau;
        let mut w_robot = products.w;
        let mut w_tau = fs.rate_tau;
        let mut field_energy = (mv.dot(&velocity) + velocity_tau * velocity_tau) * half;
        let mut field_scale = T::one();
        if let Some(cap) = self.field_cap {
            if field_energy > cap {
                // The field bounded on the level `κ̄ = cap` (docs/src/reference/control-law.md
                // §4): `V̄' = kV̄` with `k = √(cap/κ̄)`, and its rate `w' = k (w − (κ̄̇/2κ̄) M̄V̄)`,
                // `κ̄̇ = V̄ᵀw` (`M̄V̄̇ + C̄V̄` along the motion, `V̄ᵀC̄V̄ = ½V̄ᵀṀ̄V̄`), so that
                // `V̄'ᵀw' = 0`: the bounded field's energy is constant, and `w_F = 0`.
                field_scale = (cap / field_energy).sqrt_fast();
                let rate = (velocity.dot(&w_robot) + velocity_tau * w_tau) * half / field_energy;
                w_robot = (w_robot - mv * rate) * field_scale;
                w_tau = (w_tau - velocity_tau * rate) * field_scale;
                mv *= field_scale;
                velocity *= field_scale;
                velocity_tau *= field_scale;
                field_energy = cap;
            }
        }
        let vf = self.flywheel.field_speed(field_energy)?;
        let mf = self.flywheel.inertia;
        let e_bar = self.flywheel.energy;

        let w_f = -(velocity.dot(&w_robot) + velocity_tau * w_tau) / vf;
        let w = AugmentedVector::new(w_robot, w_tau, w_f);
        let big_p = AugmentedVector::new(mv, velocity_tau, mf * vf);
        let qa = s.velocity();
        let p = AugmentedVector::new(products.momentum, s.tau_dot, mf * s.flywheel_speed);

        let p_dot_q = big_p.dot(&qa);
        // G q̇_a = (w (Pᵀq̇_a) − P (wᵀq̇_a)) / 2Ē;  R q̇_a = P (pᵀq̇_a) − p (Pᵀq̇_a).
        let g_term = (w * p_dot_q - big_p * w.dot(&qa)) * self.flywheel.inv_two_energy;
        let kappa2 = p.dot(&qa); // 2 κ_a
        let r_term = big_p * kappa2 - p * p_dot_q;
        let torque = g_term + r_term * self.gamma;
        let kinetic_energy = kappa2 * half;
        Ok(CouplingOutput {
            torque,
            field_velocity: AugmentedVector::new(velocity, velocity_tau, vf),
            desired_momentum: big_p,
            momentum: p,
            w,
            kinetic_energy,
            beta: (kappa2 * self.flywheel.inv_two_energy).sqrt_fast(),
            energy_level: e_bar,
            momentum_along_field: p_dot_q,
            field_scale,
            field: fs,
        })
    }
}

/// Nominal-speed control (eq. 36): `T_forced = c · P · (r − Pᵀq̇_a/(2Ē))`, `c > 0`.
///
/// It drives `β → r` by injecting or removing energy along the desired momentum; it is **not**
/// passive (power `c (Pᵀq̇_a)(r − Pᵀq̇_a/(2Ē))`). `r` may be scheduled on line (e.g. on a
/// measured tool force, section V-A) with [`set_speed`](Self::set_speed).
///
/// The law is proportional: against a loss it leaves `β` short of `r` (by about `P_f/(c κ_a)`
/// for a friction power `P_f`). [`with_integral`](Self::with_integral) adds an integral of
/// the speed's error, `T_forced = c · P · (r + z − Pᵀq̇_a/(2Ē))` with
/// `ż = k_i (r − Pᵀq̇_a/(2Ē))`, `|z| ≤ r`, so that `β` settles at `r` exactly. `z` advances in
/// the sampled loop ([`Controller::step`](crate::controller::Controller::step), the passive
/// controller's step) once per period; a pure evaluation of the law holds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NominalSpeed<T: Real> {
    c: T,
    r: T,
    ki: T,
    z: T,
}

impl<T: Real> NominalSpeed<T> {
    /// Gain `c > 0` and nominal speed `r ≥ 0`. The paper uses `c = 0.01`, `r ∈ {1, 2, 3}`.
    pub fn new(c: T, r: T) -> Result<Self> {
        if !(c.is_finite() && r.is_finite()) {
            return Err(Error::new(ErrorKind::NonFinite, "NominalSpeed: c and r"));
        }
        if c <= T::zero() || r < T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "NominalSpeed: need c > 0 and r ≥ 0",
            ));
        }
        Ok(NominalSpeed {
            c,
            r,
            ki: T::zero(),
            z: T::zero(),
        })
    }

    /// Adds the integral of the speed's error with gain `k_i ≥ 0` (1/s; 0: none), starting
    /// at `z = 0`.
    pub fn with_integral(mut self, ki: T) -> Result<Self> {
        if !(ki.is_finite() && ki >= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "NominalSpeed: the integral gain must be finite and ≥ 0",
            ));
        }
        self.ki = ki;
        self.z = T::zero();
        Ok(self)
    }

    /// Changes the nominal speed `r ≥ 0` (the integral is kept, within the new bound `±r`).
    pub fn set_speed(&mut self, r: T) -> Result<()> {
        let n = Self::new(self.c, r)?;
        self.r = n.r;
        self.z = clamp_abs(self.z, self.r);
        Ok(())
    }

    /// The nominal speed `r`.
    pub fn speed(&self) -> T {
        self.r
    }

    /// The integral gain `k_i` (0: a proportional law).
    pub fn integral_gain(&self) -> T {
        self.ki
    }

    /// The integral `z` added to `r`.
    pub fn integral(&self) -> T {
        self.z
    }

    /// Advances the integral over a period `dt` at the speed along the field `Pᵀq̇_a/(2Ē)`
    /// measured at its start (nothing without an integral gain, or for a non-finite speed).
    pub fn integrate(&mut self, speed: T, dt: T) {
        if self.ki > T::zero() && speed.is_finite() && dt.is_finite() {
            self.z = clamp_abs(self.z + self.ki * (self.r - speed) * dt, self.r);
        }
    }

    /// The term of eq. (36) at the state whose coupling output is `out`.
    #[inline]
    pub fn torque<G, const D: usize>(
        &self,
        out: &CouplingOutput<T, G, D>,
        qa: &AugmentedVector<T, D>,
    ) -> AugmentedVector<T, D> {
        let p = &out.desired_momentum;
        let speed = p.dot(qa) / (out.energy_level * cast::<T>(2.0));
        *p * (self.c * (self.r + self.z - speed))
    }
}

/// `x` within `[−bound, bound]`.
fn clamp_abs<T: Real>(x: T, bound: T) -> T {
    if x > bound {
        bound
    } else if x < -bound {
        -bound
    } else {
        x
    }
}

/// Friction compensation (eq. 35): `T_i += fric_i · sign(q̇_i)` on the robot's joints, with an
/// optional linear band `|q̇_i| < ε` in which `sign` is replaced by `q̇_i/ε` (to avoid chatter).
/// The paper uses `fric = (2.0, 3.0)` N·m and a pure sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionCompensation<T: Real, const D: usize> {
    fric: SVector<T, D>,
    band: T,
}

impl<T: Real, const D: usize> FrictionCompensation<T, D> {
    /// Compensation levels `fric_i ≥ 0` with a pure sign.
    pub fn new(fric: SVector<T, D>) -> Result<Self> {
        if !fric.iter().all(|x| x.is_finite()) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "FrictionCompensation: fric",
            ));
        }
        if fric.iter().any(|x| *x < T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "FrictionCompensation: every fric_i must be ≥ 0",
            ));
        }
        Ok(FrictionCompensation {
            fric,
            band: T::zero(),
        })
    }

    /// Replaces `sign(q̇)` by `q̇/ε` for `|q̇| < ε` (`ε ≥ 0`; 0 is the pure sign).
    pub fn with_band(mut self, band: T) -> Result<Self> {
        if !band.is_finite() || band < T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "FrictionCompensation: band must be finite and ≥ 0",
            ));
        }
        self.band = band;
        Ok(self)
    }

    /// The robot torque of eq. (35) at the joint velocity `v`.
    #[inline]
    pub fn torque(&self, v: &Tangent<T, D>) -> Tangent<T, D> {
        let mut t = SVector::zeros();
        for i in 0..D {
            let s = if self.band > T::zero() && v[i].abs() < self.band {
                v[i] / self.band
            } else if v[i] > T::zero() {
                T::one()
            } else if v[i] < T::zero() {
                -T::one()
            } else {
                T::zero()
            };
            t[i] = self.fric[i] * s;
        }
        t
    }
}

/// Checks a share of `Ē` for [`PvfcLaw::set_field_energy_bound`]: finite and in (0, 1).
/// (The one check: a scenario's reader calls it too, to name its key before anything is built.)
pub fn field_energy_share<T: Real>(share: T) -> Result<T> {
    if !share.is_finite() {
        return Err(Error::new(
            ErrorKind::NonFinite,
            "PvfcLaw::set_field_energy_bound: the share of Ē",
        ));
    }
    if !(share > T::zero() && share < T::one()) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            "PvfcLaw::set_field_energy_bound: the share of Ē must be in (0, 1)",
        )
        .with_value(nalgebra::try_convert::<T, f64>(share).unwrap_or(f64::NAN)));
    }
    Ok(share)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;

    #[test]
    fn the_nominal_speeds_integral_grows_while_beta_is_short_and_is_bounded_by_r() {
        let mut n = NominalSpeed::<f64>::new(0.5, 2.0)
            .unwrap()
            .with_integral(0.4)
            .unwrap();
        // β short by 0.1 for 1 s: z = k_i · 0.1 · 1.
        for _ in 0..1000 {
            n.integrate(1.9, 1e-3);
        }
        assert!((n.integral() - 0.04).abs() < 1e-12, "{}", n.integral());
        // A new r keeps z; far too fast for long: z stops at −r.
        n.set_speed(1.0).unwrap();
        assert!((n.integral() - 0.04).abs() < 1e-12);
        for _ in 0..100_000 {
            n.integrate(50.0, 1e-3);
        }
        assert_eq!(n.integral(), -1.0);
        // Non-finite speeds change nothing; a proportional law has no integral.
        n.integrate(f64::NAN, 1e-3);
        assert_eq!(n.integral(), -1.0);
        let mut p = NominalSpeed::<f64>::new(0.5, 2.0).unwrap();
        p.integrate(0.0, 1.0);
        assert_eq!(p.integral(), 0.0);
        assert!(NominalSpeed::<f64>::new(0.5, 2.0)
            .unwrap()
            .with_integral(-1.0)
            .is_err());
    }
}
