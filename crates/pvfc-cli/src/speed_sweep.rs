//! Fig. 1 as the paper means it: both controllers on drives that saturate, over a sweep of the
//! demanded speed ([`fig1_saturated`](pvfc_sim::scenario::presets::fig1_saturated)). For each
//! run, the mean speed it made along the contour and its distance to the contour; the claim
//! `fig1.saturated` and the figure `fig1_saturated.png` (speed against accuracy).

use crate::canvas::{figure, panel, Series};
use crate::runs::Runs;
use pvfc_sim::error::Result;
use pvfc_sim::scenario::preset_id::{PresetId, FIG1_SATURATED_SPEEDS};
use pvfc_sim::scenario::presets::FIG1_TORQUE_LIMITS;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::trace::metrics::contour_error;
use pvfc_sim::trace::Trace;
use std::path::{Path, PathBuf};

/// The seconds at the end of each run the figures are taken over.
const WINDOW: f64 = 12.0;

/// One run of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedPoint {
    /// The demanded speed: `r` of eq. (36), or the tracker's `τ̇`.
    pub demanded: f64,
    /// The mean `τ̇` over the window.
    pub tau_rate: f64,
    /// The mean speed along the contour (rad/s in joint space): the length of `x_d`
    /// traversed over the time.
    pub speed: f64,
    /// The distance of `q` to the contour (rad): mean and largest over the window.
    pub error: (f64, f64),
    /// The fraction of the window's samples with a joint's torque at its limit.
    pub saturated: f64,
}

/// The figures of one run over its last [`WINDOW`] seconds.
pub fn speed_point(s: &Scenario, t: &Trace, demanded: f64) -> Result<SpeedPoint> {
    let contour = s.contour()?;
    let end = t.t.last().copied().unwrap_or(0.0);
    let start = t.t.iter().position(|&x| x >= end - WINDOW).unwrap_or(0);
    let range = start..t.len();
    let duration = (end - t.t[start]).max(f64::MIN_POSITIVE);
    let length: f64 = t.tau[range.clone()]
        .windows(2)
        .map(|w| (contour.coordinates(w[1])[0] - contour.coordinates(w[0])[0]).norm())
        .sum();
    let at_limit = t
        .torque
        .rows(range.clone())
        .filter(|u| {
            u.iter()
                .zip(&FIG1_TORQUE_LIMITS)
                .any(|(u, l)| u.abs() >= l * (1.0 - 1e-9))
        })
        .count();
    Ok(SpeedPoint {
        demanded,
        tau_rate: (t.tau[t.len() - 1] - t.tau[start]) / duration,
        speed: length / duration,
        error: contour_error(t, &contour, s.period(), range.clone()),
        saturated: at_limit as f64 / range.len().max(1) as f64,
    })
}

/// PVFC's and the timed tracker's points, by demanded speed.
pub fn sweep(r: &Runs) -> Result<(Vec<SpeedPoint>, Vec<SpeedPoint>)> {
    let (mut pvfc, mut timed) = (Vec::new(), Vec::new());
    for speed in FIG1_SATURATED_SPEEDS {
        let id = PresetId::Fig1Saturated { speed };
        let demanded = f64::from(speed) / 100.0;
        let (s, t) = r.run(id)?;
        pvfc.push(speed_point(s, t, demanded)?);
        timed.push(speed_point(s, &r.named(&id.timed_name())?.1, demanded)?);
    }
    Ok((pvfc, timed))
}

/// The claim: once the timed tracker's drives saturate (at their limit in over half the
/// samples), its contour error grows with the demanded speed, while PVFC makes less speed
/// than demanded and stays nearer the contour.
pub(crate) fn fig1_saturated_claim(
    r: &Runs,
    push: &mut impl FnMut(&str, &str, &str, String, bool),
) -> Result<()> {
    let (pvfc, timed) = sweep(r)?;
    let saturated: Vec<usize> = (0..timed.len())
        .filter(|&i| timed[i].saturated > 0.5)
        .collect();
    let grows = saturated
        .windows(2)
        .all(|w| timed[w[1]].error.0 > timed[w[0]].error.0);
    let pvfc_nearer = saturated
        .iter()
        .all(|&i| pvfc[i].error.0 < timed[i].error.0 && pvfc[i].tau_rate < pvfc[i].demanded);
    let rows: Vec<String> = pvfc
        .iter()
        .zip(&timed)
        .map(|(p, t)| {
            format!(
                "r = {}: PVFC τ̇ {:.2}, error {:.1e} rad (at limit {:.0} %); timed error {:.1e} rad (at limit {:.0} %)",
                p.demanded,
                p.tau_rate,
                p.error.0,
                100.0 * p.saturated,
                t.error.0,
                100.0 * t.saturated
            )
        })
        .collect();
    push(
        "fig1.saturated",
        "On drives that saturate, a timed tracker leaves the contour to keep pace as the demanded speed grows; PVFC slows down and stays nearer the contour",
        "SCARA on a circle of 1 rad in joint space, torques limited to 15 / 5 N·m on both controllers; demanded speed r (PVFC: eq. 36 at the energy of β = r, passive 1 kHz; timed: τ̇ = r, computed torque + PD at 20 rad/s); mean distance to the contour over the last 12 s; holds if, over the speeds where the tracker is at its limit in over half the samples, its error grows with r and PVFC's is smaller at a τ̇ below r",
        rows.join("; "),
        !saturated.is_empty() && grows && pvfc_nearer,
    );
    Ok(())
}

/// The speed–accuracy figure: mean speed along the contour against the mean contour error,
/// both controllers, each point a demanded speed.
pub fn figure_saturated(r: &Runs, dir: &Path) -> Result<PathBuf> {
    let (pvfc, timed) = sweep(r)?;
    let p = dir.join("fig1_saturated.png");
    let series = |label: &str, v: &[SpeedPoint]| Series {
        label: label.into(),
        points: v.iter().map(|x| (x.speed, x.error.0)).collect(),
        reference: false,
    };
    let demanded = |label: &str, v: &[SpeedPoint]| Series {
        label: label.into(),
        points: v.iter().map(|x| (x.demanded, x.tau_rate)).collect(),
        reference: false,
    };
    figure(&p, 2, |i, a| match i {
        0 => panel(
            a,
            &p,
            "Fig. 1 on saturating drives: speed against accuracy",
            "mean speed along the contour [rad/s]",
            "mean distance to the contour [rad]",
            &[series("PVFC", &pvfc), series("timed tracker", &timed)],
            true,
        ),
        _ => panel(
            a,
            &p,
            "the speed each made (mean dτ/dt) against the speed demanded",
            "demanded speed r",
            "mean dτ/dt",
            &[
                demanded("PVFC", &pvfc),
                demanded("timed tracker", &timed),
                Series {
                    label: "demanded".into(),
                    points: vec![(0.0, 0.0), (4.0, 4.0)],
                    reference: true,
                },
            ],
            false,
        ),
    })?;
    Ok(p)
}
