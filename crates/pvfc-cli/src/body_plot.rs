//! The figure of a rigid body's run (section IV-B's satellite): the attitude error, `U`, `τ̇`,
//! the energy audit, the body rates, and the path of the body's x axis on the unit sphere against the
//! desired attitude's.

use crate::canvas::{figure, panel, Series, Style};
use pvfc_core::contour::Contour;
use pvfc_core::lie::{LieGroup, So3};
use pvfc_sim::error::Result;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::trace::metrics::attitude_errors;
use pvfc_sim::trace::Trace;
use std::path::Path;

/// Draws the figure of a rigid body's run `t` of scenario `s` into `path` (PNG).
pub fn body_figure(s: &Scenario, t: &Trace, path: &Path) -> Result<()> {
    let contour = s.attitude_contour()?;
    let samples: Vec<usize> = (0..t.len()).step_by((t.len() / 2000).max(1)).collect();
    let series = |label: &str, f: &dyn Fn(usize) -> f64| Series {
        label: label.into(),
        points: samples.iter().map(|&i| (t.t[i], f(i))).collect(),
        style: Style::Line,
    };
    let angle = attitude_errors(t, &contour);
    // The work of the environment (a disturbance torque) is counted when the run has it.
    let audit: Vec<f64> = match &t.contact {
        Some(c) => c.audit_residual(&t.energy),
        None => t.energy.iter().map(|e| e - t.energy[0]).collect(),
    };
    let rates: Vec<Series> = ["ω_x", "ω_y", "ω_z"]
        .iter()
        .enumerate()
        .map(|(j, label)| series(label, &|i| t.v[i][j]))
        .collect();
    // The x axis of an attitude: the first column of its matrix.
    let axis = |r: &So3<f64>| {
        let c = r.matrix().column(0);
        (c.x, c.y, c.z)
    };
    let period = s.period();
    let desired: Vec<(f64, f64, f64)> = (0..=400)
        .map(|k| axis(&contour.sample(period * k as f64 / 400.0).point))
        .collect();
    let body: Vec<(f64, f64, f64)> = samples
        .iter()
        .map(|&i| {
            let q = nalgebra::Vector3::new(t.q[i][0], t.q[i][1], t.q[i][2]);
            axis(&So3::exp(&q))
        })
        .collect();
    let sphere = vec![
        Series {
            label: "x axis of R_d(τ)".into(),
            points: desired.iter().map(|p| (p.0, p.1)).collect(),
            style: Style::Reference,
        },
        Series {
            label: "x axis of the body".into(),
            points: body.iter().map(|p| (p.0, p.1)).collect(),
            style: Style::Line,
        },
    ];
    let title = format!("{}: attitude error", s.name);
    figure(path, 6, |i, a| match i {
        0 => panel(
            a,
            path,
            &title,
            "t [s]",
            "‖log(R_d(τ)ᵀR)‖ [rad]",
            &[series("angle", &|i| angle[i].max(1e-12))],
            true,
        ),
        1 => panel(
            a,
            path,
            "navigation function (eq. 26)",
            "t [s]",
            "U(E)",
            &[series("U", &|i| t.potential[i].max(1e-16))],
            true,
        ),
        2 => panel(
            a,
            path,
            "self-paced contour speed",
            "t [s]",
            "dτ/dt",
            &[series("τ̇", &|i| t.tau_dot[i])],
            false,
        ),
        3 => panel(
            a,
            path,
            "energy audit: κ_a − κ_a(0) − ΣW",
            "t [s]",
            "[J]",
            &[series("residual", &|i| audit[i])],
            false,
        ),
        4 => panel(
            a,
            path,
            "body angular velocity",
            "t [s]",
            "ω [rad/s]",
            &rates,
            false,
        ),
        _ => panel(
            a,
            path,
            "x axis on the unit sphere, top view",
            "x",
            "y",
            &sphere,
            false,
        ),
    })
}
