//! Numbers computed from traces: the measures behind the paper's claims.

use crate::trace::Trace;
use nalgebra::{Vector2, Vector3};
use pvfc_core::contour::{ConstantRate, Contour, Lissajous};
use pvfc_core::lie::{LieGroup, So3};

/// A rigid body's attitude error at each sample: the angle `‖log(R_d(τ)ᵀ R)‖` (rad) between
/// the body's attitude `R = exp(q̂)` (the trace's rotation vector) and the contour's at the
/// sample's `τ`. A sample whose `q` is not three numbers gives NaN.
pub fn attitude_errors(trace: &Trace, contour: &ConstantRate<f64, So3<f64>, 3>) -> Vec<f64> {
    (0..trace.len())
        .map(|i| match <[f64; 3]>::try_from(&trace.q[i][..]) {
            Ok(r) => {
                let body = So3::exp(&Vector3::from(r));
                let desired = contour.sample(trace.tau[i]).point;
                desired.inverse().compose(&body).log().norm()
            }
            Err(_) => f64::NAN,
        })
        .collect()
}

/// The last complete pass of the contour in a trace: the sample range with
/// `τ ∈ [kP, (k+1)P)` for the largest `k` whose pass the trace covers.
pub fn last_pass(trace: &Trace, period: f64) -> Option<std::ops::Range<usize>> {
    let end = *trace.tau.last()?;
    let k = (end / period).floor() - 1.0;
    if k < 0.0 {
        return None;
    }
    let (lo, hi) = (k * period, (k + 1.0) * period);
    let start = trace.tau.iter().position(|&t| t >= lo)?;
    let stop = trace.tau.iter().position(|&t| t >= hi)?;
    Some(start..stop + 1)
}

/// The mean of `U(E)` over one pass, `∫U dτ / P` over the last complete pass (the paper
/// plots `U` against `τ` over one pass). `None` if the trace does not cover a pass.
pub fn mean_potential_over_pass(trace: &Trace, period: f64) -> Option<f64> {
    let r = last_pass(trace, period)?;
    let (tau, u) = (&trace.tau[r.clone()], &trace.potential[r]);
    let integral: f64 = tau
        .windows(2)
        .zip(u.windows(2))
        .map(|(t, u)| (t[1] - t[0]) * 0.5 * (u[0] + u[1]))
        .sum();
    let span = tau.last()? - tau.first()?;
    (span > 0.0).then(|| integral / span)
}

/// Time to go once round the last complete pass (s).
pub fn pass_duration(trace: &Trace, period: f64) -> Option<f64> {
    let r = last_pass(trace, period)?;
    Some(trace.t[r.end - 1] - trace.t[r.start])
}

/// Distance (joint space, rad) from `q` to the nearest point of the contour: a grid search
/// over one period refined by Newton's method on `d/dτ ‖q − x_d(τ)‖² = 0`.
pub fn contour_distance(contour: &Lissajous<f64, 2>, period: f64, q: &Vector2<f64>) -> f64 {
    contour_closest(contour, period, q).1
}

/// The nearest point of the contour to `q`: its `τ` and the distance (as
/// [`contour_distance`]).
pub fn contour_closest(contour: &Lissajous<f64, 2>, period: f64, q: &Vector2<f64>) -> (f64, f64) {
    const GRID: usize = 720;
    let d2 = |tau: f64| (q - contour.coordinates(tau)[0]).norm_squared();
    let mut best = (0.0, f64::INFINITY);
    for k in 0..GRID {
        let tau = period * k as f64 / GRID as f64;
        let d = d2(tau);
        if d < best.1 {
            best = (tau, d);
        }
    }
    let mut tau = best.0;
    for _ in 0..6 {
        let [x, dx, ddx] = contour.coordinates(tau);
        let r = x - q;
        let g = r.dot(&dx);
        let hss = dx.dot(&dx) + r.dot(&ddx);
        if hss <= 0.0 {
            break;
        }
        tau -= g / hss;
    }
    let refined = d2(tau);
    if refined <= best.1 {
        (tau, refined.sqrt())
    } else {
        (best.0, best.1.sqrt())
    }
}

/// How an arm followed its contour over the samples in `range`, from one nearest-point
/// search per sample ([`contour_closest`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourFollowing {
    /// Mean and largest distance to the contour (rad).
    pub error: (f64, f64),
    /// The mean speed the arm made along the contour (rad/s): the joint velocity's component
    /// along the contour's unit tangent at the nearest point, integrated (trapezoidal) and
    /// divided by the time. Motion across the contour or back and forth along it adds
    /// nothing, so an arm that does not follow the contour makes about 0 whatever the pace of
    /// its reference.
    pub speed: f64,
}

/// [`ContourFollowing`] over the samples in `range`.
pub fn contour_following(
    trace: &Trace,
    contour: &Lissajous<f64, 2>,
    period: f64,
    range: std::ops::Range<usize>,
) -> ContourFollowing {
    let range = range.start..range.end.min(trace.len());
    // Per sample: the distance and the velocity along the tangent at the nearest point.
    let samples: Vec<(f64, f64)> = range
        .clone()
        .map(|i| {
            let q = Vector2::from_column_slice(&trace.q[i]);
            let (tau, d) = contour_closest(contour, period, &q);
            let tangent = contour.coordinates(tau)[1];
            let n = tangent.norm();
            let along = if n > 0.0 {
                tangent.dot(&Vector2::from_column_slice(&trace.v[i])) / n
            } else {
                0.0
            };
            (d, along)
        })
        .collect();
    let mean = samples.iter().map(|s| s.0).sum::<f64>() / samples.len().max(1) as f64;
    let max = samples.iter().map(|s| s.0).fold(0.0, f64::max);
    let speed = if samples.len() < 2 {
        0.0
    } else {
        let progress: f64 = (1..samples.len())
            .map(|k| {
                let i = range.start + k;
                0.5 * (trace.t[i] - trace.t[i - 1]) * (samples[k].1 + samples[k - 1].1)
            })
            .sum();
        progress / (trace.t[range.end - 1] - trace.t[range.start]).max(f64::MIN_POSITIVE)
    };
    ContourFollowing {
        error: (mean, max),
        speed,
    }
}

/// The mean speed the arm made along the contour over the samples in `range` (rad/s; see
/// [`ContourFollowing::speed`]).
pub fn speed_along_contour(
    trace: &Trace,
    contour: &Lissajous<f64, 2>,
    period: f64,
    range: std::ops::Range<usize>,
) -> f64 {
    contour_following(trace, contour, period, range).speed
}

/// Mean and maximum distance to the contour over the samples in `range`.
pub fn contour_error(
    trace: &Trace,
    contour: &Lissajous<f64, 2>,
    period: f64,
    range: std::ops::Range<usize>,
) -> (f64, f64) {
    contour_following(trace, contour, period, range).error
}

/// The number of peaks of `U` over the last complete pass: the separate excursions of `U` above
/// `fraction` of its largest value over the pass, counted around the closed pass (an excursion
/// across the pass's start counts once). `None` if the trace does not cover a pass.
pub fn potential_peaks(trace: &Trace, period: f64, fraction: f64) -> Option<usize> {
    let u = &trace.potential[last_pass(trace, period)?];
    let top = u.iter().copied().fold(0.0, f64::max);
    if top <= 0.0 {
        return Some(0);
    }
    let above: Vec<bool> = u.iter().map(|&x| x > fraction * top).collect();
    let n = above.len();
    let starts = (0..n)
        .filter(|&i| above[i] && !above[(i + n - 1) % n])
        .count();
    Some(starts.max(usize::from(above.iter().all(|a| *a))))
}

/// Straightness of the approach to the contour: the straight distance from the start to the
/// first point within `reach` of `x_d(τ)` (U below `reach_u`), divided by the length of the
/// path travelled until then. 1 is a straight line.
pub fn approach_straightness(trace: &Trace, reach_u: f64) -> Option<(f64, usize)> {
    let end = trace.potential.iter().position(|&u| u < reach_u)?;
    let dist = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
            .sqrt()
    };
    let length: f64 = (1..=end).map(|i| dist(&trace.q[i], &trace.q[i - 1])).sum();
    let chord = dist(&trace.q[end], &trace.q[0]);
    (length > 0.0).then(|| (chord / length, end))
}

/// The energy audit of a run with friction only: the largest `|κ_a(t) − κ_a(0) − ∫F_fᵀq̇ dt|`
/// relative to `κ_a(0)` (trapezoidal work integral at the trace's sampling).
pub fn energy_audit(trace: &Trace) -> f64 {
    let e0 = trace.energy[0];
    let mut work = 0.0;
    let mut worst: f64 = 0.0;
    for i in 1..trace.len() {
        let dt = trace.t[i] - trace.t[i - 1];
        work += 0.5 * dt * (trace.friction_power[i] + trace.friction_power[i - 1]);
        worst = worst.max((trace.energy[i] - e0 - work).abs());
    }
    worst / e0
}

/// The largest relative deviation of `κ_a` from its initial value.
pub fn energy_drift(trace: &Trace) -> f64 {
    let e0 = trace.energy[0];
    trace
        .energy
        .iter()
        .map(|e| (e - e0).abs() / e0)
        .fold(0.0, f64::max)
}

/// The least-squares slope of `ln|y − target|` against `t`, over the samples with `t` in
/// `window`: the exponential rate at which `y` approaches `target` (negative when it does).
/// `None` with fewer than two samples, or if `y` equals `target` there.
pub fn log_gap_slope(
    t: &[f64],
    y: &[f64],
    target: f64,
    window: std::ops::RangeInclusive<f64>,
) -> Option<f64> {
    least_squares_slope(
        t.iter()
            .zip(y)
            .filter(|(t, y)| window.contains(*t) && **y != target)
            .map(|(t, y)| (*t, (y - target).abs().ln())),
    )
}

/// The time constant (s) with which `y` settles to its final level `y_∞` (the mean over the
/// last quarter of the samples, so `y` must have settled by then): `−1 / slope` of `ln|y − y_∞|` over the samples from the first
/// at which the gap is below half the initial gap `|y(0) − y_∞|` until the first below a
/// hundredth of it. `None` if `y` starts at its level (gap below `1e-9`, or `1e-9 |y_∞|`), if
/// it never comes within those bounds, or if the fitted slope is not negative.
pub fn settling_time_constant(t: &[f64], y: &[f64]) -> Option<f64> {
    let tail = &y[y.len() - y.len() / 4..];
    let level = tail.iter().sum::<f64>() / tail.len() as f64;
    let gap = |v: f64| (v - level).abs();
    let gap0 = gap(*y.first()?);
    if gap0 <= 1e-9 * level.abs().max(1.0) {
        return None;
    }
    let from = y.iter().position(|&v| gap(v) < 0.5 * gap0)?;
    let to = from + y[from..].iter().position(|&v| gap(v) < 0.01 * gap0)?;
    let slope = least_squares_slope(
        t[from..to]
            .iter()
            .zip(&y[from..to])
            .map(|(t, v)| (*t, gap(*v).ln())),
    )?;
    (slope < 0.0).then(|| -1.0 / slope)
}

/// The slope of the least-squares line through `points`; `None` with fewer than two distinct
/// abscissae.
fn least_squares_slope(points: impl Iterator<Item = (f64, f64)> + Clone) -> Option<f64> {
    let (n, sx, sy) = points.clone().fold((0.0, 0.0, 0.0), |(n, sx, sy), (x, y)| {
        (n + 1.0, sx + x, sy + y)
    });
    if n < 2.0 {
        return None;
    }
    let (mx, my) = (sx / n, sy / n);
    let (num, den) = points.fold((0.0, 0.0), |(num, den), (x, y)| {
        (num + (x - mx) * (y - my), den + (x - mx) * (x - mx))
    });
    (den > 0.0).then(|| num / den)
}

/// The velocity-field convergence of Remark 1 measured on a run without environment forces
/// ([`velocity_field_convergence`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityFieldConvergence {
    /// The rate `2γβĒ` that Remark 1 gives for `‖e_β‖_a` near the field (1/s).
    pub predicted_rate: f64,
    /// The measured rate of `‖e_β‖_a = √(2W_β)` near the field: minus the least-squares slope
    /// of `½ ln W_β` over the samples with `μ > 0.999` and `W_β` above its rounding (1/s).
    pub measured_rate: f64,
    /// The largest `|d ln W_β/dt + 4Ēγβμ| / (4Ēγβ)` over the samples (central differences,
    /// `μ = 1 − W_β/(4κ_a)`): how far the run is from eq. (13) at any moment.
    pub worst_deviation: f64,
    /// The number of samples in the rate's window.
    pub samples: usize,
}

/// Eq. (13) and Remark 1 on a trace without environment forces (`κ_a`, hence `β`, constant),
/// for the law's `γ` and `Ē`: `Ẇ_β = −4Ēγβμ W_β`, and `‖e_β‖_a` converging at `2γβĒ` near
/// the field. Samples whose `W_β` is below `1e-10 κ_a` (its rounding) are left out. `None` if
/// fewer than three samples are left or none is near the field.
pub fn velocity_field_convergence(
    trace: &Trace,
    gamma: f64,
    energy_level: f64,
) -> Option<VelocityFieldConvergence> {
    let (t, w, kappa) = (&trace.t, &trace.w_beta, &trace.energy);
    let resolved = |i: usize| w[i] > 1e-10 * kappa[i];
    let mu = |i: usize| pvfc_core::coupling::convergence_factor(kappa[i], w[i]);
    let beta = trace.beta.first().copied()?;
    let scale = 4.0 * energy_level * gamma * beta;
    let mut worst: f64 = 0.0;
    for i in 1..trace.len().saturating_sub(1) {
        if resolved(i - 1) && resolved(i) && resolved(i + 1) {
            let slope = (w[i + 1].ln() - w[i - 1].ln()) / (t[i + 1] - t[i - 1]);
            worst = worst.max((slope + scale * mu(i)).abs() / scale);
        }
    }
    let near: Vec<usize> = (0..trace.len())
        .filter(|&i| resolved(i) && mu(i) > 0.999)
        .collect();
    let slope = least_squares_slope(near.iter().map(|&i| (t[i], 0.5 * w[i].ln())))?;
    Some(VelocityFieldConvergence {
        predicted_rate: 2.0 * gamma * beta * energy_level,
        measured_rate: -slope,
        worst_deviation: worst,
        samples: near.len(),
    })
}

/// What a run with contact did to the world and to itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSummary {
    /// The largest measured contact force (sum of normal forces, N).
    pub peak_force: f64,
    /// The most energy the arm had put into the contact at any time, `max_t −∫F_eᵀq̇` (J).
    pub energy_pumped: f64,
    /// The work the environment did on the arm over the run, `∫F_eᵀq̇` (J).
    pub work_contact: f64,
    /// The energy scale of the audit: `κ_a(0)`, or the largest energy of the run if that
    /// is 0 (the baseline starts at rest).
    pub energy_scale: f64,
    /// `max_t |E(t) − E(0) − W_contact − W_friction − W_controller| / energy_scale`.
    pub audit: f64,
    /// The largest audit residual (J): energy that appeared unaccounted for (> 0 means the
    /// loop created energy; a sampled-data controller can).
    pub audit_max: f64,
    /// The smallest audit residual (J): energy that disappeared unaccounted for.
    pub audit_min: f64,
    /// `min_t (E(0) + W_controller(t) + W_gravity(t) + W_contact(t))`: the passivity bound on
    /// what the arm can give the world is `−W_contact(t) ≤ E(0) + W_controller(t) +
    /// W_gravity(t)` (W_controller = 0 for PVFC without add-ons; with gravity compensation,
    /// an add-on, W_controller + W_gravity ≈ 0); this is its margin, ≥ 0 when it holds.
    pub passivity_margin: f64,
    /// `min_t (E(0) + W_contact(t) + W_controller(t) + W_gravity(t) − E(t))`: the arm's
    /// energy never exceeds its initial energy plus the work done on it (friction only takes
    /// away); ≥ 0 (up to the audit's residual) when it holds.
    pub energy_bound_margin: f64,
    /// The time of the last sample in contact (s), if any.
    pub last_contact: Option<f64>,
}

/// The [`ContactSummary`] of a run with contact columns.
pub fn contact_summary(trace: &Trace) -> Option<ContactSummary> {
    let c = trace.contact.as_ref()?;
    let e0 = *trace.energy.first()?;
    let scale = if e0 > 0.0 {
        e0
    } else {
        trace
            .energy
            .iter()
            .cloned()
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE)
    };
    let fold_max = |xs: &mut dyn Iterator<Item = f64>| xs.fold(f64::NEG_INFINITY, f64::max);
    let fold_min = |xs: &mut dyn Iterator<Item = f64>| xs.fold(f64::INFINITY, f64::min);
    let n = trace.len();
    let residual = c.audit_residual(&trace.energy);
    // The energy given to the arm by the contact, the controller's add-ons and gravity (an
    // arm's gravity compensation is an add-on: the two cancel, up to the hold of a sampled
    // controller; the planar arm has no gravity work).
    let supplied = |i: usize| c.work_contact[i] + c.work_controller[i] + c.work_gravity[i];
    Some(ContactSummary {
        peak_force: fold_max(&mut c.normal_force.iter().cloned()).max(0.0),
        energy_pumped: fold_max(&mut c.work_contact.iter().map(|w| -w)).max(0.0),
        work_contact: *c.work_contact.last()?,
        energy_scale: scale,
        audit: fold_max(&mut residual.iter().map(|r| r.abs())) / scale,
        audit_max: fold_max(&mut residual.iter().cloned()),
        audit_min: fold_min(&mut residual.iter().cloned()),
        passivity_margin: fold_min(&mut (0..n).map(|i| e0 + supplied(i))),
        energy_bound_margin: fold_min(&mut (0..n).map(|i| e0 + supplied(i) - trace.energy[i])),
        last_contact: (0..n).rev().find(|&i| c.contacts_at(i)).map(|i| trace.t[i]),
    })
}

/// The largest velocity-field error `‖e_β‖_a = √(2W_β)` (eq. 12) over the samples with
/// `from ≤ t < to`: under a bounded disturbance, the ultimate bound of section II's
/// robustness properties. `None` if no sample is in the window.
pub fn velocity_field_error_bound(trace: &Trace, from: f64, to: f64) -> Option<f64> {
    trace
        .t
        .iter()
        .zip(&trace.w_beta)
        .filter(|(t, _)| (from..to).contains(*t))
        .map(|(_, w)| velocity_field_error(*w))
        .reduce(f64::max)
}

/// The velocity-field error `‖e_β‖_a = √(2W_β)` (eq. 12) of a sample's `W_β` (the trace's
/// `w_beta` column).
pub fn velocity_field_error(w_beta: f64) -> f64 {
    (2.0 * w_beta.max(0.0)).sqrt()
}

/// What the passive controller's supervision reported over a run ([`fault_summary`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FaultSummary {
    /// The samples at fault, by the code of the trace's `fault` column (index `c − 1` for code
    /// `c`: non-finite, period, speed, acceleration, frozen).
    pub samples: [usize; 5],
    /// The largest energy the controller created at any sample, `max_t` of the audit
    /// `κ_a(t) − κ_a(0) − ΣW(t)` (J; the run's first value is 0, so this is ≥ 0).
    pub created: f64,
}

/// The [`FaultSummary`] of a run with the work columns (`None` without them).
pub fn fault_summary(trace: &Trace) -> Option<FaultSummary> {
    let mut samples = [0; 5];
    for code in &trace.fault {
        let i = *code as usize;
        if (1..=5).contains(&i) {
            samples[i - 1] += 1;
        }
    }
    Some(FaultSummary {
        samples,
        created: audit_rises(trace)?.highest,
    })
}

/// What the energy audit `a = κ_a − κ_a(0) − ΣW` of a run with the work columns did, from
/// one pass over it: its largest value, its largest rise over any stretch, and its rise from
/// its lowest value to its last (J).
#[derive(Clone, Copy, Debug, PartialEq)]
struct AuditRises {
    highest: f64,
    created: f64,
    owed_at_end: Option<f64>,
}

fn audit_rises(trace: &Trace) -> Option<AuditRises> {
    let c = trace.contact.as_ref()?;
    let a = c.audit_residual(&trace.energy);
    let (mut low, mut created, mut highest) = (f64::INFINITY, 0.0f64, 0.0f64);
    for x in &a {
        low = low.min(*x);
        created = created.max(x - low);
        highest = highest.max(*x);
    }
    let owed_at_end = a.last().map(|end| (end - low).max(0.0));
    Some(AuditRises {
        highest,
        created,
        owed_at_end,
    })
}

/// The most energy the controller created over any stretch of a run with the work columns:
/// `max_{s ≤ t} (a(t) − a(s))` for the audit `a = κ_a − κ_a(0) − ΣW` (J, ≥ 0). The audit of
/// a passive controller falls (its charges: the encoders', a fault's unseen work); a rise is
/// energy it gave that its storage did not pay for.
pub fn energy_created(trace: &Trace) -> Option<f64> {
    audit_rises(trace).map(|r| r.created)
}

/// The energy the controller owes at the end of a run with the work columns: the rise of the
/// audit from its lowest value to its last, `a(end) − min_t a(t)` (J, ≥ 0). A frozen encoder
/// that the supervision does not see lets the controller give energy it has not paid for
/// ([`energy_created`] shows it); the debt is settled when the encoder reads again, so this is
/// what remains unpaid.
pub fn energy_owed_at_end(trace: &Trace) -> Option<f64> {
    audit_rises(trace)?.owed_at_end
}

/// How long `U` takes to come back after a fault: from the end of the event's window
/// (`[at, at + duration)`, at least one period) to the first sample from which `U` stays at
/// most ten times its largest value over the half second before the event, for `hold`
/// seconds (or to the run's end). `None`: it never does within the run.
pub fn recovery_time(trace: &Trace, at: f64, duration: f64, period: f64, hold: f64) -> Option<f64> {
    let t = &trace.t;
    let first = |x: f64| t.iter().position(|s| *s >= x - 1e-9 * period);
    let k0 = first(at)?;
    let start = first(at - 0.5).unwrap_or(0).min(k0);
    let pre = trace.potential[start..k0]
        .iter()
        .copied()
        .fold(0.0, f64::max);
    let end = first(at + duration.max(period))?;
    let limit = 10.0 * pre;
    let mut k = end;
    while k < t.len() {
        let until = t[k] + hold;
        match (k..t.len())
            .take_while(|&j| t[j] <= until)
            .find(|&j| trace.potential[j] > limit)
        {
            None => return Some(t[k] - t[end]),
            Some(bad) => k = bad + 1,
        }
    }
    None
}
