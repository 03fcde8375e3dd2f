//! Scenarios: everything one run needs, as plain data (a TOML file, a Python dict) or built
//! in ([`presets`]). Nothing here reads a URDF or builds a model: [`build`] does, once.

use crate::contact::ContactSpec;
use crate::error::{Result, SimError};
use crate::model::arm::{PassiveOptions, SupervisionOptions};
use crate::model::feeds::FeedProfile;
use crate::model::miss_paced::MissPaced;
use crate::model::pace::{FieldMissLearner, PaceSettings, PathSpeed};
pub use crate::model::pace::{PaceLearningSpec, SpeedScaling};
use crate::plant::faults::FaultEvent;
use pvfc_core::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub mod build;
pub mod least_lap;
pub mod legacy;
pub mod operator;
pub mod plant;
pub use pvfc_control::model::contour::{AttitudeContourSpec, ContourSpec};
pub use pvfc_control::obstacles;
pub mod preset_id;
pub mod presets;

pub use build::{ArmSystem, System};
pub use plant::{
    direct_drive_arm, ChainSpec, PlantSpec, RigidBodySpec, RobotKind, RobotSpec,
    ScaraParameterSpec, ScaraSpec,
};

/// The velocity field of the planar arm's scenarios (section V): the Lissajous contour, the
/// torus navigation function of eq. (17), exponential self-pacing (eq. 21) with the
/// drive-limited pace of `[controller.pace]`, if any.
pub type PaperField = SuspendedField<
    f64,
    Torus<f64, 2>,
    Lissajous<f64, 2>,
    TorusNavigation<f64, 2>,
    crate::model::pace::FieldPacing,
    2,
    pvfc_core::obstacle::ObstacleSet<f64, 2>,
>;

/// The controller of the planar arm's scenarios ([`Scenario::controller`]).
pub type PaperController = Controller<f64, Torus<f64, 2>, Scara<f64>, PaperField, 2>;

/// That controller in the passive digital mode (`pvfc_core::passive`), with the learner of
/// the torque its model misses beside it if asked for (`pace_learning.miss`).
pub type PaperPassiveController = MissPaced<Torus<f64, 2>, Scara<f64>, PaperField, 2>;

/// The velocity field of a rigid body's attitude (section IV-B, the satellite): a rotation at
/// constant rate `R_d(τ) = R₀ exp(τ ω̂)`, the navigation function of SO(3) (eq. 26),
/// exponential self-pacing (eq. 21).
pub type AttitudeField = SuspendedField<
    f64,
    So3<f64>,
    ConstantRate<f64, So3<f64>, 3>,
    So3Navigation<f64>,
    ExponentialPacing<f64>,
    3,
>;

/// The controller of a rigid body's attitude scenario ([`Scenario::attitude_controller`]).
pub type AttitudeController = Controller<f64, So3<f64>, RigidBody<f64>, AttitudeField, 3>;

/// The suffix of the timed baseline's trace name (`NAME-timed`).
pub const TIMED_SUFFIX: &str = "-timed";

/// The suffix of a speed-scaling tracker's trace name (`[baseline.speed_scaling]`).
pub const SCALED_SUFFIX: &str = "-scaled";

/// Nominal-speed control, eq. (36).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NominalSpeedSpec {
    /// Gain `c` (the paper: 0.01).
    pub c: f64,
    /// Nominal speed `r`.
    pub r: f64,
    /// The gain `k_i` (1/s, ≥ 0) of the integral of the speed's error, which takes `β` to
    /// `r` against friction (`pvfc_core::coupling::NominalSpeed::with_integral`; sampled
    /// mode); 0 (the default): the paper's proportional law.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub integral: f64,
}

/// `true` for 0 (a key left out of a file).
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// The PVFC controller.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ControllerSpec {
    /// Self-pacing parameter `R` of eq. (21).
    pub self_pacing: f64,
    /// Navigation weights `h_i` of eq. (17).
    pub h: Vec<f64>,
    /// Energy level `Ē` of eq. (6).
    pub energy: f64,
    /// Flywheel inertia `M_F`.
    pub flywheel_inertia: f64,
    /// Coupling gain `γ` of eq. (7); `coupling_rate`, when given, takes its place.
    pub gamma: f64,
    /// The rate `γβĒ` (1/s) at which the velocity error converges (Remark 1), in place of
    /// `gamma`: `γ = coupling_rate / (βĒ)` with `β` the nominal speed `r` of eq. (36) (or 1)
    /// and `Ē` the energy level, also when it is sized from the pace (`energy = 0`). Keeps
    /// the controller's stiffness when the energy level changes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coupling_rate: Option<f64>,
    /// Controller rate (Hz) in the sampled-data mode.
    pub rate: f64,
    /// Friction compensation levels of eq. (35), if any (N·m).
    #[serde(default)]
    pub friction_compensation: Option<Vec<f64>>,
    /// The velocity band of the compensation's sign (0: a pure sign).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_band: Option<f64>,
    /// Gravity compensation `T += g(q)` (URDF arms; default on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity_compensation: Option<bool>,
    /// Nominal-speed control of eq. (36), if any.
    #[serde(default)]
    pub nominal_speed: Option<NominalSpeedSpec>,
    /// The bound on the suspended field's kinetic energy as a share of `Ē`, in (0, 1): where
    /// the field would carry more (an arm thrown far off its contour by a fault) it is scaled
    /// onto that level, and the law is defined at every state
    /// (`pvfc_core::coupling::PvfcLaw::set_field_energy_bound`). Absent: no bound, and such a
    /// state ends the run with "energy level too low".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field_energy_bound: Option<f64>,
    /// The passive digital controller (`[controller.passive]`, sampled mode): the energy it
    /// gives the arm accounted at the samples (`pvfc_core::passive`), with optional torque
    /// limits, encoder quantisation and position-only measurement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passive: Option<PassiveSpec>,
    /// The drive-limited pace (`[controller.pace]`): the field slows along the contour to
    /// the fastest pace the drives allow (`pvfc_core::pace`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pace: Option<PaceSpec>,
}

impl ControllerSpec {
    /// The energy level `β` the controller runs at for its coupling rate: the nominal speed
    /// `r` of eq. (36), which holds it there, or 1 (the rule of
    /// [`ArmSettings::level`](crate::model::arm::ArmSettings::level)).
    pub fn level(&self) -> f64 {
        self.nominal_speed.map_or(1.0, |n| n.r)
    }
}

/// `[controller.pace]`: the field's pace along the contour: a speed asked for along the path,
/// bounded by what the drives allow (`pvfc_core::pace::drive_limits`), computed from the
/// controller's model of the robot at the energy level the controller runs at (the nominal
/// speed `r` of eq. (36) if set, else the level it starts at).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PaceSpec {
    /// The speed asked for along the path: the tool's (m/s) along a Cartesian path, the
    /// joints' (rad/s, the norm of `q̇`) along a joint-space contour; none: the contour's own
    /// pace. With `controller.energy = 0`, the energy level is sized from it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// Per-joint torque limits (N·m, each > 0); empty: `[controller.passive]`'s, or none.
    pub torque_limit: Vec<f64>,
    /// The share of each limit the motion along the contour may use, in (0, 1]; the rest is
    /// kept for the correction of errors and for what the model misses.
    pub headroom: f64,
}

impl Default for PaceSpec {
    fn default() -> Self {
        PaceSpec {
            speed: None,
            torque_limit: Vec::new(),
            headroom: 0.8,
        }
    }
}

impl PaceSpec {
    /// This pace as plain data for a controller with the settings `controller`, starting at
    /// the energy level `level`, along a Cartesian path (`tool`: the speed is the tool's) or a
    /// joint-space contour: the limits given here, or else `[controller.passive]`'s.
    pub fn settings(
        &self,
        controller: &ControllerSpec,
        level: f64,
        tool: bool,
    ) -> Result<PaceSettings> {
        self.settings_with_feeds(controller, level, tool, None)
    }

    /// As [`settings`](Self::settings), the speed asked for being a part program's `feeds`
    /// when given (its moves without F at `speed`).
    pub fn settings_with_feeds(
        &self,
        controller: &ControllerSpec,
        level: f64,
        tool: bool,
        feeds: Option<FeedProfile>,
    ) -> Result<PaceSettings> {
        let torque_limit = match (&self.torque_limit, &controller.passive) {
            (l, _) if !l.is_empty() => l.clone(),
            (_, Some(p)) => p.torque_limit.clone(),
            _ => Vec::new(),
        };
        if torque_limit.is_empty() && self.speed.is_none() && feeds.is_none() {
            return Err(SimError::Setting(
                "controller.pace: give a speed (controller.pace.speed) or torque limits (controller.pace.torque_limit or controller.passive.torque_limit)".into(),
            ));
        }
        let speed = match feeds {
            Some(f) => Some(PathSpeed::Feeds(f)),
            None => self.speed.map(|v| match tool {
                true => PathSpeed::Tool(v),
                false => PathSpeed::Joint(v),
            }),
        };
        Ok(PaceSettings {
            speed,
            torque_limit,
            headroom: self.headroom,
            level,
        })
    }
}

/// `[controller.passive]`: the digital controller of `pvfc_core::passive`, and what the
/// drive it runs on does to its measurements and torques.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PassiveSpec {
    /// Per-joint torque limits (N·m, each > 0); empty: none.
    pub torque_limit: Vec<f64>,
    /// The encoders' counts per turn: the measured positions are rounded to `2π/counts`;
    /// none: exact positions.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub encoder_counts: Option<f64>,
    /// Measure positions only; the controller estimates the velocities.
    pub positions_only: bool,
    /// The time constant of the velocity estimate's low-pass filter (s, ≥ 0; 0: the plain
    /// backward difference).
    pub velocity_filter: f64,
    /// The storage the tank keeps in hand (J, ≥ 0).
    pub reserve: f64,
    /// `[controller.passive.supervision]`: the bounds every sample is checked against (a
    /// reading or period that breaks one is a fault, answered with zero torque); none: no
    /// supervision.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub supervision: Option<SupervisionOptions>,
    /// `[controller.passive.pace_throttle]`: the field's pace scaled on the torque margin
    /// the controller measures (`pvfc_core::pace::throttle`; needs `torque_limit`); none:
    /// the pace as planned.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pace_throttle: Option<SpeedScaling>,
    /// `[controller.passive.pace_learning]`: the field's pace learned lap over lap on the
    /// torque margin the controller measures (`pvfc_core::pace::learned`; needs
    /// `torque_limit` and `[controller.pace]` on a closed contour); none: the pace as planned.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pace_learning: Option<PaceLearningSpec>,
}

impl PassiveSpec {
    /// The share of a lap taken into the learned missed torque (`pace_learning.miss`), if it
    /// is learned (> 0).
    pub fn miss_weight(&self) -> Option<f64> {
        self.pace_learning.and_then(|l| l.miss_weight())
    }

    /// These settings as the passive options of an arm whose joints `circular` marks: the
    /// encoder's resolution `2π/counts` on those joints, exact positions on the others.
    pub fn options(&self, circular: &[bool]) -> Result<PassiveOptions> {
        self.validate_for(circular.len())?;
        let step = self.encoder_counts.map(|c| std::f64::consts::TAU / c);
        Ok(PassiveOptions {
            torque_limit: (!self.torque_limit.is_empty()).then(|| self.torque_limit.clone()),
            encoder_resolution: step
                .map(|d| circular.iter().map(|&c| if c { d } else { 0.0 }).collect()),
            velocity_filter: self.velocity_filter,
            reserve: self.reserve,
            supervision: self.supervision.clone(),
            pace_throttle: self.pace_throttle,
            pace_learning: self.pace_learning,
        })
    }

    /// Checks the numbers (the limits' length against `dof`).
    pub fn validate_for(&self, dof: usize) -> Result<()> {
        let bad = |what: &str| Err(SimError::Setting(what.to_string()));
        if !(self.torque_limit.is_empty() || self.torque_limit.len() == dof) {
            return bad("controller.passive.torque_limit: one limit per joint (or none)");
        }
        if self
            .torque_limit
            .iter()
            .any(|l| !(l.is_finite() && *l > 0.0))
        {
            return bad("controller.passive.torque_limit: each limit finite and > 0");
        }
        if let Some(c) = self.encoder_counts {
            if !(c.is_finite() && c >= 1.0) {
                return bad("controller.passive.encoder_counts: finite and ≥ 1");
            }
        }
        if !(self.velocity_filter.is_finite() && self.velocity_filter >= 0.0) {
            return bad("controller.passive.velocity_filter: finite and ≥ 0 (s)");
        }
        if !(self.reserve.is_finite() && self.reserve >= 0.0) {
            return bad("controller.passive.reserve: finite and ≥ 0 (J)");
        }
        if let Some(s) = &self.supervision {
            s.validate(dof).map_err(|e| match e {
                SimError::Setting(m) => SimError::Setting(format!("controller.passive.{m}")),
                e => e,
            })?;
        }
        if let Some(t) = &self.pace_throttle {
            t.validate_as("controller.passive.pace_throttle")?;
            if self.torque_limit.is_empty() {
                return bad("controller.passive.pace_throttle reads the drives' limits: set controller.passive.torque_limit");
            }
        }
        if let Some(l) = &self.pace_learning {
            l.rule("controller.passive.pace_learning")?;
            if self.torque_limit.is_empty() {
                return bad("controller.passive.pace_learning reads the drives' limits: set controller.passive.torque_limit");
            }
        }
        Ok(())
    }

    /// The passive controller around `controller` with these limits, encoder charge (on the
    /// joints `circular` marks), velocity filter, reserve, supervision and pace, and `miss`
    /// learning beside it (given exactly when [`miss_weight`](Self::miss_weight) is).
    pub fn controller<G, Sys, F, const N: usize>(
        &self,
        controller: Controller<f64, G, Sys, F, N>,
        circular: [bool; N],
        miss: Option<Box<FieldMissLearner<N>>>,
    ) -> Result<MissPaced<G, Sys, F, N>>
    where
        G: VectorGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        F: VelocityField<f64, G, N>,
    {
        self.options(&circular)?.controller(controller, miss)
    }

    /// A measured position: `q` rounded to the encoder's resolution.
    pub fn measure(&self, q: f64) -> f64 {
        match (self.encoder_counts, self.count(q)) {
            (Some(c), Some(n)) => n * (std::f64::consts::TAU / c),
            _ => q,
        }
    }

    /// The encoder's count of the angle `q` (rad): `q` in whole steps of `2π/counts`; `None`
    /// without an encoder.
    pub fn count(&self, q: f64) -> Option<f64> {
        self.encoder_counts
            .map(|c| (q / (std::f64::consts::TAU / c)).round())
    }
}

impl Default for ControllerSpec {
    fn default() -> Self {
        ControllerSpec {
            self_pacing: 100.0,
            h: vec![1.0, 1.0],
            energy: 50.0,
            flywheel_inertia: 1.0,
            gamma: 0.05,
            coupling_rate: None,
            rate: 1000.0,
            friction_compensation: None,
            friction_band: None,
            gravity_compensation: None,
            nominal_speed: None,
            field_energy_bound: None,
            passive: None,
            pace: None,
        }
    }
}

/// The initial state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InitialSpec {
    /// Joint positions (rad, m).
    #[serde(default)]
    pub q: Vec<f64>,
    /// Joint velocities (rad/s, m/s).
    #[serde(default)]
    pub v: Vec<f64>,
    /// Contour parameter.
    #[serde(default)]
    pub tau: f64,
    /// Its rate.
    #[serde(default)]
    pub tau_dot: f64,
    /// Flywheel speed (rad/s); default `√(2Ē/M_F)` (β = 1 with the arm at rest).
    #[serde(default)]
    pub flywheel_speed: Option<f64>,
}

impl Default for InitialSpec {
    fn default() -> Self {
        InitialSpec {
            q: vec![0.0, 1.5],
            v: vec![0.0, 0.0],
            tau: 0.0,
            tau_dot: 0.0,
            flywheel_speed: None,
        }
    }
}

/// How the loop is simulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// The controller runs at its own rate with zero-order hold (`Controller::step`), the
    /// plant is integrated with RK4 in substeps: as on a real motor controller.
    #[default]
    Sampled,
    /// The controller's states are integrated together with the plant (RKMK4 at the
    /// substep), the continuous-time closed loop of the paper's analysis.
    Continuous,
}

/// Simulation settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimulationSpec {
    /// Sampled-data or continuous.
    #[serde(default)]
    pub mode: Mode,
    /// Plant integration steps per controller period.
    #[serde(default = "default_substeps")]
    pub plant_substeps: usize,
}

fn default_substeps() -> usize {
    10
}

impl Default for SimulationSpec {
    fn default() -> Self {
        SimulationSpec {
            mode: Mode::Sampled,
            plant_substeps: default_substeps(),
        }
    }
}

/// A timed-trajectory tracker to compare with (Fig. 1): computed torque + PD on
/// `x_d(τ(t))`, `τ(t) = τ₀ + rate·t`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaselineSpec {
    /// Proportional gains (1/s²), one per joint.
    pub kp: Vec<f64>,
    /// Derivative gains (1/s), one per joint.
    pub kd: Vec<f64>,
    /// `dτ/dt`; default: the mean `τ̇` of the PVFC run of the same scenario.
    #[serde(default)]
    pub tau_rate: Option<f64>,
    /// The drives' torque limits (N·m or N, one per joint): the tracker's command is clamped
    /// to them, as a drive saturates. Empty: no limit.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub torque_limit: Vec<f64>,
    /// Also run a speed-scaling tracker (`[baseline.speed_scaling]`), as the scaled
    /// joint-trajectory controllers of industrial arms do: the same tracker, its path time
    /// slowed while a commanded torque nears its limit. Its run is `NAME-scaled`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_scaling: Option<SpeedScaling>,
}

impl BaselineSpec {
    /// The torque limits as a vector of the robot's size, `None` without limits.
    pub fn limits<const N: usize>(
        &self,
    ) -> crate::error::Result<Option<nalgebra::SVector<f64, N>>> {
        if self.torque_limit.is_empty() {
            return Ok(None);
        }
        let l = crate::model::fixed::<N>(&self.torque_limit, "baseline.torque_limit")?;
        if !l.iter().all(|x| x.is_finite() && *x > 0.0) {
            return Err(crate::error::SimError::Setting(
                "baseline.torque_limit: each limit finite and > 0".into(),
            ));
        }
        Ok(Some(l))
    }

    /// `u` clamped to the limits.
    pub fn saturate<const N: usize>(
        u: nalgebra::SVector<f64, N>,
        limits: &Option<nalgebra::SVector<f64, N>>,
    ) -> nalgebra::SVector<f64, N> {
        match limits {
            Some(l) => u.zip_map(l, |u, l| u.clamp(-l, l)),
            None => u,
        }
    }
}

/// One run: plant, contour, controller, initial state, duration, rates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// A short name (files are named after it).
    pub name: String,
    /// What the run shows.
    #[serde(default)]
    pub description: String,
    /// Simulated time (s).
    pub duration: f64,
    /// The plant.
    #[serde(default)]
    pub plant: PlantSpec,
    /// The contour.
    #[serde(default)]
    pub contour: ContourSpec,
    /// The controller.
    #[serde(default)]
    pub controller: ControllerSpec,
    /// The initial state.
    #[serde(default)]
    pub initial: InitialSpec,
    /// Simulation settings.
    #[serde(default)]
    pub simulation: SimulationSpec,
    /// A timed-trajectory baseline to run next to PVFC.
    #[serde(default)]
    pub baseline: Option<BaselineSpec>,
    /// Contact with the world: obstacles, workpieces, the contact law (the planar SCARA).
    #[serde(default)]
    pub contact: Option<ContactSpec>,
    /// Contact in 3-D of a URDF arm: its collision capsules, the obstacles, the law.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_3d: Option<crate::contact::spatial::SpatialContactSpec>,
    /// Obstacles the field keeps the robot away from (`[obstacles]`, Remark 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obstacles: Option<obstacles::ObstacleSpec>,
    /// Faults the loop meets (`[[faults]]`: encoder spikes and freezes, non-finite readings,
    /// jitter, missed periods, dropped and late commands, torque limits, impacts; see
    /// [`crate::plant::faults`]). They need `[controller.passive]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub faults: Vec<FaultEvent>,
    /// An operator's commands to the drive by time (`[[operator]]`: start, speed, stop;
    /// [`operator`]). They need `[controller.passive]`; a drive with commands starts stopped.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operator: Vec<operator::OperatorCommand>,
    /// Directory that relative paths in the scenario are resolved against (not in the file).
    #[serde(skip)]
    pub base_dir: PathBuf,
    /// The deprecated forms the scenario was read in, one message each (not in the file;
    /// see [`legacy`]).
    #[serde(skip)]
    pub deprecations: Vec<String>,
}

/// A per-joint list of a scenario as a vector of the robot's dimension (an empty or omitted
/// list is zeros), or an error naming the field.
pub fn joint_vector<const N: usize>(x: &[f64], field: &str) -> Result<nalgebra::SVector<f64, N>> {
    if x.is_empty() {
        return Ok(nalgebra::SVector::zeros());
    }
    crate::model::fixed::<N>(x, field)
}

/// The largest controller rate a scenario may ask for (Hz).
pub const MAX_RATE: f64 = 1.0e6;
/// The most samples (controller periods) one run may log: about 1.5 GB of trace for a
/// two-joint arm.
pub const MAX_SAMPLES: f64 = 1.0e7;
/// The most plant substeps per controller period.
pub const MAX_SUBSTEPS: usize = 10_000;
/// The most plant steps one run may take (about ten minutes of RK4 on this machine).
pub const MAX_PLANT_STEPS: f64 = 1.0e9;

/// Checks the numbers that size a run against [`MAX_RATE`], [`MAX_SAMPLES`],
/// [`MAX_SUBSTEPS`] and [`MAX_PLANT_STEPS`]; gives the number of controller periods.
pub fn run_size(duration: f64, rate: f64, substeps: usize) -> Result<usize> {
    let bad = |what: String| Err(SimError::Setting(what));
    if !(rate.is_finite() && rate > 0.0 && rate <= MAX_RATE) {
        return bad(format!(
            "controller.rate = {rate}: must be in (0, {MAX_RATE:e}] Hz"
        ));
    }
    if !(duration.is_finite() && duration > 0.0) {
        return bad(format!("duration = {duration}: must be finite and > 0"));
    }
    if substeps == 0 || substeps > MAX_SUBSTEPS {
        return bad(format!(
            "simulation.plant_substeps = {substeps}: must be in 1..={MAX_SUBSTEPS}"
        ));
    }
    let n = (duration * rate).round();
    if n < 1.0 {
        return bad(format!(
            "duration = {duration} s is shorter than one controller period (1/{rate} s)"
        ));
    }
    if n > MAX_SAMPLES {
        return bad(format!(
            "duration × controller.rate = {n:e} samples: at most {MAX_SAMPLES:e} per run"
        ));
    }
    if n * substeps as f64 > MAX_PLANT_STEPS {
        return bad(format!(
            "duration × controller.rate × simulation.plant_substeps = {:e} plant steps: at most {MAX_PLANT_STEPS:e} per run",
            n * substeps as f64
        ));
    }
    Ok(n as usize)
}

impl Scenario {
    /// Reads and validates a scenario file. Errors name the field and the line; relative
    /// paths in it (a URDF) are relative to the file.
    pub fn from_file(path: &Path) -> Result<Scenario> {
        let text = std::fs::read_to_string(path).map_err(|e| SimError::io(path, e))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::parse(&text, path, base)
    }

    /// Parses and validates scenario text (`path` only names it in errors; relative paths
    /// are relative to the working directory).
    pub fn from_toml(text: &str, path: &Path) -> Result<Scenario> {
        Self::parse(text, path, PathBuf::new())
    }

    /// Parses and validates scenario text whose relative paths are relative to `base_dir`
    /// (`path` only names it in errors).
    pub fn parse(text: &str, path: &Path, base_dir: PathBuf) -> Result<Scenario> {
        let mut s: Scenario = toml::from_str(text).map_err(|e| SimError::Scenario {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        s.base_dir = base_dir;
        s.deprecations = legacy::in_toml(text);
        s.validate().map_err(|e| SimError::Scenario {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Ok(s)
    }

    /// The scenario as TOML text.
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string(self).map_err(|e| SimError::Setting(e.to_string()))
    }

    /// The energy level `β` the controller runs at: the nominal speed `r` of eq. (36) if set,
    /// else the level its internal states start at (`√(κ_a(0)/Ē)` with the arm at rest).
    pub fn pace_level(&self) -> f64 {
        let c = &self.controller;
        if let Some(n) = c.nominal_speed {
            return n.r;
        }
        match self.initial.flywheel_speed {
            None => 1.0,
            Some(w) => {
                let kappa = 0.5 * (c.flywheel_inertia * w * w + self.initial.tau_dot.powi(2));
                (kappa / c.energy).sqrt()
            }
        }
    }

    /// The pace of `[controller.pace]`, if any, at [`pace_level`](Self::pace_level): the
    /// speed asked for is the tool's along a Cartesian path, the joints' along any other
    /// contour. A part program's feeds (F) are the speed asked for along their stretches
    /// (`controller.pace.speed` on moves without F), with `[controller.pace]`'s limits and
    /// headroom, or its defaults when the table is left out.
    pub fn drive_pace(&self) -> Result<Option<PaceSettings>> {
        let tool = self.contour.cartesian().is_some();
        let pace = self.controller.pace.as_ref();
        let feeds = match self.contour.cartesian() {
            Some(c) => c.feeds(&self.base_dir, pace.and_then(|p| p.speed))?,
            None => None,
        };
        match (pace, feeds) {
            (None, None) => Ok(None),
            (p, feeds) => p
                .cloned()
                .unwrap_or_default()
                .settings_with_feeds(&self.controller, self.pace_level(), tool, feeds)
                .map(Some),
        }
    }

    /// The contour's period in `τ` ([`ContourSpec::period`]): a joint curve's, a Cartesian
    /// path's, one turn of an attitude contour; infinite where there is none.
    pub fn period(&self) -> f64 {
        self.contour.period()
    }
}
