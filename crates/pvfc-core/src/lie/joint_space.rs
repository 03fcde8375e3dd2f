//! The joint space of a serial chain: a product of circles (revolute joints) and lines
//! (prismatic joints), `G = T^r × ℝ^p`, with its coordinates in joint order.

use super::{wrap_angle, LieGroup, Tangent};
use crate::Real;
use nalgebra::SVector;

/// What one coordinate of a [`JointSpace`] is: an angle on a circle or a length on a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum JointKind {
    /// A revolute or continuous joint: the coordinate is an angle on `S¹` (radians).
    #[default]
    Circular,
    /// A prismatic joint: the coordinate is a length on `ℝ` (metres).
    Linear,
}

/// An element of the joint space `T^r × ℝ^p` of a chain with `N` joints, stored as its `N`
/// coordinates and, per coordinate, whether it is circular.
///
/// The group is abelian (addition of coordinates): `Ad = I` and the bracket vanishes, as on
/// [`super::Torus`] and [`super::Rn`], which are its all-circular and all-linear cases. The only
/// place where the kinds matter is [`LieGroup::log`], which wraps the circular coordinates
/// into `(−π, π]` and leaves the linear ones as they are.
///
/// The kinds travel with the elements: [`LieGroup::identity`] and [`LieGroup::exp`] mark no
/// coordinate circular (they have no joint to ask), and a composition marks circular every
/// coordinate that is circular in either factor. So the error `E = q·x_d⁻¹` of a measured
/// configuration `q` (built with the chain's kinds) has the chain's kinds.
///
/// ```
/// use pvfc_core::lie::{JointKind, JointSpace, LieGroup};
/// use nalgebra::Vector2;
/// let kinds = [JointKind::Circular, JointKind::Linear];
/// let q = JointSpace::new(Vector2::new(7.0, 7.0), kinds);
/// let v = q.log();
/// assert!((v[0] - (7.0 - 2.0 * std::f64::consts::PI)).abs() < 1e-12); // wrapped
/// assert_eq!(v[1], 7.0); // a length is not
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSpace<T: Real, const N: usize> {
    coords: SVector<T, N>,
    circular: [bool; N],
}

impl<T: Real, const N: usize> JointSpace<T, N> {
    /// The element with the given coordinates and joint kinds.
    #[inline]
    pub fn new(coords: SVector<T, N>, kinds: [JointKind; N]) -> Self {
        JointSpace {
            coords,
            circular: kinds.map(|k| k == JointKind::Circular),
        }
    }

    /// All coordinates circular: the torus `Tᴺ`.
    #[inline]
    pub fn revolute(coords: SVector<T, N>) -> Self {
        JointSpace {
            coords,
            circular: [true; N],
        }
    }

    /// The coordinates (angles unwrapped).
    #[inline]
    pub fn coords(&self) -> &SVector<T, N> {
        &self.coords
    }

    /// The kind of every coordinate.
    #[inline]
    pub fn kinds(&self) -> [JointKind; N] {
        self.circular.map(|c| {
            if c {
                JointKind::Circular
            } else {
                JointKind::Linear
            }
        })
    }

    /// The same coordinates with other kinds.
    #[inline]
    pub fn with_kinds(self, kinds: [JointKind; N]) -> Self {
        JointSpace::new(self.coords, kinds)
    }

    #[inline]
    fn joined(&self, other: &Self, coords: SVector<T, N>) -> Self {
        let mut circular = self.circular;
        for (c, o) in circular.iter_mut().zip(other.circular.iter()) {
            *c = *c || *o;
        }
        JointSpace { coords, circular }
    }
}

impl<T: Real, const N: usize> LieGroup<T, N> for JointSpace<T, N> {
    #[inline]
    fn identity() -> Self {
        JointSpace {
            coords: SVector::zeros(),
            circular: [false; N],
        }
    }
    #[inline]
    fn compose(&self, other: &Self) -> Self {
        self.joined(other, self.coords + other.coords)
    }
    #[inline]
    fn inverse(&self) -> Self {
        JointSpace {
            coords: -self.coords,
            circular: self.circular,
        }
    }
    #[inline]
    fn exp(v: &Tangent<T, N>) -> Self {
        JointSpace {
            coords: *v,
            circular: [false; N],
        }
    }
    #[inline]
    fn log(&self) -> Tangent<T, N> {
        let mut v = self.coords;
        for (x, c) in v.iter_mut().zip(self.circular.iter()) {
            if *c {
                *x = wrap_angle(*x);
            }
        }
        v
    }
    abelian_group_algebra!();
    #[inline]
    fn chart_extent(v: &Tangent<T, N>) -> T {
        v.amax()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        crate::scalar::all_finite(self.coords.iter())
    }
    #[inline]
    fn retract(&self, v: &Tangent<T, N>, dt: T) -> Self {
        JointSpace {
            coords: self.coords + v * dt,
            circular: self.circular,
        }
    }
}
