//! What Foxglove's 3-D panel shows of a run. An arm: every link's frame as
//! `foxglove.FrameTransforms`, the arm as a line through its joints and the desired tool path
//! as a closed line (`foxglove.SceneUpdate`), all in the robot's base frame. A rigid body: its
//! frame and the desired attitude's, a box in each, and the path of the desired attitude's
//! x axis. The messages are Foxglove's own (the `foxglove` crate), in protobuf with the SDK's
//! schemas.

use crate::error::{Result, SimError};
use crate::scenario::Scenario;
use crate::scenario::{ArmSystem, RigidBodySpec, RobotSpec, System};
use crate::trace::Trace;
use foxglove::messages::{
    line_primitive, Color, CubePrimitive, FrameTransform, FrameTransforms, LinePrimitive, Point3,
    Quaternion, SceneEntity, SceneUpdate, Timestamp, Vector3,
};
use foxglove::Encode;
use nalgebra::{Rotation3, UnitQuaternion};
use pvfc_core::contour::Contour;
use pvfc_core::lie::{LieGroup, So3};
use pvfc_core::mechanics::Pose;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

/// Topic of the link frames (`foxglove.FrameTransforms`).
pub const FRAMES_TOPIC: &str = "/tf";
/// Topic of the arm drawn as a line through its joints (`foxglove.SceneUpdate`).
pub const ARM_TOPIC: &str = "/scene/arm";
/// Topic of a rigid body drawn as a box in its frame and in the desired attitude's
/// (`foxglove.SceneUpdate`, once at the start: the frames move them).
pub const BODY_TOPIC: &str = "/scene/body";
/// A rigid body's frame.
pub const BODY_FRAME: &str = "body";
/// The desired attitude's frame, `R_d(τ)` at the run's `τ`.
pub const DESIRED_FRAME: &str = "desired";
/// Topic of the desired tool path, and the Cartesian path if one was given
/// (`foxglove.SceneUpdate`, once at the start).
pub const PATH_TOPIC: &str = "/scene/path";

/// The 3-D frames are logged at most this often (Hz): enough for the panel's playback.
pub const SCENE_RATE: f64 = 50.0;

/// A run's 3-D scene: frame names, poses at the logged samples, the paths.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The base frame (the URDF's base link; `world` for a rigid body).
    pub base: String,
    /// The moving frames: an arm's links, base to tip, then `tool`; a rigid body's
    /// [`BODY_FRAME`] and [`DESIRED_FRAME`].
    pub frames: Vec<String>,
    /// `(time in ns, the poses of `frames` in the base frame)` at the logged samples.
    pub poses: Vec<(u64, Vec<Pose<f64>>)>,
    /// The desired contour's tool path (the forward kinematics of `x_d(τ)` over a period); for
    /// a rigid body, the tip of the desired attitude's x axis (1 m long) over a period.
    pub desired: Vec<[f64; 3]>,
    /// The Cartesian path the contour was made from, if any.
    pub cartesian: Vec<[f64; 3]>,
    /// The run's tool-path error budget ([`path_budget`](crate::trace::path_budget)) as
    /// named numbers in SI units (m, m/s, rad, s), written as the log's metadata record
    /// [`BUDGET_METADATA`]; empty without a Cartesian path or a steady pass.
    pub budget: BTreeMap<String, String>,
    /// A rigid body's box (its sides, m), drawn in [`BODY_FRAME`] and [`DESIRED_FRAME`]
    /// instead of an arm's line; `None` for an arm.
    pub body: Option<[f64; 3]>,
}

/// The name of the MCAP metadata record that holds a run's tool-path error budget.
pub const BUDGET_METADATA: &str = "pvfc.path_budget";

/// A tool-path error budget as named numbers.
fn budget_record(b: &crate::trace::path_budget::PathBudget) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    let mut put = |k: &str, v: f64| {
        m.insert(k.to_string(), format!("{v:e}"));
    };
    if let Some(g) = &b.geometry {
        put("geometry.samples", g.samples as f64);
        put("geometry.mean_m", g.mean);
        put("geometry.max_m", g.max);
        if let Some(a) = g.max_angle {
            put("geometry.max_angle_rad", a);
        }
    }
    put("distance.mean_m", b.spread.mean);
    put("distance.p95_m", b.spread.p95);
    put("distance.max_m", b.spread.max);
    if let Some(s) = &b.surface {
        put("surface.mean_m", s.mean);
        put("surface.p95_m", s.p95);
        put("surface.max_m", s.max);
    }
    if let Some(n) = &b.normal {
        put("normal.mean_m", n.mean);
        put("normal.min_m", n.min);
        put("normal.max_m", n.max);
    }
    put("speed_m_per_s", b.speed);
    put("worst.t_s", b.when);
    put("worst.along_m", b.distance.along);
    put("path.length_m", b.distance.length);
    put("window.start_s", b.window.0);
    put("window.end_s", b.window.1);
    m
}

/// Every how many samples of `t` the scene keeps a pose (at most [`SCENE_RATE`]).
fn scene_stride(t: &Trace) -> usize {
    (match t.t.get(1).zip(t.t.first()) {
        Some((t1, t0)) if t1 > t0 => ((1.0 / SCENE_RATE) / (t1 - t0)).round().max(1.0),
        _ => 1.0,
    }) as usize
}

impl Scene {
    /// The scene of run `t` of scenario `s`; `None` for the planar SCARA.
    pub fn of_run(s: &Scenario, t: &Trace) -> Result<Option<Self>> {
        Self::of_system(s, &System::build(s)?, t)
    }

    /// [`of_run`](Self::of_run) with the scenario's system already built.
    pub fn of_system(s: &Scenario, system: &System, t: &Trace) -> Result<Option<Self>> {
        Ok(match system {
            System::Scara(_) => None,
            System::SerialChain(sys) => Some(Self::of_run_with(s, sys, t)?),
            System::RigidBody(_) => Some(Self::of_body(s, t)?),
        })
    }

    /// The scene of run `t` of a rigid body's scenario `s`: the body's attitude `exp(q̂)` and
    /// the desired attitude `R_d(τ)` at each kept sample, the desired x axis's path over a
    /// period, and the body as a box with the proportions of a uniform box of its inertia's
    /// diagonal (the longest side 1 m).
    pub fn of_body(s: &Scenario, t: &Trace) -> Result<Self> {
        let contour = s.attitude_contour()?;
        let RobotSpec::RigidBody(RigidBodySpec { inertia }) = s.plant.robot else {
            return Err(SimError::Setting(
                "the scene of a rigid body: for kind = \"rigid_body\"".into(),
            ));
        };
        let at = |r: &So3<f64>| Pose {
            rotation: *r.matrix(),
            translation: nalgebra::Vector3::zeros(),
        };
        let poses = (0..t.len())
            .step_by(scene_stride(t))
            .map(|i| {
                let q = crate::model::fixed::<3>(&t.q[i], "trace q")?;
                let body = So3::exp(&q);
                let desired = contour.sample(t.tau[i]).point;
                Ok(((t.t[i] * 1e9).round() as u64, vec![at(&body), at(&desired)]))
            })
            .collect::<Result<Vec<_>>>()?;
        let period = s.period();
        let desired = (0..400)
            .map(|k| {
                let x = contour
                    .sample(period * k as f64 / 400.0)
                    .point
                    .matrix()
                    .column(0)
                    .into_owned();
                [x.x, x.y, x.z]
            })
            .collect();
        // A uniform box of unit mass with `J_xx = (b² + c²)/12`, …: `a² = 6(J_yy + J_zz − J_xx)`.
        let (jx, jy, jz) = (inertia[0][0], inertia[1][1], inertia[2][2]);
        let side = |a: f64, b: f64, c: f64| (6.0 * (b + c - a)).max(0.0).sqrt();
        let sides = [side(jx, jy, jz), side(jy, jz, jx), side(jz, jx, jy)];
        let longest = sides
            .iter()
            .cloned()
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        Ok(Scene {
            base: "world".into(),
            frames: vec![BODY_FRAME.into(), DESIRED_FRAME.into()],
            poses,
            desired,
            cartesian: vec![],
            budget: BTreeMap::new(),
            body: Some(sides.map(|x| x / longest)),
        })
    }

    /// The scene of run `t` of a URDF arm's scenario `s` whose system is built.
    pub fn of_run_with(s: &Scenario, system: &ArmSystem, t: &Trace) -> Result<Self> {
        let robot = &system.robot;
        let ctl = &system.controller;
        let d = robot.description();
        let mut frames: Vec<String> = d.joints.iter().map(|j| j.child_link.clone()).collect();
        frames.push("tool".into());
        let poses = (0..t.len())
            .step_by(scene_stride(t))
            .map(|i| Ok(((t.t[i] * 1e9).round() as u64, robot.link_poses(&t.q[i])?)))
            .collect::<Result<Vec<_>>>()?;
        let period = s.period();
        let desired = (0..400)
            .map(|k| {
                let (_, p) = robot.tool_pose(&ctl.contour_point(period * k as f64 / 400.0))?;
                Ok([p.x, p.y, p.z])
            })
            .collect::<Result<Vec<_>>>()?;
        let cartesian = match s.contour.cartesian() {
            Some(c) => c
                .path(&s.base_dir)?
                .sample(512)
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            None => vec![],
        };
        let budget = crate::trace::path_budget::path_budget(s, robot, t)?
            .map(|b| budget_record(&b))
            .unwrap_or_default();
        Ok(Scene {
            base: d.base_link.clone(),
            frames,
            poses,
            desired,
            cartesian,
            budget,
            body: None,
        })
    }
}

fn mcap_err(e: impl std::fmt::Display) -> SimError {
    SimError::Mcap(e.to_string())
}

fn timestamp(ns: u64) -> Timestamp {
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}

fn point(p: &[f64; 3]) -> Point3 {
    Point3 {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

fn line(
    kind: line_primitive::Type,
    points: &[[f64; 3]],
    rgba: [f64; 4],
    width: f64,
) -> LinePrimitive {
    LinePrimitive {
        r#type: kind as i32,
        pose: None,
        thickness: width,
        scale_invariant: false,
        points: points.iter().map(point).collect(),
        color: Some(Color {
            r: rgba[0],
            g: rgba[1],
            b: rgba[2],
            a: rgba[3],
        }),
        colors: vec![],
        indices: vec![],
    }
}

fn entity(id: &str, frame: &str, ns: u64, lines: Vec<LinePrimitive>) -> SceneEntity {
    SceneEntity {
        timestamp: Some(timestamp(ns)),
        frame_id: frame.into(),
        id: id.into(),
        lines,
        ..Default::default()
    }
}

/// The link frames at one sample.
pub fn frame_transforms(scene: &Scene, ns: u64, poses: &[Pose<f64>]) -> FrameTransforms {
    let transforms = scene
        .frames
        .iter()
        .zip(poses)
        .map(|(name, pose)| {
            let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                pose.rotation,
            ));
            let t = pose.translation;
            FrameTransform {
                timestamp: Some(timestamp(ns)),
                parent_frame_id: scene.base.clone(),
                child_frame_id: name.clone(),
                translation: Some(Vector3 {
                    x: t.x,
                    y: t.y,
                    z: t.z,
                }),
                rotation: Some(Quaternion {
                    x: q.i,
                    y: q.j,
                    z: q.k,
                    w: q.w,
                }),
            }
        })
        .collect();
    FrameTransforms { transforms }
}

/// The arm as one line from the base through every link frame's origin to the tool.
pub fn arm_update(scene: &Scene, ns: u64, poses: &[Pose<f64>]) -> SceneUpdate {
    let points: Vec<[f64; 3]> = std::iter::once([0.0; 3])
        .chain(poses.iter().map(|p| {
            let t = p.translation;
            [t.x, t.y, t.z]
        }))
        .collect();
    let arm = line(
        line_primitive::Type::LineStrip,
        &points,
        [0.2, 0.4, 0.9, 1.0],
        0.02,
    );
    SceneUpdate {
        deletions: vec![],
        entities: vec![entity("arm", &scene.base, ns, vec![arm])],
    }
}

/// A rigid body as a box of `sides` (m) in its frame, and a translucent one in the desired
/// attitude's.
pub fn body_update(ns: u64, sides: [f64; 3]) -> SceneUpdate {
    let cube = |rgba: [f64; 4]| CubePrimitive {
        pose: None,
        size: Some(Vector3 {
            x: sides[0],
            y: sides[1],
            z: sides[2],
        }),
        color: Some(Color {
            r: rgba[0],
            g: rgba[1],
            b: rgba[2],
            a: rgba[3],
        }),
    };
    let entity = |id: &str, frame: &str, rgba| SceneEntity {
        cubes: vec![cube(rgba)],
        ..entity(id, frame, ns, vec![])
    };
    SceneUpdate {
        deletions: vec![],
        entities: vec![
            entity("body", BODY_FRAME, [0.2, 0.4, 0.9, 1.0]),
            entity("desired", DESIRED_FRAME, [0.1, 0.7, 0.3, 0.3]),
        ],
    }
}

/// The desired tool path (and the Cartesian path), closed lines in the base frame.
pub fn path_update(scene: &Scene, ns: u64) -> SceneUpdate {
    let mut lines = vec![line(
        line_primitive::Type::LineLoop,
        &scene.desired,
        [0.1, 0.7, 0.3, 1.0],
        0.004,
    )];
    if !scene.cartesian.is_empty() {
        lines.push(line(
            line_primitive::Type::LineLoop,
            &scene.cartesian,
            [0.95, 0.5, 0.1, 1.0],
            0.002,
        ));
    }
    SceneUpdate {
        deletions: vec![],
        entities: vec![entity("desired_path", &scene.base, ns, lines)],
    }
}

/// A channel for Foxglove message type `M` on `topic`.
fn channel<M: Encode, W: Write + Seek>(
    w: &mut mcap::Writer<W>,
    topic: &str,
    meta: &BTreeMap<String, String>,
) -> Result<u16> {
    let schema = M::get_schema().ok_or_else(|| mcap_err("a Foxglove schema is missing"))?;
    let id = w
        .add_schema(&schema.name, &schema.encoding, &schema.data)
        .map_err(mcap_err)?;
    w.add_channel(id, topic, &M::get_message_encoding(), meta)
        .map_err(mcap_err)
}

fn put<M: Encode, W: Write + Seek>(
    w: &mut mcap::Writer<W>,
    channel_id: u16,
    sequence: u32,
    ns: u64,
    message: &M,
    buf: &mut Vec<u8>,
) -> Result<()> {
    buf.clear();
    message.encode(buf).map_err(mcap_err)?;
    let header = mcap::records::MessageHeader {
        channel_id,
        sequence,
        log_time: ns,
        publish_time: ns,
    };
    w.write_to_known_channel(&header, buf).map_err(mcap_err)
}

/// Writes the scene's channels into an open log.
pub(crate) fn write_scene<W: Write + Seek>(
    w: &mut mcap::Writer<W>,
    scene: &Scene,
    meta: &BTreeMap<String, String>,
) -> Result<()> {
    let frames = channel::<FrameTransforms, W>(w, FRAMES_TOPIC, meta)?;
    let robot_topic = if scene.body.is_some() {
        BODY_TOPIC
    } else {
        ARM_TOPIC
    };
    let robot = channel::<SceneUpdate, W>(w, robot_topic, meta)?;
    let path = channel::<SceneUpdate, W>(w, PATH_TOPIC, meta)?;
    if !scene.budget.is_empty() {
        w.write_metadata(&mcap::records::Metadata {
            name: BUDGET_METADATA.into(),
            metadata: scene.budget.clone(),
        })
        .map_err(mcap_err)?;
    }
    let mut buf = Vec::new();
    let start = scene.poses.first().map(|(ns, _)| *ns).unwrap_or(0);
    put(w, path, 0, start, &path_update(scene, start), &mut buf)?;
    if let Some(sides) = scene.body {
        put(w, robot, 0, start, &body_update(start, sides), &mut buf)?;
    }
    for (k, (ns, poses)) in scene.poses.iter().enumerate() {
        put(
            w,
            frames,
            k as u32,
            *ns,
            &frame_transforms(scene, *ns, poses),
            &mut buf,
        )?;
        if scene.body.is_none() {
            put(
                w,
                robot,
                k as u32,
                *ns,
                &arm_update(scene, *ns, poses),
                &mut buf,
            )?;
        }
    }
    Ok(())
}
