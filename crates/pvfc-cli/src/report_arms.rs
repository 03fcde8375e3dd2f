//! The claims of the 3-D contact scenarios of a URDF arm
//! ([`arms_3d`](pvfc_sim::scenario::presets::arms_3d)): a UR5 pressing its tool into a box's top, at a wall it cannot
//! pass and pushed on the forearm, each beside the timed tracker; the audit, the passivity
//! margins, the forces and the Cartesian path error in millimetres.

use crate::runs::Runs;
use pvfc_sim::error::{Result, SimError};
use pvfc_sim::scenario::preset_id::{Arm3dCase, PresetId};
use pvfc_sim::trace::metrics::ContactSummary;
use pvfc_sim::trace::path_budget::path_budget;

/// The PVFC runs: the three scenarios (the passive digital controller at 1 kHz) and the
/// press run in continuous time.
const PVFC_RUNS: [Arm3dCase; 4] = [
    Arm3dCase::Press,
    Arm3dCase::Wall,
    Arm3dCase::Push,
    Arm3dCase::PressContinuous,
];

fn pair(r: &Runs, case: Arm3dCase) -> Result<(ContactSummary, ContactSummary)> {
    let id = PresetId::Arm3d(case);
    Ok((r.summary(id)?, r.timed_summary(id)?))
}

pub(crate) fn arm_claims(
    r: &Runs,
    push: &mut impl FnMut(&str, &str, &str, String, bool),
) -> Result<()> {
    let mut ok = true;
    let mut rows = Vec::new();
    for case in PVFC_RUNS {
        let c = r.summary(PresetId::Arm3d(case))?;
        ok &= c.audit <= 1e-6;
        rows.push(format!("{}: {:.1e}", case.label(), c.audit));
    }
    let mut worst_timed = 0.0f64;
    for case in Arm3dCase::FILES {
        let c = r.timed_summary(PresetId::Arm3d(case))?;
        ok &= c.audit <= 1e-6;
        worst_timed = worst_timed.max(c.audit);
    }
    push(
        "arm3d.audit",
        "A 6-joint arm in 3-D contact: κ_a(t) − κ_a(0) − W_contact − W_friction − W_gravity − W_add-ons stays within 1e-6 of κ_a(0), in continuous time and at every sample of the passive digital controller",
        "max over t of |residual| / κ_a(0): UR5 (URDF), gravity and its compensation, Rapier's 3-D contact queries, plant RK4 at 10 kHz; the timed trackers as a check of the bookkeeping",
        format!("{} (timed trackers: at most {worst_timed:.1e})", rows.join(", ")),
        ok,
    );
    let mut ok = true;
    let mut rows = Vec::new();
    for case in PVFC_RUNS {
        let c = r.summary(PresetId::Arm3d(case))?;
        let e0 = c.energy_scale;
        ok &= c.passivity_margin >= -1e-6 * e0 && c.energy_bound_margin >= -1e-6 * e0;
        rows.push(format!(
            "{}: pumped {:.2} J of κ_a(0) = {:.0} J, margins {:.2} J and {:+.1e} J",
            case.label(),
            c.energy_pumped,
            e0,
            c.passivity_margin,
            c.energy_bound_margin
        ));
    }
    push(
        "arm3d.passivity",
        "Passivity in 3-D contact (eqs. 1, 9): −∫F_eᵀq̇ ≤ κ_a(0) + W_add-ons and κ_a(t) ≤ κ_a(0) + ∫F_eᵀq̇ + W_add-ons at all times",
        "min over t of both margins (≥ −1e-6 κ_a(0) counts as ≥ 0), every PVFC run of the UR5",
        rows.join("; "),
        ok,
    );
    let mut ok = true;
    let mut rows = Vec::new();
    for case in [Arm3dCase::Press, Arm3dCase::Wall] {
        let (p, t) = pair(r, case)?;
        ok &= t.peak_force > p.peak_force && t.energy_pumped > p.energy_pumped;
        rows.push(format!(
            "{}: PVFC {:.1} N / {:.2} J, timed {:.1} N / {:.2} J",
            case.label(),
            p.peak_force,
            p.energy_pumped,
            t.peak_force,
            t.energy_pumped
        ));
    }
    push(
        "arm3d.baseline",
        "On the workpiece and at a wall it cannot pass, a timed tracker pushes harder and pumps more energy into the world than PVFC",
        "peak contact force and most energy pumped into the contact, PVFC (passive, 1 kHz) vs computed torque + PD + g(q) (kp = 400, kd = 40) at PVFC's mean τ̇",
        rows.join("; "),
        ok,
    );
    let (p, t) = pair(r, Arm3dCase::Push)?;
    push(
        "arm3d.push",
        "A push on the forearm (a moving obstacle): how hard each controller resists",
        "peak contact force, work of the environment on the arm, and PVFC's final β (information, not a pass/fail: PVFC stores the push's energy in the flywheel and resists more than the stiff tracker)",
        format!(
            "PVFC {:.0} N, W_contact {:+.2} J, final β {:.3}; timed {:.0} N, W_contact {:+.2} J",
            p.peak_force,
            p.work_contact,
            r.trace(PresetId::Arm3d(Arm3dCase::Push))?.beta.last().copied().unwrap_or(f64::NAN),
            t.peak_force,
            t.work_contact
        ),
        true,
    );
    let mut rows = Vec::new();
    let press = PresetId::Arm3d(Arm3dCase::Press);
    for name in [press.name(), press.timed_name()] {
        let (s, t) = r.named(&name)?;
        let system = r.chain_system(s)?;
        let b = path_budget(s, &system.robot, t)?.ok_or_else(|| {
            SimError::Setting(format!(
                "run `{name}` has no Cartesian path or no full pass"
            ))
        })?;
        let (surface, normal) = match (b.surface, b.normal) {
            (Some(s), Some(n)) => (s, n),
            _ => {
                return Err(SimError::Setting(format!(
                    "run `{name}`: the pressed path is not planar"
                )))
            }
        };
        let who = if t.is_timed() { "timed" } else { "PVFC" };
        if rows.is_empty() {
            rows.push(match &b.geometry {
                Some(g) => format!(
                    "geometry: {} samples, contour ≤ {:.3} mm from the path",
                    g.samples,
                    g.max * 1e3
                ),
                None => "geometry: the exact path (task-space field)".into(),
            });
        }
        rows.push(format!(
            "{who}: along the surface mean {:.2} / p95 {:.2} / max {:.2} mm, press-in {:+.2} mm, 3-D max {:.2} mm, {:.0} mm/s",
            surface.mean * 1e3,
            surface.p95 * 1e3,
            surface.max * 1e3,
            normal.mean * 1e3,
            b.spread.max * 1e3,
            b.speed * 1e3
        ));
    }
    push(
        "arm3d.cartesian",
        "Pressing 3 mm into a workpiece: the tool path's error budget, in the user's units (the deburring at machining accuracy is toolpath.ur5's)",
        "the joint contour's own distance to the path (geometry); over the steady passes, the tool's distance to the path along the workpiece's surface (mean, 95th percentile, max), its mean offset normal to the surface (the press-in the contact force asks for, not an error), the 3-D distance and the speed along the path (information, not a pass/fail)",
        rows.join("; "),
        true,
    );
    Ok(())
}
