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
    let system = r
        .arm_system(s)?
        .ok_or_else(|| SimError::Setting(format!("run `{name}` is not a URDF arm's")))?;
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
    Ok(())
}
