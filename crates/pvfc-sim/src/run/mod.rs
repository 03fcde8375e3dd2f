//! Running a scenario's system: PVFC in the sampled-data or continuous-time loop, and the
//! timed baseline, for every robot. The paper's SCARA ([`planar`]), any URDF arm ([`chain`])
//! and a rigid body's attitude ([`body`]) differ only in their model and in what they touch;
//! all run through the same loops (`loops`), steppers (`stepper`) and integrator
//! ([`integrate`]).

pub mod body;
pub mod chain;
pub mod integrate;
pub mod link;
pub(crate) mod loops;
pub(crate) mod path_clock;
pub mod planar;
pub(crate) mod stepper;

use crate::error::Result;
use crate::scenario::{BaselineSpec, Scenario, System};
use crate::trace::Trace;

pub use chain::simulate_chain_with;
pub use planar::{environment, simulate_in, simulate_timed_in};

/// Runs the PVFC loop of a scenario (with its contact world, if it has one), its system built
/// from it. `progress` is called with the fraction done.
pub fn simulate(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    simulate_system(s, &System::build(s)?, progress)
}

/// [`simulate`] with the scenario's system already built: the one place a run matches on
/// the kind of robot.
pub fn simulate_system(
    s: &Scenario,
    system: &System,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    match system {
        System::Scara(arm) => planar::simulate_with(s, *arm, progress),
        System::SerialChain(sys) => chain::simulate_chain_with(s, sys, progress),
        System::RigidBody(ctl) => body::simulate_body_with(s, ctl, progress),
    }
}

/// Runs the scenario's plant (its model error, friction and contact) against a drive across
/// a serial line, in lockstep ([`link`]: hardware in the loop); the drive's controller
/// replaces the scenario's. An arm's only (a SCARA or a URDF arm with revolute joints), in the
/// sampled mode. What happened on the line is in `drive`'s report.
pub fn simulate_system_over(
    s: &Scenario,
    system: &System,
    drive: &mut link::LinkDrive<'_>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    match system {
        System::Scara(arm) => planar::simulate_on(s, *arm, Some(drive), progress),
        System::SerialChain(sys) => chain::simulate_chain_on(s, sys, Some(drive), progress),
        System::RigidBody(_) => Err(crate::SimError::Setting(
            "hardware in the loop: the drive reads encoders on an arm's joints; a rigid body has none"
                .into(),
        )),
    }
}

/// The trackers a baseline compares PVFC with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tracker {
    /// The timed trajectory (computed torque + PD on `x_d(τ₀ + rate·t)`).
    Timed,
    /// The timed trajectory on a path clock that slows near the drives' limits.
    SpeedScaling,
}

/// One tracker's run on the scenario's system (the one place a tracker's run matches on
/// the kind of robot).
pub fn simulate_tracker(
    s: &Scenario,
    system: &System,
    b: &BaselineSpec,
    tau_rate: f64,
    tracker: Tracker,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    match system {
        System::Scara(arm) => planar::simulate_tracker(s, *arm, b, tau_rate, tracker, progress),
        System::SerialChain(sys) => chain::simulate_tracker(s, sys, b, tau_rate, tracker, progress),
        System::RigidBody(_) => Err(crate::SimError::Setting(
            "baseline: the timed tracker is for arms; a rigid body runs PVFC alone".into(),
        )),
    }
}

/// The timed-trajectory baseline of Fig. 1 (computed torque + PD tracking `x_d(τ(t))` with
/// `τ(t) = τ₀ + tau_rate·t`) on the scenario's plant and contact world.
pub fn simulate_timed(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    simulate_tracker(s, &System::build(s)?, b, tau_rate, Tracker::Timed, progress)
}

/// Runs one scenario: the PVFC loop, and the timed baseline if the scenario asks for one
/// (at PVFC's mean `τ̇` over its last 12 s unless the scenario fixes the rate), and the
/// speed-scaling tracker after it if the baseline has `[baseline.speed_scaling]`.
pub fn run_scenario(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Vec<Trace>> {
    run_scenario_with(s, &System::build(s)?, progress)
}

/// [`run_scenario`] with the scenario's system already built: a URDF is read and a Cartesian
/// path solved once for every run.
pub fn run_scenario_with(
    s: &Scenario,
    system: &System,
    progress: &mut dyn FnMut(f64),
) -> Result<Vec<Trace>> {
    let pvfc = simulate_system(s, system, progress)?;
    let mut out = vec![];
    if let Some(b) = &s.baseline {
        let rate = match b.tau_rate {
            Some(r) => r,
            None => {
                let n = pvfc.len() - 1;
                let from = pvfc
                    .t
                    .iter()
                    .position(|&t| t >= pvfc.t[n] - 12.0)
                    .unwrap_or(0);
                (pvfc.tau[n] - pvfc.tau[from]) / (pvfc.t[n] - pvfc.t[from]).max(f64::EPSILON)
            }
        };
        out.push(simulate_tracker(
            s,
            system,
            b,
            rate,
            Tracker::Timed,
            &mut |_| {},
        )?);
        if b.speed_scaling.is_some() {
            out.push(simulate_tracker(
                s,
                system,
                b,
                rate,
                Tracker::SpeedScaling,
                &mut |_| {},
            )?);
        }
    }
    out.insert(0, pvfc);
    Ok(out)
}
