//! The claim of the UR5's tool paths at machining accuracy
//! ([`tool_paths`](pvfc_sim::scenario::presets::tool_paths)): the error budget of each run,
//! PVFC beside the timed tracker, against the target of a tenth of a millimetre.

use crate::runs::Runs;
use pvfc_sim::error::{Result, SimError};
use pvfc_sim::scenario::preset_id::{PresetId, ToolPathCase};
use pvfc_sim::trace::path_budget::{path_budget, PathBudget};

/// The target along the surface: mean and largest distance (m), and the least speed along the
/// path (m/s).
pub(crate) const TARGET: (f64, f64, f64) = (1e-4, 3e-4, 0.05);

fn budget(r: &Runs, name: &str) -> Result<PathBudget> {
    let (s, t) = r.named(name)?;
    let system = r.chain_system(s)?;
    path_budget(s, &system.robot, t)?.ok_or_else(|| {
        SimError::Setting(format!(
            "run `{name}` has no Cartesian path or no full pass"
        ))
    })
}

/// The distance along the surface (the 3-D distance for a path that is not planar).
fn surface(b: &PathBudget) -> (f64, f64, f64) {
    let s = b.surface.unwrap_or(b.spread);
    (s.mean, s.p95, s.max)
}

pub(crate) fn tool_path_claims(
    r: &Runs,
    push: &mut impl FnMut(&str, &str, &str, String, bool),
) -> Result<()> {
    let mut ok = true;
    let mut rows = Vec::new();
    for case in ToolPathCase::ALL {
        let id = PresetId::ToolPath(case);
        let (p, t) = (budget(r, &id.name())?, budget(r, &id.timed_name())?);
        let (mean, p95, max) = surface(&p);
        ok &= mean <= TARGET.0 && max <= TARGET.1 && p.speed >= TARGET.2;
        let (tm, tp, tx) = surface(&t);
        let press = p
            .normal
            .filter(|_| case == ToolPathCase::Deburr)
            .map(|n| format!(", press-in {:+.2} mm", n.mean * 1e3))
            .unwrap_or_default();
        rows.push(format!(
            "{}: geometry {}; PVFC mean {:.3} / p95 {:.3} / max {:.3} mm at {:.0} mm/s{press}; timed mean {:.3} / p95 {:.3} / max {:.3} mm",
            case.label(),
            match &p.geometry {
                Some(g) => format!("{} samples ≤ {:.4} mm", g.samples, g.max * 1e3),
                None => "exact (task-space field)".into(),
            },
            mean * 1e3,
            p95 * 1e3,
            max * 1e3,
            p.speed * 1e3,
            tm * 1e3,
            tp * 1e3,
            tx * 1e3,
        ));
    }
    push(
        "toolpath.ur5",
        "The tool on the path at machining accuracy: along the surface, mean ≤ 0.1 mm and max ≤ 0.3 mm at ≥ 50 mm/s",
        "UR5, rounded rectangle 20 × 35 cm sampled until the joint contour is within 10 µm of it; over the steady passes, the tool's distance to the path in the path's plane and the speed along it: free (joint friction, 80 % compensated, sampled 1 kHz) and deburring (passive 1 kHz, box top 0.5 mm above the tool), PVFC (γ = 10) beside a timed tracker (computed torque + PD, 100 rad/s)",
        rows.join("; "),
        ok,
    );
    task_field_claim(r, push)
}

/// The claim of the same tool paths followed with the task-space field: its budget against
/// the target, beside the joint contour's PVFC run and the timed tracker on the same path.
fn task_field_claim(r: &Runs, push: &mut impl FnMut(&str, &str, &str, String, bool)) -> Result<()> {
    let mut ok = true;
    let mut rows = Vec::new();
    for case in ToolPathCase::ALL {
        let task = budget(r, &PresetId::ToolPathTask(case).name())?;
        let joint = budget(r, &PresetId::ToolPath(case).name())?;
        let timed = budget(r, &PresetId::ToolPath(case).timed_name())?;
        let (mean, p95, max) = surface(&task);
        ok &= task.geometry.is_none()
            && mean <= TARGET.0
            && max <= TARGET.1
            && task.speed >= TARGET.2;
        let mm = |b: &PathBudget| {
            let (m, p, x) = surface(b);
            format!("{:.3} / {:.3} / {:.3} mm", m * 1e3, p * 1e3, x * 1e3)
        };
        rows.push(format!(
            "{}: task-space field mean {:.3} / p95 {:.3} / max {:.3} mm at {:.0} mm/s; joint contour {}; timed {}",
            case.label(),
            mean * 1e3,
            p95 * 1e3,
            max * 1e3,
            task.speed * 1e3,
            mm(&joint),
            mm(&timed),
        ));
    }
    push(
        "toolpath.ur5.task",
        "The task-space field holds the tool on the exact path at machining accuracy: along the surface, mean ≤ 0.1 mm and max ≤ 0.3 mm at ≥ 50 mm/s",
        "the runs of toolpath.ur5 with [contour.cartesian.task] (k = 4/s, the tool held pointing down with k_R = 4/s, damping 1 cm): the field follows the exact path (no geometry term), beside the joint contour's PVFC run and the timed tracker on the same path (mean / p95 / max along the surface)",
        rows.join("; "),
        ok,
    );
    Ok(())
}
