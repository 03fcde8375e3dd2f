//! Navigation functions `U : G → ℝ` (Definition 1 of the paper) and their gradients.
//!
//! A navigation function has non-degenerate critical points and a unique minimum, 0, at the
//! identity. Its gradient needs a Riemannian metric `⟨⟨·,·⟩⟩_V` on `G`; every metric used here
//! is a constant multiple of the Euclidean one in body coordinates,
//! `⟨⟨a, b⟩⟩_V = k·aᵀb` ([`NavigationFunction::metric_weight`]), so that `grad U = dU / k`.

mod joint;
mod quadratic;
mod so3;
mod torus;

pub use joint::JointNavigation;
pub use quadratic::QuadraticNavigation;
pub use so3::So3Navigation;
pub use torus::{TorusConvention, TorusNavigation};

use crate::lie::{LieGroup, Tangent};
use crate::Real;

/// `U`, `dU`, `grad U` at `E`, and their rates along a motion `Ė = E·ε̂` of the error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavigationSample<T: Real, const D: usize> {
    /// `U(E)`.
    pub value: T,
    /// `dU(E)` in body coordinates: `d/dt U(E·exp(tζ))|₀ = dU·ζ`.
    pub differential: Tangent<T, D>,
    /// `grad U(E)` in body coordinates, for the metric of the function (`= dU / k`).
    pub gradient: Tangent<T, D>,
    /// `d/dt U(E(t)) = dU·ε`.
    pub value_rate: T,
    /// `d/dt grad U(E(t))`, component-wise in body coordinates.
    pub gradient_rate: Tangent<T, D>,
}

/// A navigation function on the group `G`, with its gradient and their rates.
pub trait NavigationFunction<T: Real, G: LieGroup<T, D>, const D: usize> {
    /// Evaluates `U`, `dU`, `grad U` at `E`, and their rates along `Ė = E·ε̂`.
    fn evaluate(&self, e: &G, e_rate: &Tangent<T, D>) -> NavigationSample<T, D>;

    /// The factor `k` of the metric `⟨⟨a, b⟩⟩_V = k·aᵀb` in which the gradient is taken.
    fn metric_weight(&self) -> T;

    /// `U(E)`.
    #[inline]
    fn value(&self, e: &G) -> T {
        self.evaluate(e, &Tangent::zeros()).value
    }

    /// `grad U(E)` in body coordinates.
    #[inline]
    fn gradient(&self, e: &G) -> Tangent<T, D> {
        self.evaluate(e, &Tangent::zeros()).gradient
    }
}
