//! MCAP logs of runs, in zstd-compressed chunks, written from a finished [`Trace`] outside the
//! control loop. The plot channels are flat ROS 2 messages in CDR ([`cdr`]): binary, so that a
//! whole `pvfc reproduce` stays small, and read by Foxglove without configuration.

pub mod cdr;
pub mod scene;

use crate::error::{Result, SimError};
use crate::trace::{Column, Precision, Shape, Trace, Values, CONTACT_COLUMNS, TRACE_COLUMNS};
use cdr::{Field, MessageType, Width};
use scene::Scene;
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::Path;

/// Topic of the joint state: `q`, `v`, `torque`.
pub const JOINT_STATE_TOPIC: &str = "/joint_state";
/// Topic of the controller internals: `tau`, `tau_dot`, `flywheel_speed`, `beta`,
/// `w_beta`, `potential`, `lambda1`, `lambda2`, `energy`, `friction_power`.
pub const CONTROLLER_TOPIC: &str = "/pvfc/controller";

/// Topic of the contact columns (runs with an environment): `force`, `normal_force`,
/// `depth`, `torque`, `tool`, `work_contact`, `work_friction`, `work_controller`,
/// `work_gravity`, `nominal_speed`.
pub const CONTACT_TOPIC: &str = "/pvfc/contact";

fn mcap_err(e: impl std::fmt::Display) -> SimError {
    SimError::Mcap(e.to_string())
}

/// The message of the columns of `trace` that `keep` selects, as the log writes them (field
/// names, widths and order from [`crate::trace_columns!`]; vectors as fixed-size arrays of
/// the trace's own size), with those columns' samples, by name, for [`encode_sample`].
fn message<'a, S>(
    name: &str,
    columns: &[Column<S>],
    trace: &'a S,
    keep: impl Fn(&Column<S>) -> bool,
) -> (MessageType, Vec<(&'static str, Values<'a>)>) {
    let (fields, values) = columns
        .iter()
        .filter(|c| keep(c))
        .filter_map(|c| {
            let width = match c.precision? {
                Precision::Plot => Width::F32,
                Precision::Audit => Width::F64,
            };
            let values = (c.get)(trace);
            let field = match values {
                Values::Vectors(v) => Field::array(c.name, width, v.dof()),
                Values::Scalar(_) => Field::scalar(c.name, width),
            };
            Some((field, (c.name, values)))
        })
        .unzip();
    (
        MessageType {
            name: name.into(),
            fields,
        },
        values,
    )
}

/// Encodes sample `i` of the columns' `values` (those of [`message`]) as the message `t`.
fn encode_sample(
    t: &MessageType,
    values: &[(&'static str, Values<'_>)],
    i: usize,
    buf: &mut Vec<u8>,
) -> Result<()> {
    let samples = values
        .iter()
        .map(|(name, v)| {
            v.sample(i)
                .ok_or_else(|| mcap_err(format!("column {name} has no sample {i}")))
        })
        .collect::<Result<Vec<&[f64]>>>()?;
    t.encode(&samples, buf)
}

/// What a log holds beside the plot channels, and how densely they are sampled.
#[derive(Clone, Copy, Debug, Default)]
pub struct LogOptions<'a> {
    /// An arm's 3-D scene for Foxglove's 3-D panel ([`scene`]).
    pub scene: Option<&'a Scene>,
    /// The plot channels' rate (Hz): a sample is written when its time reaches the next
    /// multiple of `1/rate`, and the last sample always is. `None` writes every sample of the
    /// trace. The audit's claims are computed from the full trace, never from a log.
    pub rate: Option<f64>,
}

/// The indexes of the samples a log at `rate` (Hz) keeps: the first, the first at or after
/// each multiple of `1/rate`, and the last.
fn decimate(t: &[f64], rate: Option<f64>) -> Result<Vec<usize>> {
    let Some(rate) = rate else {
        return Ok((0..t.len()).collect());
    };
    if !(rate.is_finite() && rate > 0.0) {
        return Err(SimError::Setting(format!(
            "log rate {rate} Hz: must be finite and positive"
        )));
    }
    let mut keep = Vec::new();
    let mut last = None;
    for (i, &ti) in t.iter().enumerate() {
        // The period `ti` falls in; a millionth of a period of slack keeps the samples that
        // sit on the grid but round just below it.
        let period = (ti * rate + 1e-6).floor();
        if last != Some(period) || i + 1 == t.len() {
            keep.push(i);
            last = Some(period);
        }
    }
    Ok(keep)
}

/// Writes a trace to an MCAP file, one message per sample on each topic.
pub fn write_mcap(trace: &Trace, path: &Path) -> Result<()> {
    write_mcap_with(trace, &LogOptions::default(), path)
}

/// [`write_mcap`] with [`LogOptions`]: an arm's 3-D scene, a lower rate.
pub fn write_mcap_with(trace: &Trace, options: &LogOptions<'_>, path: &Path) -> Result<()> {
    let keep = decimate(&trace.t, options.rate)?;
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
    // The joint state (q, v, torque), the controller's internals, and the contact columns.
    let (jt, jvals) = message("pvfc/msg/JointState", TRACE_COLUMNS, trace, |c| {
        c.shape != Shape::Scalar
    });
    let (ct, cvals) = message("pvfc/msg/Controller", TRACE_COLUMNS, trace, |c| {
        c.shape == Shape::Scalar
    });
    let kt = trace
        .contact
        .as_ref()
        .map(|c| message("pvfc/msg/Contact", CONTACT_COLUMNS, c, |_| true));
    let jc = channel(&jt, JOINT_STATE_TOPIC)?;
    let cc = channel(&ct, CONTROLLER_TOPIC)?;
    let kc = match &kt {
        Some((kt, kvals)) => Some((channel(kt, CONTACT_TOPIC)?, kt, kvals)),
        None => None,
    };
    if let Some(scene) = options.scene {
        scene::write_scene(&mut w, scene, &meta)?;
    }
    let mut buf = Vec::new();
    for (sequence, &i) in keep.iter().enumerate() {
        let time = (trace.t[i] * 1e9).round() as u64;
        let mut put = |channel_id, data: &[u8]| {
            let header = mcap::records::MessageHeader {
                channel_id,
                sequence: sequence as u32,
                log_time: time,
                publish_time: time,
            };
            w.write_to_known_channel(&header, data).map_err(mcap_err)
        };
        encode_sample(&jt, &jvals, i, &mut buf)?;
        put(jc, &buf)?;
        encode_sample(&ct, &cvals, i, &mut buf)?;
        put(cc, &buf)?;
        if let Some((kc, kt, kvals)) = kc {
            encode_sample(kt, kvals, i, &mut buf)?;
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

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::decimate;

    #[test]
    fn decimation_keeps_one_sample_per_period_and_the_last() {
        let t: Vec<f64> = (0..=1000).map(|i| i as f64 * 1e-3).collect();
        let keep = decimate(&t, Some(250.0)).unwrap();
        assert_eq!(keep.len(), 251);
        assert!(keep.windows(2).all(|w| w[1] - w[0] == 4), "{keep:?}");
        assert_eq!(*keep.last().unwrap(), 1000);
        // A rate that does not divide the samples: still the first and the last.
        let keep = decimate(&t[..1000], Some(300.0)).unwrap();
        assert_eq!((keep[0], *keep.last().unwrap()), (0, 999));
        assert_eq!(decimate(&t, None).unwrap().len(), 1001);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(decimate(&t, Some(bad)).is_err());
        }
    }
}
