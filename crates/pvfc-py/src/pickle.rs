//! The pickled state of a `SimulationResult`: its name, its contour's period, and every
//! column of its trace (and of its contact trace) as `(name, width, bytes)`, the numbers as
//! little-endian `f64`, so that a result comes back from a worker process bit for bit (NaN
//! included). The columns are those of `pvfc_sim::trace_columns!`, the one list of them.

use pvfc_sim::trace::series::JointSeries;
use pvfc_sim::trace::{ContactTrace, Trace};

/// One column: its name, its width (numbers per sample; 0 for a scalar column) and its
/// numbers as bytes.
pub(crate) type ColumnState = (String, usize, Vec<u8>);

/// A column of a trace, as flat numbers and back.
trait Flat: Sized {
    fn flat(&self) -> (usize, &[f64]);
    fn from_flat(width: usize, data: Vec<f64>) -> Option<Self>;
}

impl Flat for Vec<f64> {
    fn flat(&self) -> (usize, &[f64]) {
        (0, self)
    }
    fn from_flat(width: usize, data: Vec<f64>) -> Option<Self> {
        (width == 0).then_some(data)
    }
}

impl Flat for JointSeries {
    fn flat(&self) -> (usize, &[f64]) {
        (self.dof(), self.as_flat())
    }
    fn from_flat(width: usize, data: Vec<f64>) -> Option<Self> {
        JointSeries::from_flat(width, data)
    }
}

fn save(name: &str, column: &impl Flat) -> ColumnState {
    let (width, data) = column.flat();
    let bytes = data.iter().flat_map(|x| x.to_le_bytes()).collect();
    (name.to_string(), width, bytes)
}

fn load<C: Flat>(columns: &[ColumnState], name: &str) -> Result<C, String> {
    let (_, width, bytes) = columns
        .iter()
        .find(|c| c.0 == name)
        .ok_or_else(|| format!("pickled result: no column `{name}`"))?;
    if !bytes.len().is_multiple_of(8) {
        return Err(format!(
            "pickled result: column `{name}` is not whole numbers"
        ));
    }
    let data = bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
        .collect();
    C::from_flat(*width, data)
        .ok_or_else(|| format!("pickled result: column `{name}` has the wrong shape"))
}

macro_rules! trace_state {
    (
        trace { $($n:ident as $p:ident : $shape:ident $log:ident $doc:literal;)* }
        contact { $($cn:ident as $cp:ident : $cshape:ident $clog:ident $cdoc:literal;)* }
    ) => {
        /// The columns of a trace, and of its contact trace if it has one.
        pub(crate) fn to_state(t: &Trace) -> (Vec<ColumnState>, Option<Vec<ColumnState>>) {
            let columns = vec![$(save(stringify!($n), &t.$n),)*];
            let contact = t.contact.as_ref().map(|c| vec![$(save(stringify!($cn), &c.$cn),)*]);
            (columns, contact)
        }

        /// The trace named `name` from its columns.
        pub(crate) fn from_state(
            name: String,
            columns: &[ColumnState],
            contact: Option<&[ColumnState]>,
        ) -> Result<Trace, String> {
            let contact = match contact {
                Some(c) => Some(ContactTrace { $($cn: load(c, stringify!($cn))?,)* }),
                None => None,
            };
            Ok(Trace {
                name,
                $($n: load(columns, stringify!($n))?,)*
                contact,
            })
        }
    };
}

pvfc_sim::trace_columns!(trace_state);
