//! The navigation function of a mixed joint space `T^r × ℝ^p` (revolute and prismatic joints).

use super::{NavigationFunction, NavigationSample};
use crate::contour::VectorGroup;
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::lie::{JointKind, Tangent};
use crate::scalar::cast;
use crate::Real;
use nalgebra::SVector;

/// `U(E) = ½ Σ_circular h_i (1 − cos E_i) + ¼ Σ_linear h_i E_i²`, with the metric
/// `⟨⟨a, b⟩⟩_V = ½ aᵀb` of eq. (17), so that `grad U = (h_i sin E_i)` on the circular
/// coordinates, as in eq. (18), and `(h_i E_i)` on the linear ones.
///
/// The circular part is eq. (17) joint by joint; the linear part is its small-angle twin
/// (`½ h (1 − cos E) = ¼ h E² + O(E⁴)`), so a chain with prismatic joints is paced and
/// steered by the same gains whatever its joints are. On `ℝ` the quadratic has compact
/// sublevel sets and a single critical point, which is what the closing remarks of the
/// paper's section IV ask of a navigation function on a non-compact group.
///
/// ```
/// use pvfc_core::navigation::{JointNavigation, NavigationFunction};
/// use pvfc_core::lie::{JointKind, JointSpace};
/// use nalgebra::Vector2;
/// let kinds = [JointKind::Circular, JointKind::Linear];
/// let nav = JointNavigation::new(Vector2::new(1.0, 4.0), kinds).unwrap();
/// let e = JointSpace::new(Vector2::new(std::f64::consts::PI, 0.5), kinds);
/// assert!((nav.value(&e) - (1.0 + 0.25)).abs() < 1e-15); // ½·(1 − cos π) + ¼·4·0.5²
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointNavigation<T: Real, const N: usize> {
    h: SVector<T, N>,
    kinds: [JointKind; N],
}

impl<T: Real, const N: usize> JointNavigation<T, N> {
    /// The navigation function with weights `h_i > 0` for joints of the given kinds.
    pub fn new(h: SVector<T, N>, kinds: [JointKind; N]) -> Result<Self> {
        ensure_finite(h.iter(), "JointNavigation: weights h")?;
        if h.iter().any(|x| *x <= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "JointNavigation: every weight h_i must be > 0",
            ));
        }
        Ok(JointNavigation { h, kinds })
    }

    /// The weights `h_i`.
    pub fn weights(&self) -> &SVector<T, N> {
        &self.h
    }

    /// The kind of every joint.
    pub fn kinds(&self) -> [JointKind; N] {
        self.kinds
    }
}

impl<T: Real, G: VectorGroup<T, N>, const N: usize> NavigationFunction<T, G, N>
    for JointNavigation<T, N>
{
    #[inline]
    fn evaluate(&self, e: &G, e_rate: &Tangent<T, N>) -> NavigationSample<T, N> {
        let half: T = cast(0.5);
        let x = e.coordinates();
        let mut value = T::zero();
        let mut gradient: SVector<T, N> = SVector::zeros();
        let mut gradient_rate = SVector::zeros();
        for i in 0..N {
            let h = self.h[i];
            match self.kinds[i] {
                JointKind::Circular => {
                    let (s, c) = x[i].sin_cos_fast();
                    value += h * (T::one() - c);
                    gradient[i] = h * s;
                    gradient_rate[i] = h * c * e_rate[i];
                }
                JointKind::Linear => {
                    value += half * h * x[i] * x[i];
                    gradient[i] = h * x[i];
                    gradient_rate[i] = h * e_rate[i];
                }
            }
        }
        let differential = gradient * half;
        NavigationSample {
            value: value * half,
            value_rate: differential.dot(e_rate),
            differential,
            gradient,
            gradient_rate,
        }
    }

    #[inline]
    fn metric_weight(&self) -> T {
        cast(0.5)
    }
}
