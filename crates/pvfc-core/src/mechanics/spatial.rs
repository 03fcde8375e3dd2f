//! Spatial (6-D) rigid-body algebra for [`super::SerialChain`]: rigid transforms, inertias
//! and the cross-product operators, after Featherstone, *Rigid Body Dynamics Algorithms*
//! (2008), ch. 2. Spatial vectors are ordered `[angular; linear]` and written in one frame
//! (the chain's base) at its origin.

use crate::error::{Error, ErrorKind, Result};
use crate::scalar::cast;
use crate::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// A spatial motion or force vector, `[angular; linear]`.
pub type Spatial<T> = SVector<T, 6>;
/// A 6×6 spatial matrix.
pub type Spatial6<T> = SMatrix<T, 6, 6>;

/// A rigid transform `x ↦ R x + p` (a frame's pose: its axes `R` and origin `p` in the
/// parent frame), kept as a rotation matrix so that composing poses needs no trigonometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<T: Real> {
    /// The rotation `R` (orthonormal, det 1).
    pub rotation: Matrix3<T>,
    /// The translation `p`.
    pub translation: Vector3<T>,
}

impl<T: Real> Pose<T> {
    /// The identity transform.
    pub fn identity() -> Self {
        Pose {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// The pose of a URDF `<origin xyz rpy>`: `R = R_z(yaw) R_y(pitch) R_x(roll)` (fixed axes
    /// x, y, z), then the translation.
    pub fn from_xyz_rpy(xyz: [T; 3], rpy: [T; 3]) -> Self {
        let (sr, cr) = rpy[0].sin_cos_fast();
        let (sp, cp) = rpy[1].sin_cos_fast();
        let (sy, cy) = rpy[2].sin_cos_fast();
        let rotation = Matrix3::new(
            cy * cp,
            cy * sp * sr - sy * cr,
            cy * sp * cr + sy * sr,
            sy * cp,
            sy * sp * sr + cy * cr,
            sy * sp * cr - cy * sr,
            -sp,
            cp * sr,
            cp * cr,
        );
        Pose {
            rotation,
            translation: Vector3::new(xyz[0], xyz[1], xyz[2]),
        }
    }

    /// `self · other`: `other` expressed in `self`'s parent frame.
    #[inline]
    pub fn compose(&self, other: &Pose<T>) -> Pose<T> {
        Pose {
            rotation: self.rotation * other.rotation,
            translation: self.translation + self.rotation * other.translation,
        }
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Pose<T> {
        let rt = self.rotation.transpose();
        Pose {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// Applies the transform to a point.
    #[inline]
    pub fn transform_point(&self, x: &Vector3<T>) -> Vector3<T> {
        self.rotation * x + self.translation
    }

    /// `true` when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rotation
            .iter()
            .chain(self.translation.iter())
            .all(|x| x.is_finite())
    }
}

/// The rotation by `angle` about the unit `axis` (Rodrigues).
#[inline]
pub fn axis_angle<T: Real>(axis: &Vector3<T>, angle: T) -> Matrix3<T> {
    axis_rotation(axis, angle.sin_cos_fast())
}

/// The rotation about the unit `axis` by the angle whose sine and cosine are `(s, c)`
/// (Rodrigues): [`axis_angle`] with the trigonometry done by the caller, so that a chain can
/// take every joint's sine and cosine first, side by side, before its pose recursion needs
/// them.
#[inline(always)]
pub(crate) fn axis_rotation<T: Real>(axis: &Vector3<T>, (s, c): (T, T)) -> Matrix3<T> {
    // R = c 1 + s [a]× + (1 − c) a aᵀ for a unit axis (= 1 + s K + (1 − c) K², K = [a]×).
    let t = T::one() - c;
    let (x, y, z) = (axis[0], axis[1], axis[2]);
    let (tx, ty, tz) = (t * x, t * y, t * z);
    let (sx, sy, sz) = (s * x, s * y, s * z);
    Matrix3::new(
        tx * x + c,
        tx * y - sz,
        tx * z + sy,
        tx * y + sz,
        ty * y + c,
        ty * z - sx,
        tx * z - sy,
        ty * z + sx,
        tz * z + c,
    )
}

/// The inertia of a rigid body: its mass, its centre of mass and its rotational inertia about
/// the centre of mass, both in the body's frame (a URDF `<inertial>` after its `<origin>` is
/// applied).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidInertia<T: Real> {
    /// Mass (kg), > 0.
    pub mass: T,
    /// Centre of mass in the body frame (m).
    pub com: Vector3<T>,
    /// Rotational inertia about the centre of mass, in the body frame's axes (kg·m²),
    /// symmetric positive definite.
    pub inertia: Matrix3<T>,
}

impl<T: Real> RigidInertia<T> {
    /// An inertia given as in URDF: mass, the inertial frame's pose in the body frame
    /// (`<origin xyz rpy>`), and the six entries `ixx ixy ixz iyy iyz izz` in that frame.
    pub fn from_urdf(mass: T, origin: &Pose<T>, i: [T; 6]) -> Self {
        let local = Matrix3::new(i[0], i[1], i[2], i[1], i[3], i[4], i[2], i[4], i[5]);
        RigidInertia {
            mass,
            com: origin.translation,
            inertia: origin.rotation * local * origin.rotation.transpose(),
        }
    }

    /// Checks the inertia: finite, `mass > 0`, the rotational inertia symmetric (to
    /// rounding) and positive definite.
    pub fn validate(&self, context: &'static str) -> Result<()> {
        let all = core::iter::once(&self.mass)
            .chain(self.com.iter())
            .chain(self.inertia.iter());
        crate::error::ensure_finite(all, context)?;
        if self.mass <= T::zero() {
            return Err(Error::new(ErrorKind::InvalidParameter, context));
        }
        let asym = (self.inertia - self.inertia.transpose()).amax();
        if asym > self.inertia.amax() * cast(1e-6) {
            return Err(Error::new(ErrorKind::InvalidParameter, context));
        }
        if self.inertia.cholesky().is_none() {
            return Err(Error::new(ErrorKind::SingularInertia, context));
        }
        Ok(())
    }

    /// The same body seen from a parent frame in which the body frame has the pose `pose`.
    pub fn transformed(&self, pose: &Pose<T>) -> Self {
        RigidInertia {
            mass: self.mass,
            com: pose.transform_point(&self.com),
            inertia: pose.rotation * self.inertia * pose.rotation.transpose(),
        }
    }

    /// Two bodies rigidly joined, in the same frame (parallel-axis theorem).
    pub fn combined(&self, other: &Self) -> Self {
        let mass = self.mass + other.mass;
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let shift = |b: &Self| {
            let d = b.com - com;
            (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * b.mass
        };
        RigidInertia {
            mass,
            com,
            inertia: self.inertia + shift(self) + other.inertia + shift(other),
        }
    }

    /// The 6×6 spatial inertia at the origin of the frame it is written in (Featherstone
    /// eq. 2.63): `[[I_c − m c×c×, m c×], [−m c×, m 1]]`.
    pub fn spatial(&self) -> Spatial6<T> {
        let cx = self.com.cross_matrix();
        let mcx = cx * self.mass;
        let mut out = Spatial6::zeros();
        out.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(self.inertia - mcx * cx));
        out.fixed_view_mut::<3, 3>(0, 3).copy_from(&mcx);
        out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-mcx));
        out.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass));
        out
    }
}

/// A spatial inertia in the world frame in ten numbers: the mass `m`, the first moment
/// `h = m c` (`c` the centre of mass) and the rotational inertia `I_o` about the world origin.
/// It stands for the 6×6 `[[I_o, h×], [−h×, m 1]]` (Featherstone eq. 2.63 with
/// `I_o = I_c − m c×c×`): adding two is adding their numbers, and applying one to a motion
/// vector costs 24 products instead of 36, so the algorithms that need only `I S` (CRBA,
/// RNEA, gravity) do not form the 6×6 matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldInertia<T: Real> {
    /// Mass (kg).
    pub mass: T,
    /// First moment `m c` (kg·m).
    pub first_moment: Vector3<T>,
    /// Rotational inertia about the origin, `R I_c Rᵀ + m (|c|² 1 − c cᵀ)` (kg·m²).
    pub rotational: Matrix3<T>,
}

impl<T: Real> WorldInertia<T> {
    /// No body.
    pub fn zeros() -> Self {
        WorldInertia {
            mass: T::zero(),
            first_moment: Vector3::zeros(),
            rotational: Matrix3::zeros(),
        }
    }

    /// The body `body` with the pose `pose` in the world.
    #[inline]
    pub fn of(body: &RigidInertia<T>, pose: &Pose<T>) -> Self {
        let b = body.transformed(pose);
        let c = b.com;
        let shift = Matrix3::identity() * c.dot(&c) - c * c.transpose();
        WorldInertia {
            mass: b.mass,
            first_moment: c * b.mass,
            rotational: b.inertia + shift * b.mass,
        }
    }

    /// `I v` for the motion vector `v = [ω; u]`: the force `[I_o ω + h × u; m u − h × ω]`.
    #[inline]
    pub fn apply(&self, v: &Spatial<T>) -> Spatial<T> {
        let w = Vector3::new(v[0], v[1], v[2]);
        let u = Vector3::new(v[3], v[4], v[5]);
        let h = &self.first_moment;
        let top = self.rotational * w + h.cross(&u);
        let bottom = u * self.mass - h.cross(&w);
        Spatial::new(top[0], top[1], top[2], bottom[0], bottom[1], bottom[2])
    }

    /// The 6×6 matrix it stands for.
    pub fn matrix(&self) -> Spatial6<T> {
        let hx = self.first_moment.cross_matrix();
        let mut out = Spatial6::zeros();
        out.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rotational);
        out.fixed_view_mut::<3, 3>(0, 3).copy_from(&hx);
        out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-hx));
        out.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass));
        out
    }
}

impl<T: Real> core::ops::AddAssign for WorldInertia<T> {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        self.mass += o.mass;
        self.first_moment += o.first_moment;
        self.rotational += o.rotational;
    }
}

/// `v ×* f` for a motion vector `v = [ω; u]` and a force `f = [n; f]` (Featherstone eq. 2.32):
/// `[ω × n + u × f; ω × f]`, without forming `v×*`.
#[inline]
pub fn force_cross_apply<T: Real>(v: &Spatial<T>, f: &Spatial<T>) -> Spatial<T> {
    let w = Vector3::new(v[0], v[1], v[2]);
    let u = Vector3::new(v[3], v[4], v[5]);
    let n = Vector3::new(f[0], f[1], f[2]);
    let l = Vector3::new(f[3], f[4], f[5]);
    let top = w.cross(&n) + u.cross(&l);
    let bottom = w.cross(&l);
    Spatial::new(top[0], top[1], top[2], bottom[0], bottom[1], bottom[2])
}

/// The motion cross product `v×` (Featherstone eq. 2.31): `(v×) m` is the rate of a motion
/// vector `m` fixed in a body moving with `v`.
#[inline]
pub fn motion_cross<T: Real>(v: &Spatial<T>) -> Spatial6<T> {
    let w = Vector3::new(v[0], v[1], v[2]).cross_matrix();
    let u = Vector3::new(v[3], v[4], v[5]).cross_matrix();
    let mut out = Spatial6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&w);
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&u);
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&w);
    out
}

/// The force cross product `v×* = −(v×)ᵀ` (Featherstone eq. 2.32).
#[inline]
pub fn force_cross<T: Real>(v: &Spatial<T>) -> Spatial6<T> {
    -motion_cross(v).transpose()
}

/// `h ×̄*`, the matrix of `m ↦ m ×* h` for a fixed force `h`: skew-symmetric (Echeandia &
/// Wensing, *Numerical methods to compute the Coriolis matrix and Christoffel symbols for
/// rigid-body systems*, J. Comput. Nonlinear Dynam. 2021, eq. 14).
#[inline]
pub fn force_cross_bar<T: Real>(h: &Spatial<T>) -> Spatial6<T> {
    let n = Vector3::new(h[0], h[1], h[2]).cross_matrix();
    let f = Vector3::new(h[3], h[4], h[5]).cross_matrix();
    let mut out = Spatial6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&(-n));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-f));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-f));
    out
}
