//! The scalar type every pvfc computation is generic over.

use nalgebra::RealField;

/// A real scalar usable by pvfc: `f32` (microcontrollers with an FPU) or `f64` (hosts).
///
/// This is [`nalgebra::RealField`] plus `Copy`; it is implemented for every such type.
pub trait Real: RealField + Copy {}

impl<T: RealField + Copy> Real for T {}

/// Converts an `f64` constant into the scalar type `T` (exact for `f64`, rounded for `f32`).
///
/// ```
/// let half: f32 = pvfc_core::scalar::cast(0.5);
/// assert_eq!(half, 0.5f32);
/// ```
#[inline(always)]
pub fn cast<T: Real>(x: f64) -> T {
    nalgebra::convert(x)
}

/// `true` when every entry of the slice-like iterator is finite (neither NaN nor infinite).
#[inline]
pub fn all_finite<'a, T: Real + 'a>(xs: impl IntoIterator<Item = &'a T>) -> bool {
    xs.into_iter().all(|x| x.is_finite())
}
