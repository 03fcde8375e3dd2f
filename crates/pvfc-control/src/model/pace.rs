//! The pace of a controller along its contour (`pvfc_core::pace`): the speed asked for along
//! the path (the tool's, or the joints'), bounded by the fastest rate `τ̇(τ)` the drives allow,
//! computed on a fine grid and held as a smooth profile `σ(τ)` of [`PACE_KNOTS`] knots that
//! stays at or below it.

use crate::error::{Result, SimError};
use crate::model::feeds::FeedProfile;
use pvfc_core::contour::{Contour, VectorGroup};
use pvfc_core::mechanics::MechanicalSystem;
use pvfc_core::pace::{
    drive_limited_rates, DriveLimits, LearnedPace, MissLearner, PaceProfile, PaceTable, Paced,
    Throttled,
};
use pvfc_core::pacing::ExponentialPacing;

/// The knots of a controller's pace profile.
pub const PACE_KNOTS: usize = 256;

/// The points per period on which the rates are computed (16 per knot).
pub const PACE_GRID: usize = 16 * PACE_KNOTS;

/// A controller's pace profile: none (the paper's uniform pace) or a table.
pub type PaceProfileTable = Option<PaceTable<f64, PACE_KNOTS>>;

/// The knots of a learned pace ([`LearnedPace`]): a scale per 1/64 of the period.
pub const LEARNED_KNOTS: usize = 64;

/// The rows of a [`FieldMissLearner`]'s plan: 4 per knot of the learned pace.
pub const MISS_ROWS: usize = 4 * LEARNED_KNOTS;

/// The learner of the torque the model misses beside a controller whose pace is learned
/// ([`MissLearner`]): its caps are the ceilings of the [`LearnedPace`]'s scales.
pub type FieldMissLearner<const N: usize> = MissLearner<f64, N, LEARNED_KNOTS, MISS_ROWS>;

/// Why `pace_learning.miss` is refused without a pace to plan against.
pub const MISS_WITHOUT_PACE: &str = "pace_learning.miss plans against a pace: give the controller a pace (controller.pace) with torque limits on a closed contour";

/// The self-pacing of the simulator's fields: eq. (21) with an optional pace profile, which
/// a [`pvfc_core::pace::PaceThrottle`] may scale on line and a passive controller may learn
/// lap over lap ([`LearnedPace`]).
pub type FieldPacing = Paced<
    ExponentialPacing<f64>,
    Throttled<f64, LearnedPace<f64, PaceProfileTable, LEARNED_KNOTS>>,
>;

/// Gives `pacing` the pace table `table` of a closed contour of period `period` (its scales,
/// learned or not, back at 1).
pub fn set_pace_table(
    pacing: &mut FieldPacing,
    table: PaceTable<f64, PACE_KNOTS>,
    period: f64,
) -> Result<()> {
    *pacing.profile_mut().profile_mut() = LearnedPace::periodic(Some(table), period)?;
    Ok(())
}

/// The speed asked for along the contour, on the contour at energy level 1.
#[derive(Clone, Debug, PartialEq)]
pub enum PathSpeed {
    /// The tool's speed along its path (m/s): `|J_p(q) ξ_d| τ̇`, `J_p` the linear rows of the
    /// tool's Jacobian (a serial chain's).
    Tool(f64),
    /// The joints' speed (rad/s, m/s for prismatic joints): `|ξ_d| τ̇`.
    Joint(f64),
    /// The tool's speed stretch by stretch (a part program's feeds): on the contour at `τ`,
    /// that of the stretch nearest the tool's position.
    Feeds(FeedProfile),
}

/// A controller's pace along its contour, as plain data: a speed asked for along the path
/// (or the contour's own pace at the energy level), bounded by the fastest pace the drives
/// allow (if their limits are given).
#[derive(Clone, Debug, PartialEq)]
pub struct PaceSettings {
    /// The speed asked for; `None`: `τ̇ = level` (the contour's own parameterisation).
    pub speed: Option<PathSpeed>,
    /// Per-joint torque limits (N·m or N, each > 0); empty: the drives do not bound the pace.
    pub torque_limit: Vec<f64>,
    /// The share of each limit the motion along the contour may use, in (0, 1].
    pub headroom: f64,
    /// The energy level `β` the controller runs at (`τ̇ = β σ(τ)` on the contour).
    pub level: f64,
}

impl PaceSettings {
    /// The limits of an `N`-joint controller that adds `friction` compensation (eq. 35) and,
    /// if `gravity`, its model's `g(q)` to the coupling's torque; `None` without limits.
    pub fn limits<const N: usize>(
        &self,
        friction: Option<&[f64]>,
        gravity: bool,
    ) -> Result<Option<DriveLimits<f64, N>>> {
        if self.torque_limit.is_empty() {
            return Ok(None);
        }
        let setting = |what: String| SimError::Setting(what);
        let limit = super::fixed::<N>(&self.torque_limit, "pace.torque_limit")?;
        let mut limits = DriveLimits::new(limit)
            .map_err(|e| setting(format!("pace.torque_limit: {e}")))?
            .with_headroom(self.headroom)
            .map_err(|e| setting(format!("pace.headroom = {}: {e}", self.headroom)))?
            .with_gravity(gravity);
        if let Some(f) = friction {
            let f = super::fixed::<N>(f, "friction_compensation")?;
            limits = limits.with_friction_compensation(f)?;
        }
        Ok(Some(limits))
    }

    /// The limits of an `N`-joint robot whose drives overcome `friction` (Coulomb and
    /// viscous) and, if `gravity`, `g(q)` on top of the motion's torque; `None` without
    /// limits.
    pub fn limits_against<const N: usize>(
        &self,
        friction: &DriveFriction,
        gravity: bool,
    ) -> Result<Option<DriveLimits<f64, N>>> {
        let coulomb = (!friction.coulomb.is_empty()).then_some(friction.coulomb.as_slice());
        let Some(limits) = self.limits::<N>(coulomb, gravity)? else {
            return Ok(None);
        };
        if friction.viscous.is_empty() {
            return Ok(Some(limits));
        }
        let b = super::fixed::<N>(&friction.viscous, "friction.viscous")?;
        limits
            .with_viscous_friction(b)
            .map(Some)
            .map_err(|e| SimError::Setting(format!("friction.viscous: {e}")))
    }

    /// The rates `τ̇` asked for at [`PACE_GRID`] points of the period: `level`, or the path
    /// speed's.
    fn asked<G, Sys, X, const N: usize>(
        &self,
        system: &Sys,
        contour: &X,
        period: f64,
    ) -> Result<Vec<f64>>
    where
        G: VectorGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        X: Contour<f64, G, N>,
    {
        if !(self.level.is_finite() && self.level > 0.0) {
            return Err(SimError::Setting(format!(
                "the pace's energy level β = {}: finite and > 0",
                self.level
            )));
        }
        let Some(speed) = &self.speed else {
            return Ok(vec![self.level; PACE_GRID]);
        };
        // A constant speed is checked here; each feed where the feeds were read.
        let constant = match speed {
            PathSpeed::Tool(v) => Some((*v, "the tool's speed")),
            PathSpeed::Joint(v) => Some((*v, "the joints' speed")),
            PathSpeed::Feeds(_) => None,
        };
        if let Some((v, name)) = constant {
            if !(v.is_finite() && v > 0.0) {
                return Err(SimError::Setting(format!(
                    "pace.speed = {v}: {name} must be finite and > 0"
                )));
            }
        }
        let chain = match speed {
            PathSpeed::Tool(_) | PathSpeed::Feeds(_) => {
                Some(system.serial_chain().ok_or_else(|| {
                    SimError::Setting(
                        "pace.speed: a tool speed needs a serial chain (a URDF arm)".into(),
                    )
                })?)
            }
            PathSpeed::Joint(_) => None,
        };
        Ok((0..PACE_GRID)
            .map(|j| {
                let c = contour.sample(j as f64 * period / PACE_GRID as f64);
                let q = c.point.coordinates();
                let per_tau = match chain {
                    Some(chain) => {
                        let jac = chain.tool_jacobian_world(&q);
                        (jac.fixed_rows::<3>(0) * c.velocity).norm()
                    }
                    None => c.velocity.norm(),
                };
                let v = match (speed, chain) {
                    (PathSpeed::Tool(v) | PathSpeed::Joint(v), _) => *v,
                    (PathSpeed::Feeds(f), Some(chain)) => {
                        f.speed_at(&chain.tool_pose(&q).translation)
                    }
                    // Not reached: feeds have a chain (checked above).
                    (PathSpeed::Feeds(_), None) => 0.0,
                };
                // Where the path stands still in τ, no rate is too fast for it.
                if per_tau > 1e-12 {
                    v / per_tau
                } else {
                    1e6
                }
            })
            .collect())
    }

    /// The pace profile `σ = τ̇(τ) / level` of `system` along `contour` (period `period`): the
    /// rates asked for, bounded by the drives'.
    pub fn profile<G, Sys, X, const N: usize>(
        &self,
        system: &Sys,
        contour: &X,
        period: f64,
        friction: Option<&[f64]>,
        gravity: bool,
    ) -> Result<PaceTable<f64, PACE_KNOTS>>
    where
        G: VectorGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        X: Contour<f64, G, N>,
    {
        let mut rates = self.asked(system, contour, period)?;
        if let Some(limits) = self.limits::<N>(friction, gravity)? {
            drive_limited_rates(system, contour, &limits, period, &mut rates)?;
        }
        if let Some((j, r)) = rates
            .iter()
            .enumerate()
            .find(|(_, r)| **r <= 1e-6 * self.level)
        {
            return Err(SimError::Setting(format!(
                "the drives cannot move along the contour at τ = {:.4} (fastest rate there {r:.3e})",
                j as f64 * period / PACE_GRID as f64
            )));
        }
        Ok(PaceTable::below(&rates, self.level, PACE_KNOTS, period)?)
    }

    /// The learner of the torque `system`'s model misses along `contour` (period `period`),
    /// on the rows of this pace's plan (the same limits, compensations and rates asked for),
    /// taking `weight` of each lap ([`MissLearner`]), on the heap (its rows are large).
    ///
    /// Errors: no torque limits to plan within ([`MISS_WITHOUT_PACE`]); the plan's.
    pub fn miss_learner<G, Sys, X, const N: usize>(
        &self,
        system: &Sys,
        contour: &X,
        period: f64,
        (friction, gravity): (Option<&[f64]>, bool),
        weight: f64,
    ) -> Result<Box<FieldMissLearner<N>>>
    where
        G: VectorGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        X: Contour<f64, G, N>,
    {
        let Some(limits) = self.limits::<N>(friction, gravity)? else {
            return Err(SimError::Setting(MISS_WITHOUT_PACE.into()));
        };
        let fine = self.asked(system, contour, period)?;
        let every = PACE_GRID / MISS_ROWS;
        let asked = std::array::from_fn(|j| fine[j * every]);
        let learner = MissLearner::new(system, contour, &limits, period, asked, weight)
            .map_err(|e| SimError::Setting(format!("pace_learning.miss = {weight}: {e}")))?;
        Ok(Box::new(learner))
    }

    /// The rates asked for along `contour` (period `period`), without the drives' bound, as
    /// a profile `σ = τ̇(τ) / level`: what a timed tracker that follows a part program's
    /// feeds runs at (`τ̇ = level · σ(τ)`).
    pub fn asked_profile<G, Sys, X, const N: usize>(
        &self,
        system: &Sys,
        contour: &X,
        period: f64,
    ) -> Result<PaceTable<f64, PACE_KNOTS>>
    where
        G: VectorGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        X: Contour<f64, G, N>,
    {
        let rates = self.asked(system, contour, period)?;
        Ok(PaceTable::below(&rates, self.level, PACE_KNOTS, period)?)
    }

    /// The least time of one lap of `contour` (period `period`) that the drives allow at
    /// full use of their limits (headroom 1, whatever this pace keeps) against `plant`'s
    /// friction (and gravity, if `gravity`), at no rate above the one this pace asks for
    /// (its level, or its speed along the path): the time-optimal parameterisation's lap on
    /// [`PACE_GRID`] points, against which a controller's lap time is measured. With the
    /// plant's own friction (not a controller's compensation of it) it is the least lap any
    /// controller can make on that plant at that demand.
    pub fn minimum_lap<G, Sys, X, const N: usize>(
        &self,
        system: &Sys,
        contour: &X,
        period: f64,
        plant: &DriveFriction,
        gravity: bool,
    ) -> Result<f64>
    where
        G: VectorGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        X: Contour<f64, G, N>,
    {
        let full = PaceSettings {
            headroom: 1.0,
            ..self.clone()
        };
        let limits = full.limits_against::<N>(plant, gravity)?.ok_or_else(|| {
            SimError::Setting(
                "pace.torque_limit: a lap's least time needs the drives' limits".into(),
            )
        })?;
        let mut rates = full.asked(system, contour, period)?;
        drive_limited_rates(system, contour, &limits, period, &mut rates)?;
        Ok(lap_time(&rates, period))
    }
}

/// The friction the drives overcome along a contour: per-joint Coulomb levels and viscous
/// coefficients (either empty: none). A plant's, for the least lap time any controller can
/// make on it ([`PaceSettings::minimum_lap`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriveFriction {
    /// Coulomb levels `f_i ≥ 0` (N·m, N).
    pub coulomb: Vec<f64>,
    /// Viscous coefficients `b_i ≥ 0` (N·m·s/rad, N·s/m).
    pub viscous: Vec<f64>,
}

/// The energy level `Ē` that a field paced by `pace` along `contour` needs, with a margin of
/// `2×` for the correction of errors: twice the largest kinetic energy of the suspended field
/// on the contour, `½ σ(τ)² (ξ_dᵀ M ξ_d + 1)` (eq. 6 asks `Ē > ½ V̄ᵀM̄V̄` everywhere the system
/// goes), over [`PACE_GRID`] points of the period.
pub fn energy_for_pace<G, Sys, X, P, const N: usize>(
    system: &Sys,
    contour: &X,
    pace: &P,
    period: f64,
) -> f64
where
    G: VectorGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
    X: Contour<f64, G, N>,
    P: PaceProfile<f64>,
{
    (0..PACE_GRID)
        .map(|j| {
            let tau = j as f64 * period / PACE_GRID as f64;
            let c = contour.sample(tau);
            let (sigma, _) = pace.pace(tau);
            let m = system.inertia(&c.point);
            0.5 * sigma * sigma * (c.velocity.dot(&(m * c.velocity)) + 1.0)
        })
        .fold(0.0, f64::max)
        * 2.0
}

/// The time of one lap at the rates `rates` (`τ̇` at evenly spaced points over `period`),
/// `Σ 2Δ / (τ̇_j + τ̇_{j+1})` (the rate's square moving linearly in `τ`, as the profile's
/// steps assume); infinite if the rate is 0 somewhere.
pub fn lap_time(rates: &[f64], period: f64) -> f64 {
    let n = rates.len();
    let step = period / n as f64;
    (0..n)
        .map(|j| 2.0 * step / (rates[j] + rates[(j + 1) % n]))
        .sum()
}

/// Eq. (21)'s self-pacing with parameter `r`, at the uniform pace.
pub fn uniform_pacing(r: f64) -> Result<FieldPacing> {
    Ok(Paced::new(
        ExponentialPacing::new(r)?,
        Throttled::new(LearnedPace::new(None)),
    ))
}

/// A speed scaling on the drives' torque margin, as plain data: the rule of
/// [`PaceThrottle`](pvfc_core::pace::PaceThrottle). The scale `s ∈ [floor, 1]` follows, with
/// time constant `time_constant`, the target `min(1, (1 − u)/(1 − threshold))` for the
/// largest share `u = max_i |T_i|/L_i` of a limit the (unclamped) command uses: 1 while every
/// torque is below `threshold` of its limit, 0 at the limit. The scaled joint-trajectory
/// controllers of UR and ros2_control slow a trajectory's time this way, from the drives'
/// speed-scaling factor: `[baseline.speed_scaling]` slows the timed tracker's path time by
/// `s`; `[controller.passive.pace_throttle]` slows PVFC's field (its pace `σ`) by `s`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SpeedScaling {
    /// The share of a limit above which the pace slows, in [0, 1).
    pub threshold: f64,
    /// The time constant of the scaling (s, > 0).
    pub time_constant: f64,
    /// The least scaling, in (0, 1].
    pub floor: f64,
}

impl Default for SpeedScaling {
    fn default() -> Self {
        SpeedScaling {
            threshold: 0.8,
            time_constant: 0.05,
            floor: 0.02,
        }
    }
}

impl SpeedScaling {
    /// Checks the numbers as `[baseline.speed_scaling]`.
    pub fn validate(&self) -> Result<()> {
        self.validate_as("baseline.speed_scaling")
    }

    /// Checks the numbers; an error names the key as `key.threshold`, ….
    pub fn validate_as(&self, key: &str) -> Result<()> {
        let bad = |what: String| Err(SimError::Setting(what));
        if !(self.threshold.is_finite() && (0.0..1.0).contains(&self.threshold)) {
            return bad(format!("{key}.threshold = {}: in [0, 1)", self.threshold));
        }
        if !(self.time_constant.is_finite() && self.time_constant > 0.0) {
            return bad(format!(
                "{key}.time_constant = {}: finite and > 0 (s)",
                self.time_constant
            ));
        }
        if !(self.floor.is_finite() && self.floor > 0.0 && self.floor <= 1.0) {
            return bad(format!("{key}.floor = {}: in (0, 1]", self.floor));
        }
        Ok(())
    }

    /// The core's throttle of this rule, at the scale 1 (checked as `key`).
    pub fn throttle(&self, key: &str) -> Result<pvfc_core::pace::PaceThrottle<f64>> {
        self.validate_as(key)?;
        Ok(pvfc_core::pace::PaceThrottle::new(
            self.threshold,
            self.time_constant,
            self.floor,
        )?)
    }
}

/// A pace learned lap over lap, as plain data: the rule of
/// [`PaceLearning`](pvfc_core::pace::PaceLearning) (TOML
/// `[controller.passive.pace_learning]`). Each of the [`LEARNED_KNOTS`] stretches of a closed
/// contour's pace falls, once a lap, where the command passed a limit (by `√(1 + excess)`, at
/// most `fall`), rises where its peak share of a limit stayed below `target` (by
/// `√(target / peak)`, at most `rise`), and differs from its neighbours by at most `slope`,
/// within `[floor, 1]` of the planned pace.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaceLearningSpec {
    /// The peak share of a limit below which a stretch's pace rises, in (0, 1].
    pub target: f64,
    /// The largest fraction a stretch's pace falls in one lap, in [0, 1).
    pub fall: f64,
    /// The largest fraction a stretch's pace rises in one lap (≥ 0).
    pub rise: f64,
    /// The largest difference between neighbouring stretches' scales, in (0, 1].
    pub slope: f64,
    /// The least scale of the planned pace, in (0, 1].
    pub floor: f64,
    /// The share of each lap's measurement of the torque the model misses taken into it, in
    /// [0, 1] ([`FieldMissLearner`]: the pace planned again against it once a lap caps each
    /// stretch's scale); 0 (the default): no such learning. Learned beside the passive
    /// controller wherever it runs ([`crate::model::miss_paced::MissPaced`]).
    #[serde(default)]
    pub miss: f64,
}

impl PaceLearningSpec {
    /// The share of a lap taken into the learned missed torque, if it is learned (`miss > 0`).
    pub fn miss_weight(&self) -> Option<f64> {
        (self.miss > 0.0).then_some(self.miss)
    }

    /// The core's rule (checked as `key`: a bound out of its range is named).
    pub fn rule(&self, key: &str) -> Result<pvfc_core::pace::PaceLearning<f64>> {
        let unit = |x: f64| x.is_finite() && x > 0.0 && x <= 1.0;
        let bad = |what: &str, v: f64, range: &str| {
            Err(SimError::Setting(format!("{key}.{what} = {v}: {range}")))
        };
        if !unit(self.target) {
            return bad("target", self.target, "in (0, 1]");
        }
        if !(self.fall.is_finite() && (0.0..1.0).contains(&self.fall)) {
            return bad("fall", self.fall, "in [0, 1)");
        }
        if !(self.rise.is_finite() && self.rise >= 0.0) {
            return bad("rise", self.rise, "finite and ≥ 0");
        }
        if !unit(self.slope) {
            return bad("slope", self.slope, "in (0, 1]");
        }
        if !unit(self.floor) {
            return bad("floor", self.floor, "in (0, 1]");
        }
        if !(self.miss.is_finite() && (0.0..=1.0).contains(&self.miss)) {
            return bad("miss", self.miss, "in [0, 1] (0: off)");
        }
        Ok(pvfc_core::pace::PaceLearning::new(
            self.target,
            self.fall,
            self.rise,
            self.slope,
            self.floor,
        )?)
    }
}
