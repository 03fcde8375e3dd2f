//! A study's table as an Arrow IPC file (Feather v2, `NAME.arrow`), the columnar format that
//! pandas (`read_feather`), Polars (`read_ipc`) and pyarrow read without parsing text.
//!
//! The columns are those of the CSV table ([`crate::study::table::header`]): `run` (Int64),
//! the axes (Float64), the metrics (Float64, null where a metric does not apply or the run
//! failed) and `error` (Utf8, null for a run that succeeded). The numbers are the rows' `f64`
//! bits, so the file and the CSV read back to the same values.
//!
//! The file is written with the `flatbuffers` runtime (the serialisation the Arrow format is
//! defined in) following the format's `Schema.fbs`, `Message.fbs` and `File.fbs`, version V5:
//! the magic `ARROW1`, the schema message, one record batch, the end-of-stream marker, the
//! footer. The `arrow-ipc` crate would add some forty crates to the build for these few
//! hundred bytes of metadata.

use crate::error::{Result, SimError};
use crate::study::runner::StudyRow;
use crate::study::table;
use flatbuffers::{FlatBufferBuilder, TableFinishedWIPOffset, WIPOffset};
use std::path::Path;

/// The format's `MetadataVersion.V5`.
const V5: i16 = 4;
/// `MessageHeader` union tags.
const SCHEMA: u8 = 1;
const RECORD_BATCH: u8 = 3;
/// `Type` union tags.
const INT: u8 = 2;
const FLOATING_POINT: u8 = 3;
const UTF8: u8 = 5;
/// `Precision.DOUBLE`.
const DOUBLE: i16 = 2;
/// The file's magic, at its start (padded to 8 bytes) and at its end.
const MAGIC: &[u8; 6] = b"ARROW1";

/// Field offsets in the flatbuffers vtables (4 + 2 × the field's index in its table; a union
/// takes two: its tag, then its value).
mod slot {
    pub const MESSAGE_VERSION: u16 = 4;
    pub const MESSAGE_HEADER_TYPE: u16 = 6;
    pub const MESSAGE_HEADER: u16 = 8;
    pub const MESSAGE_BODY_LENGTH: u16 = 10;
    pub const SCHEMA_FIELDS: u16 = 6;
    pub const FIELD_NAME: u16 = 4;
    pub const FIELD_NULLABLE: u16 = 6;
    pub const FIELD_TYPE_TYPE: u16 = 8;
    pub const FIELD_TYPE: u16 = 10;
    pub const FIELD_CHILDREN: u16 = 14;
    pub const INT_BIT_WIDTH: u16 = 4;
    pub const INT_IS_SIGNED: u16 = 6;
    pub const FLOATING_POINT_PRECISION: u16 = 4;
    pub const RECORD_BATCH_LENGTH: u16 = 4;
    pub const RECORD_BATCH_NODES: u16 = 6;
    pub const RECORD_BATCH_BUFFERS: u16 = 8;
    pub const FOOTER_VERSION: u16 = 4;
    pub const FOOTER_SCHEMA: u16 = 6;
    pub const FOOTER_DICTIONARIES: u16 = 8;
    pub const FOOTER_RECORD_BATCHES: u16 = 10;
}

/// Where a column's values come from in a [`StudyRow`]; its Arrow type and nullability follow.
#[derive(Clone, Copy)]
enum Source {
    /// The run's index: Int64, never null.
    Run,
    /// Axis `i`'s value: Float64, never null.
    Axis(usize),
    /// Metric `i`: Float64, null where absent.
    Metric(usize),
    /// The error: Utf8, null for a run that succeeded.
    Error,
}

/// A column: its name and where its values come from.
struct Column<'a> {
    name: &'a str,
    source: Source,
}

/// The columns of [`table::header`]`(keys, metrics)`, in its order.
fn columns<'a>(header: &'a [String], keys: usize, metrics: usize) -> Vec<Column<'a>> {
    let sources = std::iter::once(Source::Run)
        .chain((0..keys).map(Source::Axis))
        .chain((0..metrics).map(Source::Metric))
        .chain(std::iter::once(Source::Error));
    header
        .iter()
        .zip(sources)
        .map(|(name, source)| Column { name, source })
        .collect()
}

type Table = WIPOffset<TableFinishedWIPOffset>;

/// A vector of structs made of 8-byte words (`FieldNode`, `Buffer`, `Block`): `words` per
/// struct, little-endian as flatbuffers writes every scalar.
fn struct_vector<'a>(
    fbb: &mut FlatBufferBuilder<'a>,
    structs: &[Vec<u64>],
) -> WIPOffset<flatbuffers::Vector<'a, u64>> {
    let words: usize = structs.iter().map(Vec::len).sum();
    fbb.start_vector::<u64>(words);
    // A flatbuffer is built back to front.
    for w in structs.iter().rev().flat_map(|s| s.iter().rev()) {
        fbb.push(*w);
    }
    fbb.end_vector::<u64>(structs.len())
}

/// The `Schema` table of `columns`.
fn schema(fbb: &mut FlatBufferBuilder<'_>, columns: &[Column<'_>]) -> Table {
    let fields: Vec<Table> = columns
        .iter()
        .map(|c| {
            let name = fbb.create_string(c.name);
            let t = fbb.start_table();
            let tag = match c.source {
                Source::Run => {
                    fbb.push_slot::<i32>(slot::INT_BIT_WIDTH, 64, 0);
                    fbb.push_slot::<bool>(slot::INT_IS_SIGNED, true, false);
                    INT
                }
                Source::Axis(_) | Source::Metric(_) => {
                    fbb.push_slot::<i16>(slot::FLOATING_POINT_PRECISION, DOUBLE, 0);
                    FLOATING_POINT
                }
                Source::Error => UTF8,
            };
            let nullable = matches!(c.source, Source::Metric(_) | Source::Error);
            let ty = fbb.end_table(t);
            let children = fbb.create_vector::<Table>(&[]);
            let f = fbb.start_table();
            fbb.push_slot_always(slot::FIELD_NAME, name);
            fbb.push_slot::<bool>(slot::FIELD_NULLABLE, nullable, false);
            fbb.push_slot::<u8>(slot::FIELD_TYPE_TYPE, tag, 0);
            fbb.push_slot_always(slot::FIELD_TYPE, ty);
            fbb.push_slot_always(slot::FIELD_CHILDREN, children);
            fbb.end_table(f)
        })
        .collect();
    let fields = fbb.create_vector(&fields);
    let s = fbb.start_table();
    fbb.push_slot_always(slot::SCHEMA_FIELDS, fields);
    fbb.end_table(s)
}

/// A `Message` flatbuffer with the header `build` writes (of union tag `tag`) and a body of
/// `body_length` bytes.
fn message(
    tag: u8,
    body_length: usize,
    build: impl FnOnce(&mut FlatBufferBuilder<'_>) -> Table,
) -> Vec<u8> {
    let mut fbb = FlatBufferBuilder::new();
    let header = build(&mut fbb);
    let m = fbb.start_table();
    fbb.push_slot::<i16>(slot::MESSAGE_VERSION, V5, 0);
    fbb.push_slot::<u8>(slot::MESSAGE_HEADER_TYPE, tag, 0);
    fbb.push_slot_always(slot::MESSAGE_HEADER, header);
    fbb.push_slot::<i64>(slot::MESSAGE_BODY_LENGTH, body_length as i64, 0);
    let m = fbb.end_table(m);
    fbb.finish(m, None);
    fbb.finished_data().to_vec()
}

/// Zero bytes up to a multiple of 8.
fn pad(out: &mut Vec<u8>) {
    out.resize(out.len().next_multiple_of(8), 0);
}

/// Appends an encapsulated message (continuation marker, metadata length, metadata padded to
/// 8 bytes, body) and returns its `Block` (offset, metadata length, body length).
fn encapsulate(out: &mut Vec<u8>, metadata: &[u8], body: &[u8]) -> Vec<u64> {
    let offset = out.len();
    let length = (8 + metadata.len()).next_multiple_of(8) - 8;
    out.extend_from_slice(&u32::MAX.to_le_bytes());
    out.extend_from_slice(&(length as i32).to_le_bytes());
    out.extend_from_slice(metadata);
    pad(out);
    out.extend_from_slice(body);
    vec![offset as u64, (length + 8) as u64, body.len() as u64]
}

/// The record batch's body and its `FieldNode`s and `Buffer`s.
struct Body {
    bytes: Vec<u8>,
    nodes: Vec<Vec<u64>>,
    buffers: Vec<Vec<u64>>,
}

impl Body {
    /// Appends a buffer (padded to 8 bytes) and records its offset and length.
    fn buffer(&mut self, data: &[u8]) {
        self.buffers
            .push(vec![self.bytes.len() as u64, data.len() as u64]);
        self.bytes.extend_from_slice(data);
        pad(&mut self.bytes);
    }

    /// Appends a column's validity bitmap (none if no value is null) and records its node.
    fn validity(&mut self, valid: &[bool]) {
        let nulls = valid.iter().filter(|v| !**v).count();
        self.nodes.push(vec![valid.len() as u64, nulls as u64]);
        if nulls == 0 {
            self.buffer(&[]);
        } else {
            let mut bits = vec![0u8; valid.len().div_ceil(8)];
            for (i, _) in valid.iter().enumerate().filter(|(_, v)| **v) {
                bits[i / 8] |= 1 << (i % 8);
            }
            self.buffer(&bits);
        }
    }
}

/// The table's columns as a record batch body.
fn body(columns: &[Column<'_>], rows: &[StudyRow]) -> Body {
    let mut b = Body {
        bytes: Vec::new(),
        nodes: Vec::new(),
        buffers: Vec::new(),
    };
    let floats = |b: &mut Body, value: &dyn Fn(&StudyRow) -> Option<f64>| {
        let values: Vec<Option<f64>> = rows.iter().map(value).collect();
        b.validity(&values.iter().map(Option::is_some).collect::<Vec<_>>());
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|v| v.unwrap_or(0.0).to_le_bytes())
            .collect();
        b.buffer(&bytes);
    };
    for column in columns {
        match column.source {
            Source::Run => {
                b.validity(&vec![true; rows.len()]);
                let values: Vec<u8> = rows
                    .iter()
                    .flat_map(|r| (r.index as i64).to_le_bytes())
                    .collect();
                b.buffer(&values);
            }
            Source::Axis(i) => floats(&mut b, &|r| r.parameters.get(i).copied()),
            Source::Metric(i) => floats(&mut b, &|r| r.metrics.get(i).copied().flatten()),
            Source::Error => {
                b.validity(&rows.iter().map(|r| r.error.is_some()).collect::<Vec<_>>());
                let mut offsets = vec![0i32];
                let mut data = Vec::new();
                for r in rows {
                    data.extend_from_slice(r.error.as_deref().unwrap_or("").as_bytes());
                    offsets.push(data.len() as i32);
                }
                let offsets: Vec<u8> = offsets.iter().flat_map(|o| o.to_le_bytes()).collect();
                b.buffer(&offsets);
                b.buffer(&data);
            }
        }
    }
    b
}

/// The Arrow IPC file of a study's table: the columns of [`crate::study::table::header`] for
/// the axes `keys` and the `metrics`, one row per entry of `rows`.
pub fn encode(keys: &[String], metrics: &[&str], rows: &[StudyRow]) -> Result<Vec<u8>> {
    let axes = keys.len();
    if let Some(r) = rows
        .iter()
        .find(|r| r.parameters.len() != axes || r.metrics.len() != metrics.len())
    {
        return Err(SimError::Setting(format!(
            "study row {} has {} parameters and {} metrics, its table {axes} and {}",
            r.index,
            r.parameters.len(),
            r.metrics.len(),
            metrics.len()
        )));
    }
    let text: usize = rows
        .iter()
        .filter_map(|r| r.error.as_ref())
        .map(String::len)
        .sum();
    if text > i32::MAX as usize {
        return Err(SimError::Setting(
            "the study's error messages exceed the 2 GiB of an Arrow Utf8 column".into(),
        ));
    }
    let header = table::header(keys, metrics);
    let columns = columns(&header, axes, metrics.len());
    let body = body(&columns, rows);
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    pad(&mut out);
    let schema_message = message(SCHEMA, 0, |fbb| schema(fbb, &columns));
    encapsulate(&mut out, &schema_message, &[]);
    let batch_message = message(RECORD_BATCH, body.bytes.len(), |fbb| {
        let nodes = struct_vector(fbb, &body.nodes);
        let buffers = struct_vector(fbb, &body.buffers);
        let t = fbb.start_table();
        fbb.push_slot::<i64>(slot::RECORD_BATCH_LENGTH, rows.len() as i64, 0);
        fbb.push_slot_always(slot::RECORD_BATCH_NODES, nodes);
        fbb.push_slot_always(slot::RECORD_BATCH_BUFFERS, buffers);
        fbb.end_table(t)
    });
    let block = encapsulate(&mut out, &batch_message, &body.bytes);
    // The end-of-stream marker.
    out.extend_from_slice(&u32::MAX.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    let mut fbb = FlatBufferBuilder::new();
    let schema = schema(&mut fbb, &columns);
    let dictionaries = struct_vector(&mut fbb, &[]);
    // A Block is an offset (8 bytes), a metadata length (4 bytes and 4 of padding) and a
    // body length (8 bytes).
    let batches = struct_vector(&mut fbb, &[block]);
    let f = fbb.start_table();
    fbb.push_slot::<i16>(slot::FOOTER_VERSION, V5, 0);
    fbb.push_slot_always(slot::FOOTER_SCHEMA, schema);
    fbb.push_slot_always(slot::FOOTER_DICTIONARIES, dictionaries);
    fbb.push_slot_always(slot::FOOTER_RECORD_BATCHES, batches);
    let f = fbb.end_table(f);
    fbb.finish(f, None);
    let footer = fbb.finished_data();
    out.extend_from_slice(footer);
    out.extend_from_slice(&(footer.len() as i32).to_le_bytes());
    out.extend_from_slice(MAGIC);
    Ok(out)
}

/// Writes the Arrow IPC file of a study's table to `path` through a temporary file, so that
/// it is never half written.
pub fn write(path: &Path, keys: &[String], metrics: &[&str], rows: &[StudyRow]) -> Result<()> {
    let bytes = encode(keys, metrics, rows)?;
    let tmp = path.with_extension("arrow.tmp");
    std::fs::write(&tmp, bytes).map_err(|e| SimError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| SimError::io(path, e))
}
