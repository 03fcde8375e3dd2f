//! Fig. 1 as the paper means it: both controllers on drives that saturate, over a sweep of the
//! demanded speed ([`fig1_saturated`](pvfc_sim::scenario::presets::fig1_saturated)). For each
//! run, the mean speed it made along the contour and its distance to the contour; the claim
//! `fig1.saturated` and the figure `fig1_saturated.png` (speed against accuracy).

use crate::canvas::{figure, panel, Series, Style};
use crate::runs::Runs;
use pvfc_sim::error::Result;
use pvfc_sim::error::SimError;
use pvfc_sim::scenario::preset_id::{Fig1Contour, PresetId, SaturatedPath, FIG1_SATURATED_SPEEDS};
use pvfc_sim::scenario::presets::{FIG1_TORQUE_LIMITS, UR5_TORQUE_LIMITS};
use pvfc_sim::scenario::Scenario;
use pvfc_sim::trace::metrics::contour_following;
use pvfc_sim::trace::path_budget::path_budget;
use pvfc_sim::trace::Trace;
use std::path::{Path, PathBuf};

/// The seconds at the end of each run the figures are taken over.
pub const WINDOW: f64 = 12.0;

/// One run of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedPoint {
    /// The demanded speed: `r` of eq. (36), or the tracker's `τ̇`.
    pub demanded: f64,
    /// The mean `τ̇` over the window.
    pub tau_rate: f64,
    /// The mean speed the arm made along the contour (rad/s in joint space for the SCARA,
    /// [`ContourFollowing::speed`](pvfc_sim::trace::metrics::ContourFollowing::speed); m/s along the path for the UR5, the progress of the closest
    /// point).
    pub speed: f64,
    /// The distance of `q` to the contour (rad): mean and largest over the window.
    pub error: (f64, f64),
    /// The fraction of the window's samples with a joint's torque at its limit.
    pub saturated: f64,
    /// The least `τ̇` over the window ÷ its mean: near 0 when the controller stops and goes.
    pub slowest: f64,
    /// The time of one lap at the mean `τ̇` (s): the period ÷ `tau_rate`.
    pub lap: f64,
}

/// The least `τ̇` over `range` ÷ the mean `mean` (1 for a controller that never slows).
fn slowest(t: &Trace, range: std::ops::Range<usize>, mean: f64) -> f64 {
    let least = t.tau_dot[range]
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    if mean > 0.0 {
        least / mean
    } else {
        0.0
    }
}

/// The fraction of the samples in `range` with a joint's torque at its limit.
fn at_limit(t: &Trace, range: std::ops::Range<usize>, limits: &[f64]) -> f64 {
    let n = range.len().max(1);
    let hits = t
        .torque
        .rows(range)
        .filter(|u| {
            u.iter()
                .zip(limits)
                .any(|(u, l)| u.abs() >= l * (1.0 - 1e-9))
        })
        .count();
    hits as f64 / n as f64
}

/// The figures of one UR5 run over its steady passes: the tool's speed along the path (m/s)
/// and its distance to the path along the surface (m).
pub fn ur5_point(r: &Runs, name: &str, demanded: f64) -> Result<SpeedPoint> {
    let (s, t) = r.named(name)?;
    let system = r.chain_system(s)?;
    let b = path_budget(s, &system.robot, t)?
        .ok_or_else(|| SimError::Setting(format!("run `{name}` has no steady pass")))?;
    let start = t.t.iter().position(|&x| x >= b.window.0).unwrap_or(0);
    let stop =
        t.t.iter()
            .position(|&x| x >= b.window.1)
            .unwrap_or(t.len() - 1);
    let surface = b.surface.unwrap_or(b.spread);
    let tau_rate = (t.tau[stop] - t.tau[start]) / (b.window.1 - b.window.0).max(f64::MIN_POSITIVE);
    Ok(SpeedPoint {
        demanded,
        tau_rate,
        speed: b.speed,
        error: (surface.mean, surface.max),
        saturated: at_limit(t, start..stop + 1, &UR5_TORQUE_LIMITS),
        slowest: slowest(t, start..stop + 1, tau_rate),
        lap: s.period() / tau_rate,
    })
}

/// The points of a sweep over the demanded speed, one per speed for each controller.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sweep {
    /// PVFC's.
    pub pvfc: Vec<SpeedPoint>,
    /// The timed tracker's.
    pub timed: Vec<SpeedPoint>,
    /// The speed-scaling tracker's.
    pub scaled: Vec<SpeedPoint>,
}

/// The UR5's points on `path`, by demanded speed.
pub fn ur5_sweep(r: &Runs, path: SaturatedPath) -> Result<Sweep> {
    let mut out = Sweep::default();
    for speed in path.speeds() {
        let id = PresetId::Ur5Saturated { path, speed };
        let demanded = f64::from(speed);
        out.pvfc.push(ur5_point(r, &id.name(), demanded)?);
        out.timed.push(ur5_point(r, &id.timed_name(), demanded)?);
        out.scaled.push(ur5_point(r, &id.scaled_name(), demanded)?);
    }
    Ok(out)
}

/// The figures of one run over its last [`WINDOW`] seconds.
pub fn speed_point(s: &Scenario, t: &Trace, demanded: f64) -> Result<SpeedPoint> {
    let contour = s.contour()?;
    let end = t.t.last().copied().unwrap_or(0.0);
    let start = t.t.iter().position(|&x| x >= end - WINDOW).unwrap_or(0);
    let range = start..t.len();
    let duration = (end - t.t[start]).max(f64::MIN_POSITIVE);
    let following = contour_following(t, &contour, s.period(), range.clone());
    let tau_rate = (t.tau[t.len() - 1] - t.tau[start]) / duration;
    Ok(SpeedPoint {
        demanded,
        tau_rate,
        speed: following.speed,
        error: following.error,
        saturated: at_limit(t, range.clone(), &FIG1_TORQUE_LIMITS),
        slowest: slowest(t, range, tau_rate),
        lap: s.period() / tau_rate,
    })
}

/// The SCARA's points on `contour`, by demanded speed.
pub fn sweep(r: &Runs, contour: Fig1Contour) -> Result<Sweep> {
    let mut out = Sweep::default();
    for speed in FIG1_SATURATED_SPEEDS {
        let id = PresetId::Fig1Saturated { contour, speed };
        let demanded = f64::from(speed) / 100.0;
        let (s, t) = r.run(id)?;
        out.pvfc.push(speed_point(s, t, demanded)?);
        out.timed
            .push(speed_point(s, &r.named(&id.timed_name())?.1, demanded)?);
        out.scaled
            .push(speed_point(s, &r.named(&id.scaled_name())?.1, demanded)?);
    }
    Ok(out)
}

/// The claims, one per contour, as the paper's Fig. 1 means them: where the drives saturate
/// (the timed tracker at a limit in over 5 % of its samples), the tracker leaves the contour
/// to keep pace while PVFC slows down to the pace the drives allow and stays on it: at each
/// such speed PVFC's mean error is at most a third of the tracker's, its `τ̇` below the
/// demanded one, its largest error at most twice its largest at the speeds that do not
/// saturate, and it never stops (its least `τ̇` over 10 % of its mean).
pub(crate) fn fig1_saturated_claims(
    r: &Runs,
    push: &mut impl FnMut(&str, &str, &str, String, bool),
) -> Result<()> {
    for contour in Fig1Contour::ALL {
        let w = sweep(r, contour)?;
        let least = FIG1_SATURATED_SPEEDS
            .iter()
            .map(|&speed| {
                r.run(PresetId::Fig1Saturated { contour, speed })?
                    .0
                    .least_lap()
            })
            .collect::<Result<Vec<f64>>>()?;
        let holds = verdict(&w);
        let rows: Vec<String> = (0..w.pvfc.len())
            .map(|i| {
                let (p, t, c) = (&w.pvfc[i], &w.timed[i], &w.scaled[i]);
                format!(
                    "r = {}: PVFC τ̇ {:.2} (least {:.2} of it; lap {:.2}× the least at r), error {:.1e} / {:.1e} rad (at limit {:.0} %); timed error {:.1e} / {:.1e} rad (at limit {:.0} %); speed-scaling τ̇ {:.2}, error {:.1e} / {:.1e} rad (at limit {:.0} %)",
                    p.demanded,
                    p.tau_rate,
                    p.slowest,
                    p.lap / least[i],
                    p.error.0,
                    p.error.1,
                    100.0 * p.saturated,
                    t.error.0,
                    t.error.1,
                    100.0 * t.saturated,
                    c.tau_rate,
                    c.error.0,
                    c.error.1,
                    100.0 * c.saturated
                )
            })
            .collect();
        let (id, shape) = match contour {
            Fig1Contour::Circle => (
                "fig1.saturated",
                "SCARA on a circle of 1 rad in joint space",
            ),
            Fig1Contour::Lissajous => (
                "fig1.saturated.lissajous",
                "SCARA on the paper's Lissajous curve (as fig1)",
            ),
        };
        push(
            id,
            "On drives that saturate, a timed tracker leaves the contour to keep pace; PVFC slows down to the pace the drives allow and stays on the contour, nearer than a speed-scaling tracker",
            &format!("{shape}, torques limited to 15 / 5 N·m on every controller; demanded speed r (PVFC: eq. 36 at the energy of β = r, the field's pace bounded by the drives' limits with 20 % headroom, passive 1 kHz; timed: τ̇ = r, computed torque + PD at 20 rad/s; speed-scaling: the same tracker, τ̇ = s·r with s slowed while a command passes 80 % of its limit, time constant 50 ms); distance to the contour (mean / max) over the last 12 s; lap: PVFC's lap time ÷ the least lap any controller can make at no rate above r on this plant (the time-optimal parameterisation at full use of the same limits against the plant's own Coulomb and viscous friction); holds if, at every speed where a tracker is at a limit in over 5 % of its samples, PVFC's mean error is at most a third of the timed tracker's and at most the speed-scaling tracker's, its max at most twice its max where it makes the speed demanded (τ̇ ≥ 0.98 r), its least τ̇ over a tenth of its mean, and, where the timed tracker is at a limit, its τ̇ below r"),
            rows.join("; "),
            holds,
        );
    }
    Ok(())
}

/// The speeds where either tracker is at a limit in over 5 % of its samples.
fn saturating(w: &Sweep) -> Vec<usize> {
    (0..w.timed.len())
        .filter(|&i| w.timed[i].saturated > 0.05 || w.scaled[i].saturated > 0.05)
        .collect()
}

/// The verdict of the claims ([`fig1_saturated_claims`], [`ur5_saturated_claims`]), what
/// Fig. 1 and issue 51 say: at every speed where either tracker is at a limit in over 5 % of
/// its samples, PVFC is at most a third of the timed tracker's mean distance and at most the
/// speed-scaling tracker's, its max at most twice its own max where its drives do not bound
/// it (where it makes the speed demanded, `τ̇ ≥ 0.98 r`), it never stops (least `τ̇` over a
/// tenth of its mean), and where the timed tracker had to saturate, PVFC slowed instead
/// (`τ̇ < r`). A speed where only the speed-scaling tracker is at a limit asks nothing of
/// PVFC's pace: its drives may well allow that speed.
fn verdict(w: &Sweep) -> bool {
    let saturated = saturating(w);
    let free_max = w
        .pvfc
        .iter()
        .filter(|p| p.tau_rate >= 0.98 * p.demanded)
        .map(|p| p.error.1)
        .fold(0.0, f64::max);
    !saturated.is_empty()
        && free_max > 0.0
        && saturated.iter().all(|&i| {
            let p = &w.pvfc[i];
            p.error.0 <= w.timed[i].error.0 / 3.0
                && p.error.0 <= w.scaled[i].error.0
                && p.error.1 <= 2.0 * free_max
                && p.slowest > 0.1
                && (w.timed[i].saturated <= 0.05 || p.tau_rate < p.demanded)
        })
}

/// The UR5's claims, one per path, with the SCARA's verdict ([`fig1_saturated_claims`]): where
/// the timed tracker is at a limit in over 5 % of its samples, PVFC slows down and stays on
/// the path.
pub(crate) fn ur5_saturated_claims(
    r: &Runs,
    push: &mut impl FnMut(&str, &str, &str, String, bool),
) -> Result<()> {
    for path in SaturatedPath::ALL {
        let w = ur5_sweep(r, path)?;
        let least = path
            .speeds()
            .into_iter()
            .map(|speed| {
                r.named(&PresetId::Ur5Saturated { path, speed }.name())?
                    .0
                    .least_lap()
            })
            .collect::<Result<Vec<f64>>>()?;
        let holds = verdict(&w);
        let rows: Vec<String> = (0..w.pvfc.len())
            .map(|i| {
                let (p, t, c) = (&w.pvfc[i], &w.timed[i], &w.scaled[i]);
                format!(
                    "r = {}: PVFC {:.0} mm/s (least τ̇ {:.2} of its mean; lap {:.2}× the least at r), {:.3} / {:.2} mm (at limit {:.0} %); timed {:.0} mm/s, {:.3} / {:.2} mm (at limit {:.0} %); speed-scaling {:.0} mm/s, {:.3} / {:.2} mm (at limit {:.0} %)",
                    p.demanded,
                    p.speed * 1e3,
                    p.slowest,
                    p.lap / least[i],
                    p.error.0 * 1e3,
                    p.error.1 * 1e3,
                    100.0 * p.saturated,
                    t.speed * 1e3,
                    t.error.0 * 1e3,
                    t.error.1 * 1e3,
                    100.0 * t.saturated,
                    c.speed * 1e3,
                    c.error.0 * 1e3,
                    c.error.1 * 1e3,
                    100.0 * c.saturated
                )
            })
            .collect();
        let (id, which, shape) = match path {
            SaturatedPath::Rectangle => (
                "fig1.saturated.ur5",
                "the tool path",
                "UR5 rounded rectangle (ur5_cartesian)",
            ),
            SaturatedPath::Circle => (
                "fig1.saturated.ur5.circle",
                "a circular tool path",
                "UR5 circle of 10 cm radius (ur5_circle, 52 mm/s at r = 1)",
            ),
        };
        let statement = format!("On the UR5's saturating drives, the timed tracker leaves {which} to keep pace; PVFC slows down to the pace the drives allow and stays on it, nearer than a speed-scaling tracker");
        let setting = format!("{shape} at r times its speed, every controller limited to 60/60/30/5/5/5 N·m (PVFC passive 1 kHz at the energy of β = r, the free run's coupling rate γβĒ, the field's pace bounded by the drives' limits with 20 % headroom; timed: τ̇ = r, computed torque + PD at 100 rad/s; speed-scaling: the same tracker, τ̇ = s·r with s slowed while a command passes 80 % of its limit, time constant 50 ms); the tool's distance to the path along the surface (mean / max) and speed along it over the steady passes; lap: PVFC's lap time ÷ the least lap any controller can make at no rate above r on this plant (the time-optimal parameterisation at full use of the same limits against the plant's own Coulomb and viscous friction and gravity); holds if, at every speed where a tracker is at a limit in over 5 % of its samples, PVFC's mean distance is at most a third of the timed tracker's and at most the speed-scaling tracker's, its max at most twice its max where it makes the speed demanded (τ̇ ≥ 0.98 r), its least τ̇ over a tenth of its mean, and, where the timed tracker is at a limit, its τ̇ below r");
        push(id, &statement, &setting, rows.join("; "), holds);
    }
    Ok(())
}

/// The speed–accuracy figure: for the SCARA on each contour, mean speed along the contour
/// against the mean contour error, both controllers, each point a demanded speed; the speed
/// each made against the speed demanded; and, with the UR5's runs, the same for its rectangle
/// and its circle.
pub fn figure_saturated(r: &Runs, dir: &Path) -> Result<PathBuf> {
    let (circle, lissajous) = (
        sweep(r, Fig1Contour::Circle)?,
        sweep(r, Fig1Contour::Lissajous)?,
    );
    let first = |path: SaturatedPath| PresetId::Ur5Saturated {
        path,
        speed: path.speeds()[0],
    };
    let ur5 = if r.run(first(SaturatedPath::Rectangle)).is_ok() {
        Some((
            ur5_sweep(r, SaturatedPath::Rectangle)?,
            ur5_sweep(r, SaturatedPath::Circle)?,
        ))
    } else {
        None
    };
    let p = dir.join("fig1_saturated.png");
    let series = |label: &str, v: &[SpeedPoint]| Series {
        label: label.into(),
        points: v.iter().map(|x| (x.speed, x.error.0)).collect(),
        style: Style::Markers,
    };
    let demanded = |label: &str, v: &[SpeedPoint]| Series {
        label: label.into(),
        points: v.iter().map(|x| (x.demanded, x.tau_rate)).collect(),
        style: Style::Line,
    };
    let mm = |label: &str, v: &[SpeedPoint]| Series {
        label: label.into(),
        points: v.iter().map(|x| (x.speed * 1e3, x.error.0 * 1e3)).collect(),
        style: Style::Markers,
    };
    let by_demand = |label: &str, v: &[SpeedPoint]| Series {
        label: label.into(),
        points: v.iter().map(|x| (x.demanded, x.error.0 * 1e3)).collect(),
        style: Style::Markers,
    };
    let scara = |a: &crate::canvas::Area<'_>, title: &str, w: &Sweep| {
        panel(
            a,
            &p,
            title,
            "mean speed along the contour [rad/s]",
            "mean distance to the contour [rad]",
            &[
                series("PVFC", &w.pvfc),
                series("timed tracker", &w.timed),
                series("speed-scaling tracker", &w.scaled),
            ],
            true,
        )
    };
    figure(&p, if ur5.is_some() { 5 } else { 3 }, |i, a| match i {
        0 => scara(
            a,
            "Fig. 1 on saturating drives, a circle: speed against accuracy",
            &circle,
        ),
        1 => scara(
            a,
            "Fig. 1 on saturating drives, the paper's Lissajous curve: speed against accuracy",
            &lissajous,
        ),
        3 => match &ur5 {
            Some((w, _)) => panel(
                a,
                &p,
                "UR5 rectangle on saturating drives: speed against accuracy",
                "mean speed along the path [mm/s]",
                "mean distance along the surface [mm]",
                &[
                    mm("PVFC", &w.pvfc),
                    mm("timed tracker", &w.timed),
                    mm("speed-scaling tracker", &w.scaled),
                ],
                true,
            ),
            None => Ok(()),
        },
        // Against the demanded speed: a tracker that has lost the circle makes no speed along
        // it worth plotting (its closest point may even run backwards).
        4 => match &ur5 {
            Some((_, w)) => panel(
                a,
                &p,
                "UR5 circle on saturating drives: demanded speed against accuracy",
                "demanded speed r (times 52 mm/s)",
                "mean distance along the surface [mm]",
                &[
                    by_demand("PVFC", &w.pvfc),
                    by_demand("timed tracker", &w.timed),
                    by_demand("speed-scaling tracker", &w.scaled),
                ],
                true,
            ),
            None => Ok(()),
        },
        _ => panel(
            a,
            &p,
            "the speed each made (mean dτ/dt) against the speed demanded",
            "demanded speed r",
            "mean dτ/dt",
            &[
                demanded("PVFC, circle", &circle.pvfc),
                demanded("speed-scaling tracker, circle", &circle.scaled),
                demanded("PVFC, Lissajous", &lissajous.pvfc),
                demanded("speed-scaling tracker, Lissajous", &lissajous.scaled),
                Series {
                    label: "demanded".into(),
                    points: vec![(0.0, 0.0), (4.0, 4.0)],
                    style: Style::Reference,
                },
            ],
            false,
        ),
    })?;
    Ok(p)
}
