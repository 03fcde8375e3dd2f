//! A velocity field built on the tool's error to a path in Cartesian space, pulled back to
//! the joints through the Jacobian: the task-space counterpart of
//! [`SuspendedField`](crate::field::SuspendedField), for a serial chain. The coupling is unchanged, so
//! passivity holds as for any field (it is a property of the coupling, eq. 9).
//!
//! With the tool position `x(q)`, the path `p_d(τ)` (a contour on `ℝ³`), the error
//! `e = x(q) − p_d(τ)` and the navigation function `U = ½ k |e|²`:
//!
//! * the desired tool velocity `w = λ₁ p_d'(τ) − λ₂ k e` (eq. 30's two terms, in the task
//!   space: along the path, and down the gradient of `U`), with the self-pacing gains
//!   `λ₁(U)`, `λ₂(U)` of eq. (21);
//! * the joint field `V_q = J⁺ w + (I − J⁺J) g_r log(q⁻¹ q_r)`, `J` the tool's position
//!   Jacobian, `J⁺ = Jᵀ (J Jᵀ + μ² I)⁻¹` the damped least-squares inverse (bounded near a
//!   singularity: `|J⁺| ≤ 1/(2μ)`), and an optional pull towards a rest posture `q_r` in the
//!   null space of the task (for arms with more than three joints);
//! * `V_τ = λ₁`.
//!
//! The rate along the motion `(q̇, τ̇)` is analytic: `J̇` from the spatial axes'
//! rates `ṡ_i = V_{i−1} × s_i` (the velocity of link `i − 1` crossed into joint `i`'s axis),
//! `d(J⁺)/dt = J̇ᵀ A⁻¹ − Jᵀ A⁻¹ (J̇ Jᵀ + J J̇ᵀ) A⁻¹` with `A = J Jᵀ + μ² I`, and
//! `ẇ = λ̇₁ p_d' + λ₁ p_d'' τ̇ − λ̇₂ k e − λ₂ k ė`, `ė = J q̇ − p_d' τ̇`, `λ̇ = λ'(U) k eᵀė`.

use crate::contour::{Contour, ContourSample};
use crate::error::{Error, ErrorKind, Result};
use crate::field::{FieldSample, VelocityField};
use crate::lie::{JointSpace, LieGroup, Rn};
use crate::mechanics::SerialChain;
use crate::pacing::SelfPacing;
use crate::scalar::cast;
use crate::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// The task-space velocity field of a serial chain on a Cartesian path `X` (a contour on
/// `ℝ³`, e.g. a periodic B-spline through points of the path), with self-pacing `S`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaskSpaceField<T: Real, X, S, const N: usize> {
    chain: SerialChain<T, N>,
    path: X,
    pacing: S,
    stiffness: T,
    damping: T,
    rest: Option<(SVector<T, N>, T)>,
}

/// The tool's position Jacobian and its rate at one state.
struct TaskKinematics<T: Real, const N: usize> {
    x: Vector3<T>,
    x_dot: Vector3<T>,
    jac: SMatrix<T, 3, N>,
    jac_dot: SMatrix<T, 3, N>,
}

impl<T, X, S, const N: usize> TaskSpaceField<T, X, S, N>
where
    T: Real,
    X: Contour<T, Rn<T, 3>, 3>,
    S: SelfPacing<T>,
{
    /// The field of `chain`'s tool on `path`, with `U = ½ k |e|²` (`stiffness` `k` > 0, 1/s
    /// when `λ₂ = 1`) and the damping `μ` > 0 (m) of the Jacobian's inverse.
    pub fn new(
        chain: SerialChain<T, N>,
        path: X,
        pacing: S,
        stiffness: T,
        damping: T,
    ) -> Result<Self> {
        let positive = |x: T| x.is_finite() && x > T::zero();
        if !positive(stiffness) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "TaskSpaceField: stiffness must be finite and > 0",
            ));
        }
        if !positive(damping) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "TaskSpaceField: damping must be finite and > 0 (it bounds the field at singularities)",
            ));
        }
        Ok(TaskSpaceField {
            chain,
            path,
            pacing,
            stiffness,
            damping,
            rest: None,
        })
    }

    /// With a pull of `gain` (1/s, ≥ 0) towards the posture `rest` in the null space of the
    /// task.
    pub fn with_rest(mut self, rest: SVector<T, N>, gain: T) -> Result<Self> {
        if !(rest.iter().all(|x| x.is_finite()) && gain.is_finite() && gain >= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "TaskSpaceField: the rest posture and its gain must be finite (gain ≥ 0)",
            ));
        }
        self.rest = Some((rest, gain));
        Ok(self)
    }

    /// The chain.
    pub fn chain(&self) -> &SerialChain<T, N> {
        &self.chain
    }

    /// The path.
    pub fn path(&self) -> &X {
        &self.path
    }

    /// The tool position, its velocity, and the position Jacobian with its rate.
    fn kinematics(&self, q: &SVector<T, N>, v: &SVector<T, N>) -> TaskKinematics<T, N> {
        let k = self.chain.kinematics(q);
        let x = k.link_poses[N - 1].compose(self.chain.tool()).translation;
        let split = |s: &SVector<T, 6>| {
            (
                Vector3::new(s[0], s[1], s[2]),
                Vector3::new(s[3], s[4], s[5]),
            )
        };
        let mut jac = SMatrix::<T, 3, N>::zeros();
        for (i, s) in k.axes.iter().enumerate() {
            let (w, l) = split(s);
            jac.set_column(i, &(l + w.cross(&x)));
        }
        let x_dot = jac * v;
        // ṡ_i = V × s_i with V the spatial velocity of the links before joint i.
        let (mut om, mut nu) = (Vector3::zeros(), Vector3::zeros());
        let mut jac_dot = SMatrix::<T, 3, N>::zeros();
        for (i, s) in k.axes.iter().enumerate() {
            let (w, l) = split(s);
            let w_dot = om.cross(&w);
            let l_dot = om.cross(&l) + nu.cross(&w);
            jac_dot.set_column(i, &(l_dot + w_dot.cross(&x) + w.cross(&x_dot)));
            om += w * v[i];
            nu += l * v[i];
        }
        TaskKinematics {
            x,
            x_dot,
            jac,
            jac_dot,
        }
    }

    /// The field `V̄(q, τ)` and its rate along `(v, τ̇)`.
    pub fn evaluate(
        &self,
        q: &JointSpace<T, N>,
        v: &SVector<T, N>,
        tau: T,
        tau_dot: T,
    ) -> FieldSample<T, JointSpace<T, N>, N> {
        let kin = self.kinematics(q.coords(), v);
        let c = self.path.sample(tau);
        let k = self.stiffness;
        let e = kin.x - c.point.coords();
        let e_dot = kin.x_dot - c.velocity * tau_dot;
        let half: T = cast(0.5);
        let u = half * k * e.dot(&e);
        let u_dot = k * e.dot(&e_dot);
        let g = self.pacing.gains(u);
        let (l1_dot, l2_dot) = (g.dlambda1 * u_dot, g.dlambda2 * u_dot);
        let w = c.velocity * g.lambda1 - e * (g.lambda2 * k);
        let w_dot = c.velocity * l1_dot + c.acceleration * (g.lambda1 * tau_dot)
            - e * (l2_dot * k)
            - e_dot * (g.lambda2 * k);
        // The damped inverse and its rate (A is symmetric positive definite as μ > 0).
        let mu2 = self.damping * self.damping;
        let a = kin.jac * kin.jac.transpose() + Matrix3::identity() * mu2;
        let a_inv = a.try_inverse().unwrap_or_else(Matrix3::zeros);
        let a_dot = kin.jac_dot * kin.jac.transpose() + kin.jac * kin.jac_dot.transpose();
        let pinv = kin.jac.transpose() * a_inv;
        let pinv_dot = kin.jac_dot.transpose() * a_inv - pinv * a_dot * a_inv;
        let mut velocity = pinv * w;
        let mut rate = pinv_dot * w + pinv * w_dot;
        if let Some((rest, gain)) = &self.rest {
            let to_rest = q
                .inverse()
                .compose(&JointSpace::new(*rest, q.kinds()))
                .log()
                * *gain;
            let p = SMatrix::<T, N, N>::identity() - pinv * kin.jac;
            let p_dot = -(pinv_dot * kin.jac + pinv * kin.jac_dot);
            velocity += p * to_rest;
            rate += p_dot * to_rest - p * (v * *gain);
        }
        FieldSample {
            contour: ContourSample {
                point: *q,
                velocity: pinv * c.velocity,
                acceleration: SVector::zeros(),
            },
            error: JointSpace::identity().with_kinds(q.kinds()),
            potential: u,
            gradient: kin.jac.transpose() * (e * k),
            lambda1: g.lambda1,
            lambda2: g.lambda2,
            velocity,
            velocity_tau: g.lambda1,
            rate,
            rate_tau: l1_dot,
            error_velocity: SVector::zeros(),
        }
    }
}

impl<T, X, S, const N: usize> VelocityField<T, JointSpace<T, N>, N> for TaskSpaceField<T, X, S, N>
where
    T: Real,
    X: Contour<T, Rn<T, 3>, 3>,
    S: SelfPacing<T>,
{
    /// The field and its rate. What [`FieldSample`] holds for this field: `potential` is `U`
    /// of the tool's error and `gradient` its joint-space gradient `Jᵀ k e`; the error lives
    /// in the task space, so `error` is the identity and `error_velocity` zero; `contour` is
    /// the joint-space image at `q` (point `q`, velocity `J⁺ p_d'(τ)`, acceleration zero).
    #[inline]
    fn sample(
        &self,
        q: &JointSpace<T, N>,
        v: &SVector<T, N>,
        tau: T,
        tau_dot: T,
    ) -> FieldSample<T, JointSpace<T, N>, N> {
        self.evaluate(q, v, tau, tau_dot)
    }

    #[inline]
    fn period(&self) -> Option<T> {
        self.path.period()
    }
}
