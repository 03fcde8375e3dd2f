//! The Lissajous figure of the paper's experiment (section V), and its generalisation.

use super::{check_period, Contour, ContourSample, VectorGroup};
use crate::error::{ensure_finite, Result};
use crate::Real;
use nalgebra::SVector;

/// A Lissajous curve, coordinate by coordinate
/// `x_d,i(τ) = c_i + a_i sin(2π τ / T_i + φ_i)`.
///
/// The paper's contour (section V) is [`Lissajous::paper`]:
/// `x_d(τ) = (sin(2πτ/3), 1.5 cos(2πτ/6))`, period 6, crossing itself at the centre.
///
/// ```
/// use pvfc_core::contour::{Contour, Lissajous};
/// use pvfc_core::lie::Torus;
/// let c = Lissajous::<f64, 2>::paper();
/// let s: pvfc_core::contour::ContourSample<f64, Torus<f64, 2>, 2> = c.sample(1.0);
/// let expected = (2.0 * std::f64::consts::PI / 3.0).sin();
/// assert!((s.point.angles()[0] - expected).abs() < 1e-15);
/// assert_eq!(<Lissajous<f64, 2> as Contour<f64, Torus<f64, 2>, 2>>::period(&c), Some(6.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lissajous<T: Real, const N: usize> {
    amplitude: SVector<T, N>,
    omega: SVector<T, N>,
    phase: SVector<T, N>,
    offset: SVector<T, N>,
    period: Option<T>,
}

impl<T: Real, const N: usize> Lissajous<T, N> {
    /// A Lissajous curve with amplitudes `a_i`, periods `T_i` (> 0), phases `φ_i` and
    /// offsets `c_i`. Its overall period is unknown until [`with_period`](Self::with_period).
    pub fn new(
        amplitude: SVector<T, N>,
        periods: SVector<T, N>,
        phase: SVector<T, N>,
        offset: SVector<T, N>,
    ) -> Result<Self> {
        ensure_finite(
            amplitude.iter().chain(phase.iter()).chain(offset.iter()),
            "Lissajous: amplitude, phase and offset",
        )?;
        for p in periods.iter() {
            check_period(*p, "Lissajous: every period must be finite and > 0")?;
        }
        Ok(Lissajous {
            amplitude,
            omega: periods.map(|p| T::two_pi() / p),
            phase,
            offset,
            period: None,
        })
    }

    /// Declares the common period of the curve (e.g. the least common multiple of the `T_i`).
    pub fn with_period(mut self, period: T) -> Result<Self> {
        check_period(period, "Lissajous::with_period")?;
        self.period = Some(period);
        Ok(self)
    }

    /// Evaluates `(x_d, dx_d/dτ, d²x_d/dτ²)` as coordinate vectors.
    #[inline]
    pub fn coordinates(&self, tau: T) -> [SVector<T, N>; 3] {
        let mut x = self.offset;
        let mut dx = SVector::zeros();
        let mut ddx = SVector::zeros();
        for i in 0..N {
            let (s, c) = (self.omega[i] * tau + self.phase[i]).sin_cos_fast();
            let a = self.amplitude[i];
            let w = self.omega[i];
            x[i] += a * s;
            dx[i] = a * w * c;
            ddx[i] = -a * w * w * s;
        }
        [x, dx, ddx]
    }
}

impl<T: Real> Lissajous<T, 2> {
    /// The contour of the paper's experiment, `(sin(2πτ/3), 1.5 cos(2πτ/6))`, period 6.
    pub fn paper() -> Self {
        let half_pi = T::frac_pi_2();
        let three: T = crate::scalar::cast(3.0);
        let six: T = crate::scalar::cast(6.0);
        Lissajous {
            amplitude: SVector::<T, 2>::new(T::one(), crate::scalar::cast(1.5)),
            omega: SVector::<T, 2>::new(T::two_pi() / three, T::two_pi() / six),
            phase: SVector::<T, 2>::new(T::zero(), half_pi),
            offset: SVector::zeros(),
            period: Some(six),
        }
    }
}

impl<T: Real, G: VectorGroup<T, N>, const N: usize> Contour<T, G, N> for Lissajous<T, N> {
    #[inline]
    fn sample(&self, tau: T) -> ContourSample<T, G, N> {
        let [x, dx, ddx] = self.coordinates(tau);
        ContourSample {
            point: G::from_coordinates(x),
            velocity: dx,
            acceleration: ddx,
        }
    }

    fn period(&self) -> Option<T> {
        self.period
    }
}
