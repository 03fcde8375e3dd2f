//! The figure of a URDF arm's run: joint errors, `U`, `τ̇`, `κ_a`, and the tool's path in 3-D
//! projected on two planes, against the desired contour's.

use crate::canvas::{figure, panel, Series, Style};
use pvfc_sim::error::Result;
use pvfc_sim::scenario::ArmSystem;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::trace::Trace;
use std::path::Path;

/// Up to 2,000 samples of `f` over a trace's time.
fn thinned(t: &Trace, label: &str, f: &dyn Fn(usize) -> f64) -> Series {
    let every = (t.len() / 2000).max(1);
    Series {
        label: label.into(),
        points: (0..t.len())
            .step_by(every)
            .map(|i| (t.t[i], f(i)))
            .collect(),
        style: Style::Line,
    }
}

/// Draws the figure of a URDF arm's run `t` of scenario `s` (its system built) into `path`
/// (PNG), with the timed baseline's run beside it in the contact and path-error panels when
/// given.
pub fn chain_figure(
    s: &Scenario,
    system: &ArmSystem,
    t: &Trace,
    baseline: Option<&Trace>,
    path: &Path,
) -> Result<()> {
    let robot = &system.robot;
    let ctl = &system.controller;
    let n = t.len();
    let every = (n / 2000).max(1);
    let samples: Vec<usize> = (0..n).step_by(every).collect();
    let series = |label: String, f: &dyn Fn(usize) -> f64| Series {
        label,
        points: samples.iter().map(|&i| (t.t[i], f(i))).collect(),
        style: Style::Line,
    };
    let dof = t.q.dof();
    let desired: Vec<Vec<f64>> = samples
        .iter()
        .map(|&i| ctl.contour_point(t.tau[i]))
        .collect();
    let errors: Vec<Series> = (0..dof)
        .map(|j| Series {
            label: format!("q{} − x_d{}", j + 1, j + 1),
            points: samples
                .iter()
                .zip(&desired)
                .map(|(&i, xd)| (t.t[i], t.q[i][j] - xd[j]))
                .collect(),
            style: Style::Line,
        })
        .collect();
    // The tool's path, and the desired contour's image under forward kinematics.
    let tool = |q: &[f64]| robot.tool_pose(q).map(|(_, p)| p);
    let actual = samples
        .iter()
        .map(|&i| tool(&t.q[i]))
        .collect::<Result<Vec<_>>>()?;
    let period = s.period();
    let reference = (0..=400)
        .map(|k| tool(&ctl.contour_point(period * k as f64 / 400.0)))
        .collect::<Result<Vec<_>>>()?;
    // A Cartesian tool path: the path itself, and the tool's distance to it (mm).
    let (path_points, distance) = match s.contour.cartesian() {
        Some(c) => {
            let d = c.distances(&s.base_dir, &actual)?;
            let pts = samples
                .iter()
                .zip(&d)
                .map(|(&i, d)| (t.t[i], (d * 1e3).max(1e-3)))
                .collect();
            (c.path(&s.base_dir)?.sample(512), Some(pts))
        }
        None => (Vec::new(), None),
    };
    let projection = |a: usize, b: usize, label: &str| {
        let mut v = vec![Series {
            label: "x_d(τ)".into(),
            points: reference.iter().map(|p| (p[a], p[b])).collect(),
            style: Style::Reference,
        }];
        if !path_points.is_empty() {
            v.push(Series {
                label: "Cartesian path".into(),
                points: path_points.iter().map(|p| (p[a], p[b])).collect(),
                style: Style::Reference,
            });
        }
        v.push(Series {
            label: label.into(),
            points: actual.iter().map(|p| (p[a], p[b])).collect(),
            style: Style::Line,
        });
        v
    };
    let title = format!("{} ({} joints)", s.name, dof);
    // With 3-D contact: the normal force and the energy audit's residual, PVFC's and the
    // timed baseline's.
    let contact = t.contact.as_ref().map(|c| {
        let audit = c.audit_residual(&t.energy);
        let mut force = vec![thinned(t, "PVFC", &|i| c.normal_force[i])];
        let mut residual = vec![thinned(t, "PVFC", &|i| audit[i])];
        if let Some((b, bc)) = baseline.and_then(|b| b.contact.as_ref().map(|c| (b, c))) {
            let audit = bc.audit_residual(&b.energy);
            force.push(thinned(b, "timed tracker", &|i| bc.normal_force[i]));
            residual.push(thinned(b, "timed tracker", &|i| audit[i]));
        }
        (force, residual)
    });
    let panels = 6 + usize::from(distance.is_some()) + 2 * usize::from(contact.is_some());
    let extra = |i: usize| i - 6 - usize::from(distance.is_some());
    figure(path, panels, |i, a| match i {
        0 => panel(
            a,
            path,
            &format!("{title}: joint errors"),
            "t [s]",
            "q − x_d(τ) [rad, m]",
            &errors,
            false,
        ),
        1 => panel(
            a,
            path,
            "navigation function",
            "t [s]",
            "U(E)",
            &[series("U".into(), &|i| t.potential[i])],
            true,
        ),
        2 => panel(
            a,
            path,
            "self-paced contour speed",
            "t [s]",
            "dτ/dt",
            &[series("τ̇".into(), &|i| t.tau_dot[i])],
            false,
        ),
        3 => panel(
            a,
            path,
            "augmented kinetic energy",
            "t [s]",
            "κ_a [J]",
            &[series("κ_a".into(), &|i| t.energy[i])],
            false,
        ),
        4 => panel(
            a,
            path,
            "tool path, top view",
            "x [m]",
            "y [m]",
            &projection(0, 1, "tool"),
            false,
        ),
        5 => panel(
            a,
            path,
            "tool path, side view",
            "x [m]",
            "z [m]",
            &projection(0, 2, "tool"),
            false,
        ),
        _ if i >= 6 + usize::from(distance.is_some()) => {
            let empty = (Vec::new(), Vec::new());
            let (force, audit) = contact.as_ref().unwrap_or(&empty);
            if extra(i) == 0 {
                panel(
                    a,
                    path,
                    "contact",
                    "t [s]",
                    "normal force [N]",
                    force,
                    false,
                )
            } else {
                panel(
                    a,
                    path,
                    "energy audit: κ_a − κ_a(0) − ΣW",
                    "t [s]",
                    "[J]",
                    audit,
                    false,
                )
            }
        }
        _ => panel(
            a,
            path,
            "distance of the tool to the Cartesian path",
            "t [s]",
            "[mm]",
            &[Series {
                label: "distance".into(),
                points: distance.clone().unwrap_or_default(),
                style: Style::Line,
            }],
            true,
        ),
    })
}
