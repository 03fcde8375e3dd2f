//! The controller as a sampled-data loop drives it, whichever it is: `Controller::step` with
//! zero-order hold, or the passive digital controller of `pvfc_core::passive` with what a
//! drive does to its measurements (encoder rounding, position-only measurement). The loops
//! (`simulate.rs` for the planar arm and its contact, `chain_run.rs` for URDF arms) differ
//! from each other only by their plant and surroundings, not by the controller.

use crate::error::Result;
use crate::model::miss_paced::MissPaced;
use crate::model::pace::FieldMissLearner;
use crate::plant::faults::FaultState;
use crate::scenario::operator::Operator;
use crate::scenario::{PassiveSpec, Scenario};
use crate::trace::Row;
use nalgebra::SVector;
use pvfc_core::prelude::*;

/// What a controller gives the loop at one sample.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sample<const N: usize> {
    /// The torque held over the coming period.
    pub torque: SVector<f64, N>,
    /// The internal states to log (those the torque was computed at).
    pub state: InternalState<f64>,
    /// `U`, `λ₁`, `λ₂`, `β`, … at that state.
    pub diagnostics: Diagnostics<f64>,
    /// The controller's part of `κ_a` at the sample: `½τ̇² + ½M_F q̇_F²`, or the passive
    /// controller's accounted storage.
    pub storage: f64,
    /// The add-ons' energy of the period that ended at this sample, as the controller
    /// accounts it (the passive controller; 0 for the ZOH one).
    pub add_ons_ended: f64,
    /// The add-ons' energy of the period that starts, by the rectangle rule at the sample
    /// (the ZOH controller; 0 for the passive one).
    pub add_ons_next: f64,
    /// The fault the supervision found ([`pvfc_core::supervision::Fault::code`]; 0: none).
    pub fault: u8,
    /// What the passive controller holds aside for the work its still readings may hide
    /// ([`PassiveController::set_aside`]; zero for the others).
    pub set_aside: SetAsideAccount<f64, N>,
}

/// The set-aside account of a controller that sets nothing aside.
fn no_set_aside<const N: usize>() -> SetAsideAccount<f64, N> {
    SetAsideAccount {
        energy: SVector::zeros(),
        accounted: SVector::zeros(),
        time: SVector::zeros(),
    }
}

impl<const N: usize> Sample<N> {
    /// A drive's sample while it is stopped (or not heard from): the safe torque (zero), the
    /// internal states `state` and storage `storage` as they are, `U`, `λ` and `β` not
    /// computed (NaN).
    pub(crate) fn stopped(state: InternalState<f64>, storage: f64) -> Self {
        let nan = f64::NAN;
        Sample {
            torque: SVector::zeros(),
            state,
            diagnostics: Diagnostics {
                potential: nan,
                lambda1: nan,
                lambda2: nan,
                beta: nan,
                kinetic_energy: nan,
                flywheel_field_speed: nan,
                momentum_along_field: nan,
            },
            storage,
            add_ons_ended: 0.0,
            add_ons_next: 0.0,
            fault: 0,
            set_aside: no_set_aside(),
        }
    }
}

/// A controller of a sampled-data loop, at the true state of the plant `(q, q̇)`.
pub(crate) trait Stepper<G, const N: usize> {
    /// One control step at time `t`, `dt` after the last; `faults` are what the sensors and
    /// the drive do to the loop (the passive controller's; the ZOH one meets none).
    fn sample(
        &mut self,
        q: &G,
        v: &SVector<f64, N>,
        time: (f64, f64),
        faults: &mut FaultState<'_, N>,
    ) -> Result<Sample<N>>;
    /// The nominal-speed add-on, to schedule `r` on line.
    fn nominal_speed_mut(&mut self) -> Option<&mut NominalSpeed<f64>>;
}

/// A controller borrowed (a drive whose report the caller reads after the run).
impl<G, S: Stepper<G, N> + ?Sized, const N: usize> Stepper<G, N> for &mut S {
    fn sample(
        &mut self,
        q: &G,
        v: &SVector<f64, N>,
        time: (f64, f64),
        faults: &mut FaultState<'_, N>,
    ) -> Result<Sample<N>> {
        (**self).sample(q, v, time, faults)
    }

    fn nominal_speed_mut(&mut self) -> Option<&mut NominalSpeed<f64>> {
        (**self).nominal_speed_mut()
    }
}

impl<G, Sys, F, const N: usize> Stepper<G, N> for Controller<f64, G, Sys, F, N>
where
    G: LieGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
    F: VelocityField<f64, G, N>,
{
    fn sample(
        &mut self,
        q: &G,
        v: &SVector<f64, N>,
        (_, dt): (f64, f64),
        _: &mut FaultState<'_, N>,
    ) -> Result<Sample<N>> {
        let pre = *self.state();
        let mf = self.law().flywheel().inertia();
        let out = self.step(q, v, dt)?;
        // The coupling is workless (q̇_aᵀT_coupling = 0), so the add-ons' power is that of
        // the whole augmented torque, at the sample (rectangle rule).
        let a = out.augmented_torque;
        Ok(Sample {
            torque: out.torque,
            state: pre,
            diagnostics: out.diagnostics,
            storage: 0.5
                * (pre.tau_dot * pre.tau_dot + mf * pre.flywheel_speed * pre.flywheel_speed),
            add_ons_ended: 0.0,
            add_ons_next: (a.robot.dot(v) + a.tau * pre.tau_dot + a.flywheel * pre.flywheel_speed)
                * dt,
            fault: 0,
            set_aside: no_set_aside(),
        })
    }

    fn nominal_speed_mut(&mut self) -> Option<&mut NominalSpeed<f64>> {
        Controller::nominal_speed_mut(self)
    }
}

/// The passive digital controller on a drive as `[controller.passive]` describes it, under
/// the operator's commands of `[[operator]]`.
pub(crate) struct PassiveDrive<G, Sys, F, const N: usize> {
    /// The passive controller, and the learner of the torque the model misses beside it
    /// (`pace_learning.miss`), if any.
    controller: MissPaced<G, Sys, F, N>,
    spec: PassiveSpec,
    /// Which coordinates an encoder of `encoder_counts` per turn measures (revolute joints).
    circular: [bool; N],
    /// The operator's commands (`[[operator]]`), if any, and the control period's number.
    operator: Option<Operator>,
    period: u64,
}

impl<G, Sys, F, const N: usize> PassiveDrive<G, Sys, F, N>
where
    G: VectorGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
    F: VelocityField<f64, G, N>,
{
    /// The passive controller around `controller` with the spec's limits, encoder charge,
    /// velocity filter and reserve, and `miss` learning beside it; `circular` marks the
    /// revolute joints. Under the scenario `s`'s operator's commands, if it has any (stopped
    /// until one starts it).
    pub(crate) fn new(
        controller: Controller<f64, G, Sys, F, N>,
        spec: &PassiveSpec,
        circular: [bool; N],
        s: &Scenario,
        miss: Option<Box<FieldMissLearner<N>>>,
    ) -> Result<Self> {
        Ok(PassiveDrive {
            controller: spec.controller(controller, circular, miss)?,
            spec: spec.clone(),
            circular,
            operator: Operator::of(s)?,
            period: 0,
        })
    }
}

impl<G, Sys, F, const N: usize> Stepper<G, N> for PassiveDrive<G, Sys, F, N>
where
    G: VectorGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
    F: VelocityField<f64, G, N>,
{
    fn sample(
        &mut self,
        q: &G,
        v: &SVector<f64, N>,
        (t, dt): (f64, f64),
        faults: &mut FaultState<'_, N>,
    ) -> Result<Sample<N>> {
        let k = self.period;
        self.period += 1;
        if let Some(operator) = &mut self.operator {
            if operator.due(k).is_some() {
                if let Some(nominal) = self
                    .controller
                    .controller_mut()
                    .controller_mut()
                    .nominal_speed_mut()
                {
                    nominal.set_speed(operator.speed())?;
                }
            }
            if !operator.running() {
                // Stopped: the safe torque, the controller not stepped.
                return Ok(Sample::stopped(
                    *self.controller.controller().controller().state(),
                    self.controller.storage(),
                ));
            }
        }
        // The encoders round the revolute joints' angles, and the sensor faults act on what
        // they read (composing keeps `q`'s joint kinds).
        let measured = if self.spec.encoder_counts.is_some() || faults.any() {
            let x = q.coordinates();
            let mut reading = SVector::from_fn(|i, _| {
                if self.circular[i] {
                    self.spec.measure(x[i])
                } else {
                    x[i]
                }
            });
            faults.reading(t, &mut reading);
            q.compose(&G::from_coordinates(reading - x))
        } else {
            *q
        };
        let velocity = (!self.spec.positions_only).then_some(v);
        // A drive with faults reports the torque it applied (real drives report their
        // current); without, the controller takes its command as applied.
        let applied = faults.any().then(|| *faults.applied());
        let out = self
            .controller
            .step(&measured, velocity, applied.as_ref(), dt)?;
        Ok(Sample {
            torque: out.torque,
            state: out.state,
            diagnostics: out.diagnostics,
            storage: out.energy.storage,
            add_ons_ended: out.energy.add_ons,
            add_ons_next: 0.0,
            fault: out.fault.map_or(0, |f| f.code()),
            set_aside: self.controller.controller().set_aside(),
        })
    }

    fn nominal_speed_mut(&mut self) -> Option<&mut NominalSpeed<f64>> {
        self.controller
            .controller_mut()
            .controller_mut()
            .nominal_speed_mut()
    }
}

impl<'a> Row<'a> {
    /// The row of a sampled loop's sample: the state `(q, q̇)` and what the controller gave,
    /// with `κ_a` = the arm's kinetic energy + the controller's storage.
    pub(crate) fn of_sample<const N: usize>(
        t: f64,
        (q, v): (&'a [f64], &'a [f64]),
        out: &'a Sample<N>,
        period: f64,
        kinetic_energy: f64,
        friction_power: f64,
    ) -> Self {
        let st = out.state;
        Row {
            t,
            q,
            v,
            tau: st.unwrapped_tau(Some(period)),
            tau_dot: st.tau_dot,
            flywheel_speed: st.flywheel_speed,
            beta: out.diagnostics.beta,
            w_beta: out.diagnostics.velocity_field_error_energy(),
            potential: out.diagnostics.potential,
            lambda1: out.diagnostics.lambda1,
            lambda2: out.diagnostics.lambda2,
            torque: out.torque.as_slice(),
            energy: kinetic_energy + out.storage,
            friction_power,
            fault: f64::from(out.fault),
        }
    }
}
