//! A rigid body rotating freely: a satellite's attitude on SO(3).

use super::MechanicalSystem;
use crate::error::{Error, ErrorKind, Result};
use crate::lie::{hat, So3, Tangent};
use crate::Real;
use nalgebra::Matrix3;

/// A rigid body with body inertia `J` and body angular velocity `ω`:
/// `J ω̇ + ω × Jω = T`, i.e. `M = J`, `C(ω) = −[Jω]×`, so that `Ṁ − 2C = 2[Jω]×` is skew.
///
/// ```
/// use pvfc_core::mechanics::{MechanicalSystem, RigidBody};
/// use pvfc_core::lie::{LieGroup, So3};
/// use nalgebra::{Matrix3, Vector3};
/// let body = RigidBody::new(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))).unwrap();
/// let w = Vector3::new(0.1, 0.2, 0.3);
/// let c = body.coriolis(&So3::identity(), &w);
/// assert!((c * w - w.cross(&(body.inertia(&So3::identity()) * w))).norm() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBody<T: Real> {
    j: Matrix3<T>,
}

impl<T: Real> RigidBody<T> {
    /// A body with inertia `J` (symmetric positive definite, kg·m²).
    pub fn new(j: Matrix3<T>) -> Result<Self> {
        if !j.iter().all(|x| x.is_finite()) {
            return Err(Error::new(ErrorKind::NonFinite, "RigidBody: J"));
        }
        if (j - j.transpose()).norm() > T::default_epsilon().sqrt() * j.norm() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "RigidBody: J must be symmetric",
            ));
        }
        if j.cholesky().is_none() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "RigidBody: J must be positive definite",
            ));
        }
        Ok(RigidBody { j })
    }

    /// The inertia `J`.
    pub fn inertia_matrix(&self) -> &Matrix3<T> {
        &self.j
    }
}

impl<T: Real> MechanicalSystem<T, So3<T>, 3> for RigidBody<T> {
    #[inline]
    fn inertia(&self, _q: &So3<T>) -> Matrix3<T> {
        self.j
    }

    #[inline]
    fn coriolis(&self, _q: &So3<T>, v: &Tangent<T, 3>) -> Matrix3<T> {
        -hat(&(self.j * v))
    }

    #[inline]
    fn inertia_rate(&self, _q: &So3<T>, _v: &Tangent<T, 3>) -> Matrix3<T> {
        Matrix3::zeros()
    }
}
