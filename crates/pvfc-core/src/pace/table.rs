//! A periodic pace profile `σ(τ)` from its values at evenly spaced knots: a monotone cubic
//! Hermite interpolant (Fritsch–Butland slopes), `C¹`, that never leaves the range of the two
//! knots around it (no overshoot: a profile computed as a bound stays one between knots).

use super::PaceProfile;
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::scalar::cast;
use crate::Real;

/// `σ(τ)` through `n` knots `σ_k = σ(k·P/n)` of a closed contour of period `P`, stored in a
/// fixed capacity `K ≥ n` (no allocation).
///
/// Between knots `k` and `k+1` the interpolant is the cubic Hermite polynomial with the
/// Fritsch–Butland slopes `m_k = 2 d_{k−1} d_k / (d_{k−1} + d_k)` (0 where the secants
/// `d` change sign), so it is monotone there and stays within `[min, max](σ_k, σ_{k+1})`.
///
/// ```
/// use pvfc_core::pace::{PaceProfile, PaceTable};
/// let t = PaceTable::<f64, 16>::new(&[1.0, 0.5, 0.5, 1.0], 8.0).unwrap();
/// let (s, ds) = t.pace(1.0); // half-way between the first two knots
/// assert!(s > 0.5 && s < 1.0 && ds < 0.0);
/// assert_eq!(t.pace(8.0).0, t.pace(0.0).0); // periodic
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaceTable<T: Real, const K: usize> {
    values: [T; K],
    len: usize,
    inv_spacing: T,
    period: T,
}

impl<T: Real, const K: usize> PaceTable<T, K> {
    /// The profile through `values` (at least 3, at most `K`, each finite and > 0) at evenly
    /// spaced knots over one period `period` (finite, > 0), the first at `τ = 0`.
    pub fn new(values: &[T], period: T) -> Result<Self> {
        if values.len() < 3 || values.len() > K {
            return Err(Error::new(
                ErrorKind::DimensionMismatch,
                "PaceTable: between 3 and K knots",
            ));
        }
        ensure_finite(values.iter(), "PaceTable: knot values")?;
        if values.iter().any(|v| *v <= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PaceTable: every knot value must be > 0",
            ));
        }
        if !(period.is_finite() && period > T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PaceTable: the period must be finite and > 0",
            ));
        }
        let mut stored = [T::one(); K];
        stored[..values.len()].copy_from_slice(values);
        Ok(PaceTable {
            values: stored,
            len: values.len(),
            inv_spacing: cast::<T>(values.len() as f64) / period,
            period,
        })
    }

    /// The table of `K` knots (or fewer, `knots ≤ K`) that stays at or below `rates[j] / scale`
    /// at every one of `n = rates.len()` evenly spaced points `τ_j = j·P/n` of the period `P`:
    /// each knot takes the least of those values within one knot spacing of it, and the
    /// interpolant never leaves the range of the two knots around it. For a profile computed
    /// on a fine grid (such as [`drive_limited_rates`](super::drive_limited_rates)'s), in
    /// `σ = τ̇ / β` for a field run at energy level `β = scale`.
    ///
    /// Errors: those of [`new`](Self::new), and `InvalidParameter` for a `scale` that is not
    /// finite and > 0 or a value that is 0.
    pub fn below(rates: &[T], scale: T, knots: usize, period: T) -> Result<Self> {
        if !(scale.is_finite() && scale > T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PaceTable::below: the scale must be finite and > 0",
            ));
        }
        if knots < 3 || knots > K || rates.len() < knots {
            return Err(Error::new(
                ErrorKind::DimensionMismatch,
                "PaceTable::below: between 3 and K knots, and at least as many rates",
            ));
        }
        let n = rates.len();
        let mut values = [T::one(); K];
        for (k, value) in values.iter_mut().take(knots).enumerate() {
            // Fine points j with |j/n − k/knots| ≤ 1/knots, wrapped round the period.
            let first = ((k as i64 - 1) * n as i64).div_euclid(knots as i64);
            let last = ((k as i64 + 1) * n as i64).div_euclid(knots as i64);
            let least = (first..=last)
                .map(|j| rates[j.rem_euclid(n as i64) as usize])
                .fold(rates[(k * n / knots) % n], |a, b| if b < a { b } else { a });
            *value = least / scale;
        }
        Self::new(&values[..knots], period)
    }

    /// The knot values.
    pub fn values(&self) -> &[T] {
        &self.values[..self.len]
    }

    /// The period `P`.
    pub fn period(&self) -> T {
        self.period
    }

    /// The knot value `σ_k` for any integer `k` (periodic).
    #[inline]
    fn knot(&self, k: i64) -> T {
        // `len ≤ K` fits an i64; rem_euclid is in [0, len).
        self.values[k.rem_euclid(self.len as i64) as usize]
    }

    /// The Fritsch–Butland slope at knot `k`, per knot spacing.
    #[inline]
    fn slope(&self, k: i64) -> T {
        let d0 = self.knot(k) - self.knot(k - 1);
        let d1 = self.knot(k + 1) - self.knot(k);
        if d0 * d1 <= T::zero() {
            T::zero()
        } else {
            cast::<T>(2.0) * d0 * d1 / (d0 + d1)
        }
    }
}

impl<T: Real, const K: usize> PaceProfile<T> for PaceTable<T, K> {
    /// `(σ(τ), dσ/dτ)`; for a non-finite `τ`, the first knot's value and 0.
    #[inline]
    fn pace(&self, tau: T) -> (T, T) {
        let x = tau * self.inv_spacing;
        let floor = x.floor();
        let Some(k) = floor.to_i64_checked() else {
            return (self.values[0], T::zero());
        };
        let t = x - floor;
        let (p0, p1) = (self.knot(k), self.knot(k + 1));
        let (m0, m1) = (self.slope(k), self.slope(k + 1));
        let (two, three) = (cast::<T>(2.0), cast::<T>(3.0));
        let t2 = t * t;
        let t3 = t2 * t;
        let h00 = two * t3 - three * t2 + T::one();
        let h10 = t3 - two * t2 + t;
        let h01 = three * t2 - two * t3;
        let h11 = t3 - t2;
        let sigma = h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1;
        let six = cast::<T>(6.0);
        let dh00 = six * (t2 - t);
        let dh10 = three * t2 - cast::<T>(4.0) * t + T::one();
        let dh11 = three * t2 - two * t;
        let dsigma = (dh00 * (p0 - p1) + dh10 * m0 + dh11 * m1) * self.inv_spacing;
        (sigma, dsigma)
    }
}
