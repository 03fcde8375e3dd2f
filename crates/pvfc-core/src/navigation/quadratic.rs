//! A quadratic navigation function for the vector space `ℝⁿ`.

use super::{NavigationFunction, NavigationSample};
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::lie::{Rn, Tangent};
use crate::scalar::cast;
use crate::Real;
use nalgebra::SVector;

/// `U(E) = ½ Σ h_i E_i²` on `ℝⁿ` with the Euclidean metric: `grad U = (h_i E_i)_i`.
///
/// It has compact sublevel sets, which is what section IV's closing remarks ask of a
/// navigation function on a non-compact group. Unlike the torus' function its gradient is
/// unbounded, so choose Ē with the largest error you expect in mind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraticNavigation<T: Real, const N: usize> {
    h: SVector<T, N>,
}

impl<T: Real, const N: usize> QuadraticNavigation<T, N> {
    /// Weights `h_i > 0`.
    pub fn new(h: SVector<T, N>) -> Result<Self> {
        ensure_finite(h.iter(), "QuadraticNavigation: weights h")?;
        if h.iter().any(|x| *x <= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "QuadraticNavigation: every weight h_i must be > 0",
            ));
        }
        Ok(QuadraticNavigation { h })
    }
}

impl<T: Real, const N: usize> NavigationFunction<T, Rn<T, N>, N> for QuadraticNavigation<T, N> {
    #[inline]
    fn evaluate(&self, e: &Rn<T, N>, e_rate: &Tangent<T, N>) -> NavigationSample<T, N> {
        let gradient = e.coords().component_mul(&self.h);
        NavigationSample {
            value: gradient.dot(e.coords()) * cast::<T>(0.5),
            differential: gradient,
            gradient,
            value_rate: gradient.dot(e_rate),
            gradient_rate: e_rate.component_mul(&self.h),
        }
    }

    #[inline]
    fn metric_weight(&self) -> T {
        T::one()
    }
}
