//! A velocity field built on the tool's error to a path in Cartesian space, pulled back to
//! the joints through the Jacobian: the task-space counterpart of
//! [`SuspendedField`](crate::field::SuspendedField), for a serial chain. The coupling is unchanged, so
//! passivity holds as for any field (it is a property of the coupling, eq. 9).
//!
//! With the tool position `x(q)`, the path `p_d(τ)` (a contour on `ℝ³`), the error
//! `e = x(q) − p_d(τ)` and the navigation function `U = ½ k |e|²` (or, saturated at a
//! distance `ℓ` ([`with_saturation`](TaskSpaceField::with_saturation)), `U = kℓ²(s − 1)`,
//! `s = √(1 + |e|²/ℓ²)`, whose gradient `ke/s` stays below `kℓ`; `ke` below stands for the
//! gradient):
//!
//! * the desired tool velocity `w = λ₁ p_d'(τ) − λ₂ k e` (eq. 30's two terms, in the task
//!   space: along the path, and down the gradient of `U`), with the self-pacing gains
//!   `λ₁(U)`, `λ₂(U)` of eq. (21);
//! * the joint field `V_q = K w + (I − KJ) g_r log(q⁻¹ q_r)`, `J` the tool's position
//!   Jacobian, `J⁺ = Jᵀ (J Jᵀ + μ² I)⁻¹` the damped least-squares inverse (bounded near a
//!   singularity: `|J⁺| ≤ 1/(2μ)`) refined once, `K = J⁺(2I − JJ⁺)` (still bounded,
//!   `|K| ≤ 1/μ`, and with the damping's bias squared: `I − JK = (I − JJ⁺)²`, so that away
//!   from singularities the tool moves at the desired task velocity to `(μ/σ)⁴` instead of
//!   `(μ/σ)²`), and an optional pull towards a rest posture `q_r` in the null space of the
//!   task (for arms with more than three joints);
//! * `V_τ = λ₁`.
//!
//! With an orientation ([`with_orientation`](TaskSpaceField::with_orientation) to hold one,
//! [`with_orientation_path`](TaskSpaceField::with_orientation_path) for a contour `R_d(τ)` on
//! SO(3), an SE(3) path), the task is six-dimensional: the tool's rotation `R(q)` is pulled to
//! `R_d(τ)` by the navigation function `U_R = ½ k_R (3 − tr E) = k_R (1 − cos θ)`,
//! `E = R R_dᵀ` (θ the angle of `E`), whose gradient in the spatial angular velocity is
//! `k_R e_R` with `e_R = vee(½(E − Eᵀ)) = sin θ n`. With `ω_d = R_d ξ_d` the path's spatial
//! angular velocity per unit of `τ` (`ξ_d` its body velocity), `Ė = [ω]E − τ̇ E[ω_d]`, so
//! `ė_R = ½ (tr E · I − E) ω − ½ (tr E · I − Eᵀ) ω_d τ̇` and `U̇_R = k_R e_Rᵀ(ω − ω_d τ̇)`. The
//! desired angular velocity is `λ₁ ω_d − λ₂ k_R e_R`, `U = U_p + U_R` drives the self-pacing,
//! and `J` stacks the position rows over the spatial angular rows (the joints' axes `w_i`). `U_R` is a navigation function on
//! SO(3) apart from the rotations by π (θ = π is its unstable maximum set), the same
//! construction as [`So3Navigation`](crate::navigation::So3Navigation) with `P = k_R/2 · I`.
//!
//! With an axis instead ([`with_axis_path`](TaskSpaceField::with_axis_path): a spindle, a
//! deburring cone, a nozzle, any tool symmetric about its `z` axis), only the tool's axis
//! `z = R e₃` follows `z_d(τ) = R_d(τ) e₃` and its roll is free: the task is five-dimensional.
//! The navigation function is `U_a = k_a (1 − zᵀz_d) = k_a (1 − cos θ)` (θ the angle between
//! the axes), with `U̇_a = k_a e_aᵀ(ω − ω_d τ̇)`, `e_a = z_d × z = sin θ n`: the same form as
//! the orientation's, so the desired angular velocity is again `λ₁ ω_d − λ₂ k_a e_a`, of which
//! only the components across the axis are asked for, along the tool's own `x = R e₁` and
//! `y = R e₂` (`ẋ = ω × x`): the rows `[xᵀ; yᵀ] J_ω`, with rates `[(ω × x)ᵀ; (ω × y)ᵀ] J_ω +
//! [xᵀ; yᵀ] J̇_ω`. The roll about `z` is the task's null space (a rest posture, if any, is
//! pulled there), and an axis path need not return its roll after a lap: a tool frame that
//! turns once about the surface's normal per lap of a closed path leaves the joints periodic.
//!
//! The rate along the motion `(q̇, τ̇)` is analytic: `J̇` from the spatial axes'
//! rates `ṡ_i = V_{i−1} × s_i` (the velocity of link `i − 1` crossed into joint `i`'s axis),
//! `d(J⁺)/dt = J̇ᵀ A⁻¹ − Jᵀ A⁻¹ (J̇ Jᵀ + J J̇ᵀ) A⁻¹` with `A = J Jᵀ + μ² I`,
//! `K̇ = d(J⁺)/dt (2I − JJ⁺) − J⁺(J̇J⁺ + J d(J⁺)/dt)`, and
//! `ẇ = λ̇₁ p_d' + λ₁ p_d'' τ̇ − λ̇₂ k e − λ₂ k ė`, `ė = J q̇ − p_d' τ̇`, `λ̇ = λ'(U) k eᵀė`.

use crate::contour::ConstantRate;
use crate::contour::{Contour, ContourSample};
use crate::error::{Error, ErrorKind, Result};
use crate::field::{FieldSample, VelocityField};
use crate::lie::{JointSpace, LieGroup, Rn, So3};
use crate::linalg::{damped_gram, spd_inverse};
use crate::mechanics::{ChainKinematics, SerialChain};
use crate::pacing::SelfPacing;
use crate::scalar::cast;
use crate::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// A held orientation: the constant contour on SO(3).
pub type HeldOrientation<T> = ConstantRate<T, So3<T>, 3>;

/// The task-space velocity field of a serial chain on a Cartesian path `X` (a contour on
/// `ℝ³`, e.g. a periodic B-spline through points of the path), with self-pacing `S` and,
/// optionally, the tool's orientation along `O` (a contour on SO(3); by default one held
/// orientation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaskSpaceField<T: Real, X, S, const N: usize, O = HeldOrientation<T>> {
    chain: SerialChain<T, N>,
    path: X,
    pacing: S,
    stiffness: T,
    damping: T,
    saturation: Option<T>,
    rest: Option<(SVector<T, N>, T)>,
    orientation: Option<(O, T)>,
    /// Only the orientation's axis `R_d e₃` is followed (the roll is free).
    axis_only: bool,
}

/// The tool's pose, its velocity, and the Jacobian (position rows over spatial angular rows)
/// with its rate at one state.
struct TaskKinematics<T: Real, const N: usize> {
    x: Vector3<T>,
    x_dot: Vector3<T>,
    rotation: Matrix3<T>,
    omega: Vector3<T>,
    jac: SMatrix<T, 6, N>,
    jac_dot: SMatrix<T, 6, N>,
}

/// The desired task velocity `w` (position rows, then angular rows when the orientation is
/// held) and its rate, pulled back to the joints.
struct Pulled<T: Real, const N: usize> {
    velocity: SVector<T, N>,
    rate: SVector<T, N>,
    along: SVector<T, N>,
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
            saturation: None,
            rest: None,
            orientation: None,
            axis_only: false,
        })
    }

    /// Holding the tool's orientation at `rotation` (a rotation matrix in the base frame) with
    /// the navigation function `U_R = k_R (1 − cos θ)` (`stiffness` `k_R` > 0, 1/s when
    /// `λ₂ = 1`): the task becomes six-dimensional.
    pub fn with_orientation(self, rotation: Matrix3<T>, stiffness: T) -> Result<Self> {
        let r = So3::from_matrix(rotation, cast(1e-6)).map_err(|_| {
            Error::new(
                ErrorKind::InvalidParameter,
                "TaskSpaceField: the orientation must be a rotation matrix",
            )
        })?;
        self.with_orientation_path(ConstantRate::new(r, Vector3::zeros())?, stiffness)
    }
}

impl<T, X, S, O, const N: usize> TaskSpaceField<T, X, S, N, O>
where
    T: Real,
    X: Contour<T, Rn<T, 3>, 3>,
    S: SelfPacing<T>,
    O: Contour<T, So3<T>, 3>,
{
    /// With the tool's orientation along `orientation` (a contour `R_d(τ)` on SO(3), on the
    /// same `τ` as the path) and the navigation function `U_R = k_R (1 − cos θ)` of the angle
    /// between the tool's rotation and `R_d(τ)` (`stiffness` `k_R` > 0, 1/s when `λ₂ = 1`):
    /// the task becomes six-dimensional.
    pub fn with_orientation_path<P: Contour<T, So3<T>, 3>>(
        self,
        orientation: P,
        stiffness: T,
    ) -> Result<TaskSpaceField<T, X, S, N, P>> {
        self.with_orientation_option(Some((orientation, stiffness)))
    }

    /// With the tool's axis `z = R e₃` along `z_d(τ) = R_d(τ) e₃` of `orientation` (a contour
    /// on SO(3), on the same `τ` as the path; its roll about `z_d` is not used) and the
    /// navigation function `U_a = k_a (1 − cos θ)` of the angle between the axes
    /// (`stiffness` `k_a` > 0, 1/s when `λ₂ = 1`): the task becomes five-dimensional, the
    /// roll about the tool's axis free.
    pub fn with_axis_path<P: Contour<T, So3<T>, 3>>(
        self,
        orientation: P,
        stiffness: T,
    ) -> Result<TaskSpaceField<T, X, S, N, P>> {
        let mut field = self.with_orientation_option(Some((orientation, stiffness)))?;
        field.axis_only = true;
        Ok(field)
    }

    /// Whether only the orientation's axis is followed ([`with_axis_path`](Self::with_axis_path)).
    pub fn axis_only(&self) -> bool {
        self.axis_only
    }

    /// [`with_orientation_path`](Self::with_orientation_path) when `orientation` is given,
    /// else the position only, with the orientation's type `P` either way (for callers that
    /// choose at run time).
    pub fn with_orientation_option<P: Contour<T, So3<T>, 3>>(
        self,
        orientation: Option<(P, T)>,
    ) -> Result<TaskSpaceField<T, X, S, N, P>> {
        if let Some((_, k)) = &orientation {
            if !(k.is_finite() && *k > T::zero()) {
                return Err(Error::new(
                    ErrorKind::InvalidParameter,
                    "TaskSpaceField: the orientation's stiffness must be finite and > 0",
                ));
            }
        }
        Ok(TaskSpaceField {
            chain: self.chain,
            path: self.path,
            pacing: self.pacing,
            stiffness: self.stiffness,
            damping: self.damping,
            saturation: self.saturation,
            rest: self.rest,
            orientation,
            axis_only: false,
        })
    }

    /// The orientation's contour, with its stiffness, if any.
    pub fn orientation(&self) -> Option<&(O, T)> {
        self.orientation.as_ref()
    }

    /// The position's navigation function saturated at the distance `ℓ` > 0 (m): the
    /// pseudo-Huber `U = kℓ²(√(1 + |e|²/ℓ²) − 1)`, which is `½k|e|²` near the path and grows
    /// only linearly far from it, so that the pull `k e/√(1 + |e|²/ℓ²)` stays below `kℓ` (a
    /// start far from the path does not ask for a large `Ē` or a small `k`). Its gradient is
    /// zero only at `e = 0`, so the path stays its only minimum.
    pub fn with_saturation(mut self, distance: T) -> Result<Self> {
        if !(distance.is_finite() && distance > T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "TaskSpaceField: the saturation distance must be finite and > 0",
            ));
        }
        self.saturation = Some(distance);
        Ok(self)
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

    /// The tool pose, its velocity, and the Jacobian with its rate, from the chain's forward
    /// kinematics `k` at `q`.
    fn kinematics(&self, k: &ChainKinematics<T, N>, v: &SVector<T, N>) -> TaskKinematics<T, N> {
        let tool = k.link_poses[N - 1].compose(self.chain.tool());
        let x = tool.translation;
        let split = |s: &SVector<T, 6>| {
            (
                Vector3::new(s[0], s[1], s[2]),
                Vector3::new(s[3], s[4], s[5]),
            )
        };
        let mut jac = SMatrix::<T, 6, N>::zeros();
        for (i, s) in k.axes.iter().enumerate() {
            let (w, l) = split(s);
            jac.fixed_view_mut::<3, 1>(0, i)
                .copy_from(&(l + w.cross(&x)));
            jac.fixed_view_mut::<3, 1>(3, i).copy_from(&w);
        }
        let x_dot = jac.fixed_rows::<3>(0) * v;
        // ṡ_i = V × s_i with V the spatial velocity of the links before joint i.
        let (mut om, mut nu) = (Vector3::zeros(), Vector3::zeros());
        let mut jac_dot = SMatrix::<T, 6, N>::zeros();
        for (i, s) in k.axes.iter().enumerate() {
            let (w, l) = split(s);
            let w_dot = om.cross(&w);
            let l_dot = om.cross(&l) + nu.cross(&w);
            jac_dot
                .fixed_view_mut::<3, 1>(0, i)
                .copy_from(&(l_dot + w_dot.cross(&x) + w.cross(&x_dot)));
            jac_dot.fixed_view_mut::<3, 1>(3, i).copy_from(&w_dot);
            om += w * v[i];
            nu += l * v[i];
        }
        TaskKinematics {
            x,
            x_dot,
            rotation: tool.rotation,
            omega: om,
            jac,
            jac_dot,
        }
    }

    /// The desired task velocity `w` with its rate `ẇ` and the path's velocity `p_d'` in the
    /// same rows, pulled back through the damped inverse `J⁺` of the task's `M` rows of `jac`,
    /// with the null-space pull towards the rest posture.
    #[allow(clippy::too_many_arguments)]
    fn pull_back<const M: usize>(
        &self,
        q: &JointSpace<T, N>,
        v: &SVector<T, N>,
        jac: &SMatrix<T, M, N>,
        jac_dot: &SMatrix<T, M, N>,
        w: &SVector<T, M>,
        w_dot: &SVector<T, M>,
        along: &SVector<T, M>,
    ) -> Pulled<T, N> {
        // The damped inverse and its rate (A is symmetric positive definite as μ > 0), applied
        // to vectors only: J⁺y = Jᵀ(A⁻¹y), and d(J⁺)/dt y = J̇ᵀz − J⁺(J̇(Jᵀz) + J(J̇ᵀz)) with
        // z = A⁻¹y (Ȧ = J̇Jᵀ + JJ̇ᵀ), so no N×N or N×M product is formed; then refined once.
        let mu2 = self.damping * self.damping;
        let a = damped_gram(jac, mu2);
        let a_inv = spd_inverse(&a).unwrap_or_else(SMatrix::<T, M, M>::zeros);
        // `J⁺ = Jᵀ A⁻¹` formed once (N·M² multiply-adds): each of the twenty-odd products
        // with it below is then one N×M product instead of an M×M and an N×M one.
        let pinv: SMatrix<T, N, M> = jac.transpose() * a_inv;
        let damped = |y: &SVector<T, M>| pinv * y;
        // `J⁺y` and `d(J⁺)/dt y` together, sharing `z = A⁻¹y`.
        let damped_both = |y: &SVector<T, M>| {
            let z = a_inv * y;
            let (jt_z, jdt_z) = (pinv * y, jac_dot.tr_mul(&z));
            (jt_z, jdt_z - damped(&(jac_dot * jt_z + jac * jdt_z)))
        };
        // One step of iterative refinement, `K = J⁺(2I − JJ⁺)`: `Ky = x + J⁺r` with `x = J⁺y`
        // and the residual `r = y − Jx`. The damped inverse's bias `I − JJ⁺` (eigenvalues
        // `μ²/(σ² + μ²)`) is squared, `I − JK = (I − JJ⁺)²`, while `K` stays bounded
        // (`|K| ≤ 1/μ`). Given `y` and its rate `ẏ`, `refined` returns `Ky` and
        // `d(Ky)/dt = ẋ + d(J⁺)/dt r + J⁺ṙ`, `ẋ = d(J⁺)/dt y + J⁺ẏ`, `ṙ = ẏ − J̇x − Jẋ`.
        let refined = |y: &SVector<T, M>, y_dot: &SVector<T, M>| {
            let (x, dx) = damped_both(y);
            let x_dot = dx + damped(y_dot);
            let r = y - jac * x;
            let r_dot = y_dot - jac_dot * x - jac * x_dot;
            let (kr, dkr) = damped_both(&r);
            (x + kr, x_dot + dkr + damped(&r_dot))
        };
        // With the pull `t = g_r log(q⁻¹q_r)` towards the rest posture, the field is
        // `Kw + (I − KJ)t = K(w − Jt) + t` and its rate `d(K(w − Jt))/dt + ṫ`, `ṫ = −g_r q̇`,
        // `d(Jt)/dt = J̇t + Jṫ`: one refined product, as `refined` is linear in `(y, ẏ)`.
        let (velocity, rate) = match &self.rest {
            None => refined(w, w_dot),
            Some((rest, gain)) => {
                let to_rest = q
                    .inverse()
                    .compose(&JointSpace::new(*rest, q.kinds()))
                    .log()
                    * *gain;
                let pulled = v * *gain;
                let (k, k_rate) = refined(
                    &(w - jac * to_rest),
                    &(w_dot - (jac_dot * to_rest - jac * pulled)),
                );
                (k + to_rest, k_rate - pulled)
            }
        };
        // The path's direction needs no rate: `Ky` alone.
        let x = damped(along);
        let along = x + damped(&(along - jac * x));
        Pulled {
            velocity,
            rate,
            along,
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
        self.evaluate_with_kinematics(&self.chain.kinematics(q.coords()), q, v, tau, tau_dot)
    }

    /// [`evaluate`](Self::evaluate) given the chain's forward kinematics at `q` (computed once
    /// per step by the law, which its model's products share).
    pub fn evaluate_with_kinematics(
        &self,
        kinematics: &ChainKinematics<T, N>,
        q: &JointSpace<T, N>,
        v: &SVector<T, N>,
        tau: T,
        tau_dot: T,
    ) -> FieldSample<T, JointSpace<T, N>, N> {
        let kin = self.kinematics(kinematics, v);
        let c = self.path.sample(tau);
        let k = self.stiffness;
        let e = kin.x - c.point.coords();
        let e_dot = kin.x_dot - c.velocity * tau_dot;
        let half: T = cast(0.5);
        // The position's navigation function, its gradient `f = ∇U` in the task space and
        // the gradient's rate: `U = ½k|e|²`, `f = ke`; saturated at `ℓ`,
        // `U = kℓ²(s − 1)`, `s = √(1 + |e|²/ℓ²)`, `f = ke/s` (|f| < kℓ),
        // `ḟ = (k/s)(ė − e (eᵀė)/(ℓ²s²))`. Either way `U̇ = fᵀė`.
        let (mut u, f, f_dot) = match self.saturation {
            None => (half * k * e.dot(&e), e * k, e_dot * k),
            Some(l) => {
                let l2 = l * l;
                let s2 = T::one() + e.dot(&e) / l2;
                let s = s2.sqrt();
                let f = e * (k / s);
                let f_dot = (e_dot - e * (e.dot(&e_dot) / (l2 * s2))) * (k / s);
                (k * l2 * (s - T::one()), f, f_dot)
            }
        };
        let mut u_dot = f.dot(&e_dot);
        let mut gradient = kin.jac.fixed_rows::<3>(0).transpose() * f;
        // The orientation's error `e_R = vee(½(E − Eᵀ))`, `E = R R_dᵀ`, its rate, and the path's
        // spatial angular velocity per τ with its derivative.
        let turn = self.orientation.as_ref().map(|(o, kr)| {
            let od = o.sample(tau);
            let rd = *od.point.matrix();
            let (wd, wd_dot) = (rd * od.velocity, rd * od.acceleration);
            if self.axis_only {
                // The axes' error `e_a = z_d × z`, its rate and `U_a = k_a (1 − zᵀz_d)`.
                let z: Vector3<T> = kin.rotation.column(2).into_owned();
                let zd: Vector3<T> = rd.column(2).into_owned();
                let e_a = zd.cross(&z);
                let zd_dot = wd.cross(&zd) * tau_dot;
                let e_a_dot = zd_dot.cross(&z) + zd.cross(&kin.omega.cross(&z));
                let u_a_dot = *kr * e_a.dot(&(kin.omega - wd * tau_dot));
                return (
                    e_a,
                    e_a_dot,
                    *kr,
                    *kr * (T::one() - z.dot(&zd)),
                    u_a_dot,
                    wd,
                    wd_dot,
                );
            }
            let m = kin.rotation * rd.transpose();
            let tr = m.trace();
            let e_r = Vector3::new(
                m[(2, 1)] - m[(1, 2)],
                m[(0, 2)] - m[(2, 0)],
                m[(1, 0)] - m[(0, 1)],
            ) * half;
            let id = Matrix3::identity() * tr;
            let e_r_dot = ((id - m) * kin.omega - (id - m.transpose()) * (wd * tau_dot)) * half;
            let u_r_dot = *kr * e_r.dot(&(kin.omega - wd * tau_dot));
            (
                e_r,
                e_r_dot,
                *kr,
                half * *kr * (cast::<T>(3.0) - tr),
                u_r_dot,
                wd,
                wd_dot,
            )
        });
        if let Some((e_r, _, kr, u_r, u_r_dot, _, _)) = &turn {
            u += *u_r;
            u_dot += *u_r_dot;
            gradient += kin.jac.fixed_rows::<3>(3).transpose() * (e_r * *kr);
        }
        let g = self.pacing.gains(u, tau);
        let (l1_dot, l2_dot) = (
            crate::field::pace_rate::<T, S>(&g, u_dot, tau_dot),
            g.dlambda2 * u_dot,
        );
        let w = c.velocity * g.lambda1 - f * g.lambda2;
        let w_dot = c.velocity * l1_dot + c.acceleration * (g.lambda1 * tau_dot)
            - f * l2_dot
            - f_dot * g.lambda2;
        let pulled = match &turn {
            None => self.pull_back::<3>(
                q,
                v,
                &kin.jac.fixed_rows::<3>(0).into_owned(),
                &kin.jac_dot.fixed_rows::<3>(0).into_owned(),
                &w,
                &w_dot,
                &c.velocity,
            ),
            Some((e_r, e_r_dot, kr, _, _, wd, wd_dot)) => {
                let w_r = wd * g.lambda1 - e_r * (g.lambda2 * *kr);
                let w_r_dot = wd * l1_dot + wd_dot * (g.lambda1 * tau_dot)
                    - e_r * (l2_dot * *kr)
                    - e_r_dot * (g.lambda2 * *kr);
                let stack = |a: &Vector3<T>, b: &Vector3<T>| {
                    SVector::<T, 6>::new(a[0], a[1], a[2], b[0], b[1], b[2])
                };
                if self.axis_only {
                    self.axis_pull_back(q, v, &kin, (&w, &w_dot, &c.velocity), (&w_r, &w_r_dot, wd))
                } else {
                    self.pull_back::<6>(
                        q,
                        v,
                        &kin.jac,
                        &kin.jac_dot,
                        &stack(&w, &w_r),
                        &stack(&w_dot, &w_r_dot),
                        &stack(&c.velocity, wd),
                    )
                }
            }
        };
        FieldSample {
            contour: ContourSample {
                point: *q,
                velocity: pulled.along,
                acceleration: SVector::zeros(),
            },
            error: JointSpace::identity().with_kinds(q.kinds()),
            potential: u,
            gradient,
            lambda1: g.lambda1,
            lambda2: g.lambda2,
            velocity: pulled.velocity,
            velocity_tau: g.lambda1,
            rate: pulled.rate,
            rate_tau: l1_dot,
            error_velocity: SVector::zeros(),
        }
    }

    /// The five-row task of a position and an axis: the desired linear velocity (its rate,
    /// the path's direction) and angular velocity (the same), the latter asked for only
    /// across the tool's axis, along its `x` and `y`.
    fn axis_pull_back(
        &self,
        q: &JointSpace<T, N>,
        v: &SVector<T, N>,
        kin: &TaskKinematics<T, N>,
        linear: (&Vector3<T>, &Vector3<T>, &Vector3<T>),
        angular: (&Vector3<T>, &Vector3<T>, &Vector3<T>),
    ) -> Pulled<T, N> {
        let bx: Vector3<T> = kin.rotation.column(0).into_owned();
        let by: Vector3<T> = kin.rotation.column(1).into_owned();
        let (bx_dot, by_dot) = (kin.omega.cross(&bx), kin.omega.cross(&by));
        let jw = kin.jac.fixed_rows::<3>(3);
        let jw_dot = kin.jac_dot.fixed_rows::<3>(3);
        let mut jac = SMatrix::<T, 5, N>::zeros();
        let mut jac_dot = SMatrix::<T, 5, N>::zeros();
        jac.fixed_rows_mut::<3>(0)
            .copy_from(&kin.jac.fixed_rows::<3>(0));
        jac_dot
            .fixed_rows_mut::<3>(0)
            .copy_from(&kin.jac_dot.fixed_rows::<3>(0));
        jac.set_row(3, &(bx.transpose() * jw));
        jac.set_row(4, &(by.transpose() * jw));
        jac_dot.set_row(3, &(bx_dot.transpose() * jw + bx.transpose() * jw_dot));
        jac_dot.set_row(4, &(by_dot.transpose() * jw + by.transpose() * jw_dot));
        let (w, w_dot, along) = linear;
        let (w_r, w_r_dot, wd) = angular;
        let stack = |a: &Vector3<T>, b: T, c: T| SVector::<T, 5>::new(a[0], a[1], a[2], b, c);
        self.pull_back::<5>(
            q,
            v,
            &jac,
            &jac_dot,
            &stack(w, bx.dot(w_r), by.dot(w_r)),
            &stack(
                w_dot,
                bx_dot.dot(w_r) + bx.dot(w_r_dot),
                by_dot.dot(w_r) + by.dot(w_r_dot),
            ),
            &stack(along, bx.dot(wd), by.dot(wd)),
        )
    }
}

impl<T, X, S, O, const N: usize> VelocityField<T, JointSpace<T, N>, N>
    for TaskSpaceField<T, X, S, N, O>
where
    T: Real,
    X: Contour<T, Rn<T, 3>, 3>,
    S: SelfPacing<T>,
    O: Contour<T, So3<T>, 3>,
{
    /// The field and its rate. What [`FieldSample`] holds for this field: `potential` is `U`
    /// of the tool's error and `gradient` its joint-space gradient (`Jᵀ k e`, plus the
    /// orientation's `J_ωᵀ k_R e_R` when it is held); the error lives
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

    const USES_CHAIN_KINEMATICS: bool = true;

    #[inline]
    fn serial_chain(&self) -> Option<&SerialChain<T, N>> {
        Some(&self.chain)
    }

    #[inline]
    fn sample_with_kinematics(
        &self,
        kinematics: &ChainKinematics<T, N>,
        q: &JointSpace<T, N>,
        v: &SVector<T, N>,
        tau: T,
        tau_dot: T,
    ) -> FieldSample<T, JointSpace<T, N>, N> {
        self.evaluate_with_kinematics(kinematics, q, v, tau, tau_dot)
    }

    #[inline]
    fn period(&self) -> Option<T> {
        self.path.period()
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
