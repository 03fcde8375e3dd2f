//! MCAP logs of runs: JSON messages with JSON schemas, which Foxglove plots without
//! configuration, in zstd-compressed chunks. Logs are written from a finished [`Trace`], outside the control loop.

use crate::error::{Result, SimError};
use crate::simulate::Trace;
use serde_json::json;
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

fn schema(title: &str, properties: serde_json::Value) -> Vec<u8> {
    json!({"title": title, "type": "object", "properties": properties})
        .to_string()
        .into_bytes()
}

/// Writes a trace to an MCAP file, one message per sample on each topic.
pub fn write_mcap(trace: &Trace, path: &Path) -> Result<()> {
    let file = std::fs::File::create(path).map_err(|e| SimError::io(path, e))?;
    // Chunks compressed with zstd (Foxglove and the mcap tools read it): JSON messages
    // shrink about tenfold.
    let mut w = mcap::WriteOptions::default()
        .compression(Some(mcap::Compression::Zstd))
        .create(BufWriter::new(file))
        .map_err(mcap_err)?;
    let vec2 = json!({"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2});
    let num = json!({"type": "number"});
    let js = w
        .add_schema(
            "pvfc.JointState",
            "jsonschema",
            &schema(
                "pvfc.JointState",
                json!({"q": vec2, "v": vec2, "torque": vec2}),
            ),
        )
        .map_err(mcap_err)?;
    let cs = w
        .add_schema(
            "pvfc.Controller",
            "jsonschema",
            &schema(
                "pvfc.Controller",
                json!({"tau": num, "tau_dot": num, "flywheel_speed": num, "beta": num,
                       "potential": num, "lambda1": num, "lambda2": num, "energy": num,
                       "friction_power": num}),
            ),
        )
        .map_err(mcap_err)?;
    let contact_schema = match &trace.contact {
        Some(_) => Some(
            w.add_schema(
                "pvfc.Contact",
                "jsonschema",
                &schema(
                    "pvfc.Contact",
                    json!({"force": vec2, "normal_force": num, "depth": num, "torque": vec2,
                           "tool": vec2, "work_contact": num, "work_friction": num,
                           "work_controller": num, "nominal_speed": num}),
                ),
            )
            .map_err(mcap_err)?,
        ),
        None => None,
    };
    let meta = BTreeMap::from([("run".to_string(), trace.name.clone())]);
    let jc = w
        .add_channel(js, JOINT_STATE_TOPIC, "json", &meta)
        .map_err(mcap_err)?;
    let cc = w
        .add_channel(cs, CONTROLLER_TOPIC, "json", &meta)
        .map_err(mcap_err)?;
    let kc = match contact_schema {
        Some(id) => Some(
            w.add_channel(id, CONTACT_TOPIC, "json", &meta)
                .map_err(mcap_err)?,
        ),
        None => None,
    };
    for i in 0..trace.len() {
        let time = (trace.t[i] * 1e9).round() as u64;
        let header = |channel_id, sequence| mcap::records::MessageHeader {
            channel_id,
            sequence,
            log_time: time,
            publish_time: time,
        };
        let joint = json!({"q": trace.q[i], "v": trace.v[i], "torque": trace.torque[i]});
        w.write_to_known_channel(&header(jc, i as u32), joint.to_string().as_bytes())
            .map_err(mcap_err)?;
        let ctl = json!({
            "tau": trace.tau[i], "tau_dot": trace.tau_dot[i],
            "flywheel_speed": trace.flywheel_speed[i], "beta": trace.beta[i],
            "potential": trace.potential[i], "lambda1": trace.lambda1[i],
            "lambda2": trace.lambda2[i], "energy": trace.energy[i],
            "friction_power": trace.friction_power[i],
        });
        w.write_to_known_channel(&header(cc, i as u32), ctl.to_string().as_bytes())
            .map_err(mcap_err)?;
        if let (Some(kc), Some(c)) = (kc, &trace.contact) {
            let msg = json!({
                "force": c.force[i], "normal_force": c.normal_force[i], "depth": c.depth[i],
                "torque": c.torque[i], "tool": c.tool[i], "work_contact": c.work_contact[i],
                "work_friction": c.work_friction[i], "work_controller": c.work_controller[i],
                "nominal_speed": c.nominal_speed[i],
            });
            w.write_to_known_channel(&header(kc, i as u32), msg.to_string().as_bytes())
                .map_err(mcap_err)?;
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
    /// The JSON payload.
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
            data: serde_json::from_slice(&m.data).map_err(mcap_err)?,
        });
    }
    Ok(out)
}
