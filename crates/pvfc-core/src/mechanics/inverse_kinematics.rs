//! Inverse kinematics of a [`SerialChain`] by damped least squares, for turning a tool path
//! given in Cartesian space into a joint-space contour: the tool's position (orientation
//! free), its position and axis (the roll about the axis free), or its whole pose, from a
//! seed posture, with an optional pull towards a rest
//! posture in the null space (redundant arms), and the manipulability that tells how close
//! a posture is to a singularity.

use super::{Pose, SerialChain};
use crate::error::{Error, ErrorKind, Result};
use crate::scalar::cast;
use crate::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// What the tool must reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IkTarget<T: Real> {
    /// The tool frame's origin at this point of the base frame; its orientation free.
    Position(Vector3<T>),
    /// The tool frame at this pose.
    Pose(Pose<T>),
    /// The tool frame's origin at `position` and its `z` axis along `axis` (any length > 0),
    /// the roll about it free: a five-dimensional task (a spindle, a deburring cone, a
    /// nozzle).
    Axis {
        /// Where the tool frame's origin goes (base frame).
        position: Vector3<T>,
        /// Where its `z` axis points (base frame).
        axis: Vector3<T>,
    },
}

/// Settings of [`SerialChain::inverse_kinematics`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkSettings<T: Real, const N: usize> {
    /// The position error accepted (m); the orientation error accepted is this divided by
    /// `length_scale` (rad).
    pub tolerance: T,
    /// The damping `λ` of `Δq = Jᵀ(JJᵀ + λ²1)⁻¹ e` (in the error's units; larger is more
    /// robust near singularities and slower).
    pub damping: T,
    /// The most iterations.
    pub max_iterations: usize,
    /// The largest joint change per iteration (rad or m), for a well-behaved path from the
    /// seed.
    pub max_step: T,
    /// The length (m) that weighs an orientation error against a position error.
    pub length_scale: T,
    /// A rest posture and the gain (0 to 1) of the pull towards it in the null space of the
    /// task, for redundant arms; `None`: no pull.
    pub rest: Option<(SVector<T, N>, T)>,
}

impl<T: Real, const N: usize> Default for IkSettings<T, N> {
    fn default() -> Self {
        IkSettings {
            tolerance: cast(1e-9),
            damping: cast(1e-3),
            max_iterations: 200,
            max_step: cast(0.2),
            length_scale: cast(0.2),
            rest: None,
        }
    }
}

impl<T: Real, const N: usize> SerialChain<T, N> {
    /// Yoshikawa's manipulability of the tool's position, `√det(J_p J_pᵀ)` with `J_p` the
    /// linear rows of the world Jacobian (`√det(J_pᵀ J_p)` for fewer than three joints): 0 at
    /// a singularity of the position task. For a planar two-link arm it is `l₁ l₂ |sin q₂|`.
    pub fn manipulability(&self, q: &SVector<T, N>) -> T {
        let j = self.tool_jacobian_world(q);
        let jp: SMatrix<T, 3, N> = j.fixed_rows::<3>(0).into_owned();
        // √det A = Π L_ii for A = L Lᵀ; a matrix Cholesky refuses is (numerically) singular.
        if N >= 3 {
            (jp * jp.transpose()).cholesky().map_or(T::zero(), |c| {
                c.l_dirty().diagonal().iter().fold(T::one(), |p, d| p * *d)
            })
        } else {
            (jp.transpose() * jp).cholesky().map_or(T::zero(), |c| {
                c.l_dirty().diagonal().iter().fold(T::one(), |p, d| p * *d)
            })
        }
    }

    /// The joint coordinates that put the tool at `target`, by damped least squares from
    /// `seed` (each step `Δq = Jᵀ(JJᵀ + λ²1)⁻¹ e`, clipped to `max_step`; for a redundant
    /// task the rest posture is pulled towards with `(1 − J⁺J)`).
    ///
    /// Errors: `NonFinite` for a NaN or infinite target or seed; `InvalidParameter` for bad
    /// settings; `NoConvergence` when the error is still above the tolerance after
    /// `max_iterations` (an unreachable target, or a seed too far away), with the remaining
    /// position error (m) as the error's value.
    pub fn inverse_kinematics(
        &self,
        target: &IkTarget<T>,
        seed: &SVector<T, N>,
        s: &IkSettings<T, N>,
    ) -> Result<SVector<T, N>> {
        let finite_target = match target {
            IkTarget::Position(p) => p.iter().all(|x| x.is_finite()),
            IkTarget::Pose(p) => p.is_finite(),
            IkTarget::Axis { position, axis } => {
                position.iter().all(|x| x.is_finite()) && axis.iter().all(|x| x.is_finite())
            }
        };
        if !finite_target || !seed.iter().all(|x| x.is_finite()) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "SerialChain::inverse_kinematics: target or seed",
            ));
        }
        if let IkTarget::Axis { axis, .. } = target {
            if axis.norm() <= T::zero() {
                return Err(Error::new(
                    ErrorKind::InvalidParameter,
                    "SerialChain::inverse_kinematics: the target's axis is zero",
                ));
            }
        }
        let positive = |x: T| x.is_finite() && x > T::zero();
        if !(positive(s.tolerance)
            && s.damping.is_finite()
            && s.damping >= T::zero()
            && positive(s.max_step)
            && positive(s.length_scale)
            && s.max_iterations > 0)
        {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "SerialChain::inverse_kinematics: settings",
            ));
        }
        let mut q = *seed;
        let mut remaining = T::zero();
        for _ in 0..=s.max_iterations {
            let pose = self.tool_pose(&q);
            let jac = self.tool_jacobian_world(&q);
            // The pull towards the rest posture, projected into the task's null space by
            // `dls` (it never disturbs the task to first order).
            let pull = s.rest.map(|(rest, gain)| (rest - q) * gain);
            let (step, error) = match target {
                IkTarget::Position(p) => {
                    let e = p - pose.translation;
                    let jp: SMatrix<T, 3, N> = jac.fixed_rows::<3>(0).into_owned();
                    (dls::<T, 3, N>(&jp, &e, s.damping, pull), e.norm())
                }
                IkTarget::Pose(p) => {
                    let e_lin = p.translation - pose.translation;
                    // The rotation taking the tool's frame to the target's, as a rotation
                    // vector in the base frame.
                    let e_rot = rotation_vector(&(p.rotation * pose.rotation.transpose()));
                    let w = s.length_scale;
                    let mut e = SVector::<T, 6>::zeros();
                    e.fixed_rows_mut::<3>(0).copy_from(&e_lin);
                    e.fixed_rows_mut::<3>(3).copy_from(&(e_rot * w));
                    let mut jw = jac;
                    for mut r in jw.fixed_rows_mut::<3>(3).row_iter_mut() {
                        r *= w;
                    }
                    (dls::<T, 6, N>(&jw, &e, s.damping, pull), e.norm())
                }
                IkTarget::Axis { position, axis } => {
                    let e_lin = position - pose.translation;
                    // The rotation vector turning the tool's axis onto the target's, across
                    // the axis, in the components along the tool's x and y (its roll free).
                    let r = pose.rotation;
                    let (bx, by, z) = (r.column(0), r.column(1), r.column(2));
                    let zd = axis.normalize();
                    let cross = z.cross(&zd);
                    let (sin, cos) = (cross.norm(), z.dot(&zd));
                    let angle = sin.atan2(cos);
                    let turn = if sin > T::zero() {
                        cross * (angle / sin)
                    } else if cos < T::zero() {
                        bx.into_owned() * angle
                    } else {
                        Vector3::zeros()
                    };
                    let w = s.length_scale;
                    let jw = jac.fixed_rows::<3>(3);
                    let mut e = SVector::<T, 5>::zeros();
                    let mut j5 = SMatrix::<T, 5, N>::zeros();
                    e.fixed_rows_mut::<3>(0).copy_from(&e_lin);
                    e[3] = bx.dot(&turn) * w;
                    e[4] = by.dot(&turn) * w;
                    j5.fixed_rows_mut::<3>(0).copy_from(&jac.fixed_rows::<3>(0));
                    j5.set_row(3, &(bx.transpose() * jw * w));
                    j5.set_row(4, &(by.transpose() * jw * w));
                    (dls::<T, 5, N>(&j5, &e, s.damping, pull), e.norm())
                }
            };
            remaining = error;
            if error <= s.tolerance {
                return Ok(q);
            }
            let largest = step.amax();
            let clip = if largest > s.max_step {
                s.max_step / largest
            } else {
                T::one()
            };
            q += step * clip;
            if !q.iter().all(|x| x.is_finite()) {
                break;
            }
        }
        let value = nalgebra::try_convert::<T, f64>(remaining).unwrap_or(f64::NAN);
        Err(Error::new(
            ErrorKind::NoConvergence,
            "SerialChain::inverse_kinematics: the tool did not reach the target",
        )
        .with_value(value))
    }
}

/// One damped-least-squares step for the `R`-row task `J` and error `e`,
/// `Jᵀ(JJᵀ + λ_e²1)⁻¹ e` with `λ_e² = λ² + ½|e|²`, plus `pull` projected into the task's null
/// space, `(1 − J⁺J) pull`.
fn dls<T: Real, const R: usize, const N: usize>(
    j: &SMatrix<T, R, N>,
    e: &SVector<T, R>,
    damping: T,
    pull: Option<SVector<T, N>>,
) -> SVector<T, N> {
    // Sugihara's error-adaptive damping (Levenberg–Marquardt): `λ² + ½|e|²`, large far from
    // the target (robust), vanishing at it (fast, exact convergence).
    let lambda2 = damping * damping + e.norm_squared() * cast::<T>(0.5);
    let a = j * j.transpose() + SMatrix::<T, R, R>::identity() * lambda2;
    let Some(ch) = a.cholesky() else {
        return SVector::zeros();
    };
    let step = j.transpose() * ch.solve(e);
    match pull {
        None => step,
        // The projector with the undamped pseudo-inverse, so that the pull has no component
        // in the task at all (a damped one would leave `λ²`-sized leaks that stall the
        // convergence); none at a singular posture.
        Some(p) => match (j * j.transpose()).cholesky() {
            Some(exact) => step + p - j.transpose() * exact.solve(&(j * p)),
            None => step,
        },
    }
}

/// The rotation vector (axis × angle) of a rotation matrix.
fn rotation_vector<T: Real>(r: &Matrix3<T>) -> Vector3<T> {
    let half: T = cast(0.5);
    let c = ((r.trace() - T::one()) * half).max(-T::one()).min(T::one());
    let v = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    );
    let s = v.norm() * half;
    let angle = s.atan2(c);
    if s < cast(1e-9) {
        // Near the identity (the half antisymmetric part is the vector); near π the IK's next
        // step moves away from it.
        return v * half;
    }
    v * (angle / (s + s))
}
