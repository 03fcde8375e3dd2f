//! Running a scenario's system: PVFC in the sampled-data or continuous-time loop, and the
//! timed baseline, for every robot. The paper's SCARA ([`planar`]), any URDF arm ([`chain`])
//! and a rigid body's attitude ([`body`]) differ only in their model and in what they touch;
//! all run through the same loops (`loops`), steppers (`stepper`) and integrator
//! ([`integrate`]).

pub mod body;
pub mod chain;
pub mod integrate;
pub(crate) mod loops;
pub(crate) mod path_clock;
pub mod planar;
pub(crate) mod stepper;

use crate::error::Result;
use crate::scenario::{ArmSystem, BaselineSpec, Scenario};
use crate::trace::Trace;

pub use chain::{
    simulate_chain, simulate_chain_with, simulate_scaled_chain_with, simulate_timed_chain,
    simulate_timed_chain_with,
};
pub use planar::{environment, simulate_in, simulate_scaled, simulate_timed_in};

/// Runs the PVFC loop of a scenario (with its contact world, if it has one): the SCARA's or a
/// URDF arm's. `progress` is called with the fraction done.
pub fn simulate(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    if s.is_body() {
        body::simulate_body(s, progress)
    } else if s.is_chain() {
        chain::simulate_chain(s, progress)
    } else {
        planar::simulate(s, progress)
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
    if s.is_body() {
        Err(crate::SimError::Setting(
            "baseline: the timed tracker is for arms; a rigid body runs PVFC alone".into(),
        ))
    } else if s.is_chain() {
        chain::simulate_timed_chain(s, b, tau_rate, progress)
    } else {
        planar::simulate_timed(s, b, tau_rate, progress)
    }
}

/// Runs one scenario: the PVFC loop, and the timed baseline if the scenario asks for one
/// (at PVFC's mean `τ̇` over its last 12 s unless the scenario fixes the rate), and the
/// speed-scaling tracker after it if the baseline has `[baseline.speed_scaling]`.
pub fn run_scenario(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Vec<Trace>> {
    let system = if s.is_chain() {
        Some(ArmSystem::build(s)?)
    } else {
        None
    };
    run_scenario_with(s, system.as_ref(), progress)
}

/// [`run_scenario`] with a URDF arm's system already built (`None` for the SCARA): the URDF
/// is read and a Cartesian path solved once for both runs.
pub fn run_scenario_with(
    s: &Scenario,
    system: Option<&ArmSystem>,
    progress: &mut dyn FnMut(f64),
) -> Result<Vec<Trace>> {
    let pvfc = match system {
        Some(sys) => chain::simulate_chain_with(s, sys, progress)?,
        None => simulate(s, progress)?,
    };
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
        out.push(match system {
            Some(sys) => chain::simulate_timed_chain_with(s, sys, b, rate, &mut |_| {})?,
            None => simulate_timed(s, b, rate, &mut |_| {})?,
        });
        if b.speed_scaling.is_some() {
            out.push(match system {
                Some(sys) => chain::simulate_scaled_chain_with(s, sys, b, rate, &mut |_| {})?,
                None => planar::simulate_scaled(s, b, rate, &mut |_| {})?,
            });
        }
    }
    out.insert(0, pvfc);
    Ok(out)
}
