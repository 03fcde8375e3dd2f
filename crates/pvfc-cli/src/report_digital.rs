//! The claims of the digital controller (`pvfc_core::passive`, the `digital_*` presets):
//! `Controller::step` with zero-order hold against the passive controller, at 1 kHz, 250 Hz
//! and 100 Hz, in free motion and at the wall, the push and the obstacle; the passive
//! controller on a drive (torque limits, encoders, positions only); tracking on Fig. 8.

use crate::runs::Runs;
use pvfc_sim::error::Result;
use pvfc_sim::scenario::preset_id::{Digital, DigitalCase, PresetId, DIGITAL_RATES};
use pvfc_sim::trace::metrics::energy_drift;

/// A digital comparison's run.
fn run(case: DigitalCase, rate: u32, controller: Digital) -> PresetId {
    PresetId::Digital {
        case,
        rate,
        controller,
    }
}

/// The audit of a run relative to `κ_a(0)`: the residual of the contact columns, or, for a
/// free frictionless run without add-ons (the ZOH's free runs have no work columns), the
/// drift of `κ_a`.
fn audit(r: &Runs, id: PresetId) -> Result<f64> {
    let t = r.trace(id)?;
    Ok(match t.contact {
        Some(_) => r.summary(id)?.audit,
        None => energy_drift(t),
    })
}

/// The largest energy the controller created, `max_t (κ_a(t) − κ_a(0) − ΣW)` (J; ≤ 0 when it
/// created none), and the run's `κ_a(0)`.
fn created(r: &Runs, id: PresetId) -> Result<(f64, f64)> {
    let t = r.trace(id)?;
    let e0 = t.energy[0];
    let worst = match &t.contact {
        Some(c) => c
            .audit_residual(&t.energy)
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max),
        None => t
            .energy
            .iter()
            .map(|e| e - e0)
            .fold(f64::NEG_INFINITY, f64::max),
    };
    Ok((worst, e0))
}

pub(crate) fn digital_claims(
    r: &Runs,
    push: &mut impl FnMut(&str, &str, &str, String, bool),
) -> Result<()> {
    let mut ok = true;
    let mut rows = Vec::new();
    for case in DigitalCase::ALL {
        for rate in DIGITAL_RATES {
            let (p, z) = (
                audit(r, run(case, rate, Digital::Passive))?,
                audit(r, run(case, rate, Digital::Zoh))?,
            );
            ok &= p <= 1e-8;
            let case = case.label();
            rows.push(format!("{case} {rate} Hz: passive {p:.1e}, ZOH {z:.1e}"));
        }
    }
    push(
        "digital.audit",
        "The passive digital controller's energy audit closes at every sample, for any sampling period: κ_a(t_k) − κ_a(0) − W_env − W_friction − W_add-ons within 1e-8 of κ_a(0)",
        "max over the samples of |residual| / κ_a(0), κ_a = ½q̇ᵀMq̇ + the controller's storage; plant and contact RK4 at 20 kHz; the ZOH controller (Controller::step) beside it",
        rows.join("; "),
        ok,
    );
    let mut ok = true;
    let mut rows = Vec::new();
    for case in [DigitalCase::Wall, DigitalCase::Push, DigitalCase::Obstacle] {
        for rate in DIGITAL_RATES {
            let (p, z) = (
                r.summary(run(case, rate, Digital::Passive))?,
                r.summary(run(case, rate, Digital::Zoh))?,
            );
            let case = case.label();
            let e0 = p.energy_scale;
            ok &= p.passivity_margin >= -1e-8 * e0 && p.energy_bound_margin >= -1e-8 * e0;
            rows.push(format!(
                "{case} {rate} Hz: passive {:+.2e} J, ZOH {:+.3} J",
                p.energy_bound_margin, z.energy_bound_margin
            ));
        }
    }
    push(
        "digital.passivity",
        "The passive digital controller never gives the robot more than it has: the margin min_t (κ_a(0) + W_env + W_add-ons − κ_a(t)) is ≥ 0 (contact_wall_sampled's ZOH controller: −0.32 J)",
        "the energy-bound margin of every contact run, passive and ZOH, at 1 kHz, 250 Hz and 100 Hz (≥ −1e-8 κ_a(0) counts as ≥ 0: the plant integrator's error)",
        rows.join("; "),
        ok,
    );
    let drive = PresetId::DigitalDrive;
    let ideal_drive = run(DigitalCase::Wall, 1000, Digital::Passive);
    let (s, t) = r.run(drive)?;
    let spec = s.controller.passive.clone().unwrap_or_default();
    let delta = spec
        .encoder_counts
        .map_or(0.0, |c| std::f64::consts::TAU / c);
    let max_u1 = t
        .torque
        .iter()
        .map(|u| u.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let limit_hits = t
        .torque
        .iter()
        .filter(|u| u.iter().zip(&spec.torque_limit).any(|(x, l)| x.abs() >= *l))
        .count();
    let bound = delta * max_u1;
    let (made, e0) = created(r, drive)?;
    let ideal = r.summary(ideal_drive)?;
    let d = r.summary(drive)?;
    let (u_drive, u_ideal) = (r.mean_u(drive)?, r.mean_u(ideal_drive)?);
    push(
        "digital.drive",
        "On a drive (torque limits well below what the law asks at the wall, encoders of 2^17 counts per turn, positions only) the passive controller still creates no energy beyond the encoders' bounded rounding term",
        "wall at 1 kHz: max_t (κ_a(t) − κ_a(0) − ΣW) against δ·max|u|₁ (δ = 2π/2^17); samples at a torque limit; tracking (mean U over the last pass) against the same controller without the drive's limits",
        format!(
            "energy created at most {made:+.2e} J (bound {bound:.1e} J; κ_a(0) = {e0:.0} J), margin {:+.3} J; {limit_hits} of {} samples at a limit; peak force {:.0} N (ideal drive {:.0} N); mean U {u_drive:.3e} (ideal drive {u_ideal:.3e})",
            d.energy_bound_margin,
            t.len(),
            d.peak_force,
            ideal.peak_force
        ),
        made <= bound + 1e-8 * e0 && d.energy_bound_margin >= -bound - 1e-8 * e0,
    );
    let (p, c) = (
        r.mean_u(PresetId::Fig8Passive)?,
        r.mean_u(PresetId::Fig8Continuous)?,
    );
    push(
        "digital.tracking",
        "At 1 kHz the passive controller tracks as the continuous-time controller does: mean U over a pass of Fig. 8 within 10 %",
        "mean U over the last pass, Fig. 8 (R = 100, friction, compensation, r = 1), passive controller at 1 kHz vs the continuous loop (RK4 at 1 kHz)",
        format!("passive {p:.4e}, continuous {c:.4e} ({:+.2} %)", 100.0 * (p / c - 1.0)),
        (p / c - 1.0).abs() <= 0.1,
    );
    Ok(())
}
