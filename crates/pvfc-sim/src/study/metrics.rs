//! The summary metrics a study keeps of each run, by name: one number per run, computed from
//! its trace (and, for a Cartesian path, from its robot), or absent where it does not apply
//! (a contact metric of a run without contact, a pass metric of a run shorter than a pass).

use crate::error::{Result, SimError};
use crate::model::robot::Robot;
use crate::plant::faults::FaultKind;
use crate::scenario::RobotSpec;
use crate::scenario::Scenario;
use crate::trace::path_budget::{path_budget, PathBudget};
use crate::trace::{metrics, Trace};
use std::cell::OnceCell;

/// A finished run as the metrics see it: its scenario, its trace, and a URDF arm's robot
/// (for the tool-to-path distance). Expensive parts (the path budget) are computed once, on
/// first use.
pub struct RunView<'a> {
    scenario: &'a Scenario,
    trace: &'a Trace,
    robot: Option<&'a Robot>,
    budget: OnceCell<Result<Option<PathBudget>>>,
}

impl<'a> RunView<'a> {
    /// The view of run `trace` of `scenario` (`robot`: the URDF arm's model, `None` for the
    /// SCARA).
    pub fn new(scenario: &'a Scenario, trace: &'a Trace, robot: Option<&'a Robot>) -> Self {
        RunView {
            scenario,
            trace,
            robot,
            budget: OnceCell::new(),
        }
    }

    /// The metrics of the run, in the order given. A metric that does not apply is `None`;
    /// a part of the run's analysis that fails (the path budget's forward kinematics or
    /// inverse kinematics) is the run's error, not an absent metric.
    pub fn values(self, metrics: &[&Metric]) -> Result<Vec<Option<f64>>> {
        let values = metrics.iter().map(|m| m.of(&self)).collect();
        match self.budget.into_inner() {
            Some(Err(e)) => Err(e),
            _ => Ok(values),
        }
    }

    fn budget(&self) -> Option<&PathBudget> {
        self.budget
            .get_or_init(|| match self.robot {
                Some(r) => path_budget(self.scenario, r, self.trace),
                None => Ok(None),
            })
            .as_ref()
            .ok()?
            .as_ref()
    }

    fn contact(&self) -> Option<metrics::ContactSummary> {
        metrics::contact_summary(self.trace)
    }

    fn last(&self, column: &[f64]) -> Option<f64> {
        column.last().copied()
    }
}

/// A metric: its name (the column of a study's table), unit, meaning, and how it is computed.
pub struct Metric {
    /// The name, as a study's `metrics = [...]` lists it and its table's column.
    pub name: &'static str,
    /// The unit.
    pub unit: &'static str,
    /// What it measures.
    pub doc: &'static str,
    eval: fn(&RunView) -> Option<f64>,
}

impl Metric {
    /// The metric of a run; `None` where it does not apply.
    pub fn of(&self, run: &RunView) -> Option<f64> {
        (self.eval)(run).filter(|x| !x.is_nan())
    }
}

impl std::fmt::Debug for Metric {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Metric({})", self.name)
    }
}

/// The time the run entered its steady band (s): the last time `U` was above twice its
/// largest value over the last complete pass (0 if it never was). `None` without a complete
/// pass.
fn converge_time(run: &RunView) -> Option<f64> {
    let t = run.trace;
    let pass = metrics::last_pass(t, run.scenario.period())?;
    let band = 2.0 * t.potential[pass].iter().copied().fold(0.0, f64::max);
    Some(match t.potential.iter().rposition(|&u| u > band) {
        None => 0.0,
        Some(i) => t.t[(i + 1).min(t.len() - 1)],
    })
}

/// The mean `τ̇` over the last complete pass.
fn mean_tau_rate(run: &RunView) -> Option<f64> {
    let r = metrics::last_pass(run.trace, run.scenario.period())?;
    let (a, b) = (r.start, r.end - 1);
    let dt = run.trace.t[b] - run.trace.t[a];
    (dt > 0.0).then(|| (run.trace.tau[b] - run.trace.tau[a]) / dt)
}

/// The audit residual: with contact, the full audit's (its trace has the work of every
/// source); without, the friction-only audit's, which holds only for the planar arm (no
/// gravity) without add-ons (friction compensation, the energy loop (36)), whose work such a
/// trace does not log; `None` for the others.
fn audit(run: &RunView) -> Option<f64> {
    if let Some(c) = run.contact() {
        return Some(c.audit);
    }
    let s = run.scenario;
    let compensates = s
        .controller
        .friction_compensation
        .as_ref()
        .is_some_and(|f| f.iter().any(|x| *x != 0.0));
    // The friction-only audit does not count gravity's work, which a serial chain has.
    let without_gravity = match s.plant.robot {
        RobotSpec::Scara(_) | RobotSpec::RigidBody(_) => true,
        RobotSpec::SerialChain(_) => false,
    };
    let plain = without_gravity && !compensates && s.controller.nominal_speed.is_none();
    plain.then(|| metrics::energy_audit(run.trace))
}

/// The slowest recovery from the run's `[[faults]]` events (of `kind` only, if given) (s) and
/// how many events `U` never recovered from ([`metrics::recovery_time`]: back below ten times
/// its level of the half second before, held 0.2 s), over the events that end at least a
/// second before the run; `None` without such events.
fn recoveries(run: &RunView, kind: Option<FaultKind>) -> Option<(f64, usize)> {
    let s = run.scenario;
    if s.faults.is_empty() {
        return None;
    }
    let period = 1.0 / s.controller.rate;
    let end = run.trace.t.last().copied().unwrap_or(0.0);
    // An event that ends less than a second before the run does cannot be judged.
    let mut judged = s
        .faults
        .iter()
        .filter(|e| kind.is_none_or(|k| e.kind == k))
        .filter(|e| e.at + e.duration + 1.0 <= end)
        .peekable();
    if kind.is_some() && judged.peek().is_none() {
        return None;
    }
    let mut slowest = 0.0f64;
    let mut never = 0;
    for e in judged {
        match metrics::recovery_time(run.trace, e.at, e.duration, period, 0.2) {
            Some(r) => slowest = slowest.max(r),
            None => never += 1,
        }
    }
    Some((slowest, never))
}

/// The slowest recovery after the run's events of `kind`, if every one of them was recovered
/// from (one that was not is counted by `unrecovered`).
fn recovery_of(run: &RunView, kind: FaultKind) -> Option<f64> {
    recoveries(run, Some(kind)).and_then(|(t, never)| (never == 0).then_some(t))
}

/// The metric `recovery_KIND` of the slowest recovery after one kind of fault event (`$kind`:
/// the kind as a scenario spells it, `$variant`: its [`FaultKind`]).
macro_rules! recovery_after {
    ($kind:ident, $variant:ident) => {
        Metric {
            name: concat!("recovery_", stringify!($kind)),
            unit: "s",
            doc: concat!(
                "The slowest return after the run's `",
                stringify!($kind),
                "` events, as recovery_time (absent without one, or if one was never recovered from)."
            ),
            eval: |r| recovery_of(r, FaultKind::$variant),
        }
    };
}

/// The share of the last complete pass's samples at which a joint's torque is at its limit:
/// the tracker's `baseline.torque_limit` for a tracker's run, the passive controller's
/// `torque_limit` for PVFC's; `None` without limits or a complete pass.
fn limit_share(run: &RunView) -> Option<f64> {
    let s = run.scenario;
    let t = run.trace;
    let tracker = t.name.ends_with(crate::trace::TIMED_SUFFIX)
        || t.name.ends_with(crate::trace::SCALED_SUFFIX);
    let limits = if tracker {
        s.baseline.as_ref().map(|b| b.torque_limit.as_slice())
    } else {
        s.controller
            .passive
            .as_ref()
            .map(|p| p.torque_limit.as_slice())
    }
    .filter(|l| !l.is_empty())?;
    let pass = metrics::last_pass(t, s.period())?;
    let n = pass.len();
    let hits = t
        .torque
        .rows(pass)
        .filter(|u| {
            u.iter()
                .zip(limits)
                .any(|(u, l)| u.abs() >= l * (1.0 - 1e-9))
        })
        .count();
    (n > 0).then(|| hits as f64 / n as f64)
}

/// The distance of `q` to a SCARA's joint contour over the last complete pass (rad): mean
/// and largest ([`metrics::contour_following`]); `None` for other robots.
fn contour_distance(run: &RunView) -> Option<(f64, f64)> {
    let s = run.scenario;
    if !matches!(s.plant.robot, RobotSpec::Scara(_)) {
        return None;
    }
    let contour = s.contour().ok()?;
    let pass = metrics::last_pass(run.trace, s.period())?;
    Some(metrics::contour_following(run.trace, &contour, s.period(), pass).error)
}

/// Every metric a study can keep, in the order of a study's table when it keeps them all.
pub const METRICS: &[Metric] = &[
    Metric {
        name: "mean_u",
        unit: "",
        doc: "The mean contour error U(E) of eq. (17) over the last complete pass.",
        eval: |r| metrics::mean_potential_over_pass(r.trace, r.scenario.period()),
    },
    Metric {
        name: "max_u_last_pass",
        unit: "",
        doc: "The largest U(E) over the last complete pass.",
        eval: |r| {
            let p = metrics::last_pass(r.trace, r.scenario.period())?;
            Some(r.trace.potential[p].iter().copied().fold(0.0, f64::max))
        },
    },
    Metric {
        name: "final_u",
        unit: "",
        doc: "U(E) at the end of the run.",
        eval: |r| r.last(&r.trace.potential),
    },
    Metric {
        name: "converge_time",
        unit: "s",
        doc: "The time the run entered its steady band: the last time U was above twice its largest value over the last complete pass (0 if never).",
        eval: converge_time,
    },
    Metric {
        name: "pass_duration",
        unit: "s",
        doc: "The time of the last complete pass of the contour.",
        eval: |r| metrics::pass_duration(r.trace, r.scenario.period()),
    },
    Metric {
        name: "tau_dot_least_ratio",
        unit: "",
        doc: "The least τ̇ over the last complete pass ÷ its mean there: near 0 when the pace stops and goes (a pace profile's planned slowdowns keep it well above; 1 for a timed tracker's clock).",
        eval: |r| {
            let pass = metrics::last_pass(r.trace, r.scenario.period())?;
            let rates = r.trace.tau_dot.get(pass)?;
            let mean = rates.iter().sum::<f64>() / rates.len() as f64;
            let least = rates.iter().copied().fold(f64::INFINITY, f64::min);
            (mean > 0.0).then(|| least / mean)
        },
    },
    Metric {
        name: "least_lap",
        unit: "s",
        doc: "The least lap any controller can make on the run's plant at its demand (Scenario::least_lap: the time-optimal parameterisation under the drives' limits, against the plant's friction and model error; absent without a drive-limited pace).",
        eval: |r| r.scenario.least_lap().ok(),
    },
    Metric {
        name: "lap_ratio",
        unit: "",
        doc: "The time of the last complete pass ÷ least_lap: 1 is the fastest any controller can go on that plant at that demand.",
        eval: |r| {
            let lap = metrics::pass_duration(r.trace, r.scenario.period())?;
            Some(lap / r.scenario.least_lap().ok()?)
        },
    },
    Metric {
        name: "mean_tau_rate",
        unit: "1/s",
        doc: "The mean τ̇ over the last complete pass: the pace self-pacing settles at.",
        eval: mean_tau_rate,
    },
    Metric {
        name: "final_beta",
        unit: "",
        doc: "β = √(κ_a/Ē) at the end of the run: the speed along the field.",
        eval: |r| r.last(&r.trace.beta),
    },
    Metric {
        name: "final_w_beta",
        unit: "J",
        doc: "W_β of eq. (12) at the end of the run: the energy of the velocity-field tracking error.",
        eval: |r| r.last(&r.trace.w_beta),
    },
    Metric {
        name: "energy_drift",
        unit: "",
        doc: "The largest |κ_a(t) − κ_a(0)| / κ_a(0): how far the augmented energy moved.",
        eval: |r| Some(metrics::energy_drift(r.trace)),
    },
    Metric {
        name: "audit_residual",
        unit: "",
        doc: "The energy audit's largest residual relative to the energy scale: with contact, of E − E(0) − W_contact − W_friction − W_controller; without contact, of κ_a − κ_a(0) − ∫F_fᵀq̇ for the planar arm without add-ons (absent for the others, whose trace lacks the add-ons' and gravity's work).",
        eval: audit,
    },
    Metric {
        name: "peak_force",
        unit: "N",
        doc: "The largest measured contact force (sum of normal forces); absent without contact.",
        eval: |r| r.contact().map(|c| c.peak_force),
    },
    Metric {
        name: "energy_pumped",
        unit: "J",
        doc: "The most energy the arm had put into the contact at any time, max −∫F_eᵀq̇; absent without contact.",
        eval: |r| r.contact().map(|c| c.energy_pumped),
    },
    Metric {
        name: "passivity_margin",
        unit: "J",
        doc: "The margin of the passivity bound −W_contact ≤ E(0) + W_controller + W_gravity (≥ 0 when it holds); absent without contact.",
        eval: |r| r.contact().map(|c| c.passivity_margin),
    },
    Metric {
        name: "tool_path_mean",
        unit: "m",
        doc: "The tool's mean 3-D distance to the Cartesian path over the steady passes; absent without a Cartesian path.",
        eval: |r| r.budget().map(|b| b.distance.mean),
    },
    Metric {
        name: "tool_path_max",
        unit: "m",
        doc: "The tool's largest 3-D distance to the Cartesian path over the steady passes.",
        eval: |r| r.budget().map(|b| b.distance.max),
    },
    Metric {
        name: "tool_surface_mean",
        unit: "m",
        doc: "The tool's mean distance to a planar path within its plane (along the surface), over the steady passes.",
        eval: |r| r.budget().and_then(|b| b.surface).map(|s| s.mean),
    },
    Metric {
        name: "tool_surface_max",
        unit: "m",
        doc: "The tool's largest distance to a planar path within its plane (along the surface), over the steady passes.",
        eval: |r| r.budget().and_then(|b| b.surface).map(|s| s.max),
    },
    Metric {
        name: "contour_geometry_max",
        unit: "m",
        doc: "The joint contour's own largest distance to the Cartesian path (absent for the task-space field, which follows the exact path).",
        eval: |r| r.budget().and_then(|b| b.geometry).map(|g| g.max),
    },
    Metric {
        name: "contour_distance_mean",
        unit: "rad",
        doc: "The mean distance of the SCARA's joints to the contour over the last complete pass (absent for other robots).",
        eval: |r| contour_distance(r).map(|d| d.0),
    },
    Metric {
        name: "contour_distance_max",
        unit: "rad",
        doc: "The largest distance of the SCARA's joints to the contour over the last complete pass.",
        eval: |r| contour_distance(r).map(|d| d.1),
    },
    Metric {
        name: "limit_share",
        unit: "",
        doc: "The share of the last complete pass's samples with a joint's torque at its limit (the tracker's limits for a tracker's run, the passive controller's for PVFC's; absent without limits).",
        eval: limit_share,
    },
    Metric {
        name: "energy_created",
        unit: "J",
        doc: "The most energy the controller created over any stretch of the run: the largest rise of the energy audit κ_a − κ_a(0) − ΣW (absent without the work columns: a run with faults, contact or a disturbance has them).",
        eval: |r| metrics::energy_created(r.trace),
    },
    Metric {
        name: "energy_owed_at_end",
        unit: "J",
        doc: "The energy the controller owes at the end of the run: the rise of the energy audit from its lowest value to its last (a frozen encoder's debt is settled when it reads again; absent without the work columns).",
        eval: |r| metrics::energy_owed_at_end(r.trace),
    },
    Metric {
        name: "fault_samples",
        unit: "",
        doc: "The samples at which the passive controller's supervision reported a fault (absent without [[faults]]).",
        eval: |r| {
            (!r.scenario.faults.is_empty())
                .then(|| r.trace.fault.iter().filter(|c| **c != 0.0).count() as f64)
        },
    },
    Metric {
        name: "recovery_time",
        unit: "s",
        doc: "The slowest return after a [[faults]] event: from the event's end until U stays at most ten times its level of the half second before it, for 0.2 s (absent without faults).",
        eval: |r| recoveries(r, None).map(|(t, _)| t),
    },
    Metric {
        name: "unrecovered",
        unit: "",
        doc: "The [[faults]] events U did not return from within the run (absent without faults).",
        eval: |r| recoveries(r, None).map(|(_, n)| n as f64),
    },
    recovery_after!(encoder_spike, EncoderSpike),
    recovery_after!(encoder_freeze, EncoderFreeze),
    recovery_after!(non_finite, NonFinite),
    recovery_after!(jitter, Jitter),
    recovery_after!(missed_period, MissedPeriod),
    recovery_after!(dropped_command, DroppedCommand),
    recovery_after!(late_command, LateCommand),
    recovery_after!(torque_limit, TorqueLimit),
    recovery_after!(impact, Impact),
];

/// The metric called `name`.
pub fn metric(name: &str) -> Result<&'static Metric> {
    METRICS.iter().find(|m| m.name == name).ok_or_else(|| {
        let known: Vec<&str> = METRICS.iter().map(|m| m.name).collect();
        SimError::Setting(format!(
            "metric `{name}`: no such metric (the metrics: {})",
            known.join(", ")
        ))
    })
}

/// The metrics called `names` (all of them when `names` is empty), in that order; an
/// unknown or repeated name is an error that names it.
pub fn select(names: &[String]) -> Result<Vec<&'static Metric>> {
    if names.is_empty() {
        return Ok(METRICS.iter().collect());
    }
    let mut out: Vec<&'static Metric> = Vec::with_capacity(names.len());
    for n in names {
        let m = metric(n)?;
        if out.iter().any(|o| o.name == m.name) {
            return Err(SimError::Setting(format!("metric `{n}`: listed twice")));
        }
        out.push(m);
    }
    Ok(out)
}
