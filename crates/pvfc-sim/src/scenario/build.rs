//! The one builder of a scenario's system, as the data flows (file → spec → system → run): it
//! reads the URDF, solves a Cartesian path's inverse kinematics, and builds the robot model,
//! the contour, the field and the controller from the plain data of a [`Scenario`]. Validating
//! a scenario is building its system, so a scenario is checked by the same code that a run
//! builds it with.

use super::{
    direct_drive_arm, joint_vector, run_size, AttitudeController, ChainSpec, ContourSpec, Mode,
    PaperController, PaperField, PaperPassiveController, RobotSpec, ScaraSpec, Scenario,
};
use crate::error::{Result, SimError};
use crate::model::arm::{ArmController, ArmSettings};
use crate::model::arm_field::FieldSpec;
use crate::model::pace::uniform_pacing;
use crate::model::robot::Robot;
use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc_core::obstacle::ObstacleSet;
use pvfc_core::prelude::*;

/// A URDF arm's scenario built once, as the data flows (file → system → run): the robot (its
/// URDF read once, with the scenario's gravity), the controller's settings (a Cartesian
/// path's inverse kinematics solved once) and the controller built from them. The runs, the
/// logs' 3-D scenes, the figures and the Cartesian metrics all take it instead of reading
/// the scenario's files again.
#[derive(Clone, Debug)]
pub struct ArmSystem {
    /// The robot model: the controller's.
    pub robot: Robot,
    /// The simulated arm: the robot with the scenario's model error (`plant.mass_scale`), or
    /// the robot itself.
    pub plant: Robot,
    /// The controller's settings.
    pub settings: ArmSettings,
    /// The controller, at the scenario's initial internal states
    /// ([`Scenario::initial_internal`]).
    pub controller: ArmController,
}

impl ArmSystem {
    /// Builds the system of a serial chain's scenario (`kind = "serial_chain"`), checking the scenario
    /// against the robot on the way: this is also how [`Scenario::validate`] checks a URDF
    /// arm's scenario.
    ///
    pub fn build(s: &Scenario) -> Result<Self> {
        let robot = s.robot()?;
        s.check_chain(&robot)?;
        let settings = s.arm_settings_for(&robot)?;
        let controller =
            ArmController::new(&robot, &settings)?.with_internal(|f| s.initial_internal(f));
        let plant = s.plant_robot(&robot)?;
        Ok(ArmSystem {
            robot,
            plant,
            settings,
            controller,
        })
    }
}

/// A scenario's system, built once from its spec: the one place a run, a log's scene, a figure
/// or a binding matches on the kind of robot ([`RobotSpec`]).
#[derive(Clone, Debug)]
pub enum System {
    /// The paper's planar SCARA: its closed-form model (a URDF arm's file read once).
    Scara(Scara<f64>),
    /// A serial chain from a URDF: the robot, the plant and the controller.
    SerialChain(Box<ArmSystem>),
    /// A rigid body's attitude: its controller (which holds the body).
    RigidBody(Box<AttitudeController>),
}

impl System {
    /// Builds the system of `s`, checking `s` against its robot on the way.
    pub fn build(s: &Scenario) -> Result<Self> {
        Ok(match &s.plant.robot {
            RobotSpec::Scara(_) => System::Scara(Scara::new(s.scara()?)?),
            RobotSpec::SerialChain(_) => System::SerialChain(Box::new(ArmSystem::build(s)?)),
            RobotSpec::RigidBody(_) => System::RigidBody(Box::new(s.attitude_controller()?)),
        })
    }

    /// The serial chain's system (`None` for another kind).
    pub fn chain(&self) -> Option<&ArmSystem> {
        match self {
            System::SerialChain(a) => Some(a),
            System::Scara(_) | System::RigidBody(_) => None,
        }
    }

    /// The number of coordinates: the chain's joints, 2 for the SCARA, 3 for a rigid body
    /// (its angular velocity's).
    pub fn dof(&self) -> usize {
        match self {
            System::Scara(_) => 2,
            System::SerialChain(a) => a.robot.dof(),
            System::RigidBody(_) => 3,
        }
    }
}

impl Scenario {
    /// Checks the settings that the types alone do not (and builds the models once).
    pub fn validate(&self) -> Result<()> {
        let bad = |what: &str| Err(SimError::Setting(what.to_string()));
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return bad("duration must be finite and > 0");
        }
        if !(self.controller.rate.is_finite() && self.controller.rate > 0.0) {
            return bad("controller.rate must be finite and > 0");
        }
        if let Some(share) = self.controller.field_energy_bound {
            pvfc_core::coupling::field_energy_share(share).map_err(|e| {
                SimError::Setting(format!(
                    "controller.field_energy_bound = {share}: a share of the energy level in (0, 1) ({e})"
                ))
            })?;
        }
        // Every number that sizes work or memory is checked before anything is allocated.
        run_size(
            self.duration,
            self.controller.rate,
            self.simulation.plant_substeps,
        )?;
        self.plant.friction.validate()?;
        let learns = self
            .controller
            .passive
            .as_ref()
            .and_then(|p| p.pace_learning.as_ref());
        if learns.is_some() && self.controller.pace.is_none() {
            return bad(
                "controller.passive.pace_learning learns the pace planned along a closed \
                 contour: set [controller.pace]",
            );
        }
        let init = &self.initial;
        if !init
            .q
            .iter()
            .chain(init.v.iter())
            .chain([init.tau, init.tau_dot].iter())
            .all(|x| x.is_finite())
        {
            return bad("initial state must be finite");
        }
        if let Some(b) = &self.baseline {
            if !b
                .kp
                .iter()
                .chain(b.kd.iter())
                .all(|x| x.is_finite() && *x > 0.0)
            {
                return bad("baseline gains must be finite and > 0");
            }
        }
        if let Some(c) = &self.contact {
            c.validate()?;
            if c.force_schedule.is_some() && self.controller.nominal_speed.is_none() {
                return bad("contact.force_schedule needs controller.nominal_speed (eq. 36)");
            }
        }
        if self.controller.passive.is_some() && self.simulation.mode != Mode::Sampled {
            return bad(
                "controller.passive: the passive digital controller runs in the sampled mode",
            );
        }
        if !self.faults.is_empty() && self.controller.passive.is_none() {
            return bad(
                "faults: a run with faults needs [controller.passive] (the sampled controller that survives them)",
            );
        }
        if !self.operator.is_empty() {
            if self.controller.passive.is_none() {
                return bad(
                    "operator: an operator's commands go to a drive: they need [controller.passive]",
                );
            }
            if self.controller.nominal_speed.is_none() {
                return bad(
                    "operator: start and speed set the nominal speed r of eq. (36): they need [controller.nominal_speed]",
                );
            }
            super::operator::Operator::of(self)?;
        }
        match &self.plant.robot {
            RobotSpec::RigidBody(_) => return self.check_body(),
            // A URDF arm is validated by building its system: the same code path as a run's,
            // the URDF read once.
            RobotSpec::SerialChain(_) => return ArmSystem::build(self).map(drop),
            RobotSpec::Scara(_) => {}
        }
        if let Some(p) = &self.controller.passive {
            p.validate_for(2)?;
        }
        self.validate_faults(2)?;
        if self.contact_3d.is_some() {
            return bad("contact_3d: 3-D contact is for URDF arms; the SCARA's is [contact]");
        }
        for (x, field) in [
            (&self.initial.q, "initial.q"),
            (&self.initial.v, "initial.v"),
        ] {
            joint_vector::<2>(x, field)?;
        }
        if let Some(b) = &self.baseline {
            joint_vector::<2>(&b.kp, "baseline.kp")?;
            joint_vector::<2>(&b.kd, "baseline.kd")?;
            b.limits::<2>()?;
        }
        self.plant.friction.validate_for(2)?;
        if let Some(d) = &self.plant.disturbance {
            d.validate_for(2)?;
        }
        self.plant_scara(Scara::new(self.scara()?)?)?;
        self.controller()?;
        Ok(())
    }

    /// The coupling gain `γ` of eq. (7) of a controller at the scenario's energy level:
    /// `controller.gamma`, or the one of `controller.coupling_rate`
    /// ([`coupling_gain`](crate::model::arm::coupling_gain)) at the nominal speed's level `r`
    /// (or 1). A URDF arm's energy level may be sized from the pace: its controller resolves
    /// the rate itself ([`ArmSettings::gamma_at`](crate::model::arm::ArmSettings::gamma_at)).
    pub fn coupling_gain(&self) -> Result<f64> {
        let c = &self.controller;
        match c.coupling_rate {
            None => Ok(c.gamma),
            Some(rate) => crate::model::arm::coupling_gain(rate, c.level(), c.energy),
        }
    }

    /// The rate `γβĒ` (1/s) at which the controller's velocity error converges (Remark 1):
    /// `controller.coupling_rate`, or `γβĒ` of its `gamma` and `energy` at the nominal
    /// speed's level `r` (or 1).
    pub fn coupling_rate(&self) -> f64 {
        let c = &self.controller;
        c.coupling_rate
            .unwrap_or_else(|| c.gamma * c.level() * c.energy)
    }

    /// The number of joints: the URDF's, 2 for the planar arm, 3 for a rigid body (its
    /// angular velocity's).
    pub fn dof(&self) -> Result<usize> {
        Ok(match &self.plant.robot {
            RobotSpec::Scara(_) => 2,
            RobotSpec::SerialChain(_) => self.robot()?.dof(),
            RobotSpec::RigidBody(_) => 3,
        })
    }

    /// The serial chain's robot model (`plant.urdf`, `tip`, `base`, `tcp`, `gravity`).
    pub fn robot(&self) -> Result<Robot> {
        let c = self.plant.chain("the robot model")?;
        let mut robot = Robot::from_urdf(
            &self.base_dir.join(&c.urdf),
            c.base.as_deref(),
            c.tip.as_deref(),
        )?;
        if let Some(tcp) = &c.tcp {
            robot = robot.with_tool(tcp.pose("plant.tcp")?)?;
        }
        self.with_gravity(c, robot)
    }

    /// `robot` under the scenario's gravity (`plant.gravity`), or as it is without one.
    fn with_gravity(&self, c: &ChainSpec, robot: Robot) -> Result<Robot> {
        match c.gravity {
            Some(g) => robot.with_gravity(nalgebra::Vector3::from(g)),
            None => Ok(robot),
        }
    }

    /// The simulated arm of a URDF scenario whose controller's model is `robot`: `robot` with
    /// each link's mass and rotational inertia times `plant.mass_scale` (one factor per joint,
    /// finite and > 0; the sampled mode only), or `robot` itself without a model error.
    pub fn plant_robot(&self, robot: &Robot) -> Result<Robot> {
        let c = self.plant.chain("plant.mass_scale")?;
        let Some(scale) = self.mass_scale(robot.dof(), &robot.description().name)? else {
            return Ok(robot.clone());
        };
        let mut d = robot.description().clone();
        for (link, k) in d.links.iter_mut().zip(scale) {
            link.mass *= k;
            link.inertia *= *k;
        }
        self.with_gravity(c, Robot::from_description(d)?)
    }

    /// The simulated SCARA of a scenario whose controller's model is `arm`: `arm` with each
    /// link's mass and inertia about its centre of mass times `plant.mass_scale` (two
    /// factors, finite and > 0; the sampled mode only), or `arm` itself without a model error.
    pub fn plant_scara(&self, arm: Scara<f64>) -> Result<Scara<f64>> {
        let Some(scale) = self.mass_scale(2, "SCARA")? else {
            return Ok(arm);
        };
        let mut p = *arm.parameters();
        (p.m1, p.i1, p.m2, p.i2) = (
            p.m1 * scale[0],
            p.i1 * scale[0],
            p.m2 * scale[1],
            p.i2 * scale[1],
        );
        Ok(Scara::new(p)?)
    }

    /// `plant.mass_scale` checked for an `n`-joint arm called `name`: one factor per link,
    /// each finite and > 0, in the sampled mode; `None` without a model error.
    fn mass_scale(&self, n: usize, name: &str) -> Result<Option<&[f64]>> {
        let Some(scale) = &self.plant.mass_scale else {
            return Ok(None);
        };
        if scale.len() != n || !scale.iter().all(|k| k.is_finite() && *k > 0.0) {
            return Err(SimError::Setting(format!(
                "plant.mass_scale: {} factors for the {n}-joint robot {name}; one per link, finite and > 0",
                scale.len(),
            )));
        }
        if self.simulation.mode != Mode::Sampled {
            return Err(SimError::Setting(
                "plant.mass_scale: a model error needs the sampled mode (the continuous mode integrates the controller's own model)".into(),
            ));
        }
        Ok(Some(scale))
    }

    /// The settings of a URDF arm's controller (reads the URDF; with a robot at hand, or
    /// for a whole run, see [`arm_settings_for`](Self::arm_settings_for) and
    /// [`ArmSystem`]).
    pub fn arm_settings(&self) -> Result<ArmSettings> {
        self.arm_settings_for(&self.robot()?)
    }

    /// The settings of the controller of `robot`, this scenario's arm: a Cartesian path's
    /// inverse kinematics is solved on it.
    pub fn arm_settings_for(&self, robot: &Robot) -> Result<ArmSettings> {
        let c = &self.controller;
        let (contour, field) = match &self.contour {
            ContourSpec::Joint(j) => (j.clone(), FieldSpec::Joint),
            ContourSpec::Cartesian(p) => (
                p.joint_contour(robot, &self.base_dir)?,
                p.task_field(robot, &self.base_dir)?
                    .map_or(FieldSpec::Joint, |t| FieldSpec::Task(Box::new(t))),
            ),
            ContourSpec::Attitude(_) => {
                return Err(SimError::Setting(
                    "contour.attitude: a rigid body's; a serial chain follows a joint curve or a Cartesian path".into(),
                ))
            }
        };
        Ok(ArmSettings {
            contour,
            field,
            h: c.h.clone(),
            self_pacing: c.self_pacing,
            energy: c.energy,
            flywheel_inertia: c.flywheel_inertia,
            gamma: c.gamma,
            coupling_rate: c.coupling_rate,
            gravity_compensation: c.gravity_compensation.unwrap_or(true),
            friction_compensation: c.friction_compensation.clone(),
            friction_band: c.friction_band.unwrap_or(0.0),
            nominal_speed: c.nominal_speed.map(|n| (n.c, n.r)),
            nominal_speed_integral: c.nominal_speed.map_or(0.0, |n| n.integral),
            tau0: self.initial.tau,
            field_energy_bound: c.field_energy_bound,
            obstacles: self.obstacles.clone(),
            pace: self.drive_pace()?,
        })
    }

    /// `[contact_3d]` with every obstacle in the base frame: those in the part's frame placed
    /// by `contour.cartesian.part` ([`SpatialContactSpec::in_base_frame`]).
    ///
    /// [`SpatialContactSpec::in_base_frame`]: crate::contact::spatial::SpatialContactSpec::in_base_frame
    pub(crate) fn contact_3d_in_base_frame(
        &self,
    ) -> Result<Option<crate::contact::spatial::SpatialContactSpec>> {
        let Some(spec) = &self.contact_3d else {
            return Ok(None);
        };
        let part = match self.contour.cartesian().and_then(|c| c.part.as_ref()) {
            Some(p) => Some(p.isometry("contour.cartesian.part")?),
            None => None,
        };
        Ok(Some(spec.in_base_frame(part.as_ref())?))
    }

    /// The checks of a URDF arm's scenario against its robot (the lengths of the per-joint
    /// lists, the 3-D contact, the baseline, the passive drive), for
    /// [`ArmSystem::build`](crate::scenario::ArmSystem::build).
    pub(crate) fn check_chain(&self, robot: &Robot) -> Result<()> {
        let bad = |what: &str| Err(SimError::Setting(what.to_string()));
        if self.contact.is_some() {
            return bad(
                "contact: the planar contact is for the SCARA; a URDF arm's is [contact_3d]",
            );
        }
        let n = robot.dof();
        for (x, field) in [
            (&self.initial.q, "initial.q"),
            (&self.initial.v, "initial.v"),
        ] {
            if !x.is_empty() && x.len() != n {
                return Err(SimError::Setting(format!(
                    "{field}: {} entries for the {n}-joint robot {}",
                    x.len(),
                    robot.description().name
                )));
            }
        }
        self.plant.friction.validate_for(n)?;
        if let Some(d) = &self.plant.disturbance {
            d.validate_for(n)?;
        }
        if let Some(c) = &self.contact_3d {
            c.validate(n)?;
            self.contact_3d_in_base_frame()?;
            if c.force_schedule.is_some() && self.controller.nominal_speed.is_none() {
                return Err(SimError::Setting(
                    "contact_3d.force_schedule needs controller.nominal_speed (eq. 36)".into(),
                ));
            }
        }
        if let Some(b) = &self.baseline {
            if b.kp.len() != n || b.kd.len() != n {
                return Err(SimError::Setting(format!(
                    "baseline.kp, baseline.kd: one gain per joint ({n})"
                )));
            }
            crate::with_dof!(n, N => { b.limits::<N>()?; }, otherwise ());
        }
        if let Some(p) = &self.controller.passive {
            p.validate_for(n)?;
        }
        self.validate_faults(n)
    }

    /// The `[[faults]]` events against a `dof`-joint robot and its drive.
    fn validate_faults(&self, dof: usize) -> Result<()> {
        let limited = self
            .controller
            .passive
            .as_ref()
            .is_some_and(|p| !p.torque_limit.is_empty());
        for (i, e) in self.faults.iter().enumerate() {
            e.validate(i, dof, limited, 1.0 / self.controller.rate)?;
        }
        Ok(())
    }

    /// The checks of a rigid body's scenario (`kind = "rigid_body"`): what a body in free
    /// space does not have (contact, a timed baseline, the passive joint drive, an arm's
    /// contour), the lengths of its three-entry lists, and its controller built once.
    fn check_body(&self) -> Result<()> {
        let bad = |what: &str| Err(SimError::Setting(what.to_string()));
        if self.contact.is_some() || self.contact_3d.is_some() {
            return bad("contact, contact_3d: a rigid body's scenario is in free space");
        }
        if self.obstacles.is_some() {
            return bad(
                "obstacles: for arms (the SCARA, URDF arms); a rigid body's attitude field takes none",
            );
        }
        if self.baseline.is_some() {
            return bad("baseline: the timed tracker is for arms; a rigid body runs PVFC alone");
        }
        if self.controller.passive.is_some() {
            return bad(
                "controller.passive: the passive drive measures joint positions; a rigid body's attitude is on SO(3)",
            );
        }
        if let ContourSpec::Joint(_) | ContourSpec::Cartesian(_) = &self.contour {
            return bad("contour: a rigid body follows [contour.attitude], not an arm's contour");
        }
        for (x, field) in [
            (&self.initial.q, "initial.q"),
            (&self.initial.v, "initial.v"),
        ] {
            joint_vector::<3>(x, field)?;
        }
        self.plant.friction.validate_for(3)?;
        if let Some(d) = &self.plant.disturbance {
            d.validate_for(3)?;
        }
        self.attitude_controller().map(drop)
    }

    /// The controller of a rigid body's scenario: `plant.inertia`, the
    /// rotation at constant rate of `[contour.attitude]`, the navigation function of SO(3)
    /// (eq. 26) with `P = diag(controller.h)`, exponential self-pacing (eq. 21), with its
    /// add-ons and initial internal states.
    pub fn attitude_controller(&self) -> Result<AttitudeController> {
        let setting = |what: String| SimError::Setting(what);
        let RobotSpec::RigidBody(body) = &self.plant.robot else {
            return Err(setting(
                "attitude controller: for a rigid body (kind = \"rigid_body\")".into(),
            ));
        };
        let j = Matrix3::from_fn(|r, c| body.inertia[r][c]);
        let body = RigidBody::new(j).map_err(|e| setting(format!("plant.inertia: {e}")))?;
        let contour = self.attitude_contour()?;
        let h = &self.controller.h;
        if h.len() != 3 {
            return Err(setting(format!(
                "controller.h: {} entries; a rigid body's are the diagonal of P in eq. (26), three distinct weights",
                h.len()
            )));
        }
        let p = Matrix3::from_diagonal(&Vector3::from_column_slice(h));
        let navigation =
            So3Navigation::new(p).map_err(|e| setting(format!("controller.h: {e}")))?;
        let field = SuspendedField::new(
            contour,
            navigation,
            ExponentialPacing::new(self.controller.self_pacing)?,
        );
        self.with_add_ons(body, field)
    }

    /// A rigid body's contour (`[contour.attitude]`): `R_d(τ) = exp(r̂₀) exp(τ ω̂)`.
    pub fn attitude_contour(&self) -> Result<ConstantRate<f64, So3<f64>, 3>> {
        let setting = |what: String| SimError::Setting(what);
        let ContourSpec::Attitude(a) = self.contour else {
            return Err(setting(
                "contour.attitude: a rigid body follows a rotation at constant rate".into(),
            ));
        };
        let rate = Vector3::from(a.rate);
        if !(rate.iter().all(|x| x.is_finite()) && rate.norm() > 0.0) {
            return Err(setting(format!(
                "contour.attitude.rate = {:?}: finite and not zero (the contour turns once per 2π/‖ω‖ of τ)",
                a.rate
            )));
        }
        if !a.start.iter().all(|x| x.is_finite()) {
            return Err(setting("contour.attitude.start: not finite".into()));
        }
        Ok(ConstantRate::new(So3::exp(&Vector3::from(a.start)), rate)?)
    }

    /// The PVFC controller of `system` on `field` with the scenario's flywheel, coupling
    /// gain, initial internal states and add-ons (friction compensation, eq. 35; nominal
    /// speed, eq. 36): one builder for every robot.
    fn with_add_ons<G, Sys, F, const N: usize>(
        &self,
        system: Sys,
        field: F,
    ) -> Result<Controller<f64, G, Sys, F, N>>
    where
        G: LieGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        F: VelocityField<f64, G, N>,
    {
        let c = &self.controller;
        let flywheel = Flywheel::new(c.flywheel_inertia, c.energy)?;
        let law = PvfcLaw::new(system, field, flywheel, self.coupling_gain()?)?;
        let mut ctl = Controller::new(law).with_state(self.initial_internal(&flywheel));
        if let Some(f) = &c.friction_compensation {
            let f = joint_vector::<N>(f, "controller.friction_compensation")?;
            let mut comp = FrictionCompensation::new(f)?;
            if let Some(band) = c.friction_band {
                comp = comp.with_band(band)?;
            }
            ctl = ctl.with_friction_compensation(comp);
        }
        if let Some(n) = c.nominal_speed {
            ctl = ctl.with_nominal_speed(NominalSpeed::new(n.c, n.r)?.with_integral(n.integral)?);
        }
        if let Some(share) = c.field_energy_bound {
            // (Checked by name in `validate`.)
            ctl.set_field_energy_bound(share)?;
        }
        Ok(ctl)
    }

    /// The controller's internal states at the start, from `[initial]`: `τ`, `τ̇`, and the
    /// flywheel's speed (by default the one that gives `β = 1` at rest), no laps.
    pub fn initial_internal(&self, flywheel: &Flywheel<f64>) -> InternalState<f64> {
        InternalState {
            tau: self.initial.tau,
            tau_dot: self.initial.tau_dot,
            flywheel_speed: self
                .initial
                .flywheel_speed
                .unwrap_or_else(|| flywheel.speed_for_unit_beta()),
            laps: 0,
        }
    }

    /// The SCARA's parameters (`plant.arm` of `kind = "scara"`).
    pub fn scara(&self) -> Result<ScaraParameters<f64>> {
        let RobotSpec::Scara(arm) = &self.plant.robot else {
            return Err(SimError::Setting(
                "the SCARA's parameters: for a SCARA (kind = \"scara\")".into(),
            ));
        };
        Ok(match arm {
            ScaraSpec::DirectDrive => direct_drive_arm(),
            ScaraSpec::Pelican => ScaraParameters::pelican(),
            ScaraSpec::Urdf(p) => crate::urdf::scara_from_urdf(&self.base_dir.join(p))?,
            ScaraSpec::Parameters(a) => (*a).into(),
        })
    }

    /// The SCARA's contour: a Lissajous curve in its two joints (`[contour.lissajous]`).
    pub fn contour(&self) -> Result<Lissajous<f64, 2>> {
        let not = || {
            SimError::Setting(format!(
                "contour.{}: the SCARA follows a Lissajous curve ([contour.lissajous])",
                self.contour.kind()
            ))
        };
        match &self.contour {
            ContourSpec::Joint(j) => j.lissajous::<2>()?.ok_or_else(not),
            ContourSpec::Cartesian(_) | ContourSpec::Attitude(_) => Err(not()),
        }
    }

    /// The field, around the scenario's obstacles if it has any (`[obstacles]`).
    pub fn field(&self) -> Result<PaperField> {
        self.field_for(&self.scara()?)
    }

    /// [`field`](Self::field) with the arm's parameters already read (they place the
    /// robot's spheres among world obstacles; nothing else of the field depends on them).
    fn field_for(&self, arm: &ScaraParameters<f64>) -> Result<PaperField> {
        let navigation =
            TorusNavigation::paper(joint_vector::<2>(&self.controller.h, "controller.h")?)?;
        let contour = self.contour()?;
        let mut pacing = uniform_pacing(self.controller.self_pacing)?;
        if let Some(p) = self.drive_pace()? {
            let period = Contour::<f64, Torus<f64, 2>, 2>::period(&contour).ok_or_else(|| {
                SimError::Setting("controller.pace: the contour must be closed".into())
            })?;
            let friction = self.controller.friction_compensation.as_deref();
            let table = p.profile(&Scara::new(*arm)?, &contour, period, friction, false)?;
            crate::model::pace::set_pace_table(&mut pacing, table, period)?;
        }
        let field = SuspendedField::new(contour, navigation, pacing);
        let set = match &self.obstacles {
            None => ObstacleSet::empty(),
            Some(o) => {
                let chain = match o.world.is_empty() {
                    true => None,
                    false => Some(arm.chain()?),
                };
                let largest = navigation.value(&Torus::new(Vector2::repeat(std::f64::consts::PI)));
                o.build(chain, largest)?
            }
        };
        Ok(field.with_obstacles(set))
    }

    /// The controller, with its add-ons and initial internal states. The controller's model
    /// of the arm is the plant's (no model mismatch).
    pub fn controller(&self) -> Result<PaperController> {
        self.controller_with(Scara::new(self.scara()?)?)
    }

    /// [`controller`](Self::controller) with the arm's model already built (a run reads the
    /// arm once).
    pub fn controller_with(&self, arm: Scara<f64>) -> Result<PaperController> {
        let field = self.field_for(arm.parameters())?;
        self.with_add_ons(arm, field)
    }

    /// The learner of the torque the model `arm` misses along the contour, taking `weight`
    /// of each lap (`controller.passive.pace_learning.miss`), on the plan of the scenario's
    /// pace; `None` for no weight.
    pub fn scara_miss_learner(
        &self,
        arm: &Scara<f64>,
        weight: Option<f64>,
    ) -> Result<Option<Box<crate::model::pace::FieldMissLearner<2>>>> {
        let Some(weight) = weight else {
            return Ok(None);
        };
        let contour = self.contour()?;
        let period = Contour::<f64, Torus<f64, 2>, 2>::period(&contour);
        let (Some(pace), Some(period)) = (self.drive_pace()?, period) else {
            return Err(SimError::Setting(
                crate::model::pace::MISS_WITHOUT_PACE.into(),
            ));
        };
        let friction = self.controller.friction_compensation.as_deref();
        pace.miss_learner::<_, _, _, 2>(arm, &contour, period, (friction, false), weight)
            .map(Some)
    }

    /// The passive digital controller of `[controller.passive]` around
    /// [`controller`](Self::controller), with the learner of the torque the model misses if
    /// it asks for one, if the scenario has one.
    pub fn passive_controller(&self) -> Result<Option<PaperPassiveController>> {
        let Some(p) = &self.controller.passive else {
            return Ok(None);
        };
        self.passive_controller_with(&p.options(&[true; 2])?)
            .map(Some)
    }

    /// The passive digital controller with `options` around
    /// [`controller`](Self::controller) (the learner of the torque the model misses planned
    /// on the scenario's pace, if `options` ask for one).
    pub fn passive_controller_with(
        &self,
        options: &crate::model::arm::PassiveOptions,
    ) -> Result<PaperPassiveController> {
        let arm = Scara::new(self.scara()?)?;
        let miss = self.scara_miss_learner(&arm, options.miss_weight())?;
        options.controller(self.controller_with(arm)?, miss)
    }
}
