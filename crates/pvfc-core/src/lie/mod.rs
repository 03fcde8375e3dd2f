//! Lie groups: the configuration spaces of the mechanical systems pvfc controls.
//!
//! A [`LieGroup`] is generic over the scalar `T` and has its dimension `D` as a const generic.
//!
//! # Tangent vectors: the body (left) trivialisation
//! Every tangent vector at `g` is written in **body coordinates**: the vector `v ∈ ℝᴰ` stands
//! for the tangent vector `(L_g)_* v̂ = g·v̂` (for SO(3): `Ṙ = R ω̂`, the body angular velocity;
//! for the torus and ℝⁿ: the ordinary joint velocity). These are the coordinates in which the
//! inertia and Coriolis matrices of [`crate::mechanics`] are written, so the velocity field,
//! the momentum and the coupling torques all share them.
//!
//! In body coordinates the pushforwards that eqs. (29)–(30) of the paper use are
//! * `(L_a)_*`: tangent at `b` ↦ tangent at `a·b` — the identity on body coordinates;
//! * `(R_a)_*`: tangent at `b` ↦ tangent at `b·a` — `v ↦ Ad_{a⁻¹} v`.
//!
//! Implementations: [`Torus`] (`Tⁿ`, revolute arms), [`So3`] (attitude), [`Rn`]
//! (a vector space, for linear stages) and [`JointSpace`] (`T^r × ℝ^p`, serial chains with
//! revolute and prismatic joints).

/// The adjoint and the bracket of an abelian group of dimension `N` (`Ad = I`, `[a, b] = 0`):
/// the methods [`Torus`], [`Rn`] and [`JointSpace`] share.
macro_rules! abelian_group_algebra {
    () => {
        #[inline]
        fn adjoint(&self) -> nalgebra::SMatrix<T, N, N> {
            nalgebra::SMatrix::identity()
        }
        #[inline]
        fn adjoint_apply(&self, v: &Tangent<T, N>) -> Tangent<T, N> {
            *v
        }
        #[inline]
        fn adjoint_inverse_apply(&self, v: &Tangent<T, N>) -> Tangent<T, N> {
            *v
        }
        #[inline]
        fn lie_bracket(_a: &Tangent<T, N>, _b: &Tangent<T, N>) -> Tangent<T, N> {
            nalgebra::SVector::zeros()
        }
    };
}

mod joint_space;
mod rn;
mod so3;
mod torus;

pub use joint_space::{JointKind, JointSpace};
pub use rn::Rn;
pub use so3::{hat, vee, So3};
pub use torus::{wrap_angle, Torus, Torus2};

use crate::Real;
use nalgebra::{SMatrix, SVector};

/// A tangent vector in body coordinates of a `D`-dimensional group.
pub type Tangent<T, const D: usize> = SVector<T, D>;

/// A matrix Lie group of dimension `D` over the scalar `T`.
///
/// The laws every implementation satisfies (checked by one generic test suite for every group
/// and both `f32` and `f64`): associativity, identity, inverse, `exp(log g) = g`,
/// `g·exp(v)·g⁻¹ = exp(Ad_g v)`, and the pushforwards below agree with finite differences.
///
/// ```
/// use pvfc_core::lie::{LieGroup, Torus};
/// use nalgebra::Vector2;
/// let a = Torus::<f64, 2>::new(Vector2::new(0.5, 3.0));
/// let b = Torus::new(Vector2::new(-1.0, 4.0));
/// let e = a.compose(&b.inverse());
/// assert!((e.angles()[0] - 1.5).abs() < 1e-15);
/// ```
pub trait LieGroup<T: Real, const D: usize>: Copy + core::fmt::Debug + PartialEq {
    /// The identity element `id`.
    fn identity() -> Self;

    /// The group operation `self · other`.
    fn compose(&self, other: &Self) -> Self;

    /// The inverse `self⁻¹`.
    fn inverse(&self) -> Self;

    /// The exponential map of the Lie algebra (vector `v` in body coordinates).
    fn exp(v: &Tangent<T, D>) -> Self;

    /// The logarithm: a `v` with `exp(v) = self`, of smallest norm where several exist.
    fn log(&self) -> Tangent<T, D>;

    /// The adjoint `Ad_g` as a matrix acting on body coordinates: `g·exp(v)·g⁻¹ = exp(Ad_g v)`.
    fn adjoint(&self) -> SMatrix<T, D, D>;

    /// `Ad_g v` (may be overridden for speed).
    #[inline]
    fn adjoint_apply(&self, v: &Tangent<T, D>) -> Tangent<T, D> {
        self.adjoint() * v
    }

    /// `Ad_{g⁻¹} v` (may be overridden for speed).
    #[inline]
    fn adjoint_inverse_apply(&self, v: &Tangent<T, D>) -> Tangent<T, D> {
        self.inverse().adjoint_apply(v)
    }

    /// The Lie bracket `[a, b] = ad_a b` of two algebra elements.
    fn lie_bracket(a: &Tangent<T, D>, b: &Tangent<T, D>) -> Tangent<T, D>;

    /// `true` when every stored number is finite.
    fn is_finite(&self) -> bool;

    /// How far the algebra element `v` reaches towards the discontinuity of [`log`](Self::log)
    /// (curves built from logarithms, such as splines, must keep it below about π): the norm
    /// by default (SO(3), where `log` jumps at rotation angle π), the largest component on a
    /// torus (it wraps coordinate by coordinate), 0 on a vector space (no discontinuity).
    #[inline]
    fn chart_extent(v: &Tangent<T, D>) -> T {
        v.norm()
    }

    /// The same element with rounding drift off the group removed (integrators call it after
    /// every step). A no-op for groups stored in coordinates (torus, `ℝⁿ`).
    #[inline]
    fn normalized(&self) -> Self {
        *self
    }

    /// `(L_self)_*`: pushes a tangent vector at `b` (body coordinates) to `self·b`.
    /// In body coordinates this is the identity.
    #[inline]
    fn left_translation_pushforward(&self, v: &Tangent<T, D>) -> Tangent<T, D> {
        *v
    }

    /// `(R_self)_*`: pushes a tangent vector at `b` (body coordinates) to `b·self`:
    /// `v ↦ Ad_{self⁻¹} v`.
    #[inline]
    fn right_translation_pushforward(&self, v: &Tangent<T, D>) -> Tangent<T, D> {
        self.adjoint_inverse_apply(v)
    }

    /// Moves along the body velocity `v` for a time `dt`: `self · exp(dt·v)`.
    #[inline]
    fn retract(&self, v: &Tangent<T, D>, dt: T) -> Self {
        self.compose(&Self::exp(&(v * dt)))
    }

    /// The geodesic-like distance `‖log(self⁻¹·other)‖`.
    #[inline]
    fn distance(&self, other: &Self) -> T {
        self.inverse().compose(other).log().norm()
    }
}
