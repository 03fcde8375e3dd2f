//! # pvfc-core
//!
//! The `no_std`, allocation-free core of **Passive Velocity Field Control** (PVFC) for contour
//! following, after P. Y. Li and R. Horowitz, *Passive Velocity Field Control (PVFC): Part II —
//! Application to Contour Following*, IEEE TAC 46(9), 2001. Equation numbers in the docs refer
//! to that paper.
//!
//! A contour is a parameterised curve `x_d(τ)` on the robot's configuration group `G`
//! ([`lie`], [`contour`]). The parameter `τ` is **suspended** as one more coordinate, and a
//! velocity field on `G × I` is built from a **navigation function** of the group error
//! `E = q·x_d(τ)⁻¹` ([`navigation`], [`field`]); **self-pacing** slows `τ` when the error is
//! large ([`pacing`]). A fictitious **flywheel** is added, and the PVFC **coupling** control,
//! built from skew-symmetric matrices, steers the robot onto a multiple of the field without
//! ever creating energy ([`coupling`], [`controller`]).
//!
//! Everything is generic over the scalar (`f32`, `f64`) with const-generic dimensions, and
//! never allocates. Errors are values ([`Error`], [`ErrorKind`]), never panics or NaNs.
//!
//! ## Features
//! * `std` (off by default): use the standard library's math functions instead of `libm`.
//! * `defmt` (off by default): `defmt::Format` for [`Error`], [`ErrorKind`] and the
//!   controller's step output, diagnostics and internal states (embedded logging).
//!
//! ```
//! use pvfc_core::prelude::*;
//! use nalgebra::Vector2;
//!
//! let field = SuspendedField::new(
//!     Lissajous::<f64, 2>::paper(),
//!     TorusNavigation::paper(Vector2::new(1.0, 1.0))?,
//!     ExponentialPacing::new(100.0)?,
//! );
//! let law = PvfcLaw::new(Scara::pelican(), field, Flywheel::new(1.0, 50.0)?, 0.05)?;
//! let state = AugmentedState {
//!     q: Torus::new(Vector2::new(0.2, -0.1)),
//!     v: Vector2::new(0.3, 0.1),
//!     tau: 0.5,
//!     tau_dot: 0.2,
//!     flywheel_speed: 9.0,
//! };
//! let out = law.evaluate(&state)?;
//! // Passivity: the coupling does no work, q̇_aᵀ T_a = 0.
//! let power = out.torque.dot(&state.velocity());
//! assert!(power.abs() < 1e-12 * out.kinetic_energy);
//! # Ok::<(), pvfc_core::Error>(())
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod augmented;
pub mod contour;
pub mod controller;
pub mod coupling;
pub mod error;
pub mod field;
pub mod lie;
pub mod linalg;
pub mod mechanics;
pub mod navigation;
pub mod obstacle;
pub mod pace;
pub mod pacing;
pub mod passive;
pub mod scalar;
pub mod supervision;
pub mod task_field;

pub use error::{Error, ErrorKind, Result};
/// The linear-algebra crate of pvfc's types (vectors, matrices), re-exported so that a user
/// names the same version.
pub use nalgebra;
pub use scalar::Real;

/// The types most programs need, in one import.
pub mod prelude {
    pub use crate::augmented::{AugmentedState, AugmentedVector};
    pub use crate::contour::{
        ConstantRate, Contour, ContourSample, Ellipse, Lissajous, PeriodicBSpline, VectorGroup,
    };
    pub use crate::controller::{
        Controller, Diagnostics, InternalState, ScaraLissajousController, StepOutput,
    };
    pub use crate::coupling::{
        CouplingOutput, Flywheel, FrictionCompensation, NominalSpeed, PvfcLaw,
    };
    pub use crate::error::{Error, ErrorKind};
    pub use crate::field::{ErrorConvention, FieldSample, SuspendedField, VelocityField};
    pub use crate::lie::{JointKind, JointSpace, LieGroup, Rn, So3, Tangent, Torus};
    pub use crate::mechanics::{
        LinearStage, MechanicalSystem, RigidBody, Scara, ScaraParameters, SerialChain,
    };
    pub use crate::navigation::{
        JointNavigation, NavigationFunction, QuadraticNavigation, So3Navigation, TorusConvention,
        TorusNavigation,
    };
    pub use crate::pacing::{ConstantGains, ExponentialPacing, SelfPacing};
    pub use crate::passive::{
        EnergyAccount, PassiveController, PassiveStepOutput, SetAsideAccount,
    };
    pub use crate::supervision::{Fault, Supervision};
    pub use crate::Real;
}
