//! Running a scenario of a serial arm read from a URDF (`[plant] urdf = …`): the sampled-data
//! or continuous PVFC loop for any number of joints (1 to 8), with gravity in the plant,
//! joint friction, and the controller's gravity and friction compensation.

use crate::arm::{arm_controller, ArmControllerN, ArmSettings};
use crate::error::{Result, SimError};
use crate::integrate::ClosedLoop;
use crate::scenario::{joint_vector, Mode, Scenario};
use crate::simulate::{plant_rk4, timing, Row, Trace};
use crate::stepper::{PassiveDrive, Stepper};
use crate::with_dof;
use nalgebra::SVector;
use pvfc_core::augmented::AugmentedState;
use pvfc_core::prelude::*;

/// Runs the PVFC loop of a URDF arm's scenario. `progress` is called with the fraction done.
pub fn simulate_chain(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    // The model as `Scenario::robot` built it (with the scenario's gravity).
    let robot = s.robot()?;
    let settings = s.arm_settings()?;
    with_dof!(robot.dof(), N => {
        let chain = SerialChain::<f64, N>::try_from(robot.model())?;
        run::<N>(s, chain, &settings, progress)
    }, otherwise Err(SimError::Setting(format!(
        "robot {}: {} joints; pvfc supports 1 to 8", robot.description().name, robot.dof()
    ))))
}

fn run<const N: usize>(
    s: &Scenario,
    chain: SerialChain<f64, N>,
    settings: &ArmSettings,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let base: ArmControllerN<N> = arm_controller(chain, settings)?;
    let flywheel = *base.law().flywheel();
    let ctl = base.with_state(InternalState {
        tau: s.initial.tau,
        tau_dot: s.initial.tau_dot,
        flywheel_speed: s
            .initial
            .flywheel_speed
            .unwrap_or_else(|| flywheel.speed_for_unit_beta()),
        laps: 0,
    });
    let friction = s.plant.friction.clone();
    let (dt, h, n) = timing(s)?;
    let kinds = chain.kinds();
    let q = JointSpace::new(joint_vector::<N>(&s.initial.q, "initial.q")?, kinds);
    let v = joint_vector::<N>(&s.initial.v, "initial.v")?;
    let mut trace = Trace::with_capacity(s.name.clone(), N, n + 1);
    match s.simulation.mode {
        Mode::Sampled => match &s.controller.passive {
            None => sampled(s, &chain, ctl, q, v, &mut trace, progress)?,
            Some(spec) => {
                let circular = kinds.map(|k| k == JointKind::Circular);
                let drive = PassiveDrive::new(ctl, spec, circular)?;
                sampled(s, &chain, drive, q, v, &mut trace, progress)?
            }
        },
        Mode::Continuous => {
            let sys = ClosedLoop::matched(ctl);
            let i = *sys.controller.state();
            let mut st = AugmentedState {
                q,
                v,
                tau: i.tau,
                tau_dot: i.tau_dot,
                flywheel_speed: i.flywheel_speed,
            };
            for k in 0..=n {
                let t = k as f64 * dt;
                let (torque, c) = sys.controller.evaluate(&st)?;
                trace.push(Row {
                    t,
                    q: st.q.coords().as_slice(),
                    v: st.v.as_slice(),
                    tau: st.tau,
                    tau_dot: st.tau_dot,
                    flywheel_speed: st.flywheel_speed,
                    beta: c.beta,
                    potential: c.field.potential,
                    lambda1: c.field.lambda1,
                    lambda2: c.field.lambda2,
                    torque: torque.robot.as_slice(),
                    energy: sys.kinetic_energy(&st),
                    friction_power: friction.torque(&st.v).dot(&st.v),
                });
                if k == n {
                    break;
                }
                for _ in 0..s.simulation.plant_substeps {
                    st = sys.rk4_step_with(&st, h, |x| friction.torque(&x.v))?;
                }
                if k % 1000 == 0 {
                    progress(k as f64 / n as f64);
                }
            }
        }
    }
    progress(1.0);
    Ok(trace)
}

/// The sampled-data loop of a chain: the controller (`Controller::step` or the passive one) at
/// its rate with zero-order hold, the plant (with gravity and friction) in RK4 substeps.
fn sampled<const N: usize, S: Stepper<JointSpace<f64, N>, N>>(
    s: &Scenario,
    chain: &SerialChain<f64, N>,
    mut ctl: S,
    mut q: JointSpace<f64, N>,
    mut v: SVector<f64, N>,
    trace: &mut Trace,
    progress: &mut dyn FnMut(f64),
) -> Result<()> {
    let friction = s.plant.friction.clone();
    let (dt, h, n) = timing(s)?;
    let period = s.period();
    for k in 0..=n {
        let t = k as f64 * dt;
        let out = ctl.sample(&q, &v, dt)?;
        trace.push(Row::of_sample(
            t,
            (q.coords().as_slice(), v.as_slice()),
            &out,
            period,
            chain.kinetic_energy(&q, &v),
            friction.torque(&v).dot(&v),
        ));
        if k == n {
            break;
        }
        for _ in 0..s.simulation.plant_substeps {
            (q, v) = plant_rk4(chain, &q, &v, h, |_, _, _, v| {
                Ok(out.torque + friction.torque(v))
            })?;
        }
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    Ok(())
}
