//! The planar two-link arm (SCARA) in closed form.

use super::{acceleration_failure, positive, solve_spd2, MechanicalSystem};
use crate::error::{Error, ErrorKind, Result};
use crate::lie::{Tangent, Torus};
use crate::scalar::cast;
use crate::Real;
use nalgebra::Matrix2;

/// Physical parameters of a two-link planar arm moving in the horizontal plane (no gravity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScaraParameters<T: Real> {
    /// Mass of link 1 (kg).
    pub m1: T,
    /// Mass of link 2 (kg).
    pub m2: T,
    /// Length of link 1, joint 1 to joint 2 (m).
    pub l1: T,
    /// Length of link 2 (m); does not enter the dynamics, kept for kinematics.
    pub l2: T,
    /// Distance from joint 1 to the centre of mass of link 1 (m).
    pub lc1: T,
    /// Distance from joint 2 to the centre of mass of link 2 (m).
    pub lc2: T,
    /// Inertia of link 1 about its centre of mass, axis normal to the plane (kg·m²).
    pub i1: T,
    /// Inertia of link 2 about its centre of mass (kg·m²).
    pub i2: T,
}

impl<T: Real> ScaraParameters<T> {
    /// The CICESE "Pelican" direct-drive arm (Kelly, Santibáñez & Loría, *Control of Robot
    /// Manipulators in Joint Space*, ch. 5), the documented stand-in for the paper's robot,
    /// whose parameters are not published (the manual's control law, `docs/src/reference/control-law.md` §1).
    pub fn pelican() -> Self {
        ScaraParameters {
            m1: cast(6.5225),
            m2: cast(2.0458),
            l1: cast(0.26),
            l2: cast(0.26),
            lc1: cast(0.0983),
            lc2: cast(0.0229),
            i1: cast(0.1213),
            i2: cast(0.0116),
        }
    }
}

impl<T: Real> ScaraParameters<T> {
    /// The arm as a serial chain: both axes along `z`, the forearm's joint at `(l₁, 0, 0)`,
    /// each link's centre of mass at `(lc_i, 0, 0)` with `I_i` about every axis (the arm
    /// turns about `z` only, so its dynamics equal the closed form's). It places points on the
    /// links ([`crate::obstacle`]) and checks the closed form against the chain's algorithms.
    pub fn chain(&self) -> Result<super::SerialChain<T, 2>> {
        use super::{ChainJoint, Pose, RigidInertia};
        let joint = |x: T| ChainJoint {
            kind: crate::lie::JointKind::Circular,
            origin: Pose::from_xyz_rpy([x, T::zero(), T::zero()], [T::zero(); 3]),
            axis: nalgebra::Vector3::z(),
        };
        let link = |m: T, c: T, i: T| RigidInertia {
            mass: m,
            com: nalgebra::Vector3::new(c, T::zero(), T::zero()),
            inertia: nalgebra::Matrix3::identity() * i,
        };
        super::SerialChain::new(
            [joint(T::zero()), joint(self.l1)],
            [
                link(self.m1, self.lc1, self.i1),
                link(self.m2, self.lc2, self.i2),
            ],
        )
    }
}

/// The two-link SCARA: `M = [[a₁ + 2a₃ cos q₂, a₂ + a₃ cos q₂], [a₂ + a₃ cos q₂, a₂]]`,
/// `C = a₃ sin q₂ [[−q̇₂, −(q̇₁ + q̇₂)], [q̇₁, 0]]` with
/// `a₁ = I₁ + I₂ + m₁lc₁² + m₂(l₁² + lc₂²)`, `a₂ = I₂ + m₂lc₂²`, `a₃ = m₂ l₁ lc₂`.
///
/// ```
/// use pvfc_core::mechanics::{MechanicalSystem, Scara};
/// use pvfc_core::lie::Torus;
/// use nalgebra::Vector2;
/// let arm = Scara::<f64>::pelican();
/// let m = arm.inertia(&Torus::new(Vector2::new(0.0, 0.3)));
/// assert!(m.cholesky().is_some());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scara<T: Real> {
    params: ScaraParameters<T>,
    a1: T,
    a2: T,
    a3: T,
}

impl<T: Real> Scara<T> {
    /// Builds the model, checking that every parameter is finite and positive
    /// (`lc2` may be 0) and that the inertia matrix is positive definite for every `q₂`.
    pub fn new(p: ScaraParameters<T>) -> Result<Self> {
        positive(p.m1, "Scara: m1 must be finite and > 0")?;
        positive(p.m2, "Scara: m2 must be finite and > 0")?;
        positive(p.l1, "Scara: l1 must be finite and > 0")?;
        positive(p.l2, "Scara: l2 must be finite and > 0")?;
        positive(p.i1, "Scara: i1 must be finite and > 0")?;
        positive(p.i2, "Scara: i2 must be finite and > 0")?;
        for (x, what) in [(p.lc1, "Scara: lc1"), (p.lc2, "Scara: lc2")] {
            if !x.is_finite() {
                return Err(Error::new(ErrorKind::NonFinite, what));
            }
            if x < T::zero() {
                return Err(Error::new(ErrorKind::InvalidParameter, what));
            }
        }
        let a1 = p.i1 + p.i2 + p.m1 * p.lc1 * p.lc1 + p.m2 * (p.l1 * p.l1 + p.lc2 * p.lc2);
        let a2 = p.i2 + p.m2 * p.lc2 * p.lc2;
        let a3 = p.m2 * p.l1 * p.lc2;
        // det M = a₂(a₁ − a₂) − a₃² cos² q₂ is smallest at cos² q₂ = 1.
        if a2 * (a1 - a2) - a3 * a3 <= T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "Scara: inertia matrix not positive definite",
            ));
        }
        Ok(Scara {
            params: p,
            a1,
            a2,
            a3,
        })
    }

    /// The Pelican arm of [`ScaraParameters::pelican`].
    pub fn pelican() -> Self {
        let p = ScaraParameters::pelican();
        let a1 = p.i1 + p.i2 + p.m1 * p.lc1 * p.lc1 + p.m2 * (p.l1 * p.l1 + p.lc2 * p.lc2);
        let a2 = p.i2 + p.m2 * p.lc2 * p.lc2;
        let a3 = p.m2 * p.l1 * p.lc2;
        Scara {
            params: p,
            a1,
            a2,
            a3,
        }
    }

    /// The physical parameters.
    pub fn parameters(&self) -> &ScaraParameters<T> {
        &self.params
    }

    /// The lumped constants `(a₁, a₂, a₃)`.
    pub fn lumped(&self) -> (T, T, T) {
        (self.a1, self.a2, self.a3)
    }

    /// Forward kinematics: the position of the elbow (joint 2, the end of link 1).
    pub fn elbow(&self, q: &Torus<T, 2>) -> nalgebra::Vector2<T> {
        let q1 = q.angles()[0];
        nalgebra::Vector2::new(q1.cos(), q1.sin()) * self.params.l1
    }

    /// Forward kinematics: the position of the end of link 2 in the plane.
    pub fn end_effector(&self, q: &Torus<T, 2>) -> nalgebra::Vector2<T> {
        let s = q.angles()[0] + q.angles()[1];
        self.elbow(q) + nalgebra::Vector2::new(s.cos(), s.sin()) * self.params.l2
    }
}

impl<T: Real> MechanicalSystem<T, Torus<T, 2>, 2> for Scara<T> {
    #[inline]
    fn inertia(&self, q: &Torus<T, 2>) -> Matrix2<T> {
        let (_, c2) = q.angles()[1].sin_cos_fast();
        let m12 = self.a2 + self.a3 * c2;
        Matrix2::new(self.a1 + (self.a3 + self.a3) * c2, m12, m12, self.a2)
    }

    #[inline]
    fn coriolis(&self, q: &Torus<T, 2>, v: &Tangent<T, 2>) -> Matrix2<T> {
        let (s2, _) = q.angles()[1].sin_cos_fast();
        let h = self.a3 * s2;
        Matrix2::new(-h * v[1], -h * (v[0] + v[1]), h * v[0], T::zero())
    }

    #[inline]
    fn inertia_and_coriolis(&self, q: &Torus<T, 2>, v: &Tangent<T, 2>) -> (Matrix2<T>, Matrix2<T>) {
        let (s2, c2) = q.angles()[1].sin_cos_fast();
        let m12 = self.a2 + self.a3 * c2;
        let h = self.a3 * s2;
        (
            Matrix2::new(self.a1 + (self.a3 + self.a3) * c2, m12, m12, self.a2),
            Matrix2::new(-h * v[1], -h * (v[0] + v[1]), h * v[0], T::zero()),
        )
    }

    /// The forward dynamics by Cramer's rule ([`solve_spd2`]: one division, no square root).
    #[inline]
    fn acceleration(
        &self,
        q: &Torus<T, 2>,
        v: &Tangent<T, 2>,
        force: &Tangent<T, 2>,
    ) -> Result<Tangent<T, 2>> {
        let (m, c) = self.inertia_and_coriolis(q, v);
        let rhs = force - c * v;
        solve_spd2(&m, &rhs).ok_or_else(|| acceleration_failure(m.iter(), rhs.iter()))
    }
}
