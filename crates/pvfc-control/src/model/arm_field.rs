//! The velocity field of an arm, chosen per scenario: the joint-space contour's
//! ([`SuspendedField`]: the mixed navigation function of the joint error, eq. 30) or the
//! task-space field on a Cartesian tool path ([`TaskSpaceField`]: the tool's position error,
//! and its orientation's on SO(3) when it is held, pulled back through the damped inverse of
//! the Jacobian). Both feed the same coupling, so passivity and the audits are the same.

use super::fixed;
use crate::error::{Result, SimError};
use crate::model::joint_contour::JointContour;
use crate::model::pace::FieldPacing;
use crate::model::path_orientation::{OrientationLaw, PathOrientation};
use crate::model::tool_path::{PathContour, ToolPath};
use nalgebra::{Matrix3, SVector};
use pvfc_core::field::FieldSample;
use pvfc_core::mechanics::ChainKinematics;
use pvfc_core::prelude::*;
use pvfc_core::task_field::TaskSpaceField;

/// The joint-space field of an `N`-joint arm: its joint contour, the mixed navigation
/// function, exponential self-pacing (eq. 21) with the drive-limited pace, if any.
pub type JointField<const N: usize> = SuspendedField<
    f64,
    JointSpace<f64, N>,
    JointContour<N>,
    JointNavigation<f64, N>,
    FieldPacing,
    N,
    pvfc_core::obstacle::ObstacleSet<f64, N>,
>;

/// The task-space field of an `N`-joint arm on the exact tool path, with the tool's
/// orientation along it (if any).
pub type TaskField<const N: usize> =
    TaskSpaceField<f64, PathContour, FieldPacing, N, PathOrientation>;

/// The field of an `N`-joint arm.
// One field per controller, read at every step: the joint field (with its obstacle set's
// fixed-capacity storage) stays inline rather than behind a pointer.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum ArmField<const N: usize> {
    /// The joint-space contour's field.
    Joint(JointField<N>),
    /// The task-space field, with the path's joint-space image (its inverse kinematics, the
    /// contour the timed tracker and the figures use; the field itself does not).
    Task {
        /// The field.
        field: Box<TaskField<N>>,
        /// The joint-space image of the path.
        image: JointContour<N>,
    },
}

impl<const N: usize> ArmField<N> {
    /// The joint-space contour: the field's own, or the tool path's joint-space image.
    pub fn joint_contour(&self) -> &JointContour<N> {
        match self {
            ArmField::Joint(f) => f.contour(),
            ArmField::Task { image, .. } => image,
        }
    }
}

impl<const N: usize> VelocityField<f64, JointSpace<f64, N>, N> for ArmField<N> {
    fn set_pace_scale(&mut self, scale: f64) -> bool {
        match self {
            ArmField::Joint(f) => f.set_pace_scale(scale),
            ArmField::Task { field, .. } => field.set_pace_scale(scale),
        }
    }

    fn learn_pace(
        &mut self,
        tau: f64,
        share: f64,
        dt: f64,
        rule: &pvfc_core::pace::PaceLearning<f64>,
    ) -> bool {
        match self {
            ArmField::Joint(f) => f.learn_pace(tau, share, dt, rule),
            ArmField::Task { field, .. } => field.learn_pace(tau, share, dt, rule),
        }
    }

    fn set_pace_caps(&mut self, caps: &[f64]) -> bool {
        match self {
            ArmField::Joint(f) => f.set_pace_caps(caps),
            ArmField::Task { field, .. } => field.set_pace_caps(caps),
        }
    }

    #[inline(always)]
    fn sample(
        &self,
        q: &JointSpace<f64, N>,
        v: &SVector<f64, N>,
        tau: f64,
        tau_dot: f64,
    ) -> FieldSample<f64, JointSpace<f64, N>, N> {
        match self {
            ArmField::Joint(f) => f.evaluate(q, v, tau, tau_dot),
            ArmField::Task { field, .. } => field.evaluate(q, v, tau, tau_dot),
        }
    }

    // The task-space field takes the chain's forward kinematics from the law, which shares
    // them with the model's products (one computation per step).
    const USES_CHAIN_KINEMATICS: bool = true;

    fn serial_chain(&self) -> Option<&SerialChain<f64, N>> {
        match self {
            ArmField::Joint(_) => None,
            ArmField::Task { field, .. } => Some(field.chain()),
        }
    }

    #[inline(always)]
    fn sample_with_kinematics(
        &self,
        kinematics: &ChainKinematics<f64, N>,
        q: &JointSpace<f64, N>,
        v: &SVector<f64, N>,
        tau: f64,
        tau_dot: f64,
    ) -> FieldSample<f64, JointSpace<f64, N>, N> {
        match self {
            ArmField::Task { field, .. } => {
                field.evaluate_with_kinematics(kinematics, q, v, tau, tau_dot)
            }
            ArmField::Joint(_) => self.sample(q, v, tau, tau_dot),
        }
    }

    fn period(&self) -> Option<f64> {
        match self {
            ArmField::Joint(f) => VelocityField::period(f),
            ArmField::Task { field, .. } => VelocityField::period(field.as_ref()),
        }
    }
}

/// Which field an arm's controller follows, as plain data.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum FieldSpec {
    /// The joint-space contour's field (the settings' `contour`, `h`).
    #[default]
    Joint,
    /// The task-space field on a tool path.
    Task(Box<TaskFieldSpec>),
}

/// The task-space field's settings, as plain data.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskFieldSpec {
    /// The tool path (m, base frame), traced once per period of the settings' contour.
    pub path: ToolPath,
    /// `k` of `U = ½ k |e|²` (1/s, > 0).
    pub stiffness: f64,
    /// The damping `μ` of the Jacobian's inverse (m, > 0).
    pub damping: f64,
    /// The distance `ℓ` (m, > 0) at which the position's navigation function saturates;
    /// `None`: `½k|e|²`.
    pub saturation: Option<f64>,
    /// The tool's orientation along the path and its stiffness `k_R` (1/s, > 0); `None`: the
    /// orientation is free.
    pub orientation: Option<(TaskOrientation, f64)>,
    /// The rest posture pulled towards in the task's null space, and the pull's gain (1/s).
    pub rest: Option<(Vec<f64>, f64)>,
}

/// The tool's orientation along a task-space field's path, as plain data.
#[derive(Clone, Debug, PartialEq)]
pub enum TaskOrientation {
    /// One orientation held (a rotation matrix in the base frame).
    Held(Matrix3<f64>),
    /// The orientation along the path (the polyline's corners': an SE(3) path).
    Along(OrientationLaw),
    /// The tool's axis along the path (the axis of the law's rotation, its roll free: the
    /// path's frame of a `tool_frame`).
    Axis(OrientationLaw),
}

impl TaskFieldSpec {
    /// The field of `chain` with self-pacing `pacing`, one pass of the path every `period`.
    pub fn build<const N: usize>(
        &self,
        chain: SerialChain<f64, N>,
        pacing: FieldPacing,
        period: f64,
    ) -> Result<TaskField<N>> {
        let path = PathContour::new(self.path.clone(), period)
            .map_err(|e| SimError::Setting(format!("contour.cartesian.task: {e}")))?;
        let orientation = match &self.orientation {
            None => None,
            Some((TaskOrientation::Held(r), k)) => Some((
                PathOrientation::Held(So3::from_matrix(*r, 1e-6).map_err(|_| {
                    SimError::Setting(
                        "contour.cartesian.task: the orientation is not a rotation".into(),
                    )
                })?),
                *k,
            )),
            Some((TaskOrientation::Along(law) | TaskOrientation::Axis(law), k)) => Some((
                PathOrientation::Along {
                    law: law.clone(),
                    period,
                },
                *k,
            )),
        };
        let field = TaskSpaceField::new(chain, path, pacing, self.stiffness, self.damping)?;
        let mut field = match (&self.orientation, orientation) {
            (Some((TaskOrientation::Axis(_), _)), Some((along, k))) => {
                field.with_axis_path(along, k)?
            }
            (_, orientation) => field.with_orientation_option(orientation)?,
        };
        if let Some((rest, gain)) = &self.rest {
            field = field.with_rest(fixed::<N>(rest, "contour.cartesian.rest")?, *gain)?;
        }
        if let Some(l) = self.saturation {
            field = field.with_saturation(l)?;
        }
        Ok(field)
    }
}
