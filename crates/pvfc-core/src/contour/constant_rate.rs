//! One-parameter subgroups: `x_d(τ) = g₀·exp(τ ξ)` — a rotation at constant rate on SO(3).

use super::{Contour, ContourSample};
use crate::error::{ensure_finite, Result};
use crate::lie::{LieGroup, Tangent};
use crate::Real;
use core::marker::PhantomData;

/// The curve `x_d(τ) = g₀·exp(τ ξ)` with constant body velocity `ξ` (on SO(3): a rotation
/// at constant angular rate about a body-fixed axis).
///
/// ```
/// use pvfc_core::contour::{ConstantRate, Contour};
/// use pvfc_core::lie::{LieGroup, So3};
/// use nalgebra::Vector3;
/// let spin = ConstantRate::new(So3::<f64>::identity(), Vector3::new(0.0, 0.0, 0.5)).unwrap();
/// let s = spin.sample(2.0);
/// assert!((s.point.log() - Vector3::new(0.0, 0.0, 1.0)).norm() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantRate<T: Real, G: LieGroup<T, D>, const D: usize> {
    start: G,
    rate: Tangent<T, D>,
    _t: PhantomData<T>,
}

impl<T: Real, G: LieGroup<T, D>, const D: usize> ConstantRate<T, G, D> {
    /// Starts at `start` and moves with body velocity `rate` per unit of `τ`.
    pub fn new(start: G, rate: Tangent<T, D>) -> Result<Self> {
        ensure_finite(rate.iter(), "ConstantRate: rate")?;
        if !start.is_finite() {
            return Err(crate::Error::new(
                crate::ErrorKind::NonFinite,
                "ConstantRate: start",
            ));
        }
        Ok(ConstantRate {
            start,
            rate,
            _t: PhantomData,
        })
    }
}

impl<T: Real, G: LieGroup<T, D>, const D: usize> Contour<T, G, D> for ConstantRate<T, G, D> {
    #[inline]
    fn sample(&self, tau: T) -> ContourSample<T, G, D> {
        ContourSample {
            point: self.start.compose(&G::exp(&(self.rate * tau))),
            velocity: self.rate,
            acceleration: Tangent::zeros(),
        }
    }
}
