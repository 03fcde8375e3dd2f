//! Obstacles in the task space: spheres fixed on a chain's links (the tool, the links as
//! chains of spheres) kept a clearance away from shapes placed in the world.

use super::{step_barrier, Barrier};
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
    /// A capsule: the points within `radius` of the segment from `a` to `b` (a bar, a
    /// pipe, another robot's link).
    Capsule {
        /// One end of its axis.
        a: Vector3<T>,
        /// The other end.
        b: Vector3<T>,
        /// Its radius (≥ 0).
        radius: T,
    },
    /// A box with rounded edges: the points within `radius` of the box of half extents
    /// `half_extents` about `center`, turned by `rotation` (a fixture, a table, a wall).
    Box {
        /// Its centre.
        center: Vector3<T>,
        /// Its axes in the world frame (a rotation matrix's columns).
        rotation: Matrix3<T>,
        /// Half its sizes along its axes (> 0).
        half_extents: Vector3<T>,
        /// The rounding of its edges and faces (≥ 0).
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

/// A capsule's or a box's radius: `≥ 0`, and then taken as positive for the common check.
fn rounding<T: Real>(radius: T) -> Result<T> {
    if radius < T::zero() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            "WorldObstacle: a capsule's or a box's radius must be ≥ 0",
        ));
    }
    Ok(radius.max(T::default_epsilon()))
}

/// The distance `d` from a point to a shape's surface, its gradient `n` and Hessian `H` in
/// the point.
struct Surface<T: Real> {
    distance: T,
    normal: Vector3<T>,
    hessian: Matrix3<T>,
}

impl<T: Real> WorldObstacle<T> {
    /// The shape (radius > 0; ≥ 0 for a capsule and a box), the margin `m ≥ 0` kept between
    /// it and the robot's spheres (the barrier is 0 there) and the influence width `w > 0`
    /// beyond the margin.
    ///
    /// The distance to a sphere or a cylinder is smooth outside it; to a capsule or a box it
    /// is `C¹` with a Lipschitz gradient: the field is continuous and its rate bounded, with a
    /// jump across the planes where the closest feature changes (a capsule's end caps, a
    /// box's faces, edges and corners).
    pub fn new(shape: WorldShape<T>, margin: T, influence: T) -> Result<Self> {
        let (radius, shape) = match shape {
            WorldShape::Sphere { center, radius } => {
                ensure_finite(center.iter(), "WorldObstacle: sphere centre")?;
                (radius, shape)
            }
            WorldShape::Capsule { a, b, radius } => {
                ensure_finite(a.iter().chain(b.iter()), "WorldObstacle: capsule ends")?;
                // A capsule of radius 0 is a segment: allowed (the margin keeps the robot off).
                (rounding(radius)?, shape)
            }
            WorldShape::Box {
                center,
                rotation,
                half_extents,
                radius,
            } => {
                ensure_finite(
                    center
                        .iter()
                        .chain(rotation.iter())
                        .chain(half_extents.iter()),
                    "WorldObstacle: box centre, rotation, half extents",
                )?;
                let orthonormal = (rotation.transpose() * rotation - Matrix3::identity()).norm()
                    < crate::scalar::cast(1e-6);
                if !orthonormal || half_extents.iter().any(|h| *h <= T::zero()) {
                    return Err(Error::new(
                        ErrorKind::InvalidParameter,
                        "WorldObstacle: a box needs a rotation matrix and half extents > 0",
                    ));
                }
                (radius.max(T::default_epsilon()), shape)
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
        // `offset = p − c(p)` from the closest point `c` of the shape's core (its centre, axis,
        // segment or box), and the projector `P = ∂offset/∂p` onto the directions in which
        // `c` stays put: the Hessian of `|offset|` is `(P − n nᵀ)/|offset|`.
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
            WorldShape::Capsule { a, b, radius } => {
                let ab = b - a;
                let length2 = ab.norm_squared();
                let t = if length2 > T::zero() {
                    (p - a).dot(&ab) / length2
                } else {
                    T::zero()
                };
                if t > T::zero() && t < T::one() {
                    let u = ab / length2.sqrt();
                    let projector = Matrix3::identity() - u * u.transpose();
                    (projector * (p - a), radius, projector)
                } else {
                    let end = if t <= T::zero() { a } else { b };
                    (p - end, radius, Matrix3::identity())
                }
            }
            WorldShape::Box {
                center,
                rotation,
                half_extents,
                radius,
            } => {
                let local = rotation.transpose() * (p - center);
                let mut outside = Vector3::zeros();
                let mut closest = local;
                for i in 0..3 {
                    if local[i] > half_extents[i] {
                        closest[i] = half_extents[i];
                        outside[i] = T::one();
                    } else if local[i] < -half_extents[i] {
                        closest[i] = -half_extents[i];
                        outside[i] = T::one();
                    }
                }
                if outside == Vector3::zeros() {
                    // Inside: the distance to the nearest face, negative.
                    let slack = half_extents - local.abs();
                    let i = slack.imin();
                    let mut n = Vector3::zeros();
                    n[i] = if local[i] >= T::zero() {
                        T::one()
                    } else {
                        -T::one()
                    };
                    return Surface {
                        distance: -slack[i] - radius,
                        normal: rotation * n,
                        hessian: Matrix3::zeros(),
                    };
                }
                let projector = rotation * Matrix3::from_diagonal(&outside) * rotation.transpose();
                (rotation * (local - closest), radius, projector)
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
        if clearance * inv_w >= T::one() {
            return Barrier::free();
        }
        let jt_n: SVector<T, N> = m.jacobian.transpose() * s.normal;
        let jt_n_dot: SVector<T, N> = m.jacobian_rate.transpose() * s.normal
            + m.jacobian.transpose() * (s.hessian * m.velocity);
        step_barrier(
            clearance * inv_w,
            &(jt_n * inv_w),
            s.normal.dot(&m.velocity) * inv_w,
            &(jt_n_dot * inv_w),
        )
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::mechanics::Pose;

    /// The distance's gradient and Hessian against central differences, for every shape, at
    /// points inside each region of its closest feature (faces, edges, corners, end caps).
    #[test]
    fn the_distance_has_its_gradient_and_hessian() {
        let rotation = Pose::<f64>::from_xyz_rpy([0.0; 3], [0.3, -0.2, 0.5]).rotation;
        let shapes = [
            WorldShape::Sphere {
                center: Vector3::new(0.1, 0.2, 0.3),
                radius: 0.1,
            },
            WorldShape::Cylinder {
                point: Vector3::new(0.0, 0.1, 0.0),
                axis: Vector3::new(0.2, 0.1, 1.0),
                radius: 0.05,
            },
            WorldShape::Capsule {
                a: Vector3::new(-0.2, 0.0, 0.0),
                b: Vector3::new(0.3, 0.1, 0.1),
                radius: 0.04,
            },
            WorldShape::Box {
                center: Vector3::new(0.05, -0.05, 0.1),
                rotation,
                half_extents: Vector3::new(0.1, 0.2, 0.05),
                radius: 0.01,
            },
        ];
        let points = [
            Vector3::new(0.4, 0.35, 0.2),
            Vector3::new(-0.45, 0.05, -0.1),
            Vector3::new(0.05, -0.05, 0.4),
            Vector3::new(0.05, 0.4, 0.1),
            Vector3::new(0.35, 0.4, 0.45),
            Vector3::new(0.1, -0.3, -0.2),
        ];
        let h = 1e-6;
        for shape in shapes {
            let o = WorldObstacle::new(shape, 0.01, 0.1).unwrap();
            for p in points {
                let s = o.surface(&p);
                for i in 0..3 {
                    let mut dp = Vector3::zeros();
                    dp[i] = h;
                    let plus = o.surface(&(p + dp));
                    let minus = o.surface(&(p - dp));
                    let fd = (plus.distance - minus.distance) / (2.0 * h);
                    assert!(
                        (fd - s.normal[i]).abs() < 1e-8,
                        "{shape:?} at {p:?}: ∂d/∂p_{i}"
                    );
                    let fd = (plus.normal - minus.normal) / (2.0 * h);
                    assert!(
                        (fd - s.hessian.column(i)).norm() < 1e-6,
                        "{shape:?} at {p:?}: Hessian column {i}"
                    );
                }
            }
        }
        let bad = WorldShape::Capsule {
            a: Vector3::zeros(),
            b: Vector3::x(),
            radius: -0.1,
        };
        assert!(WorldObstacle::new(bad, 0.0, 0.1).is_err());
    }
}
