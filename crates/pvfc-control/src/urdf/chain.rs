//! Any serial chain from a URDF: the joints between a base and a tip link, with fixed joints
//! and side branches folded into the links that carry them.

use super::collision::{link_collisions, LinkCollision};
use super::err;
use crate::error::{Result, SimError};
use pvfc_core::lie::JointKind;
use pvfc_core::mechanics::{ChainJoint, Pose, RigidInertia, SerialChain};
use std::collections::HashMap;
use std::path::Path;

/// The limits a URDF gives a joint, kept for reporting and for later use (the controller does
/// not enforce them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Lower position limit (rad or m); `None` for a continuous joint.
    pub lower: Option<f64>,
    /// Upper position limit (rad or m); `None` for a continuous joint.
    pub upper: Option<f64>,
    /// Effort limit (N·m or N); `None` when the URDF gives none or 0.
    pub effort: Option<f64>,
    /// Velocity limit (rad/s or m/s); `None` when the URDF gives none or 0.
    pub velocity: Option<f64>,
}

/// One moving joint of a [`ChainDescription`].
#[derive(Clone, Debug, PartialEq)]
pub struct JointDescription {
    /// The joint's name in the URDF.
    pub name: String,
    /// The link it moves (the body's frame).
    pub child_link: String,
    /// The joint as the core models it (origin relative to the previous body's frame).
    pub joint: ChainJoint<f64>,
    /// Its limits.
    pub limits: JointLimits,
}

/// A serial chain read from a URDF, with its number of joints known at run time. Turn it into
/// the core's const-generic [`SerialChain`] with [`ChainDescription::chain`].
///
/// How the URDF's tree becomes a chain:
/// * the chain is the path of joints from `base` down to `tip`;
/// * every fixed joint on that path is folded: its child link's inertia joins the body that
///   carries it, and its transform joins the next joint's origin (or the tool frame);
/// * every side branch hanging from a body of the chain (a gripper's fingers, a sensor) is
///   locked at its zero position and folded into that body, movable joints included (they are
///   listed in [`locked_joints`](Self::locked_joints)); Pinocchio's `buildReducedModel` with
///   those joints locked at 0 gives the same model;
/// * links fixed to the base do not move and are left out;
/// * `<collision>` elements of the moving bodies are kept ([`collisions`](Self::collisions))
///   with mesh files by name: a mesh file need not exist unless a 3-D contact world uses it;
///   `<visual>` is not read.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainDescription {
    /// The robot's name.
    pub name: String,
    /// The base link (fixed to the world).
    pub base_link: String,
    /// The tip link (the tool frame).
    pub tip_link: String,
    /// The moving joints from base to tip.
    pub joints: Vec<JointDescription>,
    /// The inertia of each body (the link a joint moves, with what is folded into it), in
    /// that link's frame.
    pub links: Vec<RigidInertia<f64>>,
    /// The tip link's frame in the last body's frame.
    pub tool: Pose<f64>,
    /// The tool centre point (TCP) in the tip link's frame: the tool's working point and
    /// orientation (a spindle's tip, a deburring cone's), identity for the tip link's own
    /// frame. The model's tool frame is `tool ∘ tcp`: every tool pose, Jacobian, tool-path
    /// measure, task-space field and contact uses it.
    pub tcp: Pose<f64>,
    /// Movable joints of side branches locked at 0 and folded into the chain.
    pub locked_joints: Vec<String>,
    /// The `<collision>` elements of the moving bodies (with what is folded into them).
    pub collisions: Vec<LinkCollision>,
    /// The directory of the URDF file (relative mesh names resolve against it).
    pub urdf_dir: std::path::PathBuf,
}

/// The largest number of joints the run-time dispatch supports.
pub const MAX_JOINTS: usize = 8;

impl ChainDescription {
    /// Reads a serial chain from a URDF file; `tip` names the tip link when the URDF is a
    /// tree (otherwise its only leaf), `base` the base link (otherwise its root).
    pub fn from_file(path: &Path, base: Option<&str>, tip: Option<&str>) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| SimError::io(path, e))?;
        Self::from_str(&text, path, base, tip)
    }

    /// As [`from_file`](Self::from_file), from the file's text (`path` only names it in
    /// errors).
    pub fn from_str(
        text: &str,
        path: &Path,
        base: Option<&str>,
        tip: Option<&str>,
    ) -> Result<Self> {
        let robot = super::parse(text, path)?;
        Reader::new(&robot, path)?.read(base, tip)
    }

    /// A chain from plain data (no URDF): joints named `joint1…`, links `link1…`, the tip
    /// `tool`; the joints' origins are relative to the previous link's frame, the tool's to the
    /// last link's. Checked when the model is built ([`Self::chain`]).
    pub fn from_parts(
        name: &str,
        joints: Vec<ChainJoint<f64>>,
        links: Vec<RigidInertia<f64>>,
        tool: Pose<f64>,
    ) -> Result<Self> {
        if joints.len() != links.len() {
            return Err(SimError::Setting(format!(
                "{} joints but {} links: one link per joint",
                joints.len(),
                links.len()
            )));
        }
        let unlimited = JointLimits {
            lower: None,
            upper: None,
            effort: None,
            velocity: None,
        };
        Ok(ChainDescription {
            name: name.to_string(),
            base_link: "base".into(),
            tip_link: "tool".into(),
            joints: joints
                .into_iter()
                .enumerate()
                .map(|(i, joint)| JointDescription {
                    name: format!("joint{}", i + 1),
                    child_link: format!("link{}", i + 1),
                    joint,
                    limits: unlimited,
                })
                .collect(),
            links,
            tool,
            tcp: Pose::identity(),
            locked_joints: vec![],
            collisions: vec![],
            urdf_dir: std::path::PathBuf::from("."),
        })
    }

    /// The number of joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The joints' names, base to tip.
    pub fn joint_names(&self) -> Vec<String> {
        self.joints.iter().map(|j| j.name.clone()).collect()
    }

    /// The joints' kinds, base to tip.
    pub fn kinds(&self) -> Vec<JointKind> {
        self.joints.iter().map(|j| j.joint.kind).collect()
    }

    /// The core's model, for `N` equal to [`dof`](Self::dof) (else `DimensionMismatch`).
    pub fn chain<const N: usize>(&self) -> Result<SerialChain<f64, N>> {
        if N != self.dof() {
            return Err(SimError::Core(
                pvfc_core::Error::new(
                    pvfc_core::ErrorKind::DimensionMismatch,
                    "ChainDescription::chain: N differs from the URDF's number of joints",
                )
                .with_value(self.dof() as f64),
            ));
        }
        let joints: [ChainJoint<f64>; N] = std::array::from_fn(|i| self.joints[i].joint);
        let links: [RigidInertia<f64>; N] = std::array::from_fn(|i| self.links[i]);
        Ok(SerialChain::new(joints, links)?.with_tool(self.tool.compose(&self.tcp))?)
    }
}

struct Reader<'a> {
    robot: &'a urdf_rs::Robot,
    path: &'a Path,
    links: HashMap<&'a str, &'a urdf_rs::Link>,
    /// The joint whose child is the link.
    parent_joint: HashMap<&'a str, &'a urdf_rs::Joint>,
    /// The joints whose parent is the link.
    child_joints: HashMap<&'a str, Vec<&'a urdf_rs::Joint>>,
}

fn pose_of(p: &urdf_rs::Pose) -> Pose<f64> {
    Pose::from_xyz_rpy(p.xyz.0, p.rpy.0)
}

impl<'a> Reader<'a> {
    fn new(robot: &'a urdf_rs::Robot, path: &'a Path) -> Result<Self> {
        let mut links = HashMap::new();
        for l in &robot.links {
            if links.insert(l.name.as_str(), l).is_some() {
                return Err(err(path, format!("link {}", l.name), "defined twice"));
            }
        }
        let mut parent_joint = HashMap::new();
        let mut child_joints: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
        for j in &robot.joints {
            for end in [&j.parent.link, &j.child.link] {
                if !links.contains_key(end.as_str()) {
                    return Err(err(
                        path,
                        format!("joint {}", j.name),
                        format!("names link {end}, which the URDF does not define"),
                    ));
                }
            }
            if parent_joint.insert(j.child.link.as_str(), j).is_some() {
                return Err(err(
                    path,
                    format!("link {}", j.child.link),
                    "is the child of two joints (a URDF is a tree)",
                ));
            }
            child_joints
                .entry(j.parent.link.as_str())
                .or_default()
                .push(j);
        }
        Ok(Reader {
            robot,
            path,
            links,
            parent_joint,
            child_joints,
        })
    }

    fn e(&self, element: impl Into<String>, message: impl Into<String>) -> SimError {
        err(self.path, element, message)
    }

    fn root(&self) -> Result<&'a str> {
        let roots: Vec<&str> = self
            .robot
            .links
            .iter()
            .map(|l| l.name.as_str())
            .filter(|n| !self.parent_joint.contains_key(n))
            .collect();
        match roots.as_slice() {
            [one] => Ok(one),
            [] if self.robot.links.is_empty() => Err(self.e("robot", "the URDF has no <link>")),
            [] => Err(self.e("robot", "no root link (the joints form a cycle)")),
            many => Err(self.e("robot", format!("several root links: {}", many.join(", ")))),
        }
    }

    fn read(&self, base: Option<&str>, tip: Option<&str>) -> Result<ChainDescription> {
        let base = match base {
            Some(b) => self.link(b)?.name.as_str(),
            None => self.root()?,
        };
        let tip = match tip {
            Some(t) => self.link(t)?.name.as_str(),
            None => {
                let mut leaves: Vec<&str> = self
                    .robot
                    .links
                    .iter()
                    .map(|l| l.name.as_str())
                    .filter(|n| !self.child_joints.contains_key(n))
                    .collect();
                leaves.sort_unstable();
                match leaves.as_slice() {
                    [one] => *one,
                    many => {
                        return Err(self.e(
                            "robot",
                            format!(
                                "the URDF is a tree: choose the tip link among its leaves ({})",
                                many.join(", ")
                            ),
                        ))
                    }
                }
            }
        };
        // The path from the tip up to the base.
        let mut path: Vec<&urdf_rs::Joint> = Vec::new();
        let mut at = tip;
        while at != base {
            match self.parent_joint.get(at) {
                // A link met twice: the joints above the tip close a loop that never reaches
                // the base (the walk would go round it for ever).
                Some(j) if path.iter().any(|p| p.child.link == j.child.link) => {
                    return Err(self.e(
                        format!("joint {}", j.name),
                        format!(
                            "the joints above the tip {tip} form a cycle ({} → {}) that does not reach the base link {base}",
                            path.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(" → "),
                            j.name
                        ),
                    ));
                }
                Some(j) => {
                    path.push(j);
                    at = j.parent.link.as_str();
                }
                None => {
                    return Err(self.e(
                        format!("link {tip}"),
                        format!("the tip is not below the base link {base}"),
                    ))
                }
            }
        }
        path.reverse();
        let on_path: Vec<&str> = path.iter().map(|j| j.child.link.as_str()).collect();

        let mut joints = Vec::new();
        let mut bodies: Vec<RigidInertia<f64>> = Vec::new();
        let mut body_links: Vec<&str> = Vec::new();
        let mut locked = Vec::new();
        // For every link on the path: the body that carries it (None: fixed to the base) and
        // its pose in that body's frame, for the side branches below.
        let mut carriers: Vec<(&str, Option<usize>, Pose<f64>)> = Vec::new();
        // Transform from the current body's frame (or the base's) to the current link.
        let mut to_link = Pose::identity();
        for j in &path {
            let element = format!("joint {}", j.name);
            if let Some(m) = &j.mimic {
                return Err(self.e(
                    element,
                    format!("mimic joints (of {}) are not supported", m.joint),
                ));
            }
            let origin = to_link.compose(&pose_of(&j.origin));
            let kind = match j.joint_type {
                urdf_rs::JointType::Fixed => {
                    to_link = origin;
                    if let Some(body) = bodies.last_mut() {
                        let link = self.link(&j.child.link)?;
                        *body = self.fold(Some(*body), link, &to_link)?.unwrap_or(*body);
                    }
                    carriers.push((j.child.link.as_str(), bodies.len().checked_sub(1), to_link));
                    continue;
                }
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                    JointKind::Circular
                }
                urdf_rs::JointType::Prismatic => JointKind::Linear,
                ref other => {
                    return Err(self.e(
                        element,
                        format!(
                            "{other:?} joints are not supported (revolute, continuous, prismatic and fixed are)"
                        ),
                    ))
                }
            };
            let axis = nalgebra::Vector3::from(j.axis.xyz.0);
            if !axis.iter().all(|x| x.is_finite()) || axis.norm() < 1e-9 {
                return Err(self.e(element, "<axis> must be a finite, non-zero vector"));
            }
            let continuous = matches!(j.joint_type, urdf_rs::JointType::Continuous);
            let positive = |x: f64| (x.is_finite() && x > 0.0).then_some(x);
            let limits = JointLimits {
                lower: (!continuous).then_some(j.limit.lower),
                upper: (!continuous).then_some(j.limit.upper),
                effort: positive(j.limit.effort),
                velocity: positive(j.limit.velocity),
            };
            if let (Some(lo), Some(hi)) = (limits.lower, limits.upper) {
                if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                    return Err(self.e(element, format!("<limit> lower {lo} > upper {hi}")));
                }
            }
            let link = self.link(&j.child.link)?;
            let own = self.fold(None, link, &Pose::identity())?.ok_or_else(|| {
                self.e(
                    format!("link {}", link.name),
                    "a moving link needs an <inertial> with mass > 0 (urdf-rs reads a missing one as mass 0)",
                )
            })?;
            joints.push(JointDescription {
                name: j.name.clone(),
                child_link: link.name.clone(),
                joint: ChainJoint {
                    kind,
                    origin,
                    axis: axis / axis.norm(),
                },
                limits,
            });
            bodies.push(own);
            body_links.push(link.name.as_str());
            to_link = Pose::identity();
            carriers.push((link.name.as_str(), Some(bodies.len() - 1), to_link));
        }
        if joints.is_empty() {
            return Err(self.e("robot", format!("no moving joint between {base} and {tip}")));
        }
        // Side branches: every link hanging from a moving chain link, off the path, is
        // locked at 0 and folded into the body that carries it.
        let mut collisions = Vec::new();
        for (link, body, from_body) in &carriers {
            let Some(b) = *body else {
                continue; // fixed to the base: does not move
            };
            collisions.extend(link_collisions(self.link(link)?, b, from_body));
            for side in self.child_joints.get(link).into_iter().flatten() {
                if on_path.contains(&side.child.link.as_str()) {
                    continue;
                }
                let at = from_body.compose(&pose_of(&side.origin));
                bodies[b] = self.fold_subtree(bodies[b], side, &at, &mut locked)?;
                self.subtree_collisions(b, side, &at, &mut collisions)?;
            }
        }
        let tool = to_link;
        for (i, b) in bodies.iter().enumerate() {
            b.validate("body inertia").map_err(|e| {
                self.e(
                    format!("link {}", body_links[i]),
                    format!("the body's inertia (with what is folded into it) is invalid: {e}"),
                )
            })?;
        }
        Ok(ChainDescription {
            name: self.robot.name.clone(),
            base_link: base.to_string(),
            tip_link: tip.to_string(),
            joints,
            links: bodies,
            tool,
            tcp: Pose::identity(),
            locked_joints: locked,
            collisions,
            urdf_dir: self
                .path
                .parent()
                .map_or_else(|| std::path::PathBuf::from("."), Path::to_path_buf),
        })
    }

    /// The collision elements of a side branch (joint `j` and below, locked at 0) on body `b`.
    fn subtree_collisions(
        &self,
        b: usize,
        j: &urdf_rs::Joint,
        at: &Pose<f64>,
        out: &mut Vec<LinkCollision>,
    ) -> Result<()> {
        let link = self.link(&j.child.link)?;
        out.extend(link_collisions(link, b, at));
        for below in self
            .child_joints
            .get(link.name.as_str())
            .into_iter()
            .flatten()
        {
            self.subtree_collisions(b, below, &at.compose(&pose_of(&below.origin)), out)?;
        }
        Ok(())
    }

    fn link(&self, name: &str) -> Result<&'a urdf_rs::Link> {
        self.links
            .get(name)
            .copied()
            .ok_or_else(|| self.e(format!("link {name}"), "not found in the URDF"))
    }

    /// Adds `link`'s inertia, placed at `at` in the body frame, to `body`. `Ok(None)` when
    /// neither has mass.
    fn fold(
        &self,
        body: Option<RigidInertia<f64>>,
        link: &urdf_rs::Link,
        at: &Pose<f64>,
    ) -> Result<Option<RigidInertia<f64>>> {
        let i = &link.inertial;
        let element = || format!("link {}", link.name);
        let m = i.mass.value;
        if !m.is_finite() || m < 0.0 {
            return Err(self.e(
                element(),
                format!("<mass value> {m} must be ≥ 0 and finite"),
            ));
        }
        if m == 0.0 {
            return Ok(body);
        }
        let t = &i.inertia;
        let entries = [t.ixx, t.ixy, t.ixz, t.iyy, t.iyz, t.izz];
        // A link's own inertia may be a point mass's (zero) or otherwise semi-definite, as
        // Pinocchio accepts: a tool, a sensor or a flange fixed to a link adds its mass and
        // its parallel-axis term. What must be positive definite is each moving body's
        // inertia with everything folded into it, checked in `read`.
        if !semi_definite(entries) {
            return Err(self.e(
                element(),
                format!(
                    "<inertia> {entries:?} must be finite, symmetric positive definite, or \
                     semi-definite (a point mass)"
                ),
            ));
        }
        let own = RigidInertia::from_urdf(m, &pose_of(&i.origin), entries);
        let placed = own.transformed(at);
        Ok(Some(match body {
            Some(b) => b.combined(&placed),
            None => placed,
        }))
    }

    /// Folds a side branch (joint `j` and everything below it) locked at 0.
    fn fold_subtree(
        &self,
        mut body: RigidInertia<f64>,
        j: &urdf_rs::Joint,
        at: &Pose<f64>,
        locked: &mut Vec<String>,
    ) -> Result<RigidInertia<f64>> {
        if !matches!(j.joint_type, urdf_rs::JointType::Fixed) {
            locked.push(j.name.clone());
        }
        let link = self.link(&j.child.link)?;
        if let Some(b) = self.fold(Some(body), link, at)? {
            body = b;
        }
        for below in self
            .child_joints
            .get(link.name.as_str())
            .into_iter()
            .flatten()
        {
            let next = at.compose(&pose_of(&below.origin));
            body = self.fold_subtree(body, below, &next, locked)?;
        }
        Ok(body)
    }
}

/// `true` when the URDF's inertia entries `[ixx, ixy, ixz, iyy, iyz, izz]` are finite and
/// form a positive semi-definite matrix, to rounding: eigenvalues ≥ −1e-12 of the largest, or
/// of 1 kg·m² when all are smaller (iCub's point masses carry entries such as −5.4e-20).
fn semi_definite(i: [f64; 6]) -> bool {
    if !i.iter().all(|x| x.is_finite()) {
        return false;
    }
    let m = nalgebra::Matrix3::new(i[0], i[1], i[2], i[1], i[3], i[4], i[2], i[4], i[5]);
    let e = m.symmetric_eigenvalues();
    let scale = e.amax().max(1.0);
    e.iter().all(|l| *l >= -1e-12 * scale)
}
