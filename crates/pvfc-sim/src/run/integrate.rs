//! The closed loop `plant + controller` and its fixed-step integration.

use crate::trace::Work;
use pvfc_core::augmented::{AugmentedState, AugmentedVector};
use pvfc_core::controller::Controller;
use pvfc_core::coupling::CouplingOutput;
use pvfc_core::field::VelocityField;
use pvfc_core::lie::{LieGroup, Tangent};
use pvfc_core::mechanics::MechanicalSystem;
use pvfc_core::{Real, Result};

/// The weights of the classical RK4 stages `k1..k4`: a quantity `∫ p dt` integrated along
/// [`ClosedLoop::rk4_with_stages`] is `dt · Σ RK4_WEIGHTS[i] · p(s_i)`.
pub const RK4_WEIGHTS: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];

/// The time derivative of an [`AugmentedState`]: body velocity of `q`, and the rates of the
/// vector-valued states.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Derivative<T: Real, const D: usize> {
    /// Body velocity of `q` (`q̇ = q·v̂`).
    pub q: Tangent<T, D>,
    /// `v̇ = M⁻¹(T + F_e − C v)`.
    pub v: Tangent<T, D>,
    /// `τ̇`.
    pub tau: T,
    /// `τ̈ = T_τ`.
    pub tau_dot: T,
    /// `q̈_F = T_F / M_F`.
    pub flywheel_speed: T,
}

/// One evaluation of the closed loop: the state's rate, the torque applied, and the
/// coupling's internals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evaluation<T: Real, G, const D: usize> {
    /// The rate of the augmented state.
    pub derivative: Derivative<T, D>,
    /// The total augmented torque (coupling + add-ons).
    pub torque: AugmentedVector<T, D>,
    /// The coupling output (field sample, `β`, energy, ...).
    pub coupling: CouplingOutput<T, G, D>,
}

/// A plant in closed loop with a PVFC controller. The plant model may differ from the model
/// inside the controller (to study model mismatch); [`ClosedLoop::matched`] uses the same.
#[derive(Clone, Debug)]
pub struct ClosedLoop<T: Real, G, P, Sys, F, const D: usize> {
    /// The simulated mechanical system.
    pub plant: P,
    /// The controller (its internal states are part of the simulated state, not of this).
    pub controller: Controller<T, G, Sys, F, D>,
}

impl<T, G, Sys, F, const D: usize> ClosedLoop<T, G, Sys, Sys, F, D>
where
    T: Real,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D> + Clone,
    F: VelocityField<T, G, D>,
{
    /// The plant is the controller's own model.
    pub fn matched(controller: Controller<T, G, Sys, F, D>) -> Self {
        ClosedLoop {
            plant: controller.law().system().clone(),
            controller,
        }
    }
}

impl<T, G, P, Sys, F, const D: usize> ClosedLoop<T, G, P, Sys, F, D>
where
    T: Real,
    G: LieGroup<T, D>,
    P: MechanicalSystem<T, G, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    /// The augmented kinetic energy `κ_a` of the *plant* plus the controller's states.
    pub fn kinetic_energy(&self, s: &AugmentedState<T, G, D>) -> T {
        let half: T = pvfc_core::scalar::cast(0.5);
        let mf = self.controller.law().flywheel().inertia();
        self.plant.kinetic_energy(&s.q, &s.v)
            + (s.tau_dot * s.tau_dot + mf * s.flywheel_speed * s.flywheel_speed) * half
    }

    /// The closed-loop vector field at `s` with the environment force `f_e` on the robot,
    /// with the torque and the coupling's internals.
    pub fn evaluate(
        &self,
        s: &AugmentedState<T, G, D>,
        f_e: &Tangent<T, D>,
    ) -> Result<Evaluation<T, G, D>> {
        let (torque, coupling) = self.controller.evaluate(s)?;
        Ok(Evaluation {
            derivative: self.rate(s, &torque, f_e)?,
            torque,
            coupling,
        })
    }

    /// The rate of the augmented state at `s` under the augmented motor torque `torque` (from
    /// [`Controller::evaluate`]) and the environment force `f_e`.
    pub fn rate(
        &self,
        s: &AugmentedState<T, G, D>,
        torque: &AugmentedVector<T, D>,
        f_e: &Tangent<T, D>,
    ) -> Result<Derivative<T, D>> {
        let acc = self.plant.acceleration(&s.q, &s.v, &(torque.robot + f_e))?;
        let mf = self.controller.law().flywheel().inertia();
        Ok(Derivative {
            q: s.v,
            v: acc,
            tau: s.tau_dot,
            tau_dot: torque.tau,
            flywheel_speed: torque.flywheel / mf,
        })
    }

    /// The closed-loop vector field at `s` with the environment force `f_e` on the robot.
    pub fn derivative(
        &self,
        s: &AugmentedState<T, G, D>,
        f_e: &Tangent<T, D>,
    ) -> Result<Derivative<T, D>> {
        Ok(self.evaluate(s, f_e)?.derivative)
    }

    /// One step of RKMK4 (Runge–Kutta–Munthe-Kaas, classical RK4 tableau) of length `dt`,
    /// with the environment force held constant over the step. On a group, `q` is moved by
    /// `q₀·exp(θ)` with `θ' = dexp⁻¹_θ(v) ≈ v − ½[θ, v] + 1/12 [θ, [θ, v]]` (4th order), so it
    /// stays on the group exactly; on abelian groups this is plain RK4.
    pub fn rk4_step(
        &self,
        s: &AugmentedState<T, G, D>,
        dt: T,
        f_e: &Tangent<T, D>,
    ) -> Result<AugmentedState<T, G, D>> {
        self.rk4_step_with(s, dt, |_| *f_e)
    }

    /// One RKMK4 step with an environment force that depends on the state (friction,
    /// contact), evaluated at every stage.
    pub fn rk4_step_with(
        &self,
        s: &AugmentedState<T, G, D>,
        dt: T,
        force: impl Fn(&AugmentedState<T, G, D>) -> Tangent<T, D>,
    ) -> Result<AugmentedState<T, G, D>> {
        let k1 = self.derivative(s, &force(s))?;
        self.rk4_from(s, &k1, dt, force)
    }

    /// [`rk4_step_with`](Self::rk4_step_with) given the first stage `k1` (the derivative at
    /// `s`, e.g. from an [`evaluate`](Self::evaluate) made for logging), saving one
    /// evaluation of the law.
    pub fn rk4_from(
        &self,
        s: &AugmentedState<T, G, D>,
        k1: &Derivative<T, D>,
        dt: T,
        force: impl Fn(&AugmentedState<T, G, D>) -> Tangent<T, D>,
    ) -> Result<AugmentedState<T, G, D>> {
        self.rk4_with_stages(s, k1, dt, |_, _, x| self.derivative(x, &force(x)))
    }

    /// The RKMK4 step with the stage derivatives supplied by `stage(i, c·dt, s_i)` for the
    /// stages `i = 1, 2, 3` (`k2`, `k3`, `k4`; `c·dt` is the stage's time offset, `dt/2` or
    /// `dt`), given `k1` at `s`. A caller that also integrates a power along the step (the
    /// work of a contact force, of friction, of the controller's add-ons) evaluates it at the
    /// same stage states and sums it with [`RK4_WEIGHTS`]: the work is then integrated to
    /// the same order as the energy, and an energy audit's residual is integration error.
    pub fn rk4_with_stages<E>(
        &self,
        s: &AugmentedState<T, G, D>,
        k1: &Derivative<T, D>,
        dt: T,
        stage: impl FnMut(
            usize,
            T,
            &AugmentedState<T, G, D>,
        ) -> core::result::Result<Derivative<T, D>, E>,
    ) -> core::result::Result<AugmentedState<T, G, D>, E> {
        rkmk4(s, k1, dt, stage)
    }
}

/// The RKMK4 step (Runge–Kutta–Munthe-Kaas, classical RK4 tableau) of an augmented state:
/// the one integrator of the simulation. [`ClosedLoop::rk4_with_stages`] steps the closed
/// loop with it; a sampled-data run steps the plant alone under its held torque with it
/// (the internal states' rates are then zero). `stage(i, c·dt, s_i)` gives the derivatives of
/// the stages `i = 1, 2, 3`, given `k1` at `s`.
pub fn rkmk4<T, G, E, const D: usize>(
    s: &AugmentedState<T, G, D>,
    k1: &Derivative<T, D>,
    dt: T,
    mut stage: impl FnMut(
        usize,
        T,
        &AugmentedState<T, G, D>,
    ) -> core::result::Result<Derivative<T, D>, E>,
) -> core::result::Result<AugmentedState<T, G, D>, E>
where
    T: Real,
    G: LieGroup<T, D>,
{
    let half: T = pvfc_core::scalar::cast(0.5);
    let sixth: T = pvfc_core::scalar::cast(1.0 / 6.0);
    let twelfth: T = pvfc_core::scalar::cast(1.0 / 12.0);
    let dexpinv = |theta: &Tangent<T, D>, v: &Tangent<T, D>| {
        let b = G::lie_bracket(theta, v);
        v - b * half + G::lie_bracket(theta, &b) * twelfth
    };
    let at = |theta: &Tangent<T, D>, k: &Derivative<T, D>, c: T| AugmentedState {
        q: s.q.compose(&G::exp(theta)),
        v: s.v + k.v * (c * dt),
        tau: s.tau + k.tau * (c * dt),
        tau_dot: s.tau_dot + k.tau_dot * (c * dt),
        flywheel_speed: s.flywheel_speed + k.flywheel_speed * (c * dt),
    };
    let k1 = *k1;
    let t1 = k1.q; // θ = 0
    let th2 = t1 * (half * dt);
    let s2 = at(&th2, &k1, half);
    let k2 = stage(1, half * dt, &s2)?;
    let t2 = dexpinv(&th2, &k2.q);
    let th3 = t2 * (half * dt);
    let s3 = at(&th3, &k2, half);
    let k3 = stage(2, half * dt, &s3)?;
    let t3 = dexpinv(&th3, &k3.q);
    let th4 = t3 * dt;
    let s4 = at(&th4, &k3, T::one());
    let k4 = stage(3, dt, &s4)?;
    let t4 = dexpinv(&th4, &k4.q);
    let w = dt * sixth;
    let two = T::one() + T::one();
    let theta = (t1 + t2 * two + t3 * two + t4) * w;
    Ok(AugmentedState {
        q: s.q.compose(&G::exp(&theta)).normalized(),
        v: s.v + (k1.v + k2.v * two + k3.v * two + k4.v) * w,
        tau: s.tau + (k1.tau + k2.tau * two + k3.tau * two + k4.tau) * w,
        tau_dot: s.tau_dot + (k1.tau_dot + k2.tau_dot * two + k3.tau_dot * two + k4.tau_dot) * w,
        flywheel_speed: s.flywheel_speed
            + (k1.flywheel_speed
                + k2.flywheel_speed * two
                + k3.flywheel_speed * two
                + k4.flywheel_speed)
                * w,
    })
}

impl Work {
    /// Adds one RK4 step of length `h` given the powers at its four stages.
    pub(crate) fn add(&mut self, h: f64, p: &[[f64; 4]; 4]) {
        for (w, pi) in RK4_WEIGHTS.iter().zip(p) {
            for (acc, x) in self.0.iter_mut().zip(pi) {
                *acc += h * w * x;
            }
        }
    }
}
