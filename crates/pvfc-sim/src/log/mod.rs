//! MCAP logs of runs, in zstd-compressed chunks, written from a finished [`Trace`] outside the
//! control loop. The plot channels are flat ROS 2 messages in CDR ([`cdr`]): binary, so that a
//! whole `pvfc reproduce` stays small, and read by Foxglove without configuration.

pub mod cdr;
pub mod scene;

use crate::error::{Result, SimError};
use crate::simulate::Trace;
use cdr::{Field, MessageType, Width};
use scene::ArmScene;
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::Path;

/// Topic of the joint state: `q`, `v`, `torque`.
pub const JOINT_STATE_TOPIC: &str = "/joint_state";
/// Topic of the controller internals: `tau`, `tau_dot`, `flywheel_speed`, `beta`,
/// `potential`, `lambda1`, `lambda2`, `energy`, `friction_power`.
pub const CONTROLLER_TOPIC: &str = "/pvfc/controller";

/// Topic of the contact columns (runs with an environment): `force`, `normal_force`,
/// `depth`, `torque`, `tool`, `work_contact`, `work_friction`, `work_controller`,
/// `nominal_speed`.
pub const CONTACT_TOPIC: &str = "/pvfc/contact";

fn mcap_err(e: impl std::fmt::Display) -> SimError {
    SimError::Mcap(e.to_string())
}

/// The joint state's message for `n` joints.
fn joint_state(n: usize) -> MessageType {
    MessageType {
        name: "pvfc/msg/JointState".into(),
        fields: vec![
            Field::array("q", Width::F32, n),
            Field::array("v", Width::F32, n),
            Field::array("torque", Width::F32, n),
        ],
    }
}

/// The controller's message: `energy` (κ_a, the audit's) in `float64`.
fn controller() -> MessageType {
    let f = |name| Field::scalar(name, Width::F32);
    MessageType {
        name: "pvfc/msg/Controller".into(),
        fields: vec![
            Field::scalar("energy", Width::F64),
            f("tau"),
            f("tau_dot"),
            f("flywheel_speed"),
            f("beta"),
            f("potential"),
            f("lambda1"),
            f("lambda2"),
            f("friction_power"),
        ],
    }
}

/// The contact columns' message for a `dim`-D workspace and `dof` joints: the works (the
/// audit's) in `float64`.
fn contact(dim: usize, dof: usize) -> MessageType {
    let f = |name| Field::scalar(name, Width::F32);
    let vector = |name, n| Field::array(name, Width::F32, n);
    MessageType {
        name: "pvfc/msg/Contact".into(),
        fields: vec![
            Field::scalar("work_contact", Width::F64),
            Field::scalar("work_friction", Width::F64),
            Field::scalar("work_controller", Width::F64),
            Field::scalar("work_gravity", Width::F64),
            vector("force", dim),
            f("normal_force"),
            f("depth"),
            vector("torque", dof),
            vector("tool", dim),
            f("nominal_speed"),
        ],
    }
}

/// Writes a trace to an MCAP file, one message per sample on each topic.
pub fn write_mcap(trace: &Trace, path: &Path) -> Result<()> {
    write_mcap_with_scene(trace, None, path)
}

/// [`write_mcap`], plus an arm's 3-D scene for Foxglove's 3-D panel ([`scene`]).
pub fn write_mcap_with_scene(trace: &Trace, scene: Option<&ArmScene>, path: &Path) -> Result<()> {
    let file = std::fs::File::create(path).map_err(|e| SimError::io(path, e))?;
    let mut w = mcap::WriteOptions::default()
        .compression(Some(mcap::Compression::Zstd))
        .emit_message_indexes(false)
        .chunk_size(Some(4 << 20))
        .create(BufWriter::new(file))
        .map_err(mcap_err)?;
    let meta = BTreeMap::from([("run".to_string(), trace.name.clone())]);
    let mut channel = |t: &MessageType, topic: &str| -> Result<u16> {
        let schema = w
            .add_schema(&t.name, "ros2msg", t.schema().as_bytes())
            .map_err(mcap_err)?;
        w.add_channel(schema, topic, "cdr", &meta).map_err(mcap_err)
    };
    let kt = trace
        .contact
        .as_ref()
        .map(|c| contact(c.force.dof(), c.torque.dof()));
    let (jt, ct) = (joint_state(trace.q.dof()), controller());
    let jc = channel(&jt, JOINT_STATE_TOPIC)?;
    let cc = channel(&ct, CONTROLLER_TOPIC)?;
    let kc = match &kt {
        Some(kt) => Some((channel(kt, CONTACT_TOPIC)?, kt)),
        None => None,
    };
    if let Some(scene) = scene {
        scene::write_scene(&mut w, scene, &meta)?;
    }
    let mut buf = Vec::new();
    for i in 0..trace.len() {
        let time = (trace.t[i] * 1e9).round() as u64;
        let mut put = |channel_id, data: &[u8]| {
            let header = mcap::records::MessageHeader {
                channel_id,
                sequence: i as u32,
                log_time: time,
                publish_time: time,
            };
            w.write_to_known_channel(&header, data).map_err(mcap_err)
        };
        jt.encode(&[&trace.q[i], &trace.v[i], &trace.torque[i]], &mut buf)?;
        put(jc, &buf)?;
        ct.encode(
            &[
                &[trace.energy[i]],
                &[trace.tau[i]],
                &[trace.tau_dot[i]],
                &[trace.flywheel_speed[i]],
                &[trace.beta[i]],
                &[trace.potential[i]],
                &[trace.lambda1[i]],
                &[trace.lambda2[i]],
                &[trace.friction_power[i]],
            ],
            &mut buf,
        )?;
        put(cc, &buf)?;
        if let (Some((kc, kt)), Some(c)) = (kc, &trace.contact) {
            kt.encode(
                &[
                    &[c.work_contact[i]],
                    &[c.work_friction[i]],
                    &[c.work_controller[i]],
                    &[c.work_gravity[i]],
                    &c.force[i],
                    &[c.normal_force[i]],
                    &[c.depth[i]],
                    &c.torque[i],
                    &c.tool[i],
                    &[c.nominal_speed[i]],
                ],
                &mut buf,
            )?;
            put(kc, &buf)?;
        }
    }
    w.finish().map_err(mcap_err)?;
    Ok(())
}

/// One message read back from a log.
#[derive(Clone, Debug, PartialEq)]
pub struct LoggedMessage {
    /// The topic.
    pub topic: String,
    /// Log time (ns).
    pub log_time: u64,
    /// The payload as a JSON object (CDR messages decoded field by field).
    pub data: serde_json::Value,
}

/// Reads every message of an MCAP log written by [`write_mcap`].
pub fn read_mcap(path: &Path) -> Result<Vec<LoggedMessage>> {
    let bytes = std::fs::read(path).map_err(|e| SimError::io(path, e))?;
    let mut out = Vec::new();
    for m in mcap::MessageStream::new(&bytes).map_err(mcap_err)? {
        let m = m.map_err(mcap_err)?;
        out.push(LoggedMessage {
            topic: m.channel.topic.clone(),
            log_time: m.log_time,
            data: decode(&m.channel, &m.data)?,
        });
    }
    Ok(out)
}

/// A message's payload as JSON: CDR by its `ros2msg` schema, JSON as it is.
fn decode(channel: &mcap::Channel<'_>, data: &[u8]) -> Result<serde_json::Value> {
    match (channel.message_encoding.as_str(), &channel.schema) {
        ("cdr", Some(schema)) if schema.encoding == "ros2msg" => {
            let text = std::str::from_utf8(&schema.data).map_err(mcap_err)?;
            MessageType::parse(&schema.name, text)?.decode(data)
        }
        ("json", _) => serde_json::from_slice(data).map_err(mcap_err),
        ("protobuf", Some(schema)) if schema.name == "foxglove.FrameTransforms" => {
            foxglove_json::<foxglove::messages::FrameTransforms>(data)
        }
        ("protobuf", Some(schema)) if schema.name == "foxglove.SceneUpdate" => {
            foxglove_json::<foxglove::messages::SceneUpdate>(data)
        }
        (other, _) => Err(mcap_err(format!(
            "{}: message encoding `{other}` is not read here",
            channel.topic
        ))),
    }
}

/// A Foxglove message as JSON (the SDK's own decoding and field names).
fn foxglove_json<M: foxglove::Decode + serde::Serialize>(data: &[u8]) -> Result<serde_json::Value> {
    let m = M::decode(data).map_err(mcap_err)?;
    serde_json::to_value(&m).map_err(mcap_err)
}
