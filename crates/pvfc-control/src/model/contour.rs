//! The contour a robot follows, as plain data: one table under `[contour]` named for its
//! kind. `[contour.lissajous]`, `[contour.waypoints]` and `[contour.ellipse]` are closed curves
//! in joint space ([`JointContourSpec`], built in `joint_contour.rs`), `[contour.cartesian]` a
//! tool path in Cartesian space ([`CartesianSpec`], followed through its inverse kinematics or
//! the task-space field), `[contour.attitude]` a rigid body's rotation at constant rate.
//!
//! A new closed joint-space curve is a variant of [`JointContourSpec`] and its formula in the
//! core: this file, the scenario files, the Python dicts and the C ABI's
//! `pvfc_contour_toml` read it without a change.
//!
//! The form before kinds (the SCARA's Lissajous keys directly under `[contour]`, a URDF arm's
//! `waypoints = [[…]]` and `spacing` beside them, a Cartesian path's `period` and `spacing`
//! outside its table) still reads: [`ContourSpec::from_value`] rewrites it, and
//! [`ContourSpec::before_kinds`] says whether a table is in it (for a deprecation message).

use super::cartesian::CartesianSpec;
use super::joint_contour::JointContourSpec;
use serde::{Deserialize, Deserializer, Serialize};
use serde_json::{Map, Value};

/// `[contour.attitude]`: a rotation at constant rate, `R_d(τ) = exp(r̂₀) exp(τ ω̂)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AttitudeContourSpec {
    /// The attitude at `τ = 0`, as a rotation vector `r₀` (rad).
    #[serde(default)]
    pub start: [f64; 3],
    /// The body angular velocity `ω` per unit of `τ` (rad); the contour's period is
    /// `2π/‖ω‖`.
    pub rate: [f64; 3],
}

/// A contour, of one kind.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum ContourSpec {
    /// A tool path in Cartesian space (`[contour.cartesian]`), for a serial chain.
    #[serde(rename = "cartesian")]
    Cartesian(Box<CartesianSpec>),
    /// A rigid body's rotation at constant rate (`[contour.attitude]`).
    #[serde(rename = "attitude")]
    Attitude(AttitudeContourSpec),
    /// A closed curve in joint space (`[contour.lissajous]`, `[contour.waypoints]`,
    /// `[contour.ellipse]`, …), for the SCARA (a Lissajous curve) or a serial chain.
    #[serde(untagged)]
    Joint(JointContourSpec),
}

/// The paper's Lissajous contour (section V): `x₁ = sin(2πτ/3)`, `x₂ = 1.5 sin(2πτ/6 + π/2)`,
/// closed every 6 of `τ`.
impl Default for ContourSpec {
    fn default() -> Self {
        ContourSpec::Joint(JointContourSpec::Lissajous {
            amplitude: vec![1.0, 1.5],
            periods: vec![3.0, 6.0],
            phase: vec![0.0, std::f64::consts::FRAC_PI_2],
            offset: vec![0.0, 0.0],
            period: Some(6.0),
        })
    }
}

/// The keys of the form before kinds, directly under `[contour]`.
const BEFORE_KINDS: [&str; 6] = [
    "amplitude",
    "periods",
    "phase",
    "offset",
    "period",
    "spacing",
];

/// The kinds that are not joint-space curves.
const OTHER_KINDS: [&str; 2] = ["cartesian", "attitude"];

impl ContourSpec {
    /// The contour's period in `τ`: a joint curve's, a Cartesian path's (`spacing ×
    /// samples` with fixed samples, else its `period`), one turn of an attitude contour
    /// (`2π/‖ω‖`); infinite where there is none.
    pub fn period(&self) -> f64 {
        match self {
            ContourSpec::Joint(j) => j.period().unwrap_or(f64::INFINITY),
            ContourSpec::Cartesian(c) => c.period_in_tau().unwrap_or(f64::INFINITY),
            ContourSpec::Attitude(a) => {
                let rate = a.rate.iter().map(|x| x * x).sum::<f64>().sqrt();
                std::f64::consts::TAU / rate
            }
        }
    }

    /// The Cartesian path, if the contour is one.
    pub fn cartesian(&self) -> Option<&CartesianSpec> {
        match self {
            ContourSpec::Cartesian(c) => Some(c),
            ContourSpec::Joint(_) | ContourSpec::Attitude(_) => None,
        }
    }

    /// The Cartesian path, if the contour is one, to edit.
    pub fn cartesian_mut(&mut self) -> Option<&mut CartesianSpec> {
        match self {
            ContourSpec::Cartesian(c) => Some(c),
            ContourSpec::Joint(_) | ContourSpec::Attitude(_) => None,
        }
    }

    /// The kind's name, as its table under `[contour]` is named.
    pub fn kind(&self) -> &'static str {
        match self {
            ContourSpec::Cartesian(_) => "cartesian",
            ContourSpec::Attitude(_) => "attitude",
            ContourSpec::Joint(j) => j.kind(),
        }
    }

    /// Whether a `[contour]` table (as a JSON value) is in the form before kinds.
    pub fn before_kinds(v: &Value) -> bool {
        let Value::Object(map) = v else {
            return false;
        };
        BEFORE_KINDS.iter().any(|k| map.contains_key(*k))
            || map.get("waypoints").is_some_and(Value::is_array)
    }

    /// Reads a `[contour]` table (a TOML table or a Python dict, as a JSON value), in the
    /// form with kinds or the one before; errors name the key.
    pub fn from_value(v: Value) -> Result<Self, String> {
        let before = Self::before_kinds(&v);
        let Value::Object(map) = v else {
            return Err("contour: a table with one kind of contour in it".into());
        };
        let map = if before { from_before_kinds(map)? } else { map };
        let mut kinds = map.into_iter();
        let (key, value) = match (kinds.next(), kinds.next()) {
            (Some(one), None) => one,
            (None, _) => {
                return Err("contour: say its kind with one table, e.g. [contour.lissajous], [contour.waypoints], [contour.ellipse], [contour.cartesian] or [contour.attitude]".into())
            }
            (Some((a, _)), Some((b, _))) => {
                return Err(format!(
                    "contour: one kind of contour, got [contour.{a}] and [contour.{b}]"
                ))
            }
        };
        let named = |e: serde_json::Error| format!("contour.{key}: {e}");
        Ok(match key.as_str() {
            "cartesian" => {
                ContourSpec::Cartesian(Box::new(serde_json::from_value(value).map_err(named)?))
            }
            "attitude" => ContourSpec::Attitude(serde_json::from_value(value).map_err(named)?),
            _ => {
                let mut one = Map::new();
                one.insert(key.clone(), value);
                ContourSpec::Joint(serde_json::from_value(Value::Object(one)).map_err(|e| {
                    let e = e.to_string();
                    match e.contains("unknown variant") {
                        true => format!("contour: {e}, or one of `{}`", OTHER_KINDS.join("`, `")),
                        false => format!("contour.{key}: {e}"),
                    }
                })?)
            }
        })
    }
}

impl<'de> Deserialize<'de> for ContourSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        ContourSpec::from_value(Value::deserialize(d)?).map_err(serde::de::Error::custom)
    }
}

/// The form before kinds rewritten with them: a URDF arm's `waypoints` array and `spacing`
/// become `[contour.waypoints]`; a Cartesian path takes `spacing` (or, without it, `period`,
/// by default 6) into its table; a joint or attitude table stands as it is (the Lissajous keys
/// beside it were unused); else the keys are the SCARA's Lissajous curve, the paper's where
/// left out.
fn from_before_kinds(mut map: Map<String, Value>) -> Result<Map<String, Value>, String> {
    let mut old = Map::new();
    for k in BEFORE_KINDS {
        if let Some(v) = map.remove(k) {
            old.insert(k.to_string(), v);
        }
    }
    let mut out = Map::new();
    if let Some(points) = map.remove("waypoints") {
        let spacing = old
            .remove("spacing")
            .ok_or("contour.spacing is needed with waypoints")?;
        let mut w = Map::new();
        w.insert("points".into(), points);
        w.insert("spacing".into(), spacing);
        out.insert("waypoints".into(), Value::Object(w));
    } else if let Some(Value::Object(mut c)) = map
        .get("cartesian")
        .is_some_and(Value::is_object)
        .then(|| map.remove("cartesian"))
        .flatten()
    {
        match old.remove("spacing") {
            Some(h) => c.insert("spacing".into(), h),
            None => c.insert(
                "period".into(),
                old.remove("period").unwrap_or(Value::from(6.0)),
            ),
        };
        out.insert("cartesian".into(), Value::Object(c));
    } else if map.is_empty() {
        let Ok(Value::Object(paper)) = serde_json::to_value(ContourSpec::default()) else {
            return Err("contour: the paper's contour does not serialize".into());
        };
        let Some(Value::Object(mut l)) = paper.get("lissajous").cloned() else {
            return Err("contour: the paper's contour is not a Lissajous curve".into());
        };
        for (k, v) in old {
            if k == "spacing" {
                return Err("contour.spacing: for waypoints or a Cartesian path".into());
            }
            l.insert(k, v);
        }
        out.insert("lissajous".into(), Value::Object(l));
    }
    out.extend(map);
    Ok(out)
}
