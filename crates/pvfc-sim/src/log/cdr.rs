//! Flat ROS 2 messages in CDR: the binary encoding Foxglove reads (schema encoding `ros2msg`,
//! message encoding `cdr`). A message here is a list of `float32`/`float64` scalars and
//! fixed-size arrays, enough for every plot channel of a run. Plot values go as `float32`
//! (seven digits, as a plot shows), the energy audit's columns as `float64` (their residuals are
//! 1e-15 of the energy: `float32` would hide them).
//!
//! Encoding (OMG CDR, little endian, as Fast-CDR writes it for ROS 2): a four-byte
//! encapsulation header `00 01 00 00`, then the fields in order, each number aligned to its
//! own size counted from the end of the header; fixed-size arrays carry no length.

use crate::error::{Result, SimError};

/// The width of a field's numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Width {
    /// `float32`.
    F32,
    /// `float64`.
    F64,
}

impl Width {
    fn bytes(self) -> usize {
        match self {
            Width::F32 => 4,
            Width::F64 => 8,
        }
    }

    fn ros_name(self) -> &'static str {
        match self {
            Width::F32 => "float32",
            Width::F64 => "float64",
        }
    }
}

/// One field: a name, a width and a count (`None`: a scalar; `Some(n)`: `n` numbers).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Field {
    /// The field's name.
    pub name: String,
    /// `float32` or `float64`.
    pub width: Width,
    /// `None` for a scalar, `Some(n)` for a fixed-size array.
    pub count: Option<usize>,
}

impl Field {
    /// A scalar field.
    pub fn scalar(name: &str, width: Width) -> Self {
        Field {
            name: name.into(),
            width,
            count: None,
        }
    }

    /// A fixed-size array field.
    pub fn array(name: &str, width: Width, n: usize) -> Self {
        Field {
            name: name.into(),
            width,
            count: Some(n),
        }
    }

    fn len(&self) -> usize {
        self.count.unwrap_or(1)
    }
}

/// A flat message type: its ROS 2 name (`pvfc/msg/JointState`) and fields.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MessageType {
    /// The type's name, as Foxglove shows it.
    pub name: String,
    /// The fields, in order.
    pub fields: Vec<Field>,
}

const HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

fn cdr_err(what: impl Into<String>) -> SimError {
    SimError::Mcap(what.into())
}

impl MessageType {
    /// The `.msg` text (schema encoding `ros2msg`): one `float64[6] q` line per field.
    pub fn schema(&self) -> String {
        self.fields
            .iter()
            .map(|f| match f.count {
                Some(n) => format!("{}[{n}] {}\n", f.width.ros_name(), f.name),
                None => format!("{} {}\n", f.width.ros_name(), f.name),
            })
            .collect()
    }

    /// The type back from its `.msg` text (only what [`schema`](Self::schema) writes).
    pub fn parse(name: &str, text: &str) -> Result<Self> {
        let fields = text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .map(|line| {
                let bad = || cdr_err(format!("{name}: unsupported field `{line}`"));
                let (ty, field) = line.split_once(' ').ok_or_else(bad)?;
                let (base, count) = match ty.split_once('[') {
                    Some((b, n)) => {
                        let n = n.strip_suffix(']').ok_or_else(bad)?;
                        (b, Some(n.parse::<usize>().map_err(|_| bad())?))
                    }
                    None => (ty, None),
                };
                let width = match base {
                    "float32" => Width::F32,
                    "float64" => Width::F64,
                    _ => return Err(bad()),
                };
                Ok(Field {
                    name: field.trim().into(),
                    width,
                    count,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(MessageType {
            name: name.into(),
            fields,
        })
    }

    /// Encodes one message: `values[k]` holds field `k`'s numbers (one for a scalar).
    pub fn encode(&self, values: &[&[f64]], out: &mut Vec<u8>) -> Result<()> {
        if values.len() != self.fields.len() {
            return Err(cdr_err(format!(
                "{}: {} fields given, {} expected",
                self.name,
                values.len(),
                self.fields.len()
            )));
        }
        out.clear();
        out.extend_from_slice(&HEADER);
        for (f, v) in self.fields.iter().zip(values) {
            if v.len() != f.len() {
                return Err(cdr_err(format!(
                    "{}.{}: {} numbers given, {} expected",
                    self.name,
                    f.name,
                    v.len(),
                    f.len()
                )));
            }
            pad(out, f.width.bytes());
            for x in v.iter() {
                match f.width {
                    Width::F32 => out.extend_from_slice(&(*x as f32).to_le_bytes()),
                    Width::F64 => out.extend_from_slice(&x.to_le_bytes()),
                }
            }
        }
        Ok(())
    }

    /// Decodes one message into a JSON object (arrays for array fields).
    pub fn decode(&self, data: &[u8]) -> Result<serde_json::Value> {
        let short = || cdr_err(format!("{}: message too short", self.name));
        if data.get(..4) != Some(&HEADER[..]) {
            return Err(cdr_err(format!(
                "{}: not little-endian plain CDR",
                self.name
            )));
        }
        let body = &data[4..];
        let mut at = 0usize;
        let mut map = serde_json::Map::new();
        for f in &self.fields {
            let w = f.width.bytes();
            at = at.next_multiple_of(w);
            let mut xs = Vec::with_capacity(f.len());
            for _ in 0..f.len() {
                let b = body.get(at..at + w).ok_or_else(short)?;
                xs.push(match f.width {
                    Width::F32 => f32::from_le_bytes(b.try_into().map_err(|_| short())?) as f64,
                    Width::F64 => f64::from_le_bytes(b.try_into().map_err(|_| short())?),
                });
                at += w;
            }
            let value = match f.count {
                Some(_) => serde_json::Value::from(xs),
                None => serde_json::Value::from(xs[0]),
            };
            map.insert(f.name.clone(), value);
        }
        if at != body.len() {
            return Err(cdr_err(format!("{}: trailing bytes", self.name)));
        }
        Ok(serde_json::Value::Object(map))
    }
}

/// Zero bytes up to the next multiple of `align`, counted after the header.
fn pad(out: &mut Vec<u8>, align: usize) {
    let body = out.len() - HEADER.len();
    out.resize(HEADER.len() + body.next_multiple_of(align), 0);
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;

    fn joint() -> MessageType {
        MessageType {
            name: "pvfc/msg/Test".into(),
            fields: vec![
                Field::scalar("a", Width::F32),
                Field::scalar("e", Width::F64),
                Field::array("q", Width::F32, 3),
                Field::array("w", Width::F64, 2),
            ],
        }
    }

    #[test]
    fn layout_is_plain_cdr_with_alignment() {
        let t = joint();
        let mut out = vec![];
        t.encode(&[&[1.5], &[2.0], &[1.0, 2.0, 3.0], &[4.0, 5.0]], &mut out)
            .unwrap();
        // header 4 | a: 4 | pad 4 | e: 8 | q: 12 | pad 4 | w: 16
        assert_eq!(out.len(), 4 + 4 + 4 + 8 + 12 + 4 + 16);
        assert_eq!(&out[..4], &HEADER);
        assert_eq!(&out[4..8], &1.5f32.to_le_bytes());
        assert_eq!(&out[8..12], &[0, 0, 0, 0]);
        assert_eq!(&out[12..20], &2.0f64.to_le_bytes());
        assert_eq!(&out[32..36], &[0, 0, 0, 0]);
        assert_eq!(&out[36..44], &4.0f64.to_le_bytes());
        let back = t.decode(&out).unwrap();
        assert_eq!(back["a"], 1.5);
        assert_eq!(back["q"][2], 3.0);
        assert_eq!(back["w"][1], 5.0);
        assert!(t.decode(&out[..out.len() - 1]).is_err());
        assert!(t.decode(&[out.clone(), vec![0]].concat()).is_err());
    }

    #[test]
    fn schema_text_parses_back() {
        let t = joint();
        assert_eq!(
            t.schema(),
            "float32 a\nfloat64 e\nfloat32[3] q\nfloat64[2] w\n"
        );
        assert_eq!(MessageType::parse(&t.name, &t.schema()).unwrap(), t);
        assert!(MessageType::parse("x", "string s\n").is_err());
        assert!(MessageType::parse("x", "float64[] s\n").is_err());
    }

    #[test]
    fn wrong_counts_are_errors() {
        let t = joint();
        let mut out = vec![];
        assert!(t.encode(&[&[1.0]], &mut out).is_err());
        assert!(t
            .encode(&[&[1.0], &[2.0], &[1.0, 2.0], &[4.0, 5.0]], &mut out)
            .is_err());
    }
}
