//! `ℝⁿ` as an additive Lie group: the configuration space of linear stages.

use super::{LieGroup, Tangent};
use crate::Real;
use nalgebra::SVector;

/// An element of the vector space `ℝⁿ`, seen as a (non-compact, abelian) Lie group under
/// addition; also known as the translation group `T(n)`.
///
/// Section IV of the paper assumes a compact group; its closing remarks note that `ℝⁿ` still
/// works when the navigation function has compact sublevel sets and the field stays bounded,
/// which [`crate::navigation::QuadraticNavigation`] with bounded gains provides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rn<T: Real, const N: usize> {
    coords: SVector<T, N>,
}

impl<T: Real, const N: usize> Rn<T, N> {
    /// The point with the given coordinates.
    #[inline]
    pub fn new(coords: SVector<T, N>) -> Self {
        Rn { coords }
    }

    /// The coordinates.
    #[inline]
    pub fn coords(&self) -> &SVector<T, N> {
        &self.coords
    }
}

impl<T: Real, const N: usize> From<SVector<T, N>> for Rn<T, N> {
    fn from(coords: SVector<T, N>) -> Self {
        Rn::new(coords)
    }
}

impl<T: Real, const N: usize> LieGroup<T, N> for Rn<T, N> {
    #[inline]
    fn identity() -> Self {
        Rn::new(SVector::zeros())
    }
    #[inline]
    fn compose(&self, other: &Self) -> Self {
        Rn::new(self.coords + other.coords)
    }
    #[inline]
    fn inverse(&self) -> Self {
        Rn::new(-self.coords)
    }
    #[inline]
    fn exp(v: &Tangent<T, N>) -> Self {
        Rn::new(*v)
    }
    #[inline]
    fn log(&self) -> Tangent<T, N> {
        self.coords
    }
    abelian_group_algebra!();
    #[inline]
    fn chart_extent(_v: &Tangent<T, N>) -> T {
        T::zero()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        crate::scalar::all_finite(self.coords.iter())
    }
}
