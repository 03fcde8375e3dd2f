//! The control law at one augmented state, as plain run-time-sized data for any robot: what
//! a binding (Python, a log) shows of [`Controller::evaluate`](pvfc_core::prelude::Controller)
//! without knowing the robot's number of joints at compile time.

use crate::error::Result;
use nalgebra::DMatrix;
use pvfc_core::augmented::AugmentedVector;
use pvfc_core::coupling::CouplingOutput;

/// The law evaluated at one augmented state `(q, q̇, τ, τ̇, q̇_F)`. Augmented vectors have
/// `dof + 2` entries: the robot's, then `τ`'s, then the flywheel's.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// The full augmented torque: the coupling's `T_a` (eq. 7) plus the add-ons (gravity and
    /// friction compensation, nominal speed (36)).
    pub torque: Vec<f64>,
    /// The coupling's torque `T_a = G q̇_a + γ R q̇_a` alone (eq. 7).
    pub coupling_torque: Vec<f64>,
    /// The augmented field `V_a = (V_G, V_I, V_F)`.
    pub field_velocity: Vec<f64>,
    /// The desired momentum `P = M_a V_a`.
    pub desired_momentum: Vec<f64>,
    /// The momentum `p = M_a q̇_a`.
    pub momentum: Vec<f64>,
    /// `w = M_a V̇_a + C_a V_a`.
    pub w: Vec<f64>,
    /// `κ_a = ½ q̇_aᵀ M_a q̇_a` (eq. 5).
    pub kinetic_energy: f64,
    /// `β = √(κ_a / Ē)` (eq. 10).
    pub beta: f64,
    /// The energy level `Ē`.
    pub energy_level: f64,
    /// The navigation function `U` at the group error; with obstacles, its composition `φ`
    /// with their barrier (Remark 3).
    pub potential: f64,
    /// `λ₁` of the self-pacing (eq. 21).
    pub lambda1: f64,
    /// `λ₂` of the self-pacing (eq. 21).
    pub lambda2: f64,
    /// `W_β = ½‖q̇_a − βV_a‖²_a` (eq. 12).
    pub velocity_field_error_energy: f64,
    /// `μ` of eq. (13).
    pub convergence_factor: f64,
    /// The skew-symmetric `G = (w Pᵀ − P wᵀ)/(2Ē)` of eq. (7), `(dof + 2)²`.
    pub g: DMatrix<f64>,
    /// The skew-symmetric `R = P pᵀ − p Pᵀ` of eq. (7), `(dof + 2)²`.
    pub r: DMatrix<f64>,
}

fn entries<const D: usize>(a: &AugmentedVector<f64, D>) -> Vec<f64> {
    let mut v = a.robot.as_slice().to_vec();
    v.extend([a.tau, a.flywheel]);
    v
}

impl Evaluation {
    /// From the core's `(torque, coupling output)` of a `D`-dimensional robot, with
    /// `A = D + 2` (the augmented dimension, for the matrices; `DimensionMismatch`
    /// otherwise).
    pub fn from_core<G, const D: usize, const A: usize>(
        torque: &AugmentedVector<f64, D>,
        o: &CouplingOutput<f64, G, D>,
    ) -> Result<Self> {
        let (g, r) = o.coupling_matrices::<A>()?;
        Ok(Evaluation {
            torque: entries(torque),
            coupling_torque: entries(&o.torque),
            field_velocity: entries(&o.field_velocity),
            desired_momentum: entries(&o.desired_momentum),
            momentum: entries(&o.momentum),
            w: entries(&o.w),
            kinetic_energy: o.kinetic_energy,
            beta: o.beta,
            energy_level: o.energy_level,
            potential: o.field.potential,
            lambda1: o.field.lambda1,
            lambda2: o.field.lambda2,
            velocity_field_error_energy: o.velocity_field_error_energy(),
            convergence_factor: o.convergence_factor(),
            g: DMatrix::from_column_slice(A, A, g.as_slice()),
            r: DMatrix::from_column_slice(A, A, r.as_slice()),
        })
    }

    /// The number of the robot's coordinates (`dof`).
    pub fn dof(&self) -> usize {
        self.torque.len().saturating_sub(2)
    }

    /// The robot's part of the full torque: what the motors apply.
    pub fn robot_torque(&self) -> &[f64] {
        &self.torque[..self.dof()]
    }
}
