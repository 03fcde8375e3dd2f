//! Rimon and Koditschek's composition of the contour's navigation function with the
//! obstacles' barrier, and the field's terms built from it.
//!
//! E. Rimon and D. E. Koditschek, "Exact robot navigation using artificial potential
//! functions", IEEE Trans. Robotics and Automation 8(5), 1992: for a goal function `γ ≥ 0`,
//! zero only at the goal, and an obstacle function `β ≥ 0`, zero on the obstacles' surfaces,
//!
//! ```text
//!   φ = γ₀ · x / (x^κ + β)^{1/κ},   x = γ / γ₀            (RK)
//! ```
//!
//! is `γ₀ · σ(x^κ/β)^{1/κ}` with `σ(y) = y/(1+y)` increasing, so its critical points are those
//! of `x^κ/β`: away from the obstacles' influence (`β = 1`) those of `γ` (the contour's
//! minimum, and the navigation function's own saddles), and near an obstacle, once `κ` is
//! large enough for the obstacles given (Rimon–Koditschek's bound, checked numerically for a
//! set in our tests), saddles only. `φ ∈ [0, γ₀]`, `φ = 0` only on the contour and `φ = γ₀`
//! only on the obstacles' surfaces: the surfaces are the highest level set.
//!
//! Here `γ = U(E(q, τ))`, the contour's navigation function, so `φ` moves with the contour,
//! and `γ₀` (the scale) is of the order of `U`'s largest value. Near the contour
//! `φ = γ β^{−1/κ} (1 + O(x^κ))`: the contour is still `φ`'s zero set, followed as before.

use super::Barrier;
use crate::error::{Error, ErrorKind, Result};
use crate::lie::Tangent;
use crate::scalar::cast;
use crate::Real;

/// The composition's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Composition<T: Real> {
    pub(super) kappa: T,
    pub(super) scale: T,
    pub(super) speed: Option<T>,
}

/// The contour's potential at one state, as the composition needs it: `γ = U(E(q, τ))`,
/// `grad_q γ` (the gradient of `γ` in `q` at fixed `τ`, body coordinates at `q`, in the
/// navigation function's metric), and their rates along the motion of `(q, τ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Potential<T: Real, const D: usize> {
    /// `γ`.
    pub value: T,
    /// `γ̇`.
    pub value_rate: T,
    /// `grad_q γ`.
    pub gradient: Tangent<T, D>,
    /// `d/dt grad_q γ`.
    pub gradient_rate: Tangent<T, D>,
}

/// The composed function and the two terms of the field built from it, with their rates:
/// `V_G = λ₁(φ) b ξ_d − λ₂(φ) g`, `V_I = λ₁(φ) b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Composed<T: Real, const D: usize> {
    /// `φ` (RK).
    pub value: T,
    /// `φ̇`.
    pub value_rate: T,
    /// `g = grad_q φ / n`, with `n = √(1 + ‖grad_q φ‖²/v_max²)` when a speed limit `v_max`
    /// is set (the direction of `grad_q φ`, its length kept below `v_max`), else `n = 1`.
    pub gradient: Tangent<T, D>,
    /// `ġ`.
    pub gradient_rate: Tangent<T, D>,
    /// `b = β`: the share of the feed-forward (and of `τ`'s rate) kept near an obstacle, so
    /// that the contour's motion never pushes the robot into one (`b = 0` on the surfaces).
    pub feed: T,
    /// `ḃ`.
    pub feed_rate: T,
}

impl<T: Real> Composition<T> {
    /// `κ ≥ 1`, the scale `γ₀ > 0`, and an optional speed limit `v_max > 0` of the gradient
    /// term.
    pub fn new(kappa: T, scale: T, speed: Option<T>) -> Result<Self> {
        let finite = kappa.is_finite() && scale.is_finite() && speed.is_none_or(|v| v.is_finite());
        if !finite {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "obstacle composition: κ, the scale and the speed limit must be finite",
            ));
        }
        if kappa < T::one() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "obstacle composition: κ must be ≥ 1",
            ));
        }
        if scale <= T::zero() || speed.is_some_and(|v| v <= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "obstacle composition: the scale and the speed limit must be > 0",
            ));
        }
        Ok(Composition {
            kappa,
            scale,
            speed,
        })
    }

    /// `κ`.
    pub fn kappa(&self) -> T {
        self.kappa
    }

    /// `γ₀`.
    pub fn scale(&self) -> T {
        self.scale
    }

    /// `v_max`, if set.
    pub fn speed(&self) -> Option<T> {
        self.speed
    }

    /// `φ` (RK) from `γ` and `β`, without rates.
    #[inline]
    pub fn value(&self, gamma: T, beta: T) -> T {
        let s = (gamma / self.scale).powf(self.kappa) + beta;
        gamma * s.max(floor()).powf(-T::one() / self.kappa)
    }

    /// `φ`, the field's gradient term and feed factor, and their rates, from the contour's
    /// potential and the obstacles' barrier; `k` is the navigation function's metric weight
    /// (`grad β = dβ / k`).
    ///
    /// With `s = x^κ + β`: `∂φ/∂γ = β s^{−1/κ−1}`, `∂φ/∂β = −(γ/κ) s^{−1/κ−1}`,
    /// `grad φ = ∂φ/∂γ · grad γ + ∂φ/∂β · dβ/k`, and the rates by the chain rule.
    #[inline]
    pub fn compose<const D: usize>(
        &self,
        u: &Potential<T, D>,
        b: &Barrier<T, D>,
        k: T,
    ) -> Composed<T, D> {
        let one = T::one();
        let kappa = self.kappa;
        let (gamma, gamma_dot) = (u.value.max(T::zero()), u.value_rate);
        let x = gamma / self.scale;
        let x_dot = gamma_dot / self.scale;
        let x_k1 = x.powf(kappa - one);
        let s = (x * x_k1 + b.value).max(floor());
        let s_dot = kappa * x_k1 * x_dot + b.value_rate;
        let q1 = s.powf(-one / kappa);
        let q2 = q1 / s;
        let q2_dot = -(one / kappa + one) * q2 / s * s_dot;
        let value = gamma * q1;
        let phi_g = b.value * q2;
        let phi_b = -gamma / kappa * q2;
        let phi_g_dot = b.value_rate * q2 + b.value * q2_dot;
        let phi_b_dot = -(gamma_dot * q2 + gamma * q2_dot) / kappa;
        let value_rate = phi_g * gamma_dot + phi_b * b.value_rate;
        let inv_k = one / k;
        let g = u.gradient * phi_g + b.differential * (phi_b * inv_k);
        let g_dot = u.gradient * phi_g_dot
            + u.gradient_rate * phi_g
            + (b.differential * phi_b_dot + b.differential_rate * phi_b) * inv_k;
        let (gradient, gradient_rate) = match self.speed {
            None => (g, g_dot),
            Some(v) => {
                let v2 = v * v;
                let n = (one + g.norm_squared() / v2).sqrt();
                let n_dot = g.dot(&g_dot) / (v2 * n);
                (g / n, g_dot / n - g * (n_dot / (n * n)))
            }
        };
        Composed {
            value,
            value_rate,
            gradient,
            gradient_rate,
            feed: b.value,
            feed_rate: b.value_rate,
        }
    }
}

/// The smallest `x^κ + β` used: only reached on the contour inside an obstacle, which the
/// composition's conditions exclude; it keeps `φ` finite there.
#[inline(always)]
fn floor<T: Real>() -> T {
    cast(1e-12)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// `γ = |q − c|²/2` (metric weight 1, gradient `q − c`) and `β = σ(|q − o| − 0.3)`-like
    /// barrier `β = 1 − exp(−(|q − o|² − r²))`, along `q(t) = q₀ + t v`.
    fn sample(comp: &Composition<f64>, q: Vector2<f64>, v: Vector2<f64>) -> Composed<f64, 2> {
        let c = Vector2::new(1.0, 0.5);
        let o = Vector2::new(0.2, 0.1);
        let u = Potential {
            value: 0.5 * (q - c).norm_squared(),
            value_rate: (q - c).dot(&v),
            gradient: q - c,
            gradient_rate: v,
        };
        let e = (-((q - o).norm_squared() - 0.09)).exp();
        let de = -2.0 * e * (q - o);
        let e_dot = de.dot(&v);
        let b = Barrier {
            value: 1.0 - e,
            differential: -de,
            value_rate: -e_dot,
            differential_rate: 2.0 * (e_dot * (q - o) + e * v),
        };
        comp.compose(&u, &b, 1.0)
    }

    #[test]
    fn rates_and_gradient_match_finite_differences() {
        for comp in [
            Composition::<f64>::new(1.0, 2.0, None).unwrap(),
            Composition::<f64>::new(3.0, 1.5, None).unwrap(),
            Composition::<f64>::new(2.5, 1.0, Some(0.7)).unwrap(),
        ] {
            let (q, v, h) = (Vector2::new(0.5, -0.3), Vector2::new(0.8, 0.6), 1e-6);
            let s = sample(&comp, q, v);
            let p = sample(&comp, q + v * h, v);
            let m = sample(&comp, q - v * h, v);
            assert!(((p.value - m.value) / (2.0 * h) - s.value_rate).abs() < 1e-8);
            assert!(((p.gradient - m.gradient) / (2.0 * h) - s.gradient_rate).norm() < 1e-7);
            assert!(((p.feed - m.feed) / (2.0 * h) - s.feed_rate).abs() < 1e-8);
            if comp.speed().is_none() {
                // The gradient is φ's: compare with differences of φ along each axis.
                for i in 0..2 {
                    let mut dq = Vector2::zeros();
                    dq[i] = h;
                    let fd = (sample(&comp, q + dq, v).value - sample(&comp, q - dq, v).value)
                        / (2.0 * h);
                    assert!((fd - s.gradient[i]).abs() < 1e-8, "∂φ/∂q_{i}");
                }
            } else {
                let n = s.gradient.norm();
                assert!(n < 0.7, "the speed limit holds: {n}");
            }
        }
    }

    #[test]
    fn the_composition_is_zero_on_the_contour_and_its_scale_on_the_surfaces() {
        let c = Composition::<f64>::new(2.0, 4.0, None).unwrap();
        assert_eq!(c.value(0.0, 0.5), 0.0);
        assert!((c.value(1.3, 0.0) - 4.0).abs() < 1e-12);
        // Away from obstacles (β = 1) and near the contour, φ = γ (1 − x^κ/κ + O(x^2κ)).
        let g = 1e-3;
        let x2: f64 = (g / 4.0) * (g / 4.0);
        let relative = (c.value(g, 1.0) - g).abs() / g;
        assert!(
            (relative - x2 / 2.0).abs() < 1e-3 * x2,
            "{relative} against {}",
            x2 / 2.0
        );
        // φ < γ₀ wherever β > 0.
        for (g, b) in [(0.1, 1e-6), (3.9, 0.01), (100.0, 1e-3)] {
            assert!(c.value(g, b) < 4.0);
        }
    }

    #[test]
    fn bad_parameters_are_errors() {
        assert!(Composition::<f64>::new(0.5, 1.0, None).is_err());
        assert!(Composition::<f64>::new(2.0, 0.0, None).is_err());
        assert!(Composition::<f64>::new(2.0, 1.0, Some(-1.0)).is_err());
        assert_eq!(
            Composition::<f64>::new(f64::NAN, 1.0, None)
                .unwrap_err()
                .kind(),
            ErrorKind::NonFinite
        );
    }
}
