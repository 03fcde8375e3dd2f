//! Ellipses and circles in joint space.

use super::{check_period, Contour, ContourSample, VectorGroup};
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::Real;
use nalgebra::SVector;

/// An ellipse in coordinate space, `x_d(τ) = c + u cos(2πτ/T) + w sin(2πτ/T)`, period `T`.
///
/// `u` and `w` are its conjugate semi-axes (orthogonal ones give the principal axes).
///
/// ```
/// use pvfc_core::contour::{Contour, Ellipse};
/// use pvfc_core::lie::Torus;
/// use nalgebra::Vector2;
/// let circle = Ellipse::circle(Vector2::new(0.5, 0.0), 0.3, 4.0).unwrap();
/// let p: Torus<f64, 2> = circle.point(1.0); // a quarter turn
/// assert!((p.angles() - Vector2::new(0.5, 0.3)).norm() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse<T: Real, const N: usize> {
    center: SVector<T, N>,
    u: SVector<T, N>,
    w: SVector<T, N>,
    omega: T,
    period: T,
}

impl<T: Real, const N: usize> Ellipse<T, N> {
    /// The ellipse with centre `c`, conjugate semi-axes `u`, `w`, and period `T > 0`.
    pub fn new(
        center: SVector<T, N>,
        u: SVector<T, N>,
        w: SVector<T, N>,
        period: T,
    ) -> Result<Self> {
        ensure_finite(
            center.iter().chain(u.iter()).chain(w.iter()),
            "Ellipse: centre and axes",
        )?;
        check_period(period, "Ellipse: period must be finite and > 0")?;
        Ok(Ellipse {
            center,
            u,
            w,
            omega: T::two_pi() / period,
            period,
        })
    }

    /// A circle of the given radius in the plane of the first two coordinates
    /// (counter-clockwise, starting at `c + r e₁`). Needs `N ≥ 2`.
    pub fn circle(center: SVector<T, N>, radius: T, period: T) -> Result<Self> {
        if N < 2 {
            return Err(Error::new(
                ErrorKind::DimensionMismatch,
                "Ellipse::circle needs at least two coordinates",
            ));
        }
        if !radius.is_finite() || radius <= T::zero() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "Ellipse::circle: radius must be > 0",
            ));
        }
        let mut u = SVector::zeros();
        let mut w = SVector::zeros();
        u[0] = radius;
        w[1] = radius;
        Self::new(center, u, w, period)
    }
}

impl<T: Real, G: VectorGroup<T, N>, const N: usize> Contour<T, G, N> for Ellipse<T, N> {
    #[inline]
    fn sample(&self, tau: T) -> ContourSample<T, G, N> {
        let (s, c) = (self.omega * tau).sin_cos_fast();
        let om = self.omega;
        ContourSample {
            point: G::from_coordinates(self.center + self.u * c + self.w * s),
            velocity: (self.w * c - self.u * s) * om,
            acceleration: (self.u * c + self.w * s) * (-om * om),
        }
    }

    fn period(&self) -> Option<T> {
        Some(self.period)
    }
}
