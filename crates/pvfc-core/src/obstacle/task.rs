//! Obstacles in the task space: spheres fixed on a chain's links (the tool, the links as
//! chains of spheres) kept a clearance away from shapes placed in the world.

use super::{smooth_step, Barrier};
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::mechanics::PointMotion;
use crate::Real;
use nalgebra::{Matrix3, SVector, Vector3};

/// A sphere fixed on a link: the part of the robot kept away from the obstacles. A link is
/// covered by a few of them along its length (a capsule's sphere-swept outline), the tool by
/// one at its tip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodySphere<T: Real> {
    /// The link it is fixed on (joint `i` moves link `i`, from 0).
    pub link: usize,
    /// Its centre in the link's frame.
    pub offset: Vector3<T>,
    /// Its radius (≥ 0; 0 for a point).
    pub radius: T,
}

impl<T: Real> BodySphere<T> {
    /// A checked sphere.
    pub fn new(link: usize, offset: Vector3<T>, radius: T) -> Result<Self> {
        ensure_finite(
            offset.iter().chain([radius].iter()),
            "BodySphere: offset, radius",
        )?;
        if radius < T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "BodySphere: the radius must be ≥ 0",
            ));
        }
        Ok(BodySphere {
            link,
            offset,
            radius,
        })
    }
}

/// A shape in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WorldShape<T: Real> {
    /// A ball.
    Sphere {
        /// Its centre.
        center: Vector3<T>,
        /// Its radius.
        radius: T,
    },
    /// An infinite cylinder (a post, a column; for a planar arm, a disc in its plane).
    Cylinder {
        /// A point on its axis.
        point: Vector3<T>,
        /// The axis' direction (normalised when built).
        axis: Vector3<T>,
        /// Its radius.
        radius: T,
    },
}

/// A shape with the margin the robot keeps from it and the width over which the field
/// feels it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldObstacle<T: Real> {
    shape: WorldShape<T>,
    margin: T,
    influence: T,
}

/// The distance `d` from a point to a shape's surface, its gradient `n` and Hessian `H` in
/// the point.
struct Surface<T: Real> {
    distance: T,
    normal: Vector3<T>,
    hessian: Matrix3<T>,
}

impl<T: Real> WorldObstacle<T> {
    /// The shape (radius > 0), the margin `m ≥ 0` kept between it and the robot's spheres
    /// (the barrier is 0 there) and the influence width `w > 0` beyond the margin.
    pub fn new(shape: WorldShape<T>, margin: T, influence: T) -> Result<Self> {
        let (radius, shape) = match shape {
            WorldShape::Sphere { center, radius } => {
                ensure_finite(center.iter(), "WorldObstacle: sphere centre")?;
                (radius, shape)
            }
            WorldShape::Cylinder {
                point,
                axis,
                radius,
            } => {
                ensure_finite(
                    point.iter().chain(axis.iter()),
                    "WorldObstacle: cylinder axis",
                )?;
                let n = axis.norm();
                if n <= T::default_epsilon() {
                    return Err(Error::new(
                        ErrorKind::InvalidParameter,
                        "WorldObstacle: the cylinder's axis must not be zero",
                    ));
                }
                (
                    radius,
                    WorldShape::Cylinder {
                        point,
                        axis: axis / n,
                        radius,
                    },
                )
            }
        };
        ensure_finite(
            [radius, margin, influence].iter(),
            "WorldObstacle: radius, margin, influence",
        )?;
        if radius <= T::zero() || margin < T::zero() || influence <= T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "WorldObstacle: the radius and influence must be > 0, the margin ≥ 0",
            ));
        }
        Ok(WorldObstacle {
            shape,
            margin,
            influence,
        })
    }

    /// The shape.
    pub fn shape(&self) -> &WorldShape<T> {
        &self.shape
    }

    /// The margin.
    pub fn margin(&self) -> T {
        self.margin
    }

    /// The influence width.
    pub fn influence(&self) -> T {
        self.influence
    }

    fn surface(&self, p: &Vector3<T>) -> Surface<T> {
        let tiny: T = crate::scalar::cast(1e-12);
        let (offset, radius, projector) = match self.shape {
            WorldShape::Sphere { center, radius } => (p - center, radius, Matrix3::identity()),
            WorldShape::Cylinder {
                point,
                axis,
                radius,
            } => {
                let projector = Matrix3::identity() - axis * axis.transpose();
                (projector * (p - point), radius, projector)
            }
        };
        let length = offset.norm().max(tiny);
        let normal = offset / length;
        Surface {
            distance: length - radius,
            normal,
            hessian: (projector - normal * normal.transpose()) / length,
        }
    }

    /// The clearance between a body sphere at `p` and the shape: the distance between their
    /// surfaces (negative when they overlap).
    pub fn clearance(&self, p: &Vector3<T>, sphere: &BodySphere<T>) -> T {
        self.surface(p).distance - sphere.radius
    }

    /// The barrier of one body sphere, moving with `m`: `β = σ((d − ρ − margin)/w)`, with
    /// `dβ = σ'/w · J_pᵀ n` and `d/dt dβ = σ''/w² ℓ̇ J_pᵀ n + σ'/w (J̇_pᵀ n + J_pᵀ H ṗ)`.
    pub fn barrier<const N: usize>(
        &self,
        m: &PointMotion<T, N>,
        sphere: &BodySphere<T>,
    ) -> Barrier<T, N> {
        let s = self.surface(&m.position);
        let inv_w = T::one() / self.influence;
        let clearance = s.distance - sphere.radius - self.margin;
        let (b, b1, b2) = smooth_step(clearance * inv_w);
        if b1 == T::zero() && b2 == T::zero() {
            return Barrier::free();
        }
        let jt_n: SVector<T, N> = m.jacobian.transpose() * s.normal;
        let rate = s.normal.dot(&m.velocity);
        let jt_n_dot: SVector<T, N> = m.jacobian_rate.transpose() * s.normal
            + m.jacobian.transpose() * (s.hessian * m.velocity);
        Barrier {
            value: b,
            differential: jt_n * (b1 * inv_w),
            value_rate: b1 * inv_w * rate,
            differential_rate: jt_n * (b2 * inv_w * inv_w * rate) + jt_n_dot * (b1 * inv_w),
        }
    }
}
