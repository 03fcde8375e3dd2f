//! The sampled-data loop with the passive digital controller (`pvfc_core::passive`): the
//! controller at its rate with zero-order hold, the plant (and its contact) integrated with
//! RK4 in substeps, and what a drive does between them: encoder quantisation, position-only
//! measurement, torque limits. The trace's energy column is `κ_a = ½q̇ᵀMq̇ + S` with `S` the
//! controller's storage, and its controller-work column the add-ons' energy as the controller
//! accounts it, so the audit residual is the plant integrator's error alone.

use crate::contact::{Environment, PlanarArm};
use crate::error::Result;
use crate::scenario::{joint_vector, Scenario};
use crate::simulate::{plant_rk4, timing, ContactTrace, Row, Trace, Work};
use pvfc_core::prelude::*;

/// Runs a scenario with `[controller.passive]` against `env` (the contact columns are always
/// filled: with no contact they carry the audit's work columns).
pub(crate) fn simulate_passive<E: Environment + ?Sized>(
    s: &Scenario,
    env: &mut E,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let Some(mut ctl) = s.passive_controller()? else {
        return Err(crate::error::SimError::Setting(
            "simulate_passive: the scenario has no [controller.passive]".into(),
        ));
    };
    let spec = s.controller.passive.clone().unwrap_or_default();
    let arm = Scara::new(s.arm()?)?;
    let kin = PlanarArm::from(&s.arm()?);
    let friction = s.plant.friction.clone();
    let (dt, h, n) = timing(s)?;
    let period = s.contour.period;
    let schedule = s.contact.as_ref().and_then(|c| c.force_schedule);
    let r0 = s.controller.nominal_speed.map(|n| n.r);
    let mut q = Torus::new(joint_vector::<2>(&s.initial.q, "initial.q")?);
    let mut v = joint_vector::<2>(&s.initial.v, "initial.v")?;
    let mut trace = Trace::with_capacity(s.name.clone(), 2, n + 1);
    let mut contact = ContactTrace::with_capacity(n + 1);
    let mut work = Work::default();
    for k in 0..=n {
        let t = k as f64 * dt;
        let cf = env.contact(t, &q, &v)?;
        if let (Some(sch), Some(r0)) = (schedule, r0) {
            if let Some(ns) = ctl.controller_mut().nominal_speed_mut() {
                ns.set_speed(sch.speed(r0, cf.normal_force))?;
            }
        }
        let measured = Torus::new(q.angles().map(|x| spec.measure(x)));
        let velocity = (!spec.positions_only).then_some(&v);
        let out = ctl.step(&measured, velocity, None, dt)?;
        // The addons' energy of the period that ended at this sample.
        work.0[2] += out.energy.add_ons;
        let st = out.state;
        trace.push(Row {
            t,
            q: q.angles().as_slice(),
            v: v.as_slice(),
            tau: st.unwrapped_tau(Some(period)),
            tau_dot: st.tau_dot,
            flywheel_speed: st.flywheel_speed,
            beta: out.diagnostics.beta,
            potential: out.diagnostics.potential,
            lambda1: out.diagnostics.lambda1,
            lambda2: out.diagnostics.lambda2,
            torque: out.torque.as_slice(),
            energy: arm.kinetic_energy(&q, &v) + out.energy.storage,
            friction_power: friction.torque(&v).dot(&v),
        });
        let r = ctl
            .controller_mut()
            .nominal_speed_mut()
            .map_or(0.0, |n| n.speed());
        contact.push(&cf, kin.tip(&q), &work, r);
        if k == n {
            break;
        }
        for j in 0..s.simulation.plant_substeps {
            let t0 = t + j as f64 * h;
            let mut p = [[0.0; 3]; 4];
            (q, v) = plant_rk4(&arm, &q, &v, h, |i, c, q, v| {
                let ff = friction.torque(v);
                let fc = if i == 0 && j == 0 {
                    cf.torque
                } else {
                    env.contact(t0 + c, q, v)?.torque
                };
                p[i] = [fc.dot(v), ff.dot(v), 0.0];
                Ok(out.torque + ff + fc)
            })?;
            work.add(h, &p);
        }
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    trace.contact = Some(contact);
    progress(1.0);
    Ok(trace)
}
