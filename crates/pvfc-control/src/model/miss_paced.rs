//! A passive controller with the learner of the torque its model misses beside it
//! (`pace_learning.miss`): the one place where the learner reads a step and caps the learned
//! pace, for every robot and every binding (the simulator's drive, Python, C).

use crate::model::pace::FieldMissLearner;
use pvfc_core::contour::VectorGroup;
use pvfc_core::mechanics::MechanicalSystem;
use pvfc_core::passive::{PassiveController, PassiveStepOutput};
use pvfc_core::prelude::*;

/// A [`PassiveController`] and, if asked for, a [`FieldMissLearner`] beside it: after each
/// step without a fault the learner records the command against the model's motion torque at
/// the step's `τ`, `τ̇` and `τ̈`, and once a lap its caps become the ceilings of the field's
/// learned pace ([`Controller::set_pace_caps`]). Passivity does not depend on the learner:
/// the caps only shape the field's pace (eq. 27: the coupling is workless for any field).
#[derive(Clone, Debug)]
pub struct MissPaced<G, Sys, F, const N: usize> {
    controller: PassiveController<f64, G, Sys, F, N>,
    miss: Option<Box<FieldMissLearner<N>>>,
}

impl<G, Sys, F, const N: usize> MissPaced<G, Sys, F, N>
where
    G: VectorGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
    F: VelocityField<f64, G, N>,
{
    /// `controller`, with `miss` learning beside it (`None`: the controller alone).
    pub fn new(
        controller: PassiveController<f64, G, Sys, F, N>,
        miss: Option<Box<FieldMissLearner<N>>>,
    ) -> Self {
        MissPaced { controller, miss }
    }

    /// The passive controller.
    pub fn controller(&self) -> &PassiveController<f64, G, Sys, F, N> {
        &self.controller
    }

    /// The passive controller, to schedule its nominal speed on line.
    pub fn controller_mut(&mut self) -> &mut PassiveController<f64, G, Sys, F, N> {
        &mut self.controller
    }

    /// The learner of the torque the model misses, if any.
    pub fn miss_learner(&self) -> Option<&FieldMissLearner<N>> {
        self.miss.as_deref()
    }

    /// The storage `S` (J) as of the last step.
    pub fn storage(&self) -> f64 {
        self.controller.storage()
    }

    /// One step of the passive controller ([`PassiveController::step`]), then, without a
    /// fault, the learner's record of it. On error nothing changes.
    pub fn step(
        &mut self,
        q: &G,
        v: Option<&Tangent<f64, N>>,
        applied: Option<&Tangent<f64, N>>,
        dt: f64,
    ) -> pvfc_core::error::Result<PassiveStepOutput<f64, N>> {
        let out = self.controller.step(q, v, applied, dt)?;
        if let (Some(miss), None) = (&mut self.miss, out.fault) {
            let c = self.controller.controller_mut();
            // The step advanced τ̇ from the state the torque was computed at.
            let tau_ddot = (c.state().tau_dot - out.state.tau_dot) / dt;
            if miss.record(out.state.tau, out.state.tau_dot, tau_ddot, &out.torque, dt) {
                c.set_pace_caps(miss.caps());
            }
        }
        Ok(out)
    }
}
