//! Obstacles through navigation functions (the paper's Remark 3: "the navigation function
//! should be defined such that its value is large at the locations of the obstacles").
//!
//! An obstacle set gives, at a configuration `q`, a **barrier** `β(q) ∈ [0, 1]`: `0` on the
//! obstacles' surfaces (grown by a margin), `1` farther than an influence width from all of
//! them, with its differential and their rates along the motion ([`Barrier`]). The field
//! composes it with the contour's navigation function `U` after Rimon and Koditschek
//! ([`Composition`], eq. RK below), so that the contour's minimum stays the only minimum away
//! from the obstacles and the obstacles' surfaces are the composed function's highest level
//! set, which the field's flow never reaches.
//!
//! * [`JointRegion`]: a region of the joint space (a ball, an ellipsoid, a rounded box).
//! * [`WorldObstacle`] against [`BodySphere`]s: spheres fixed on a chain's links kept a
//!   clearance away from spheres and cylinders placed in the world (the task space).
//! * [`ObstacleSet`]: both kinds, a fixed number of each (no allocation), and the
//!   composition's parameters. [`NoObstacles`] is the contour's field itself, at no cost.

mod compose;
mod joint;
mod set;
mod task;

pub use compose::{Composed, Composition, Potential};
pub use joint::JointRegion;
pub use set::{ObstacleSet, MAX_BODY_SPHERES, MAX_JOINT_REGIONS, MAX_WORLD_OBSTACLES};
pub use task::{BodySphere, WorldObstacle, WorldShape};

use crate::lie::{LieGroup, Tangent};
use crate::Real;

/// `β(q)`, its differential `dβ` in body coordinates at `q`, and their rates along a motion
/// `q̇ = v`: what the composition needs of an obstacle set at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Barrier<T: Real, const D: usize> {
    /// `β(q)`, in `[0, 1]`.
    pub value: T,
    /// `dβ(q)` in body coordinates: `d/dt β(q·exp(tζ))|₀ = dβ·ζ`.
    pub differential: Tangent<T, D>,
    /// `β̇ = dβ·v`.
    pub value_rate: T,
    /// `d/dt dβ(q(t))`, component-wise.
    pub differential_rate: Tangent<T, D>,
}

impl<T: Real, const D: usize> Barrier<T, D> {
    /// No obstacle within reach: `β ≡ 1`.
    pub fn free() -> Self {
        Barrier {
            value: T::one(),
            differential: Tangent::zeros(),
            value_rate: T::zero(),
            differential_rate: Tangent::zeros(),
        }
    }

    /// The barrier of both sets, `β = β₁β₂`, with the product rule for the differential and
    /// the rates.
    #[inline]
    pub fn product(&self, other: &Self) -> Self {
        Barrier {
            value: self.value * other.value,
            differential: self.differential * other.value + other.differential * self.value,
            value_rate: self.value_rate * other.value + other.value_rate * self.value,
            differential_rate: self.differential_rate * other.value
                + self.differential * other.value_rate
                + other.differential_rate * self.value
                + other.differential * self.value_rate,
        }
    }
}

/// The smooth step of a barrier: `σ(t) = 1 − (1 − t)³` on `[0, 1]`, `1` beyond, with
/// `σ(0) = 0`, `σ'(0) = 3` (a non-degenerate zero on the surface, as Rimon–Koditschek ask)
/// and `σ' = σ'' = 0` at `t = 1` (`C²` where the influence ends). Inside an obstacle
/// (`t < 0`) it keeps `σ(0)`'s slope, so that the gradient still points out. Returns
/// `(σ, σ', σ'')`.
#[inline]
pub(crate) fn smooth_step<T: Real>(t: T) -> (T, T, T) {
    let one = T::one();
    if t >= one {
        return (one, T::zero(), T::zero());
    }
    let t = if t > T::zero() { t } else { T::zero() };
    let u = one - t;
    let three = crate::scalar::cast::<T>(3.0);
    (one - u * u * u, three * u * u, -(three + three) * u)
}

/// The barrier `β = σ(t)` of a scaled clearance `t = ℓ/w`, from `t`'s differential `dt`, its
/// rate `ṫ` and the rate of `dt`: `dβ = σ' dt`, `β̇ = σ' ṫ`, `d/dt dβ = σ'' ṫ dt + σ' d/dt dt`.
/// `β ≡ 1` beyond the influence (`t ≥ 1`).
#[inline]
pub(crate) fn step_barrier<T: Real, const D: usize>(
    t: T,
    dt: &Tangent<T, D>,
    t_rate: T,
    dt_rate: &Tangent<T, D>,
) -> Barrier<T, D> {
    let (s, s1, s2) = smooth_step(t);
    if s1 == T::zero() && s2 == T::zero() {
        return Barrier::free();
    }
    Barrier {
        value: s,
        differential: dt * s1,
        value_rate: s1 * t_rate,
        differential_rate: dt * (s2 * t_rate) + dt_rate * s1,
    }
}

/// What a velocity field asks of its obstacles at one state.
pub trait Obstacles<T: Real, G: LieGroup<T, D>, const D: usize> {
    /// The barrier at `q` and its rates along `v`, with the composition's parameters;
    /// `None` when there is no obstacle (the field is then the contour's, exactly).
    fn barrier(&self, q: &G, v: &Tangent<T, D>) -> Option<(Barrier<T, D>, Composition<T>)>;
}

/// No obstacle: the field is the contour's own, and the check is compiled away.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoObstacles;

impl<T: Real, G: LieGroup<T, D>, const D: usize> Obstacles<T, G, D> for NoObstacles {
    #[inline(always)]
    fn barrier(&self, _q: &G, _v: &Tangent<T, D>) -> Option<(Barrier<T, D>, Composition<T>)> {
        None
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn smooth_step_is_c2_and_non_degenerate_on_the_surface() {
        let (s0, d0, _) = smooth_step(0.0_f64);
        assert_eq!((s0, d0), (0.0, 3.0));
        let (s1, d1, dd1) = smooth_step(1.0_f64);
        assert_eq!((s1, d1, dd1), (1.0, 0.0, 0.0));
        let h = 1e-6;
        for t in [0.1_f64, 0.35, 0.8, 0.999] {
            let (_, d, dd) = smooth_step(t);
            let fd = (smooth_step(t + h).0 - smooth_step(t - h).0) / (2.0 * h);
            let fdd = (smooth_step(t + h).1 - smooth_step(t - h).1) / (2.0 * h);
            assert!((fd - d).abs() < 1e-8 && (fdd - dd).abs() < 1e-7, "t = {t}");
        }
    }

    #[test]
    fn the_product_rule_matches_finite_differences() {
        // β₁ = 1 − x², β₂ = 0.5 + 0.25 y along q(t) = q₀ + t v.
        let b = |q: Vector2<f64>, v: Vector2<f64>| {
            let b1 = Barrier {
                value: 1.0 - q.x * q.x,
                differential: Vector2::new(-2.0 * q.x, 0.0),
                value_rate: -2.0 * q.x * v.x,
                differential_rate: Vector2::new(-2.0 * v.x, 0.0),
            };
            let b2 = Barrier {
                value: 0.5 + 0.25 * q.y,
                differential: Vector2::new(0.0, 0.25),
                value_rate: 0.25 * v.y,
                differential_rate: Vector2::zeros(),
            };
            b1.product(&b2)
        };
        let (q, v, h) = (Vector2::new(0.3, -0.4), Vector2::new(0.7, 1.1), 1e-6);
        let s = b(q, v);
        let fd = (b(q + v * h, v).value - b(q - v * h, v).value) / (2.0 * h);
        assert!((fd - s.value_rate).abs() < 1e-9);
        assert!((s.differential.dot(&v) - s.value_rate).abs() < 1e-15);
        let fd = (b(q + v * h, v).differential - b(q - v * h, v).differential) / (2.0 * h);
        assert!((fd - s.differential_rate).norm() < 1e-9);
    }
}
