//! Mechanical systems `M(q) q̈ + C(q, q̇) q̇ + g(q) = T + F_e` (eq. 3, with gravity for
//! arms that are not horizontal), in body coordinates.

mod chain_products;
mod inverse_kinematics;
mod point_motion;
mod rigid_body;
mod scara;
mod serial_chain;
mod spatial;
mod stage;

pub use inverse_kinematics::{IkSettings, IkTarget};
pub use point_motion::{ChainMotion, PointMotion};
pub use rigid_body::RigidBody;
pub use scara::{Scara, ScaraParameters};
pub use serial_chain::{ChainJoint, ChainKinematics, SerialChain, STANDARD_GRAVITY};
pub use spatial::{
    axis_angle, force_cross, force_cross_apply, force_cross_bar, motion_cross, Pose, RigidInertia,
    Spatial, Spatial6, WorldInertia,
};
pub use stage::LinearStage;

use crate::error::{Error, ErrorKind, Result};
use crate::lie::{LieGroup, Tangent};
use crate::scalar::cast;
use crate::Real;
use nalgebra::{Matrix2, SMatrix, Vector2};

/// A fully actuated mechanical system on the group `G`: its inertia matrix `M(q)` and a
/// Coriolis matrix `C(q, v)` such that `Ṁ − 2C` is skew-symmetric (the Christoffel form),
/// both in the body coordinates of [`crate::lie`].
pub trait MechanicalSystem<T: Real, G: LieGroup<T, D>, const D: usize> {
    /// `true` when [`gravity`](Self::gravity) may be non-zero. `false` (the default) lets a
    /// controller leave out its gravity-compensation path entirely (code size on a
    /// microcontroller).
    const HAS_GRAVITY: bool = false;

    /// `M(q)`, symmetric positive definite.
    fn inertia(&self, q: &G) -> SMatrix<T, D, D>;

    /// `C(q, v)` with `Ṁ − 2C` skew-symmetric.
    fn coriolis(&self, q: &G, v: &Tangent<T, D>) -> SMatrix<T, D, D>;

    /// `M(q)` and `C(q, v)` together (a model may share work between them).
    #[inline]
    fn inertia_and_coriolis(
        &self,
        q: &G,
        v: &Tangent<T, D>,
    ) -> (SMatrix<T, D, D>, SMatrix<T, D, D>) {
        (self.inertia(q), self.coriolis(q, v))
    }

    /// `Ṁ(q, v) = d/dt M(q(t))` along `q̇ = v`. The default uses `Ṁ = C + Cᵀ`, which holds
    /// for every Christoffel-form `C`.
    fn inertia_rate(&self, q: &G, v: &Tangent<T, D>) -> SMatrix<T, D, D> {
        let c = self.coriolis(q, v);
        c + c.transpose()
    }

    /// `g(q)`, the gradient of the potential energy (gravity) in body coordinates: the
    /// torque that holds the system still. Zero for the paper's horizontal SCARA, a free rigid
    /// body and a horizontal stage (the default).
    #[inline]
    fn gravity(&self, q: &G) -> Tangent<T, D> {
        let _ = q;
        Tangent::zeros()
    }

    /// The model as a serial chain, when it is one (`None` by default). A velocity field on
    /// the same chain's forward kinematics (the task-space field) then shares them with the
    /// model's products: [`PvfcLaw`](crate::coupling::PvfcLaw) computes them once per step
    /// ([`chain_kinematics`](Self::chain_kinematics)) and hands them to both, as Pinocchio
    /// keeps a model's quantities at one state in one `Data`.
    #[inline]
    fn serial_chain(&self) -> Option<&SerialChain<T, D>> {
        None
    }

    /// The forward kinematics at `q` when the model is a serial chain (see
    /// [`serial_chain`](Self::serial_chain)), else `None` (the default).
    #[inline]
    fn chain_kinematics(&self, q: &G) -> Option<ChainKinematics<T, D>> {
        let _ = q;
        None
    }

    /// [`law_products`](Self::law_products) given the forward kinematics that
    /// [`chain_kinematics`](Self::chain_kinematics) computed at the same `q`. The default
    /// ignores them.
    #[inline]
    fn law_products_with_kinematics(
        &self,
        kinematics: &ChainKinematics<T, D>,
        q: &G,
        v: &Tangent<T, D>,
        x: &Tangent<T, D>,
        a: &Tangent<T, D>,
        with_gravity: bool,
    ) -> LawProducts<T, D> {
        let _ = kinematics;
        self.law_products(q, v, x, a, with_gravity)
    }

    /// `M(q)`, `C(q, v)` and `g(q)` together (a serial chain computes them in one pass).
    #[inline]
    fn inertia_coriolis_gravity(
        &self,
        q: &G,
        v: &Tangent<T, D>,
    ) -> (SMatrix<T, D, D>, SMatrix<T, D, D>, Tangent<T, D>) {
        let (m, c) = self.inertia_and_coriolis(q, v);
        (m, c, self.gravity(q))
    }

    /// The products of the model that the coupling law needs (eq. 7), at the robot's state
    /// `(q, v)` and the field's value `x = V(q, τ)` and rate `a = V̇`: `M v`, `M x`,
    /// `M a + C(q, v) x` and, when `with_gravity`, `g(q)`. The default forms `M` and `C`; a
    /// model that can apply them without forming them overrides it (a serial chain does, by
    /// one O(N) recursion).
    #[inline]
    fn law_products(
        &self,
        q: &G,
        v: &Tangent<T, D>,
        x: &Tangent<T, D>,
        a: &Tangent<T, D>,
        with_gravity: bool,
    ) -> LawProducts<T, D> {
        let (m, c, gravity) = if with_gravity {
            self.inertia_coriolis_gravity(q, v)
        } else {
            let (m, c) = self.inertia_and_coriolis(q, v);
            (m, c, Tangent::zeros())
        };
        LawProducts {
            field_momentum: m * x,
            w: m * a + c * x,
            momentum: m * v,
            gravity,
        }
    }

    /// `½ vᵀ M(q) v`.
    #[inline]
    fn kinetic_energy(&self, q: &G, v: &Tangent<T, D>) -> T {
        (self.inertia(q) * v).dot(v) * cast::<T>(0.5)
    }

    /// The forward dynamics `q̈ = M⁻¹ (T + F_e − C v − g)` (Cholesky; no allocation), with
    /// `M`, `C`, `g` from one [`inertia_coriolis_gravity`](Self::inertia_coriolis_gravity).
    fn acceleration(
        &self,
        q: &G,
        v: &Tangent<T, D>,
        force: &Tangent<T, D>,
    ) -> Result<Tangent<T, D>> {
        // One pass over the model (a SCARA shares its sin/cos, a chain its kinematics).
        let (m, c, g) = self.inertia_coriolis_gravity(q, v);
        solve_acceleration(&m, force - c * v - g)
    }
}

/// `q̈ = M⁻¹ rhs` by Cholesky (no allocation), or why not ([`acceleration_failure`]).
pub(crate) fn solve_acceleration<T: Real, const D: usize>(
    m: &SMatrix<T, D, D>,
    rhs: Tangent<T, D>,
) -> Result<Tangent<T, D>> {
    match m.cholesky() {
        Some(ch) => Ok(ch.solve(&rhs)),
        None => Err(acceleration_failure(m.iter(), rhs.iter())),
    }
}

/// Why the forward dynamics failed: a state or a force that is not finite (a run that
/// diverged) makes `M` or the right-hand side non-finite, which says so rather than blame the
/// inertia; else `M(q)` is not positive definite.
pub(crate) fn acceleration_failure<'a, T: Real + 'a>(
    m: impl IntoIterator<Item = &'a T>,
    rhs: impl IntoIterator<Item = &'a T>,
) -> Error {
    if crate::scalar::all_finite(m) && crate::scalar::all_finite(rhs) {
        Error::new(
            ErrorKind::SingularInertia,
            "MechanicalSystem::acceleration: M(q) not positive definite",
        )
    } else {
        Error::new(
            ErrorKind::NonFinite,
            "MechanicalSystem::acceleration: the state or the force is not finite (did the run diverge?)",
        )
    }
}

/// Solves `M x = b` for a symmetric positive definite 2×2 `M` by Cramer's rule,
/// `x = (m₁₁b₀ − m₁₀b₁, m₀₀b₁ − m₁₀b₀) / det M`: one division and no square root, where a
/// Cholesky solve chains two roots and four divisions. `None` unless `m₀₀ > 0` and
/// `det M > 0` (Sylvester's criterion: positive definite), or for NaN. Reads `M`'s lower
/// triangle. Its error is the condition number times a few ε, as the Cholesky solve's
/// (held to nalgebra's Cholesky within `κ(M) · 8ε` in `tests/integration/forward_dynamics.rs`).
#[inline]
pub fn solve_spd2<T: Real>(m: &Matrix2<T>, b: &Vector2<T>) -> Option<Vector2<T>> {
    let (m00, m10, m11) = (m[(0, 0)], m[(1, 0)], m[(1, 1)]);
    let det = m00 * m11 - m10 * m10;
    if !(m00 > T::zero() && det > T::zero()) {
        return None;
    }
    let inv = T::one() / det;
    Some(Vector2::new(
        (m11 * b[0] - m10 * b[1]) * inv,
        (m00 * b[1] - m10 * b[0]) * inv,
    ))
}

/// What the coupling law (eq. 7) needs of the model at one state, from
/// [`MechanicalSystem::law_products`]: products with `M(q)` and `C(q, q̇)`, never the
/// matrices themselves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawProducts<T: Real, const D: usize> {
    /// `p = M(q) q̇`, the robot's momentum.
    pub momentum: Tangent<T, D>,
    /// `P = M(q) V`, the field's momentum.
    pub field_momentum: Tangent<T, D>,
    /// `w = M(q) V̇ + C(q, q̇) V`, the rate of the field's momentum along the motion (eq. 7).
    pub w: Tangent<T, D>,
    /// `g(q)` when it was asked for, else zero.
    pub gravity: Tangent<T, D>,
}

/// Checks a physical parameter: finite and strictly positive.
pub(crate) fn positive<T: Real>(x: T, context: &'static str) -> Result<T> {
    if !x.is_finite() {
        return Err(Error::new(ErrorKind::NonFinite, context));
    }
    if x <= T::zero() {
        return Err(Error::new(ErrorKind::InvalidParameter, context));
    }
    Ok(x)
}
