//! Helpers shared by the property tests: scalar-dependent tolerances and conversions.
#![allow(dead_code)]

pub mod held;
pub mod setups;

use nalgebra::SVector;
use pvfc_core::scalar::cast;
use pvfc_core::Real;

/// Number of random cases per property (the issue asks for at least 10,000).
pub const CASES: u32 = 10_000;

/// Tolerances that fit each scalar type.
pub trait Tolerance: Real {
    /// Relative tolerance for quantities that should agree to rounding.
    const ROUNDING: f64;
    /// Relative tolerance for quantities computed along different formula paths.
    const LOOSE: f64;
}

impl Tolerance for f64 {
    const ROUNDING: f64 = 1e-12;
    const LOOSE: f64 = 1e-9;
}

impl Tolerance for f32 {
    const ROUNDING: f64 = 2e-5;
    const LOOSE: f64 = 5e-4;
}

/// An `SVector<T, N>` from `f64` values.
pub fn vec<T: Real, const N: usize>(xs: [f64; N]) -> SVector<T, N> {
    SVector::from_fn(|i, _| cast(xs[i]))
}

/// `f64` of a scalar.
pub fn f<T: Real>(x: T) -> f64 {
    nalgebra::try_convert::<T, f64>(x).unwrap_or(f64::NAN)
}

/// `|a − b| ≤ tol · scale`, with a message on failure.
pub fn close(a: f64, b: f64, tol: f64, scale: f64, what: &str) -> Result<(), String> {
    if (a - b).abs() <= tol * scale.max(1e-300) && a.is_finite() && b.is_finite() {
        Ok(())
    } else {
        Err(format!(
            "{what}: {a:e} vs {b:e} (diff {:e}, allowed {:e})",
            (a - b).abs(),
            tol * scale
        ))
    }
}

/// Component-wise `close` for vectors, with scale `1 + ‖b‖` unless given.
pub fn close_vec<T: Real, const N: usize>(
    a: &SVector<T, N>,
    b: &SVector<T, N>,
    tol: f64,
    scale: f64,
    what: &str,
) -> Result<(), String> {
    let d = f((a - b).norm());
    if d <= tol * scale && d.is_finite() {
        Ok(())
    } else {
        Err(format!(
            "{what}: {a:?} vs {b:?} (diff {d:e}, allowed {:e})",
            tol * scale
        ))
    }
}
