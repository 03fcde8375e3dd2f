//! The digital controller's figure (`digital_passivity.png`): `Controller::step` with
//! zero-order hold against the passive controller (`pvfc_core::passive`) at 1 kHz and 100 Hz,
//! at the wall, the push and the obstacle: the audit residual (the energy the controller
//! created or destroyed) and the passivity margin against time.

use crate::canvas::{figure, panel, Series, Style};
use crate::runs::Runs;
use pvfc_sim::error::Result;
use pvfc_sim::scenario::preset_id::{Digital, DigitalCase, PresetId};
use pvfc_sim::trace::Trace;
use std::path::{Path, PathBuf};

/// `(t, residual)` of a run with work columns, relative to `κ_a(0)` and as an absolute
/// value floored for a log scale.
fn residual(t: &Trace) -> Vec<(f64, f64)> {
    let e0 = t.energy[0];
    match &t.contact {
        Some(c) => {
            t.t.iter()
                .zip(c.audit_residual(&t.energy))
                .map(|(x, r)| (*x, (r.abs() / e0).max(1e-16)))
                .collect()
        }
        None => Vec::new(),
    }
}

/// `(t, κ_a(0) + W_env + W_add-ons − κ_a(t))` (J): ≥ 0 while the controller has not given the
/// robot more than it had.
fn margin(t: &Trace) -> Vec<(f64, f64)> {
    let e0 = t.energy[0];
    match &t.contact {
        Some(c) => (0..t.len())
            .map(|i| {
                (
                    t.t[i],
                    e0 + c.work_contact[i] + c.work_controller[i] + c.work_friction[i]
                        - t.energy[i],
                )
            })
            .collect(),
        None => Vec::new(),
    }
}

/// Draws `digital_passivity.png` into `dir`.
pub fn digital_figure(runs: &Runs, dir: &Path) -> Result<PathBuf> {
    let p = dir.join("digital_passivity.png");
    let label = |rate: u32, kind: Digital| {
        format!(
            "{} {}",
            if kind == Digital::Zoh {
                "ZOH"
            } else {
                "passive"
            },
            if rate == 1000 { "1 kHz" } else { "100 Hz" }
        )
    };
    let run = |case, rate, controller| {
        runs.trace(PresetId::Digital {
            case,
            rate,
            controller,
        })
    };
    let mut panels = Vec::new();
    for case in [DigitalCase::Wall, DigitalCase::Push, DigitalCase::Obstacle] {
        let mut series = Vec::new();
        for kind in [Digital::Zoh, Digital::Passive] {
            for rate in [1000u32, 100] {
                let t = run(case, rate, kind)?;
                series.push(Series {
                    label: label(rate, kind),
                    points: residual(t),
                    style: Style::Line,
                });
            }
        }
        panels.push((case.label(), series));
    }
    let mut margins = Vec::new();
    for kind in [Digital::Zoh, Digital::Passive] {
        for rate in [1000u32, 100] {
            let t = run(DigitalCase::Wall, rate, kind)?;
            margins.push(Series {
                label: label(rate, kind),
                points: margin(t),
                style: Style::Line,
            });
        }
    }
    figure(&p, 4, |i, a| {
        if let Some((case, series)) = panels.get(i) {
            panel(
                a,
                &p,
                &format!("{case}: energy created or lost, |κ_a(t) − κ_a(0) − ΣW| / κ_a(0)"),
                "t [s]",
                "relative",
                series,
                true,
            )
        } else {
            panel(
                a,
                &p,
                "wall: passivity margin κ_a(0) + ΣW − κ_a(t) (< 0: energy created)",
                "t [s]",
                "[J]",
                &margins,
                false,
            )
        }
    })?;
    Ok(p)
}
