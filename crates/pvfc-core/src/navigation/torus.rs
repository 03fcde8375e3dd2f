//! The navigation function of the n-torus, eqs. (17) and (28).

use super::{NavigationFunction, NavigationSample};
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::lie::{Tangent, Torus};
use crate::scalar::cast;
use crate::Real;
use nalgebra::SVector;

/// Which of the paper's two equivalent forms of the torus navigation function to use.
///
/// Both give the same gradient `h_i sin E_i` (the second term of eq. 18) and so the same
/// velocity field; they differ in the reported value of `U`, which the self-pacing gains of
/// eq. (21) and the paper's figures use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TorusConvention {
    /// Eq. (17): `U = ½ Σ h_i (1 − cos E_i)`, gradient for the metric `½·Euclidean`.
    /// This is what section V's experiments and figures use: the default.
    #[default]
    HalfSum,
    /// Eq. (28): `U = Σ h_i (1 − cos E_i)`, gradient for the Euclidean metric.
    Sum,
}

/// The navigation function of `Tⁿ`, `U(E) = k Σ h_i (1 − cos E_i)` with `k = ½` (eq. 17) or
/// `k = 1` (eq. 28), and the metric `⟨⟨a, b⟩⟩_V = k aᵀb`, so that in either convention
/// `grad U = (h_i sin E_i)_i` exactly as in eq. (18) and Proposition 1 holds exactly.
///
/// Critical points are `E_i ∈ {0, π}`; the Hessian `k·diag(h_i cos E_i)` is positive definite
/// only at the identity.
///
/// ```
/// use pvfc_core::navigation::{NavigationFunction, TorusNavigation};
/// use pvfc_core::lie::Torus;
/// use nalgebra::Vector2;
/// let nav = TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap();
/// let e = Torus::new(Vector2::new(std::f64::consts::PI, 0.0));
/// assert!((nav.value(&e) - 1.0).abs() < 1e-15); // ½·1·(1 − cos π)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorusNavigation<T: Real, const N: usize> {
    h: SVector<T, N>,
    k: T,
    convention: TorusConvention,
}

impl<T: Real, const N: usize> TorusNavigation<T, N> {
    /// The navigation function with weights `h_i > 0` in the given convention.
    pub fn new(h: SVector<T, N>, convention: TorusConvention) -> Result<Self> {
        ensure_finite(h.iter(), "TorusNavigation: weights h")?;
        if h.iter().any(|x| *x <= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "TorusNavigation: every weight h_i must be > 0",
            ));
        }
        let k = match convention {
            TorusConvention::HalfSum => cast(0.5),
            TorusConvention::Sum => T::one(),
        };
        Ok(TorusNavigation { h, k, convention })
    }

    /// Eq. (17), the convention of the paper's experiments.
    pub fn paper(h: SVector<T, N>) -> Result<Self> {
        Self::new(h, TorusConvention::HalfSum)
    }

    /// The weights `h_i`.
    pub fn weights(&self) -> &SVector<T, N> {
        &self.h
    }

    /// The convention in use.
    pub fn convention(&self) -> TorusConvention {
        self.convention
    }
}

impl<T: Real, const N: usize> NavigationFunction<T, Torus<T, N>, N> for TorusNavigation<T, N> {
    #[inline]
    fn evaluate(&self, e: &Torus<T, N>, e_rate: &Tangent<T, N>) -> NavigationSample<T, N> {
        let mut value = T::zero();
        let mut gradient: SVector<T, N> = SVector::zeros();
        let mut gradient_rate = SVector::zeros();
        for i in 0..N {
            let (s, c) = e.angles()[i].sin_cos_fast();
            let h = self.h[i];
            value += h * (T::one() - c);
            gradient[i] = h * s;
            gradient_rate[i] = h * c * e_rate[i];
        }
        let differential = gradient * self.k;
        NavigationSample {
            value: value * self.k,
            value_rate: differential.dot(e_rate),
            differential,
            gradient,
            gradient_rate,
        }
    }

    #[inline]
    fn metric_weight(&self) -> T {
        self.k
    }
}
