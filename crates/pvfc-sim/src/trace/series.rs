//! `JointSeries`: a time series of joint-space vectors (one row per sample, `dof` columns),
//! for robots of any number of joints.

use serde::ser::{Serialize, SerializeSeq, Serializer};

/// Samples of a joint-space quantity (angles, velocities, torques): `len()` rows of `dof()`
/// numbers, stored row after row. `series[i]` is sample `i` as a slice.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointSeries {
    dof: usize,
    data: Vec<f64>,
}

impl JointSeries {
    /// An empty series of `dof`-vectors with room for `n` samples.
    pub fn with_capacity(dof: usize, n: usize) -> Self {
        JointSeries {
            dof,
            data: Vec::with_capacity(dof.saturating_mul(n)),
        }
    }

    /// Appends one sample; its length must be [`dof`](Self::dof) (a shorter or longer slice
    /// is cut or padded with NaN, so a bug shows in the data rather than as a panic).
    pub fn push(&mut self, x: &[f64]) {
        for i in 0..self.dof {
            self.data.push(x.get(i).copied().unwrap_or(f64::NAN));
        }
    }

    /// A series of `dof`-vectors from all its numbers, row after row; `None` unless their
    /// count is a multiple of `dof` (`dof = 0` takes no numbers).
    pub fn from_flat(dof: usize, data: Vec<f64>) -> Option<Self> {
        let whole = match dof {
            0 => data.is_empty(),
            d => data.len().is_multiple_of(d),
        };
        whole.then_some(JointSeries { dof, data })
    }

    /// The number of joints.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.data.len().checked_div(self.dof).unwrap_or(0)
    }

    /// `true` with no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sample `i`, if there is one.
    pub fn get(&self, i: usize) -> Option<&[f64]> {
        self.data.get(i * self.dof..(i + 1) * self.dof)
    }

    /// The samples in order.
    pub fn iter(&self) -> impl Iterator<Item = &[f64]> + '_ {
        self.data.chunks_exact(self.dof.max(1))
    }

    /// The samples of a range of indices.
    pub fn rows(&self, range: std::ops::Range<usize>) -> impl Iterator<Item = &[f64]> + '_ {
        self.iter().skip(range.start).take(range.len())
    }

    /// Column `j` (one joint over time).
    pub fn column(&self, j: usize) -> Vec<f64> {
        self.iter()
            .map(|r| r.get(j).copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// All the numbers, row after row.
    pub fn as_flat(&self) -> &[f64] {
        &self.data
    }
}

impl std::ops::Index<usize> for JointSeries {
    type Output = [f64];
    fn index(&self, i: usize) -> &[f64] {
        &self.data[i * self.dof..(i + 1) * self.dof]
    }
}

impl Serialize for JointSeries {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.len()))?;
        for r in self.iter() {
            seq.serialize_element(r)?;
        }
        seq.end()
    }
}
