//! `[plant]`: the robot a scenario simulates, its kind named once (`kind = "scara"`,
//! `"serial_chain"` or `"rigid_body"`), and the environment of its joints (friction, a
//! disturbance). Every concern that differs by robot matches [`RobotSpec`] (or the built
//! [`System`](super::System)); nothing infers the kind from which fields are set.
//!
//! The form before `kind` (a `urdf` key for a serial chain, a `[plant.rigid_body]` table for
//! a rigid body, neither for the SCARA) still reads: [`super::legacy`] names it in a
//! deprecation message.

use crate::error::SimError;
use crate::model::pose::PoseSpec;
use crate::plant::disturbance::Disturbance;
use crate::plant::friction::JointFriction;
use pvfc_core::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The default arm of the experiments (the numbers of `models/scara.urdf`): a direct-drive
/// two-link SCARA heavier than the Pelican, so that at the paper's energy (50) and friction
/// (2–3 N·m) the arm's kinetic energy on the contour is a sizeable share of the total.
pub fn direct_drive_arm() -> ScaraParameters<f64> {
    ScaraParameters {
        m1: 15.0,
        m2: 6.0,
        l1: 0.4,
        l2: 0.35,
        lc1: 0.2,
        lc2: 0.15,
        i1: 0.4,
        i2: 0.15,
    }
}

/// A rigid body rotating freely (`kind = "rigid_body"`), `J ω̇ + ω × Jω = T` with `ω` its body
/// angular velocity: a satellite's attitude on SO(3) (section IV-B). Its configuration is
/// the attitude `R`; a scenario gives attitudes as rotation vectors (`R = exp(r̂)`, rad) and
/// the trace logs them so.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBodySpec {
    /// The body's inertia `J` about its centre of mass, in body axes (kg·m², symmetric
    /// positive definite), row by row.
    pub inertia: [[f64; 3]; 3],
}

/// Which SCARA (`plant.arm` of `kind = "scara"`): its parameters built in, from a URDF or given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum ScaraSpec {
    /// The built-in direct-drive arm ([`direct_drive_arm`], the same as `models/scara.urdf`).
    DirectDrive,
    /// The CICESE Pelican arm (the manual's control law, `docs/src/reference/control-law.md` §1).
    Pelican,
    /// An arm read from a URDF file (relative paths are relative to the scenario file).
    Urdf(PathBuf),
    /// An arm given by its parameters.
    Parameters(ScaraParameterSpec),
}

impl From<ScaraParameterSpec> for ScaraParameters<f64> {
    fn from(a: ScaraParameterSpec) -> Self {
        ScaraParameters {
            m1: a.m1,
            m2: a.m2,
            l1: a.l1,
            l2: a.l2,
            lc1: a.lc1,
            lc2: a.lc2,
            i1: a.i1,
            i2: a.i2,
        }
    }
}

/// The physical parameters of a two-link arm (SI units), as in a scenario file.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScaraParameterSpec {
    /// Mass of link 1 (kg).
    pub m1: f64,
    /// Mass of link 2 (kg).
    pub m2: f64,
    /// Length of link 1 (m).
    pub l1: f64,
    /// Length of link 2 (m).
    pub l2: f64,
    /// Joint 1 to the centre of mass of link 1 (m).
    pub lc1: f64,
    /// Joint 2 to the centre of mass of link 2 (m).
    pub lc2: f64,
    /// Inertia of link 1 about its centre of mass (kg·m²).
    pub i1: f64,
    /// Inertia of link 2 about its centre of mass (kg·m²).
    pub i2: f64,
}

/// The kind of robot of a scenario (`[plant] kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RobotKind {
    /// The paper's planar two-link arm (section V), in closed form.
    Scara,
    /// A serial arm read from a URDF file, 1 to 8 joints, with gravity.
    SerialChain,
    /// A rigid body's attitude on SO(3) (section IV-B's satellite).
    RigidBody,
}

impl RobotKind {
    /// The kind as the scenario's `kind` key spells it.
    pub fn key(self) -> &'static str {
        match self {
            RobotKind::Scara => "scara",
            RobotKind::SerialChain => "serial_chain",
            RobotKind::RigidBody => "rigid_body",
        }
    }
}

/// A serial arm read from a URDF file (`kind = "serial_chain"`).
#[derive(Clone, Debug, PartialEq)]
pub struct ChainSpec {
    /// The URDF file (relative to the scenario file).
    pub urdf: PathBuf,
    /// The URDF's tip link (needed when the URDF is a tree).
    pub tip: Option<String>,
    /// The URDF's base link (default: its root).
    pub base: Option<String>,
    /// Gravity in the base frame (m/s²; default `(0, 0, −9.80665)`).
    pub gravity: Option<[f64; 3]>,
    /// The tool centre point in the tip link's frame (`tcp = { xyz = [...], rpy = [...] }`;
    /// default: the tip link's origin): the point and frame that follow the path.
    pub tcp: Option<PoseSpec>,
}

impl ChainSpec {
    /// A chain read from `urdf` with its defaults (the URDF's root and only tip, standard
    /// gravity, no model error).
    pub fn new(urdf: impl Into<PathBuf>) -> Self {
        ChainSpec {
            urdf: urdf.into(),
            tip: None,
            base: None,
            gravity: None,
            tcp: None,
        }
    }
}

/// The robot of a scenario: one variant per [`RobotKind`], each with what only it has.
#[derive(Clone, Debug, PartialEq)]
pub enum RobotSpec {
    /// The planar SCARA: which arm.
    Scara(ScaraSpec),
    /// A serial arm from a URDF.
    SerialChain(ChainSpec),
    /// A rigid body's attitude.
    RigidBody(RigidBodySpec),
}

impl RobotSpec {
    /// The robot's kind.
    pub fn kind(&self) -> RobotKind {
        match self {
            RobotSpec::Scara(_) => RobotKind::Scara,
            RobotSpec::SerialChain(_) => RobotKind::SerialChain,
            RobotSpec::RigidBody(_) => RobotKind::RigidBody,
        }
    }
}

/// The plant: the robot and the environment of its joints.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "PlantFile", into = "PlantFile")]
pub struct PlantSpec {
    /// The robot, of one kind.
    pub robot: RobotSpec,
    /// Joint friction of the simulated plant.
    pub friction: JointFriction,
    /// A disturbance torque on the joints (section II's robustness): part of the plant's
    /// environment, unknown to the controller, its work in `work_contact`.
    pub disturbance: Option<Disturbance>,
    /// A model error of an arm (a SCARA or a serial chain), one positive finite factor per
    /// link (one per joint): the simulated arm's link masses and rotational inertias are the
    /// model's times these, while the controller (its coupling, compensation and field) and
    /// the trackers keep the model. Sampled mode only.
    pub mass_scale: Option<Vec<f64>>,
}

impl Default for PlantSpec {
    /// The direct-drive SCARA without friction.
    fn default() -> Self {
        PlantSpec::of(RobotSpec::Scara(ScaraSpec::DirectDrive))
    }
}

impl PlantSpec {
    /// `robot` without friction or disturbance.
    pub fn of(robot: RobotSpec) -> Self {
        PlantSpec {
            robot,
            friction: JointFriction::default(),
            disturbance: None,
            mass_scale: None,
        }
    }

    /// The serial chain, or an error naming `what` needs one.
    pub fn chain(&self, what: &str) -> Result<&ChainSpec, SimError> {
        match &self.robot {
            RobotSpec::SerialChain(c) => Ok(c),
            r => Err(SimError::Setting(format!(
                "{what}: for a serial chain (kind = \"serial_chain\"); this plant is kind = \"{}\"",
                r.kind().key()
            ))),
        }
    }
}

/// The kind the form before `kind` implies: a serial chain with a `urdf` key, a rigid body
/// with a `[plant.rigid_body]` table, else the SCARA (the one rule, for reading that form and
/// for naming it in its deprecation message).
pub(crate) fn inferred_kind(urdf: bool, rigid_body: bool) -> RobotKind {
    match (urdf, rigid_body) {
        (true, _) => RobotKind::SerialChain,
        (false, true) => RobotKind::RigidBody,
        (false, false) => RobotKind::Scara,
    }
}

/// `[plant]` as written in a file: every key of every kind, checked against the kind by
/// `TryFrom` (the form before `kind` is read by inferring it).
#[derive(Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct PlantFile {
    #[serde(skip_serializing_if = "Option::is_none")]
    kind: Option<RobotKind>,
    #[serde(skip_serializing_if = "Option::is_none")]
    arm: Option<ScaraSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    urdf: Option<PathBuf>,
    #[serde(skip_serializing_if = "Option::is_none")]
    tip: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    base: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    gravity: Option<[f64; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mass_scale: Option<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    tcp: Option<PoseSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    inertia: Option<[[f64; 3]; 3]>,
    /// The rigid body's table before `kind` (`[plant.rigid_body] inertia`).
    #[serde(skip_serializing_if = "Option::is_none")]
    rigid_body: Option<RigidBodySpec>,
    friction: JointFriction,
    #[serde(skip_serializing_if = "Option::is_none")]
    disturbance: Option<Disturbance>,
}

impl PlantFile {
    /// The kind the file names, or the one the form before `kind` implies.
    fn kind(&self) -> RobotKind {
        self.kind
            .unwrap_or_else(|| inferred_kind(self.urdf.is_some(), self.rigid_body.is_some()))
    }

    /// The keys set in the file that `kind` does not have.
    fn foreign_keys(&self, kind: RobotKind) -> Vec<&'static str> {
        let set = [
            ("arm", self.arm.is_some(), RobotKind::Scara),
            ("urdf", self.urdf.is_some(), RobotKind::SerialChain),
            ("tip", self.tip.is_some(), RobotKind::SerialChain),
            ("base", self.base.is_some(), RobotKind::SerialChain),
            ("gravity", self.gravity.is_some(), RobotKind::SerialChain),
            ("tcp", self.tcp.is_some(), RobotKind::SerialChain),
            ("inertia", self.inertia.is_some(), RobotKind::RigidBody),
            (
                "rigid_body",
                self.rigid_body.is_some(),
                RobotKind::RigidBody,
            ),
        ];
        set.iter()
            .filter(|(_, present, owner)| *present && *owner != kind)
            .map(|(key, _, _)| *key)
            .collect()
    }
}

impl TryFrom<PlantFile> for PlantSpec {
    type Error = String;

    fn try_from(f: PlantFile) -> Result<Self, String> {
        if f.kind.is_none() && f.urdf.is_some() && f.rigid_body.is_some() {
            return Err("plant.rigid_body and plant.urdf: a scenario has one robot; say which with plant.kind".into());
        }
        let kind = f.kind();
        let foreign = f.foreign_keys(kind);
        if let Some(key) = foreign.first() {
            let unsaid = match f.kind {
                Some(_) => "",
                None => "; plant.kind is left out, so the plant is read in the form before `kind`: say the kind",
            };
            return Err(format!(
                "plant.{key}: not a key of kind = \"{}\" (plant.{} {} for another kind of robot){unsaid}",
                kind.key(),
                foreign.join(", plant."),
                if foreign.len() == 1 { "is" } else { "are" }
            ));
        }
        let robot =
            match kind {
                RobotKind::Scara => RobotSpec::Scara(f.arm.unwrap_or(ScaraSpec::DirectDrive)),
                RobotKind::SerialChain => RobotSpec::SerialChain(ChainSpec {
                    urdf: f
                        .urdf
                        .ok_or("plant.urdf: a serial chain's URDF file is needed")?,
                    tip: f.tip,
                    base: f.base,
                    gravity: f.gravity,
                    tcp: f.tcp,
                }),
                RobotKind::RigidBody => RobotSpec::RigidBody(match (f.inertia, f.rigid_body) {
                    (Some(inertia), None) => RigidBodySpec { inertia },
                    (None, Some(b)) => b,
                    (Some(_), Some(_)) => return Err(
                        "plant.inertia and plant.rigid_body: give the inertia once (plant.inertia)"
                            .into(),
                    ),
                    (None, None) => {
                        return Err("plant.inertia: a rigid body's inertia is needed".into())
                    }
                }),
            };
        if f.mass_scale.is_some() && kind == RobotKind::RigidBody {
            return Err(
                "plant.mass_scale: a model error per link is for arms (kind = \"scara\" or \"serial_chain\")"
                    .into(),
            );
        }
        Ok(PlantSpec {
            robot,
            friction: f.friction,
            disturbance: f.disturbance,
            mass_scale: f.mass_scale,
        })
    }
}

impl From<PlantSpec> for PlantFile {
    fn from(p: PlantSpec) -> Self {
        let mut f = PlantFile {
            kind: Some(p.robot.kind()),
            friction: p.friction,
            disturbance: p.disturbance,
            mass_scale: p.mass_scale,
            ..PlantFile::default()
        };
        match p.robot {
            RobotSpec::Scara(arm) => f.arm = Some(arm),
            RobotSpec::SerialChain(c) => {
                f.urdf = Some(c.urdf);
                f.tip = c.tip;
                f.base = c.base;
                f.gravity = c.gravity;
                f.tcp = c.tcp;
            }
            RobotSpec::RigidBody(b) => f.inertia = Some(b.inertia),
        }
        f
    }
}
