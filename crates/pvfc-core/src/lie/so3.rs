//! The rotation group SO(3): the configuration space of a satellite or any rigid body's attitude.

use super::{LieGroup, Tangent};
use crate::error::{Error, ErrorKind, Result};
use crate::scalar::cast;
use crate::Real;
use nalgebra::{Matrix3, Vector3};

/// The skew-symmetric matrix `ω̂` with `ω̂ x = ω × x` (the "hat" map of so(3)).
///
/// ```
/// use nalgebra::Vector3;
/// let w = Vector3::new(1.0, 2.0, 3.0);
/// let x = Vector3::new(-1.0, 0.5, 2.0);
/// assert!((pvfc_core::lie::hat(&w) * x - w.cross(&x)).norm() < 1e-15);
/// ```
#[inline]
pub fn hat<T: Real>(w: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -w.z, w.y, w.z, z, -w.x, -w.y, w.x, z)
}

/// The inverse of [`hat`], reading the skew-symmetric part of `m`: `vee(m) = ½ vee(m − mᵀ)`.
#[inline]
pub fn vee<T: Real>(m: &Matrix3<T>) -> Vector3<T> {
    let half: T = cast(0.5);
    Vector3::new(
        (m[(2, 1)] - m[(1, 2)]) * half,
        (m[(0, 2)] - m[(2, 0)]) * half,
        (m[(1, 0)] - m[(0, 1)]) * half,
    )
}

/// An element of SO(3): a 3×3 rotation matrix (`RᵀR = I`, `det R = 1`).
///
/// Tangent vectors are body angular velocities `ω` (`Ṙ = R ω̂`), as in the paper's
/// `T_q SO(3) = {q ω̂}` and the rigid-body model of [`crate::mechanics::RigidBody`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct So3<T: Real> {
    m: Matrix3<T>,
}

impl<T: Real> So3<T> {
    /// Accepts a matrix that is a rotation to within `tolerance` (`‖RᵀR − I‖ ≤ tol`,
    /// `det R > 0`) and re-orthonormalises it; otherwise an `InvalidParameter` error.
    pub fn from_matrix(m: Matrix3<T>, tolerance: T) -> Result<Self> {
        if !m.iter().all(|x| x.is_finite()) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "So3::from_matrix: entries",
            ));
        }
        let err = (m.transpose() * m - Matrix3::identity()).norm();
        if err > tolerance || m.determinant() <= T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "So3::from_matrix: not a rotation matrix",
            ));
        }
        // Newton–Schulz converges quadratically from any drift below the tolerance checked.
        let mut r = So3 { m };
        for _ in 0..6 {
            r = r.orthonormalized();
        }
        Ok(r)
    }

    /// Wraps a matrix the caller guarantees is a rotation (not checked).
    #[inline]
    pub fn from_matrix_unchecked(m: Matrix3<T>) -> Self {
        So3 { m }
    }

    /// The rotation by `angle` radians about the (not necessarily unit) `axis`.
    pub fn from_axis_angle(axis: &Vector3<T>, angle: T) -> Self {
        let n = axis.norm();
        if n > T::zero() {
            Self::exp(&(axis * (angle / n)))
        } else {
            Self::identity()
        }
    }

    /// The rotation matrix.
    #[inline]
    pub fn matrix(&self) -> &Matrix3<T> {
        &self.m
    }

    /// `‖RᵀR − I‖_F`, the drift from orthogonality (0 for an exact rotation).
    pub fn orthogonality_error(&self) -> T {
        (self.m.transpose() * self.m - Matrix3::identity()).norm()
    }

    /// The nearest rotation, to first order in the drift, by one Newton–Schulz step of the
    /// polar decomposition, `R ← R (3I − RᵀR)/2`: it squares the orthogonality error, so a
    /// rotation drifted by rounding is restored to rounding in one call.
    pub fn orthonormalized(&self) -> Self {
        let three: T = cast(3.0);
        let half: T = cast(0.5);
        let rtr = self.m.transpose() * self.m;
        So3 {
            m: self.m * (Matrix3::identity() * three - rtr) * half,
        }
    }

    /// Rotates a vector: `R x`.
    #[inline]
    pub fn rotate(&self, x: &Vector3<T>) -> Vector3<T> {
        self.m * x
    }

    /// The unit quaternion `(w, x, y, z)`, `w ≥ 0`, of the rotation (Shepperd's method).
    pub fn quaternion(&self) -> [T; 4] {
        let m = &self.m;
        let one = T::one();
        let quarter: T = cast(0.25);
        let half: T = cast(0.5);
        let tr = m[(0, 0)] + m[(1, 1)] + m[(2, 2)];
        let (w, x, y, z);
        if tr >= m[(0, 0)] && tr >= m[(1, 1)] && tr >= m[(2, 2)] {
            let s = (one + tr).sqrt() * half; // = w
            let k = quarter / s;
            w = s;
            x = (m[(2, 1)] - m[(1, 2)]) * k;
            y = (m[(0, 2)] - m[(2, 0)]) * k;
            z = (m[(1, 0)] - m[(0, 1)]) * k;
        } else if m[(0, 0)] >= m[(1, 1)] && m[(0, 0)] >= m[(2, 2)] {
            let s = (one + m[(0, 0)] - m[(1, 1)] - m[(2, 2)]).sqrt() * half; // = x
            let k = quarter / s;
            x = s;
            w = (m[(2, 1)] - m[(1, 2)]) * k;
            y = (m[(0, 1)] + m[(1, 0)]) * k;
            z = (m[(0, 2)] + m[(2, 0)]) * k;
        } else if m[(1, 1)] >= m[(2, 2)] {
            let s = (one - m[(0, 0)] + m[(1, 1)] - m[(2, 2)]).sqrt() * half; // = y
            let k = quarter / s;
            y = s;
            w = (m[(0, 2)] - m[(2, 0)]) * k;
            x = (m[(0, 1)] + m[(1, 0)]) * k;
            z = (m[(1, 2)] + m[(2, 1)]) * k;
        } else {
            let s = (one - m[(0, 0)] - m[(1, 1)] + m[(2, 2)]).sqrt() * half; // = z
            let k = quarter / s;
            z = s;
            w = (m[(1, 0)] - m[(0, 1)]) * k;
            x = (m[(0, 2)] + m[(2, 0)]) * k;
            y = (m[(1, 2)] + m[(2, 1)]) * k;
        }
        if w < T::zero() {
            [-w, -x, -y, -z]
        } else {
            [w, x, y, z]
        }
    }
}

impl<T: Real> LieGroup<T, 3> for So3<T> {
    #[inline]
    fn identity() -> Self {
        So3 {
            m: Matrix3::identity(),
        }
    }
    #[inline]
    fn compose(&self, other: &Self) -> Self {
        So3 {
            m: self.m * other.m,
        }
    }
    #[inline]
    fn inverse(&self) -> Self {
        So3 {
            m: self.m.transpose(),
        }
    }
    /// Rodrigues' formula `exp(ω̂) = I + A ω̂ + B ω̂²` with `A = sin θ/θ`, `B = (1 − cos θ)/θ²`
    /// (Taylor series below θ = 1e-3 in `f64`'s worth of accuracy).
    fn exp(v: &Tangent<T, 3>) -> Self {
        let theta2 = v.norm_squared();
        let theta = theta2.sqrt();
        let (a, b) = if theta < cast(1e-3) {
            (
                T::one() - theta2 / cast(6.0) + theta2 * theta2 / cast(120.0),
                cast::<T>(0.5) - theta2 / cast(24.0) + theta2 * theta2 / cast(720.0),
            )
        } else {
            let (s, c) = theta.sin_cos_fast();
            (s / theta, (T::one() - c) / theta2)
        };
        let w = hat(v);
        So3 {
            m: Matrix3::identity() + w * a + w * w * b,
        }
    }
    /// Through the quaternion: `θ = 2 atan2(‖q_v‖, q_w)`, accurate at 0 and at π.
    fn log(&self) -> Tangent<T, 3> {
        let [w, x, y, z] = self.quaternion();
        let v = Vector3::new(x, y, z);
        let n = v.norm();
        let scale = if n < cast(1e-6) {
            // θ/n = 2 atan2(n, w)/n ≈ (2/w)(1 − n²/(3w²)), w ≈ 1 here.
            (T::one() - n * n / (cast::<T>(3.0) * w * w)) * cast::<T>(2.0) / w
        } else {
            T::atan2(n, w) * cast::<T>(2.0) / n
        };
        v * scale
    }
    #[inline]
    fn adjoint(&self) -> Matrix3<T> {
        self.m
    }
    #[inline]
    fn adjoint_apply(&self, v: &Tangent<T, 3>) -> Tangent<T, 3> {
        self.m * v
    }
    #[inline]
    fn adjoint_inverse_apply(&self, v: &Tangent<T, 3>) -> Tangent<T, 3> {
        self.m.tr_mul(v)
    }
    #[inline]
    fn lie_bracket(a: &Tangent<T, 3>, b: &Tangent<T, 3>) -> Tangent<T, 3> {
        a.cross(b)
    }
    #[inline]
    fn is_finite(&self) -> bool {
        self.m.iter().all(|x| x.is_finite())
    }
    #[inline]
    fn normalized(&self) -> Self {
        self.orthonormalized()
    }
}
