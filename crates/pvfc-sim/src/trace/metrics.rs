//! Numbers computed from traces: the measures behind the paper's claims.

use crate::trace::Trace;
use nalgebra::Vector2;
use pvfc_core::contour::Lissajous;

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
