//! PVFC for any serial arm whose number of joints is known at run time: its field (a closed
//! joint-space contour with the mixed navigation function, or the task-space field on a tool
//! path, [`crate::model::arm_field`]), self-pacing, the flywheel, and the add-ons (gravity,
//! friction, nominal speed), dispatched into the const-generic core.

use super::fixed;
use crate::error::{Result, SimError};
use crate::model::arm_field::{ArmField, FieldSpec};
use crate::model::evaluation::Evaluation;
pub use crate::model::joint_contour::{DynJointContour, JointContour, JointContourSpec};
use crate::model::miss_paced::MissPaced;
use crate::model::pace::{
    energy_for_pace, set_pace_table, uniform_pacing, DriveFriction, FieldMissLearner,
    PaceLearningSpec, PaceSettings, SpeedScaling, MISS_WITHOUT_PACE,
};
use crate::model::robot::{ChainModel, Robot};
use nalgebra::SVector;
use pvfc_core::augmented::AugmentedState;
use pvfc_core::obstacle::ObstacleSet;
use pvfc_core::passive::{EnergyAccount, PassiveController};
use pvfc_core::prelude::*;

/// The controller of an `N`-joint arm.
pub type ArmControllerN<const N: usize> =
    Controller<f64, JointSpace<f64, N>, SerialChain<f64, N>, ArmField<N>, N>;

/// The settings of an arm controller, as plain data (lengths checked against the robot).
#[derive(Clone, Debug, PartialEq)]
pub struct ArmSettings {
    /// The closed joint-space contour (with the task-space field: the tool path's joint-space
    /// image, for the timed tracker and the figures; its period is the field's).
    pub contour: JointContourSpec,
    /// The field: the joint-space contour's, or the task-space field on a tool path.
    pub field: FieldSpec,
    /// Navigation weights `h_i`, one per joint.
    pub h: Vec<f64>,
    /// Self-pacing `R` of eq. (21) (0: off).
    pub self_pacing: f64,
    /// The energy level `Ē`; 0: sized from the pace ([`energy_for_pace`]).
    pub energy: f64,
    /// The flywheel's inertia `M_F`.
    pub flywheel_inertia: f64,
    /// The coupling gain `γ` (eq. 7); not read when [`coupling_rate`](Self::coupling_rate)
    /// is given.
    pub gamma: f64,
    /// The rate `γβĒ` (1/s) at which the velocity error converges (Remark 1), in place of
    /// `γ`: the controller takes `γ = rate / (βĒ)` ([`coupling_gain`]) with `β` the level it
    /// runs at ([`level`](Self::level)) and `Ē` its energy level, sized from the pace or not.
    /// A coupling rate keeps the controller's stiffness when the energy level changes.
    pub coupling_rate: Option<f64>,
    /// Add `g(q)` to the torque.
    pub gravity_compensation: bool,
    /// Coulomb levels of the friction compensation (eq. 35), one per joint.
    pub friction_compensation: Option<Vec<f64>>,
    /// The velocity band of the friction compensation's sign (0: a pure sign).
    pub friction_band: f64,
    /// Nominal-speed control (eq. 36): `(c, r)`.
    pub nominal_speed: Option<(f64, f64)>,
    /// The nominal speed's integral gain `k_i` (1/s, ≥ 0; 0: the paper's proportional law;
    /// [`NominalSpeed::with_integral`]).
    pub nominal_speed_integral: f64,
    /// The contour parameter to start at.
    pub tau0: f64,
    /// The bound on the field's kinetic energy as a share of `Ē` (in (0, 1);
    /// [`PvfcLaw::set_field_energy_bound`]): beyond it the field is scaled onto it, so that the
    /// law is defined at every state. `None`: no bound (`EnergyTooLow` where the field would
    /// carry more than `Ē`).
    pub field_energy_bound: Option<f64>,
    /// Obstacles the joint-space field keeps the arm away from (Remark 3).
    pub obstacles: Option<crate::obstacles::ObstacleSpec>,
    /// The drive-limited pace: the field slows along the contour to the fastest pace the
    /// drives allow (`pvfc_core::pace`); `None`: the paper's uniform pace.
    pub pace: Option<PaceSettings>,
}

impl ArmSettings {
    /// Settings on `contour` with navigation weights `h` (one per joint) and the defaults
    /// every binding shares: the joint-space field, no self-pacing, `Ē = 10`, `M_F = 1`,
    /// `γ = 1`, gravity compensation on, no friction compensation, nominal speed, obstacles or
    /// pace, `τ₀ = 0`. Change a field with struct update syntax:
    /// `ArmSettings { energy: 40.0, ..ArmSettings::new(contour, h) }`.
    pub fn new(contour: JointContourSpec, h: Vec<f64>) -> Self {
        ArmSettings {
            contour,
            field: FieldSpec::Joint,
            h,
            self_pacing: 0.0,
            energy: 10.0,
            flywheel_inertia: 1.0,
            gamma: 1.0,
            coupling_rate: None,
            gravity_compensation: true,
            friction_compensation: None,
            friction_band: 0.0,
            nominal_speed: None,
            nominal_speed_integral: 0.0,
            tau0: 0.0,
            field_energy_bound: None,
            obstacles: None,
            pace: None,
        }
    }

    /// The energy level `β` the controller runs at: the nominal speed `r` of eq. (36), which
    /// holds it there, or 1.
    pub fn level(&self) -> f64 {
        self.nominal_speed.map_or(1.0, |(_, r)| r)
    }

    /// The coupling gain `γ` for the energy level `energy`: `gamma`, or the one of
    /// `coupling_rate` ([`coupling_gain`]).
    pub fn gamma_at(&self, energy: f64) -> Result<f64> {
        match self.coupling_rate {
            None => Ok(self.gamma),
            Some(rate) => coupling_gain(rate, self.level(), energy),
        }
    }
}

/// The largest coupling rate `γβĒ` taken (1/s): a million corrections of the velocity error
/// per second, beyond what any sampled controller follows (a 1 kHz loop goes unstable near
/// 1,600/s on the SCARA).
pub const MAX_COUPLING_RATE: f64 = 1e6;

/// The coupling gain `γ` of eq. (7) whose velocity error converges at `rate = γβĒ` (1/s):
/// with the flywheel holding the augmented kinetic energy at `β²Ē`, the coupling's
/// correction of `q̇_a − βV_a` has the rate `γβĒ` (Remark 1; about 2–4 × that in the
/// measured closed loop). `level` is `β`, `energy` is `Ē`.
pub fn coupling_gain(rate: f64, level: f64, energy: f64) -> Result<f64> {
    if !(rate > 0.0 && rate <= MAX_COUPLING_RATE) {
        return Err(setting(format!(
            "coupling_rate = {rate}: in (0, {MAX_COUPLING_RATE:e}] (1/s)"
        )));
    }
    let gamma = rate / (level * energy);
    match gamma.is_finite() && gamma > 0.0 {
        true => Ok(gamma),
        false => Err(setting(format!(
            "coupling_rate = {rate}: at the level β = {level} and energy Ē = {energy}, γ = rate / (βĒ) = {gamma} is not a finite number > 0"
        ))),
    }
}

/// What one control step gives, with the numbers a log wants.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmStep {
    /// Motor torques (N·m, N).
    pub torque: Vec<f64>,
    /// `U(E)`; with obstacles, its composition `φ` with their barrier.
    pub potential: f64,
    /// `β`.
    pub beta: f64,
    /// `κ_a` at the state the torque was computed at.
    pub kinetic_energy: f64,
    /// `τ` (wrapped), `τ̇`, `q̇_F` before the step.
    pub internal: (f64, f64, f64),
}

/// The numbers of one control step besides the torque ([`ArmController::step_into`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepDiagnostics {
    /// `U(E)`; with obstacles, its composition `φ` with their barrier.
    pub potential: f64,
    /// `β`.
    pub beta: f64,
    /// `κ_a` at the state the torque was computed at.
    pub kinetic_energy: f64,
    /// `τ` (wrapped), `τ̇`, `q̇_F` before the step.
    pub internal: (f64, f64, f64),
}

crate::dof_enum! {
    /// An arm controller for 1 to 8 joints.
    #[derive(Clone, Debug)]
    pub enum ArmController of ArmControllerN
}

macro_rules! on_arm {
    ($self:expr, $c:ident, $N:ident => $body:expr) => {
        crate::on_joints!(ArmController, $self, $c, $N => $body)
    };
}

fn setting(message: String) -> SimError {
    SimError::Setting(message)
}

/// [`arm_controller`] on the heap, built in a stack frame of its own (not inlined into the
/// dispatch on the number of joints, whose frame would otherwise hold every `N`'s value).
#[inline(never)]
fn arm_controller_boxed<const N: usize>(
    chain: &SerialChain<f64, N>,
    s: &ArmSettings,
) -> Result<ArmController>
where
    ArmController: From<ArmControllerN<N>>,
{
    Ok(ArmController::from(arm_controller::<N>(*chain, s)?))
}

/// Builds the controller of an `N`-joint chain.
pub fn arm_controller<const N: usize>(
    chain: SerialChain<f64, N>,
    s: &ArmSettings,
) -> Result<ArmControllerN<N>> {
    let kinds = chain.kinds();
    if !s.tau0.is_finite() {
        return Err(setting(format!(
            "tau0 = {}: the contour parameter's start must be finite",
            s.tau0
        )));
    }
    let contour = s.contour.build(kinds)?;
    let mut pacing = uniform_pacing(s.self_pacing)?;
    let mut energy = s.energy;
    if let Some(p) = &s.pace {
        let period = s.contour.period().ok_or_else(|| {
            setting("pace: a pace along the contour needs a closed contour (a period)".into())
        })?;
        let friction = s.friction_compensation.as_deref();
        let table = p.profile(&chain, &contour, period, friction, s.gravity_compensation)?;
        if energy == 0.0 {
            energy = energy_for_pace(&chain, &contour, &table, period);
        }
        set_pace_table(&mut pacing, table, period)?;
    }
    if energy == 0.0 {
        return Err(setting(
            "energy = 0 sizes the energy level from the pace; give a pace (pace.speed)".into(),
        ));
    }
    let field = match &s.field {
        FieldSpec::Joint => {
            let navigation = JointNavigation::new(fixed::<N>(&s.h, "h")?, kinds)?;
            let set = match &s.obstacles {
                None => ObstacleSet::empty(),
                Some(o) => {
                    let far = JointSpace::new(SVector::repeat(std::f64::consts::PI), kinds);
                    o.build(Some(chain), navigation.value(&far))?
                }
            };
            ArmField::Joint(SuspendedField::new(contour, navigation, pacing).with_obstacles(set))
        }
        FieldSpec::Task(_) if s.obstacles.is_some() => {
            return Err(setting(
                "obstacles: the task-space field (contour.cartesian.field = \"task\") does not take obstacles yet; use the joint-space field".into(),
            ))
        }
        FieldSpec::Task(t) => {
            let period = s.contour.period().ok_or_else(|| {
                setting("contour: the task-space field needs a closed contour (a period)".into())
            })?;
            ArmField::Task {
                field: Box::new(t.build(chain, pacing, period)?),
                image: contour,
            }
        }
    };
    let flywheel = Flywheel::new(s.flywheel_inertia, energy)?;
    let law = PvfcLaw::new(chain, field, flywheel, s.gamma_at(energy)?)?;
    let mut ctl = Controller::new(law).starting_at_rest(s.tau0);
    if s.gravity_compensation {
        ctl = ctl.with_gravity_compensation();
    }
    if let Some(f) = &s.friction_compensation {
        ctl = ctl.with_friction_compensation(
            FrictionCompensation::new(fixed::<N>(f, "friction_compensation")?)?
                .with_band(s.friction_band)?,
        );
    }
    if let Some((c, r)) = s.nominal_speed {
        ctl = ctl
            .with_nominal_speed(NominalSpeed::new(c, r)?.with_integral(s.nominal_speed_integral)?);
    }
    // (On the controller, in place: an arm's law is large, and moving it through a builder
    // is a copy on the stack of an unoptimised build.)
    if let Some(share) = s.field_energy_bound {
        ctl.set_field_energy_bound(share).map_err(|e| {
            setting(format!(
                "field_energy_bound = {share}: a share of the energy level in (0, 1) ({e})"
            ))
        })?;
    }
    first_step_is_finite(&ctl, s)?;
    Ok(ctl)
}

/// Refuses, where it is built, a controller whose settings are each finite but together beyond
/// what a double holds (an energy of 1e308, a flywheel of 1e-308 kg·m², a contour traced in
/// 1e-300 of `τ`): its law at rest on the contour's start must be finite, or every step would
/// fail and blame the measured state.
fn first_step_is_finite<const N: usize>(ctl: &ArmControllerN<N>, s: &ArmSettings) -> Result<()> {
    let st = ctl.state();
    let start = AugmentedState {
        q: ctl.law().field().joint_contour().point(st.tau),
        v: SVector::zeros(),
        tau: st.tau,
        tau_dot: st.tau_dot,
        flywheel_speed: st.flywheel_speed,
    };
    let finite = match ctl.evaluate(&start) {
        Ok((torque, out)) => {
            torque.robot.iter().all(|x| x.is_finite())
                && out.beta.is_finite()
                && out.kinetic_energy.is_finite()
        }
        // Another error (an energy level below the field's kinetic energy there, say) is the
        // state's to report, as a step does, unless its number overflowed (a field traced in
        // 1e-300 of τ has a kinetic energy of NaN).
        Err(e) => {
            e.kind() != pvfc_core::ErrorKind::NonFinite && e.value().is_none_or(f64::is_finite)
        }
    };
    match finite && st.flywheel_speed.is_finite() {
        true => Ok(()),
        false => Err(setting(format!(
            "settings: the law is not a finite number at rest on the contour's start (energy {}, flywheel_inertia {}, gamma {}, self_pacing {}, the contour's period {:?}): together they are beyond what a double holds",
            s.energy,
            s.flywheel_inertia,
            s.gamma,
            s.self_pacing,
            s.contour.period()
        ))),
    }
}

/// The fastest rates `τ̇` the drives allow at `points` evenly spaced points of one period of
/// the joint contour `contour` for `robot` (`pvfc_core::pace::drive_limited_rates`): `pace`'s
/// torque limits and headroom, at most `pace.level`, with `friction` (a controller's
/// compensation, eq. 35, or a plant's Coulomb and viscous friction) and gravity (if
/// `gravity`) counted against the limits.
pub fn drive_limited_rates(
    robot: &Robot,
    contour: &JointContourSpec,
    pace: &PaceSettings,
    friction: &DriveFriction,
    gravity: bool,
    points: usize,
) -> Result<Vec<f64>> {
    let period = contour.period().ok_or_else(|| {
        setting("contour: the drive-limited rates need a closed contour (a period)".into())
    })?;
    if !(pace.level.is_finite() && pace.level > 0.0) {
        return Err(setting(format!(
            "pace.level = {}: finite and > 0",
            pace.level
        )));
    }
    let mut rates = vec![pace.level; points];
    crate::on_joints!(ChainModel, robot.model(), c, N => {
        let built = contour.build(c.kinds())?;
        let limits = pace.limits_against::<N>(friction, gravity)?.ok_or_else(|| {
            setting("torque_limit: the drive-limited rates need the drives' limits".into())
        })?;
        pvfc_core::pace::drive_limited_rates(c.as_ref(), &built, &limits, period, &mut rates)?;
    });
    Ok(rates)
}

/// The least time of one lap of the settings' joint contour that `pace`'s drives allow at
/// full use of their limits ([`PaceSettings::minimum_lap`]), for `robot` under gravity
/// against the plant's friction `plant`.
pub fn minimum_lap(
    robot: &Robot,
    s: &ArmSettings,
    pace: &PaceSettings,
    plant: &DriveFriction,
) -> Result<f64> {
    let period = s
        .contour
        .period()
        .ok_or_else(|| setting("contour: a lap needs a closed contour (a period)".into()))?;
    crate::on_joints!(ChainModel, robot.model(), c, N => {
        let contour = s.contour.build(c.kinds())?;
        pace.minimum_lap(c.as_ref(), &contour, period, plant, true)
    })
}

impl ArmController {
    /// The controller of `robot` with the given settings.
    pub fn new(robot: &Robot, s: &ArmSettings) -> Result<Self> {
        Ok(crate::on_joints!(ChainModel, robot.model(), c, N => {
            arm_controller_boxed::<N>(c, s)?
        }))
    }

    /// The number of joints.
    pub fn dof(&self) -> usize {
        on_arm!(self, _c, N => N)
    }

    /// This controller with the internal states `state` gives for its flywheel.
    pub fn with_internal(self, state: impl FnOnce(&Flywheel<f64>) -> InternalState<f64>) -> Self {
        on_arm!(self, c, N => {
            let s = state(c.law().flywheel());
            ArmController::from(c.with_state(s))
        })
    }

    /// One control step at the measured `(q, q̇)`: the torque, and the internal states advanced
    /// over `dt`. On error the state is unchanged.
    pub fn step(&mut self, q: &[f64], v: &[f64], dt: f64) -> Result<ArmStep> {
        let mut torque = vec![0.0; self.dof()];
        let d = self.step_into(q, v, dt, &mut torque)?;
        Ok(ArmStep {
            torque,
            potential: d.potential,
            beta: d.beta,
            kinetic_energy: d.kinetic_energy,
            internal: d.internal,
        })
    }

    /// [`step`](Self::step) writing the torque into `torque` (one entry per joint): allocates
    /// nothing, for real-time callers (the C ABI). On error the state and `torque` are
    /// unchanged.
    pub fn step_into(
        &mut self,
        q: &[f64],
        v: &[f64],
        dt: f64,
        torque: &mut [f64],
    ) -> Result<StepDiagnostics> {
        on_arm!(self, c, N => {
            if torque.len() != N {
                return Err(setting(format!("torque: {} entries for {N} joints", torque.len())));
            }
            let kinds = c.law().system().kinds();
            let q = JointSpace::new(fixed::<N>(q, "q")?, kinds);
            let out = c.step(&q, &fixed::<N>(v, "v")?, dt)?;
            torque.copy_from_slice(out.torque.as_slice());
            Ok(StepDiagnostics {
                potential: out.diagnostics.potential,
                beta: out.diagnostics.beta,
                kinetic_energy: out.diagnostics.kinetic_energy,
                internal: (out.state.tau, out.state.tau_dot, out.state.flywheel_speed),
            })
        })
    }

    /// The law at a full augmented state (pure): the full torque with its add-ons and the
    /// coupling's quantities ([`Evaluation`]).
    pub fn evaluate(&self, q: &[f64], v: &[f64], internal: (f64, f64, f64)) -> Result<Evaluation> {
        on_arm!(self, c, N => {
            let kinds = c.law().system().kinds();
            let s = AugmentedState {
                q: JointSpace::new(fixed::<N>(q, "q")?, kinds),
                v: fixed::<N>(v, "v")?,
                tau: internal.0,
                tau_dot: internal.1,
                flywheel_speed: internal.2,
            };
            let (t, o) = c.evaluate(&s)?;
            Evaluation::from_core::<_, N, { N + 2 }>(&t, &o)
        })
    }

    /// `x_d(τ)`: the joint contour's point at `τ` (with the task-space field: the tool path's
    /// joint-space image).
    pub fn contour_point(&self, tau: f64) -> Vec<f64> {
        on_arm!(self, c, N => c.law().field().joint_contour().point(tau).coords().as_slice().to_vec())
    }

    /// The energy level `Ē` (J): the settings', or the one sized from the pace
    /// ([`energy_for_pace`]) when they give 0.
    pub fn energy_level(&self) -> f64 {
        on_arm!(self, c, N => c.law().flywheel().energy())
    }

    /// The internal states `(τ, τ̇, q̇_F, laps)`.
    pub fn state(&self) -> (f64, f64, f64, i64) {
        on_arm!(self, c, N => {
            let s = c.state();
            (s.tau, s.tau_dot, s.flywheel_speed, s.laps)
        })
    }

    /// This controller in the passive digital mode ([`pvfc_core::passive`]), with its
    /// internal states as they are now; `settings` are those it was built from (the learner
    /// of the torque the model misses, `pace_learning.miss`, plans on their pace).
    pub fn passive(&self, o: &PassiveOptions, settings: &ArmSettings) -> Result<PassiveArm> {
        Ok(on_arm!(self, c, N => o.build_boxed::<N>(c, settings)?))
    }
}

/// The settings of the passive digital mode as plain data (lengths checked against the
/// robot): see [`PassiveController`]'s builders.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassiveOptions {
    /// Per-joint torque limits (N·m, N; each > 0); `None`: no limits.
    pub torque_limit: Option<Vec<f64>>,
    /// Per-joint encoder resolution (rad, m; each ≥ 0) charged to the storage; `None`: exact
    /// positions.
    pub encoder_resolution: Option<Vec<f64>>,
    /// The velocity estimate's filter time constant (s, ≥ 0).
    pub velocity_filter: f64,
    /// The storage the tank keeps in hand (J, ≥ 0).
    pub reserve: f64,
    /// The bounds every sample is checked against; `None`: no supervision (a non-finite
    /// reading is an error, every other reading is believed).
    pub supervision: Option<SupervisionOptions>,
    /// The field's pace scaled on the torque margin (needs `torque_limit`); `None`: the
    /// pace as planned.
    pub pace_throttle: Option<SpeedScaling>,
    /// The field's pace learned lap over lap on the torque margin (needs `torque_limit` and
    /// a pace planned on a closed contour); `None`: the pace as planned.
    pub pace_learning: Option<PaceLearningSpec>,
}

/// The bounds of [`Supervision`] as plain data: what a reading can be, for the passive
/// controller to tell a fault from motion (TOML `[controller.passive.supervision]`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupervisionOptions {
    /// The fastest each joint can move (rad/s, m/s; each > 0), with a margin.
    pub max_speed: Vec<f64>,
    /// The most each joint can be accelerated (rad/s², m/s²; each > 0), with a margin;
    /// `None`: only the speed is checked, and no encoder is found frozen.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_acceleration: Option<Vec<f64>>,
    /// The shortest and the longest period the controller accepts (s, `0 < min ≤ max`).
    pub period: (f64, f64),
}

impl SupervisionOptions {
    /// Checks the bounds for a `dof`-joint arm: one speed (and acceleration) bound per joint,
    /// each finite and > 0, and `0 < min ≤ max` for the period; the error names the key
    /// (`supervision.max_speed`, …).
    pub fn validate(&self, dof: usize) -> Result<()> {
        let lists = [
            ("max_speed", Some(&self.max_speed)),
            ("max_acceleration", self.max_acceleration.as_ref()),
        ];
        for (name, list) in lists {
            let Some(list) = list else { continue };
            if list.len() != dof {
                return Err(setting(format!(
                    "supervision.{name}: {} entries for a {dof}-joint robot",
                    list.len()
                )));
            }
            if !list.iter().all(|x| x.is_finite() && *x > 0.0) {
                return Err(setting(format!("supervision.{name}: each finite and > 0")));
            }
        }
        let (lo, hi) = self.period;
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
            return Err(setting(
                "supervision.period: [min, max] finite, 0 < min ≤ max (s)".into(),
            ));
        }
        Ok(())
    }

    /// The core's bounds for an `N`-joint arm (checked by [`validate`](Self::validate)).
    pub fn build<const N: usize>(&self) -> Result<Supervision<f64, N>> {
        self.validate(N)?;
        let s = Supervision::new(
            fixed::<N>(&self.max_speed, "max_speed")?,
            self.period.0,
            self.period.1,
        )?;
        Ok(match &self.max_acceleration {
            Some(a) => s.with_max_acceleration(fixed::<N>(a, "max_acceleration")?)?,
            None => s,
        })
    }
}

impl PassiveOptions {
    /// The share of a lap taken into the learned missed torque (`pace_learning.miss`), if it
    /// is learned (> 0).
    pub fn miss_weight(&self) -> Option<f64> {
        self.pace_learning.and_then(|l| l.miss_weight())
    }

    /// The passive controller of `c` (built from `settings`) on the heap, built in a stack
    /// frame of its own (see [`arm_controller_boxed`]).
    #[inline(never)]
    fn build_boxed<const N: usize>(
        &self,
        c: &ArmControllerN<N>,
        settings: &ArmSettings,
    ) -> Result<PassiveArm>
    where
        PassiveArm: From<PassiveArmN<N>>,
    {
        // The rule checked first: the learner's plan is not made for a weight out of range.
        if let Some(l) = &self.pace_learning {
            l.rule("pace_learning")?;
        }
        let miss = arm_miss_learner(self.miss_weight(), c, settings)?;
        Ok(PassiveArm::from(self.controller(c.clone(), miss)?))
    }

    /// The passive controller around `controller` with these options, and `miss` learning
    /// beside it (given exactly when [`miss_weight`](Self::miss_weight) is: build it with
    /// [`PaceSettings::miss_learner`]).
    pub fn controller<G, Sys, F, const N: usize>(
        &self,
        controller: Controller<f64, G, Sys, F, N>,
        miss: Option<Box<FieldMissLearner<N>>>,
    ) -> Result<MissPaced<G, Sys, F, N>>
    where
        G: VectorGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        F: VelocityField<f64, G, N>,
    {
        let mut p = PassiveController::new(controller)
            .with_velocity_filter(self.velocity_filter)?
            .with_reserve(self.reserve)?;
        if let Some(l) = &self.torque_limit {
            p = p.with_torque_limits(fixed::<N>(l, "torque_limit")?)?;
        }
        if let Some(d) = &self.encoder_resolution {
            p = p.with_encoder_resolution(fixed::<N>(d, "encoder_resolution")?)?;
        }
        if let Some(s) = &self.supervision {
            p = p.with_supervision(s.build::<N>()?);
        }
        if let Some(t) = &self.pace_throttle {
            if self.torque_limit.is_none() {
                return Err(SimError::Setting(
                    "pace_throttle reads the drives' limits: give torque_limit".into(),
                ));
            }
            p = p.with_pace_throttle(t.throttle("pace_throttle")?)?;
        }
        if let Some(l) = &self.pace_learning {
            let rule = l.rule("pace_learning")?;
            if self.torque_limit.is_none() {
                return Err(SimError::Setting(
                    "pace_learning reads the drives' limits: give torque_limit".into(),
                ));
            }
            p = p.with_pace_learning(rule)?;
        }
        if self.miss_weight().is_some() != miss.is_some() {
            return Err(SimError::Setting(
                "pace_learning.miss: the learner is given exactly when the miss is learned (> 0)"
                    .into(),
            ));
        }
        Ok(MissPaced::new(p, miss))
    }
}

/// The learner of the torque the model misses (`pace_learning.miss` = `weight`) beside the
/// arm controller `ctl` built from `settings`, on the plan of their pace; `None` for no
/// weight.
///
/// Errors: a weight without a pace (`settings.pace`) on a closed contour, or without the
/// pace's torque limits; those of [`PaceSettings::miss_learner`].
pub fn arm_miss_learner<const N: usize>(
    weight: Option<f64>,
    ctl: &ArmControllerN<N>,
    settings: &ArmSettings,
) -> Result<Option<Box<FieldMissLearner<N>>>> {
    let Some(weight) = weight else {
        return Ok(None);
    };
    let (Some(pace), Some(period)) = (&settings.pace, settings.contour.period()) else {
        return Err(SimError::Setting(MISS_WITHOUT_PACE.into()));
    };
    let contour = ctl.law().field().joint_contour();
    let compensation = (
        settings.friction_compensation.as_deref(),
        settings.gravity_compensation,
    );
    let system = ctl.law().system();
    pace.miss_learner::<_, _, _, N>(system, contour, period, compensation, weight)
        .map(Some)
}

/// The passive digital controller of an `N`-joint arm.
pub type PassiveArmN<const N: usize> =
    MissPaced<JointSpace<f64, N>, SerialChain<f64, N>, ArmField<N>, N>;

/// What one passive step gives: the torque to hold and the period's energy account.
#[derive(Clone, Debug, PartialEq)]
pub struct PassiveArmStep {
    /// Motor torques to hold for the next period (after the torque limits).
    pub torque: Vec<f64>,
    /// The velocity the law used (measured, or estimated from the positions).
    pub velocity: Vec<f64>,
    /// `U(E)`; with obstacles, its composition `φ` with their barrier.
    pub potential: f64,
    /// The period's energy account.
    pub energy: EnergyAccount<f64>,
    /// The fault detected at this sample (with supervision); the torque is then zero.
    pub fault: Option<Fault>,
}

crate::dof_enum! {
    /// A passive arm controller for 1 to 8 joints ([`ArmController::passive`]).
    #[derive(Clone, Debug)]
    pub enum PassiveArm of PassiveArmN
}

impl PassiveArm {
    /// The number of joints.
    pub fn dof(&self) -> usize {
        crate::on_joints!(PassiveArm, self, _c, N => N)
    }

    /// One step at the measured positions `q` (and velocities `v`, if measured), with
    /// `applied` the torque the drive applied over the last period (`None`: the command).
    /// On error nothing changes.
    pub fn step(
        &mut self,
        q: &[f64],
        v: Option<&[f64]>,
        applied: Option<&[f64]>,
        dt: f64,
    ) -> Result<PassiveArmStep> {
        let n = self.dof();
        let (mut torque, mut velocity) = (vec![0.0; n], vec![0.0; n]);
        let (potential, energy, fault) =
            self.step_into(q, v, applied, dt, &mut torque, Some(&mut velocity))?;
        Ok(PassiveArmStep {
            torque,
            velocity,
            potential,
            energy,
            fault,
        })
    }

    /// [`step`](Self::step) writing the torque (and, if given, the velocity the law used) into
    /// the caller's slices: allocates nothing. Returns `U`, the period's energy account and
    /// the fault detected, if any. On error nothing changes.
    pub fn step_into(
        &mut self,
        q: &[f64],
        v: Option<&[f64]>,
        applied: Option<&[f64]>,
        dt: f64,
        torque: &mut [f64],
        velocity: Option<&mut [f64]>,
    ) -> Result<(f64, EnergyAccount<f64>, Option<Fault>)> {
        crate::on_joints!(PassiveArm, self, c, N => {
            if torque.len() != N || velocity.as_ref().is_some_and(|x| x.len() != N) {
                return Err(SimError::Setting(format!(
                    "torque, velocity: {N} entries each"
                )));
            }
            let kinds = c.controller().controller().law().system().kinds();
            let q = JointSpace::new(fixed::<N>(q, "q")?, kinds);
            let v = v.map(|v| fixed::<N>(v, "v")).transpose()?;
            let u = applied.map(|u| fixed::<N>(u, "applied")).transpose()?;
            let out = c.step(&q, v.as_ref(), u.as_ref(), dt)?;
            torque.copy_from_slice(out.torque.as_slice());
            if let Some(w) = velocity {
                w.copy_from_slice(out.velocity.as_slice());
            }
            Ok((out.diagnostics.potential, out.energy, out.fault))
        })
    }

    /// The storage `½τ̇² + ½M_F q̇_F²` as accounted (J).
    pub fn storage(&self) -> f64 {
        crate::on_joints!(PassiveArm, self, c, N => c.storage())
    }

    /// Whether the torque the model misses is learned beside it (`pace_learning.miss`).
    pub fn learns_miss(&self) -> bool {
        crate::on_joints!(PassiveArm, self, c, N => c.miss_learner().is_some())
    }

    /// Whether every sample is checked against bounds ([`SupervisionOptions`]).
    pub fn supervised(&self) -> bool {
        crate::on_joints!(PassiveArm, self, c, N => c.controller().supervision().is_some())
    }

    /// The scale of the field's pace the next step uses (the pace throttle's, in
    /// `[floor, 1]`; 1 without a throttle).
    pub fn pace_scale(&self) -> f64 {
        crate::on_joints!(PassiveArm, self, c, N => c.controller().pace_throttle().map_or(1.0, |t| t.scale()))
    }

    /// The internal states `(τ, τ̇, q̇_F, laps)`.
    pub fn state(&self) -> (f64, f64, f64, i64) {
        crate::on_joints!(PassiveArm, self, c, N => {
            let s = c.controller().controller().state();
            (s.tau, s.tau_dot, s.flywheel_speed, s.laps)
        })
    }
}
