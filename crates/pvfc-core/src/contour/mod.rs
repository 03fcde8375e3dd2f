//! Parameterised contours `x_d : I → G` (section III-B, IV-B of the paper).
//!
//! A [`Contour`] gives, at each parameter value `τ`, the point `x_d(τ)` and its first two
//! derivatives in **body coordinates** ([`crate::lie`]): `ξ_d(τ)` with
//! `dx_d/dτ = x_d·ξ̂_d` (for SO(3) this is the paper's `Ω(τ)`; for the torus the plain
//! derivative `dx_d/dτ`), and `dξ_d/dτ` (for the torus `d²x_d/dτ²`). The second derivative is
//! what the rate of the velocity field `V̇` needs.

mod bspline;
mod constant_rate;
mod ellipse;
mod lissajous;

pub use bspline::{spline_segment_logs, spline_through, PeriodicBSpline, SplineView};
pub use constant_rate::ConstantRate;
pub use ellipse::Ellipse;
pub use lissajous::Lissajous;

use crate::lie::{JointSpace, LieGroup, Rn, Tangent, Torus};
use crate::Real;
use nalgebra::SVector;

/// `x_d(τ)` with its body-coordinate derivatives, computed together (they share the work).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourSample<T: Real, G, const D: usize> {
    /// The point `x_d(τ)`.
    pub point: G,
    /// `ξ_d(τ)`: `dx_d/dτ = x_d(τ)·ξ̂_d(τ)`.
    pub velocity: Tangent<T, D>,
    /// `dξ_d/dτ`.
    pub acceleration: Tangent<T, D>,
}

/// A parameterised curve on the group `G`, with two derivatives.
pub trait Contour<T: Real, G: LieGroup<T, D>, const D: usize> {
    /// `x_d(τ)`, `ξ_d(τ)` and `dξ_d/dτ` at `τ`.
    fn sample(&self, tau: T) -> ContourSample<T, G, D>;

    /// `x_d(τ)` alone.
    #[inline]
    fn point(&self, tau: T) -> G {
        self.sample(tau).point
    }

    /// The period in `τ`, for closed contours (`x_d(τ + period) = x_d(τ)`).
    fn period(&self) -> Option<T> {
        None
    }
}

/// A group whose elements are given by `N` real coordinates with addition as the group
/// operation: the torus (angles), `ℝⁿ` and the mixed joint space of a serial chain. Curves written coordinate-wise ([`Lissajous`],
/// [`Ellipse`]) are contours on any such group.
pub trait VectorGroup<T: Real, const N: usize>: LieGroup<T, N> {
    /// The element with these coordinates.
    fn from_coordinates(x: SVector<T, N>) -> Self;
    /// The coordinates (for the torus: unwrapped angles).
    fn coordinates(&self) -> SVector<T, N>;
}

impl<T: Real, const N: usize> VectorGroup<T, N> for Torus<T, N> {
    #[inline]
    fn from_coordinates(x: SVector<T, N>) -> Self {
        Torus::new(x)
    }
    #[inline]
    fn coordinates(&self) -> SVector<T, N> {
        *self.angles()
    }
}

impl<T: Real, const N: usize> VectorGroup<T, N> for Rn<T, N> {
    #[inline]
    fn from_coordinates(x: SVector<T, N>) -> Self {
        Rn::new(x)
    }
    #[inline]
    fn coordinates(&self) -> SVector<T, N> {
        *self.coords()
    }
}

/// The coordinates carry no kinds ([`JointSpace`]'s identity and `exp` do the same); an
/// error `E = q·x_d⁻¹` takes the kinds of the measured `q`.
impl<T: Real, const N: usize> VectorGroup<T, N> for JointSpace<T, N> {
    #[inline]
    fn from_coordinates(x: SVector<T, N>) -> Self {
        JointSpace::exp(&x)
    }
    #[inline]
    fn coordinates(&self) -> SVector<T, N> {
        *self.coords()
    }
}

/// Validates a period: finite and strictly positive.
pub(crate) fn check_period<T: Real>(period: T, context: &'static str) -> crate::Result<()> {
    if !period.is_finite() {
        return Err(crate::Error::new(crate::ErrorKind::NonFinite, context));
    }
    if period <= T::zero() {
        return Err(crate::Error::new(
            crate::ErrorKind::InvalidParameter,
            context,
        ));
    }
    Ok(())
}
