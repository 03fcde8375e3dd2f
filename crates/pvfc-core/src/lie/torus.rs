//! The n-torus `Tⁿ = S¹ × … × S¹`: the configuration space of an arm with `N` revolute joints.

use super::{LieGroup, Tangent};
use crate::Real;
use nalgebra::SVector;

/// Wraps an angle into `(−π, π]`.
///
/// ```
/// let w = pvfc_core::lie::wrap_angle(3.0 * std::f64::consts::PI);
/// assert!((w - std::f64::consts::PI).abs() < 1e-12);
/// ```
#[inline]
pub fn wrap_angle<T: Real>(x: T) -> T {
    if x > -T::pi() && x <= T::pi() {
        // Already wrapped (the same value the general path gives, without its rounding).
        return x;
    }
    wrap_angle_far(x)
}

/// [`wrap_angle`] beyond `(−π, π]`: out of line and cold, so that this path's rounding (a
/// libm call on targets without a rounding instruction, a dozen instructions inlined on
/// x86-64) does not raise the register pressure of every caller's usual path (inlined, it cost
/// the f32 passive step ten register spills per step on x86-64, measured with callgrind).
#[cold]
#[inline(never)]
fn wrap_angle_far<T: Real>(x: T) -> T {
    let two_pi = T::two_pi();
    let mut w = x - two_pi * (x / two_pi).round();
    if w <= -T::pi() {
        w += two_pi;
    } else if w > T::pi() {
        w -= two_pi;
    }
    w
}

/// An element of the n-torus `Tⁿ`, stored as `N` joint angles (radians).
///
/// The paper (eq. 27) identifies it with `(e^{jq¹}, …, e^{jqⁿ})`; angles are kept unwrapped
/// (any real number) so that a trajectory stays continuous, and two elements are the same
/// group element when their angles differ by multiples of 2π ([`LieGroup::distance`] is 0).
/// The group is abelian: `Ad = I` and the bracket vanishes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Torus<T: Real, const N: usize> {
    angles: SVector<T, N>,
}

/// The 2-torus of a two-link arm.
pub type Torus2<T> = Torus<T, 2>;

impl<T: Real, const N: usize> Torus<T, N> {
    /// The element with the given joint angles.
    #[inline]
    pub fn new(angles: SVector<T, N>) -> Self {
        Torus { angles }
    }

    /// The joint angles, unwrapped.
    #[inline]
    pub fn angles(&self) -> &SVector<T, N> {
        &self.angles
    }

    /// The joint angles wrapped into `(−π, π]` (the same group element).
    #[inline]
    pub fn wrapped(&self) -> SVector<T, N> {
        self.angles.map(wrap_angle)
    }
}

impl<T: Real, const N: usize> From<SVector<T, N>> for Torus<T, N> {
    fn from(angles: SVector<T, N>) -> Self {
        Torus::new(angles)
    }
}

impl<T: Real, const N: usize> LieGroup<T, N> for Torus<T, N> {
    #[inline]
    fn identity() -> Self {
        Torus::new(SVector::zeros())
    }
    #[inline]
    fn compose(&self, other: &Self) -> Self {
        Torus::new(self.angles + other.angles)
    }
    #[inline]
    fn inverse(&self) -> Self {
        Torus::new(-self.angles)
    }
    #[inline]
    fn exp(v: &Tangent<T, N>) -> Self {
        Torus::new(*v)
    }
    #[inline]
    fn log(&self) -> Tangent<T, N> {
        self.wrapped()
    }
    abelian_group_algebra!();
    #[inline]
    fn chart_extent(v: &Tangent<T, N>) -> T {
        v.amax()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        crate::scalar::all_finite(self.angles.iter())
    }
    #[inline]
    fn retract(&self, v: &Tangent<T, N>, dt: T) -> Self {
        Torus::new(self.angles + v * dt)
    }
}
