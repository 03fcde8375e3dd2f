//! The torque the model misses along a closed contour, learned lap over lap, and the pace
//! planned again against it.
//!
//! A plant is never its model: friction left uncompensated, links heavier or lighter than
//! their parameters. The pace planned on the model ([`super::drive_limits`]) keeps a headroom
//! `h` of each limit for what it misses, but the miss is not spread evenly: where it asks for
//! more than `1 − h` of a limit the drives run out, and a [`super::LearnedPace`] that learns
//! a speed, not a torque, creeps back into the limit lap after lap.
//!
//! A `MissLearner` keeps the rows of the plan ([`MotionRow`]: the model's motion torque
//! `a τ̈ + b τ̇² + d τ̇ + c`, computed once) at `N` evenly spaced points `τ_j = j·P/N` of the
//! period `P`, and measures, at each of `K` knots `τ_k = k·P/K` (`N` a multiple of `K`) and
//! per joint, the mean over the steps nearest that knot of what the drives were commanded
//! beyond the model's torque at the pace the robot had (the row nearest `τ`):
//!
//! `m_k = ∫ (u − a τ̈ − b τ̇² − d τ̇ − c) dt / ∫ dt`.
//!
//! On a robot that follows its contour, what the coupling adds to the model's torque is what
//! the plant needs beyond the model. Each lap (when `τ` wraps) the lap's means are taken into
//! the learned miss (`m ← m + w (m_lap − m)`, a knot not visited keeps its value), and the
//! plan is made again on the rows with the miss added ([`drive_limited_rates_on_rows`]; at a
//! row between two knots, the miss interpolated linearly); the **cap** of knot `k` is the
//! least ratio, over the rows nearest it, of that plan's rate to the plan without a miss on
//! the same rows, at most 1: the
//! grid's error cancels in the ratio, and the headroom of the plan
//! is kept, now on what the model and the miss leave. A [`super::LearnedPace`] takes the caps
//! ([`super::PaceProfile::set_caps`]) as the ceilings of its scales, knot by knot as `τ`
//! leaves each one, so that the pace never jumps. The first lap (the start from rest) is not
//! measured.
//!
//! The caller runs it beside the controller, after each step (the control step is unchanged);
//! the lap's plan, about `N × 3 × 64` row tests, runs in the step at which `τ` wraps (a host
//! loop; on a microcontroller, between steps). Passivity does not depend on it: the caps only
//! shape the field's pace (eq. 27: the coupling is workless for any field).

use super::drive_limits::{drive_limited_rates_on_rows, DriveLimits, MotionRow};
use super::learned::nearest_knot;
use crate::contour::Contour;
use crate::error::{Error, ErrorKind, Result};
use crate::lie::{LieGroup, Tangent};
use crate::mechanics::MechanicalSystem;
use crate::scalar::cast;
use crate::Real;

/// The torque the model misses, per knot and joint, learned lap over lap on a closed contour,
/// and the caps on the pace it implies (see the [module](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct MissLearner<T: Real, const D: usize, const K: usize, const N: usize> {
    rows: [MotionRow<T, D>; N],
    /// The rates asked for at the rows, and the plan on the rows without a miss.
    asked: [T; N],
    planned: [T; N],
    /// The miss at the rows, interpolated between the knots.
    spread: [Tangent<T, D>; N],
    period: T,
    /// The share `w ∈ (0, 1]` of a lap's measurement taken into the miss.
    weight: T,
    /// This lap's `∫ (u − T_model) dt` and `∫ dt` per knot.
    sums: [Tangent<T, D>; K],
    time: [T; K],
    /// The learned miss, whether each knot has one, and the caps.
    miss: [Tangent<T, D>; K],
    known: [bool; K],
    caps: [T; K],
    /// The knot of the last step recorded, and the laps begun since the first step.
    last: Option<usize>,
    laps: u32,
}

impl<T: Real, const D: usize, const K: usize, const N: usize> MissLearner<T, D, K, N> {
    /// The learner of `contour` (period `period`) driven by `system`'s model within `limits`,
    /// the plan's rates at the rows being `asked` (the pace the controller was planned at,
    /// `τ̇` on the contour), taking `weight` of each lap's measurement.
    ///
    /// Errors: those of [`Self::from_rows`].
    pub fn new<G, Sys, X>(
        system: &Sys,
        contour: &X,
        limits: &DriveLimits<T, D>,
        period: T,
        asked: [T; N],
        weight: T,
    ) -> Result<Self>
    where
        G: LieGroup<T, D>,
        Sys: MechanicalSystem<T, G, D>,
        X: Contour<T, G, D>,
    {
        let step = period / cast::<T>(N as f64);
        let rows = core::array::from_fn(|j| {
            MotionRow::at(system, contour, limits, step * cast::<T>(j as f64))
        });
        Self::from_rows(rows, asked, period, weight)
    }

    /// The learner on rows computed at `τ_j = j·period/N` ([`MotionRow::at`]).
    ///
    /// Errors: `InvalidParameter` for fewer than 3 knots, `N` not a multiple of `K`, a
    /// non-finite or non-positive period, a weight outside (0, 1], a rate asked for that is
    /// not finite and positive, or rows on which the drives cannot hold the contour at rest.
    pub fn from_rows(
        rows: [MotionRow<T, D>; N],
        asked: [T; N],
        period: T,
        weight: T,
    ) -> Result<Self> {
        if !(K >= 3
            && N.is_multiple_of(K)
            && weight.is_finite()
            && weight > T::zero()
            && weight <= T::one())
        {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "MissLearner: at least 3 knots, a multiple of them as rows, a weight in (0, 1]",
            ));
        }
        let mut planned = asked;
        drive_limited_rates_on_rows(&rows, None, period, &mut planned)?;
        Ok(MissLearner {
            rows,
            asked,
            planned,
            spread: [Tangent::zeros(); N],
            period,
            weight,
            sums: [Tangent::zeros(); K],
            time: [T::zero(); K],
            miss: [Tangent::zeros(); K],
            known: [false; K],
            caps: [T::one(); K],
            last: None,
            laps: 0,
        })
    }

    /// The caps on the pace's scales at the knots, in (0, 1] (1 until a lap has been learned).
    pub fn caps(&self) -> &[T; K] {
        &self.caps
    }

    /// The learned miss at the knots (zero where none is known yet).
    pub fn miss(&self) -> &[Tangent<T, D>; K] {
        &self.miss
    }

    /// The torque the model says the motion needs at `τ` (the row nearest it), at `τ̇`, `τ̈`.
    pub fn model_torque(&self, tau: T, tau_dot: T, tau_ddot: T) -> Tangent<T, D> {
        self.rows[nearest_knot::<T, N>(self.period, tau)].torque(tau_ddot, tau_dot)
    }

    /// Records a step of `dt` at `τ`, `τ̇ = tau_dot`, `τ̈ = tau_ddot`, whose command was
    /// `command` (the drives' torque, compensations included). When `τ` has wrapped to a new
    /// lap, the lap is learned and the pace planned again: `true` when the caps changed.
    /// A reading that is not finite is not recorded.
    pub fn record(
        &mut self,
        tau: T,
        tau_dot: T,
        tau_ddot: T,
        command: &Tangent<T, D>,
        dt: T,
    ) -> bool {
        let finite = crate::scalar::all_finite_in(command.iter(), [&tau, &tau_dot, &tau_ddot, &dt]);
        if !(finite && dt >= T::zero()) {
            return false;
        }
        let k = nearest_knot::<T, K>(self.period, tau);
        let wrapped = self.last.is_some_and(|l| k + K / 2 < l);
        self.last = Some(k);
        let mut changed = false;
        if wrapped {
            self.laps = self.laps.saturating_add(1);
            // The first lap ends the start from rest: not learned.
            if self.laps >= 2 {
                changed = self.learn_lap();
            }
            self.sums = [Tangent::zeros(); K];
            self.time = [T::zero(); K];
        }
        if self.laps >= 1 {
            let model = self.model_torque(tau, tau_dot, tau_ddot);
            self.sums[k] += (command - model) * dt;
            self.time[k] += dt;
        }
        changed
    }

    /// Takes the lap's means into the miss and plans again; `true` when the caps changed. A
    /// plan that fails (a miss beyond a limit at rest) leaves the caps as they were.
    fn learn_lap(&mut self) -> bool {
        for k in 0..K {
            if self.time[k] > T::zero() {
                let lap = self.sums[k] / self.time[k];
                self.miss[k] = if self.known[k] {
                    self.miss[k] + (lap - self.miss[k]) * self.weight
                } else {
                    lap
                };
                self.known[k] = true;
            }
        }
        let per = N / K;
        for (j, m) in self.spread.iter_mut().enumerate() {
            let (k, f) = (j / per, cast::<T>((j % per) as f64 / per as f64));
            *m = self.miss[k] + (self.miss[(k + 1) % K] - self.miss[k]) * f;
        }
        let mut rates = self.asked;
        if drive_limited_rates_on_rows(&self.rows, Some(&self.spread), self.period, &mut rates)
            .is_err()
        {
            return false;
        }
        let before = self.caps;
        // Each knot's cap: the least ratio over the rows nearest it.
        for (k, cap) in self.caps.iter_mut().enumerate() {
            let mut least = T::one();
            for i in 0..per {
                let j = (k * per + N - per / 2 + i) % N;
                let p = self.planned[j];
                if p > T::zero() {
                    least = least.min(rates[j] / p);
                }
            }
            *cap = least.max(cast::<T>(1e-3));
        }
        self.caps != before
    }
}
