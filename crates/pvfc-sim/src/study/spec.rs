//! A study's specification: a base scenario, the axes over its keys, and how the runs are
//! drawn; expanded into one scenario per run, every run checked before anything runs.

use crate::error::{Result, SimError};
use crate::scenario::Scenario;
use crate::study::metrics::Metric;
use crate::study::sample::{latin_hypercube, normal_quantile, SplitMix64};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A sweep or a Monte Carlo study over a base scenario (a TOML file of its own).
///
/// ```toml
/// name = "pacing_vs_energy"
/// base = "fig8_R100.toml"          # relative to this file
/// metrics = ["mean_u", "mean_tau_rate"]   # all of them when left out
/// [[axis]]
/// key = "controller.self_pacing"
/// values = [0, 50, 100, 200]
/// [[axis]]
/// key = "controller.energy"
/// range = { from = 500, to = 4000, steps = 8 }
/// ```
///
/// With only `values` and `range` axes the runs are their grid (every combination, the last
/// axis fastest). With only `draw` axes they are `samples` random draws from `seed`, or a
/// Latin hypercube of `samples` points with `latin_hypercube = true`. Design points
/// (`[[point]]` tables, each the same keys with its own values: a fractional factorial, a
/// list of named conditions) multiply the runs, the points fastest:
///
/// ```toml
/// [[point]]
/// "plant.mass_scale[0]" = 0.85
/// "plant.friction.coulomb[0]" = 3.6
/// [[point]]
/// "plant.mass_scale[0]" = 1.15
/// "plant.friction.coulomb[0]" = 2.4
/// ```
///
/// `controller = "timed"` or `"speed_scaling"` runs the base scenario's baseline tracker
/// instead of PVFC (its `[baseline]` must give `tau_rate`, and `speed_scaling` for the
/// second), so that a tracker is tuned and measured by the same studies as PVFC.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// The study's name: its runs are `NAME_0000`, `NAME_0001`, …
    pub name: String,
    /// The base scenario's file, relative to the study's file (a study built with its base
    /// scenario in hand, [`StudySpec::from_toml`], may leave it out).
    #[serde(default, skip_serializing_if = "is_empty_path")]
    pub base: PathBuf,
    /// The axes.
    #[serde(default, rename = "axis")]
    pub axes: Vec<Axis>,
    /// The design points: each sets the same keys, to values of its own; every run of the
    /// axes is run at every point.
    #[serde(default, rename = "point", skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<std::collections::BTreeMap<String, f64>>,
    /// The number of runs of a random study.
    #[serde(default)]
    pub samples: Option<usize>,
    /// The seed of a random study's draws.
    #[serde(default)]
    pub seed: u64,
    /// Draw a random study as a Latin hypercube (each axis's strata each hit once).
    #[serde(default)]
    pub latin_hypercube: bool,
    /// Settings every run shares, by dotted key (`set = { duration = 45.0 }`), applied to the
    /// base before the axes.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub set: std::collections::BTreeMap<String, f64>,
    /// The metrics to keep of each run, by name ([`crate::study::metrics::METRICS`]); all
    /// of them when empty.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub metrics: Vec<String>,
    /// The controller the runs run: PVFC, or the base scenario's timed or speed-scaling
    /// tracker.
    #[serde(default, skip_serializing_if = "StudyController::is_pvfc")]
    pub controller: StudyController,
}

/// The controller a study's runs run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StudyController {
    /// PVFC, as the scenario sets it up.
    #[default]
    Pvfc,
    /// The scenario's timed tracker (`[baseline]`, at its `tau_rate`).
    Timed,
    /// The scenario's speed-scaling tracker (`[baseline]` with `speed_scaling`, at its
    /// `tau_rate`).
    SpeedScaling,
}

impl std::str::FromStr for StudyController {
    type Err = SimError;

    /// `pvfc`, `timed` or `speed_scaling`.
    fn from_str(s: &str) -> Result<Self> {
        [
            StudyController::Pvfc,
            StudyController::Timed,
            StudyController::SpeedScaling,
        ]
        .into_iter()
        .find(|c| c.label() == s)
        .ok_or_else(|| {
            setting(format!(
                "controller `{s}`: one of pvfc, timed, speed_scaling"
            ))
        })
    }
}

impl StudyController {
    /// Its name in a study's file (`pvfc`, `timed`, `speed_scaling`).
    pub fn label(self) -> &'static str {
        match self {
            StudyController::Pvfc => "pvfc",
            StudyController::Timed => "timed",
            StudyController::SpeedScaling => "speed_scaling",
        }
    }

    /// Whether it is PVFC (the default).
    pub fn is_pvfc(&self) -> bool {
        *self == StudyController::Pvfc
    }

    /// The tracker it names, `None` for PVFC.
    pub fn tracker(self) -> Option<crate::run::Tracker> {
        match self {
            StudyController::Pvfc => None,
            StudyController::Timed => Some(crate::run::Tracker::Timed),
            StudyController::SpeedScaling => Some(crate::run::Tracker::SpeedScaling),
        }
    }

    /// Why `s` cannot run this controller, if it cannot: a tracker needs `[baseline]` with
    /// `tau_rate` (a study's tracker runs at a rate of its own, not at a PVFC run's), and the
    /// speed-scaling one its `speed_scaling` table.
    fn missing(self, s: &Scenario) -> Option<&'static str> {
        let b = match (self, &s.baseline) {
            (StudyController::Pvfc, _) => return None,
            (_, None) => return Some("a tracker's study needs the base's [baseline]"),
            (_, Some(b)) => b,
        };
        if b.tau_rate.is_none() {
            return Some("a tracker's study needs baseline.tau_rate (the rate it runs at)");
        }
        (self == StudyController::SpeedScaling && b.speed_scaling.is_none())
            .then_some("controller = \"speed_scaling\" needs [baseline.speed_scaling]")
    }
}

/// One axis: a scenario key by its dotted path, and its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    /// The key, e.g. `controller.self_pacing` or `plant.friction.coulomb[1]`.
    pub key: String,
    /// More keys set to the same value on every run (a model error shared by several links,
    /// a gain shared by every joint); the table's column is `key`'s.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub also: Vec<String>,
    /// The values as a list.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
    /// The values as a range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<Range>,
    /// The values as random draws.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub draw: Option<Draw>,
}

/// `steps` values from `from` to `to`, both included, equally spaced (`log = true`: equally
/// spaced in the logarithm, both ends `> 0`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    /// The first value.
    pub from: f64,
    /// The last value.
    pub to: f64,
    /// The number of values, `≥ 2`.
    pub steps: usize,
    /// Logarithmic spacing.
    #[serde(default)]
    pub log: bool,
}

/// A random axis's distribution.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Draw {
    /// Uniform on `[low, high)`.
    Uniform {
        /// The lower end.
        low: f64,
        /// The upper end, `> low`.
        high: f64,
    },
    /// Normal with a mean and a standard deviation `> 0`.
    Normal {
        /// The mean.
        mean: f64,
        /// The standard deviation.
        std: f64,
    },
    /// The integers `low, low + 1, …, high`, each as likely (for an integer key, such as a
    /// fault's `joint`).
    Integer {
        /// The least.
        low: i64,
        /// The largest, `≥ low`.
        high: i64,
    },
}

impl Draw {
    /// The value at the quantile `u ∈ (0, 1)`.
    fn at(&self, u: f64) -> f64 {
        match *self {
            Draw::Uniform { low, high } => low + (high - low) * u,
            Draw::Normal { mean, std } => mean + std * normal_quantile(u),
            Draw::Integer { low, high } => {
                let span = (high - low + 1) as f64;
                (low as f64 + (u * span).floor()).min(high as f64)
            }
        }
    }
}

/// One run of a study: its index, the values of the axes (in the spec's order), and its
/// scenario.
#[derive(Clone, Debug)]
pub struct StudyRun {
    /// The run's index, `0..runs`.
    pub index: usize,
    /// `(key, value)` per axis.
    pub parameters: Vec<(String, f64)>,
    /// The scenario to run.
    pub scenario: Scenario,
    /// The controller to run on it.
    pub controller: StudyController,
}

fn is_empty_path(p: &Path) -> bool {
    p.as_os_str().is_empty()
}

fn setting(message: String) -> SimError {
    SimError::Setting(message)
}

impl StudySpec {
    /// Parses a study's TOML text (`path` only names it in errors).
    pub fn from_toml(text: &str, path: &Path) -> Result<StudySpec> {
        toml::from_str(text).map_err(|e| SimError::Scenario {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }

    /// The study as TOML text.
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string(self).map_err(|e| setting(format!("study `{}`: {e}", self.name)))
    }

    /// Reads a study's file; its base scenario is resolved relative to it.
    pub fn from_file(path: &Path) -> Result<(StudySpec, Scenario)> {
        let text = std::fs::read_to_string(path).map_err(|e| SimError::io(path, e))?;
        let spec = StudySpec::from_toml(&text, path)?;
        if is_empty_path(&spec.base) {
            return Err(SimError::Scenario {
                path: path.to_path_buf(),
                message: "no `base`: the base scenario's file, relative to this one".into(),
            });
        }
        let base_path = path
            .parent()
            .map(|d| d.join(&spec.base))
            .unwrap_or_else(|| spec.base.clone());
        let base = Scenario::from_file(&base_path)?;
        Ok((spec, base))
    }

    /// The metrics the study keeps, in its table's order (all of them if it names none); an
    /// unknown name is an error that names it and lists the metrics.
    pub fn metrics(&self) -> Result<Vec<&'static Metric>> {
        crate::study::metrics::select(&self.metrics)
    }

    /// The keys of the axes, in the spec's order, then the design points' keys: the parameter
    /// columns of its table.
    pub fn keys(&self) -> Vec<String> {
        let points = self.points.first().into_iter().flat_map(|p| p.keys());
        self.axes
            .iter()
            .map(|a| &a.key)
            .chain(points)
            .cloned()
            .collect()
    }

    /// Checks the design points: every point the same keys, none an axis's, every value
    /// finite. Errors name the point and the key.
    fn check_points(&self) -> Result<()> {
        let Some(first) = self.points.first() else {
            return Ok(());
        };
        if first.is_empty() {
            return Err(setting(format!(
                "study `{}`: point 0 sets no key",
                self.name
            )));
        }
        for (i, p) in self.points.iter().enumerate() {
            if !p.keys().eq(first.keys()) {
                let differ = p
                    .keys()
                    .chain(first.keys())
                    .find(|k| p.contains_key(*k) != first.contains_key(*k))
                    .cloned()
                    .unwrap_or_default();
                return Err(setting(format!(
                    "study `{}`: point {i} and point 0 differ in `{differ}` (every point sets the same keys)",
                    self.name
                )));
            }
            if let Some((k, v)) = p.iter().find(|(_, v)| !v.is_finite()) {
                return Err(setting(format!(
                    "study `{}`: point {i}: `{k}` = {v} is not finite",
                    self.name
                )));
            }
        }
        let mut axis_keys = self
            .axes
            .iter()
            .flat_map(|a| std::iter::once(&a.key).chain(&a.also));
        if let Some(k) = axis_keys.find(|k| first.contains_key(*k)) {
            return Err(setting(format!(
                "study `{}`: `{k}` is both an axis's key and a point's",
                self.name
            )));
        }
        Ok(())
    }

    /// The values of each axis: its list, its range, or its draws (`samples` of them, from
    /// `seed`, stratified when `latin_hypercube`). Errors name the axis.
    fn axis_values(&self) -> Result<Vec<Vec<f64>>> {
        if self.axes.is_empty() {
            if self.points.is_empty() {
                return Err(setting(format!(
                    "study `{}`: no axis and no point",
                    self.name
                )));
            }
            return Ok(Vec::new());
        }
        let random = self.axes.iter().filter(|a| a.draw.is_some()).count();
        if random != 0 && random != self.axes.len() {
            return Err(setting(format!(
                "study `{}`: axes are either all drawn at random or none (a grid)",
                self.name
            )));
        }
        let mut values = Vec::with_capacity(self.axes.len());
        for a in &self.axes {
            let given = [a.values.is_some(), a.range.is_some(), a.draw.is_some()];
            if given.iter().filter(|g| **g).count() != 1 {
                return Err(setting(format!(
                    "axis `{}`: give exactly one of `values`, `range` and `draw`",
                    a.key
                )));
            }
            if let Some(v) = &a.values {
                if v.is_empty() || v.iter().any(|x| !x.is_finite()) {
                    return Err(setting(format!(
                        "axis `{}`: values must be finite, at least one",
                        a.key
                    )));
                }
                values.push(v.clone());
            } else if let Some(r) = a.range {
                values.push(range_values(&a.key, r)?);
            } else if let Some(d) = a.draw {
                check_draw(&a.key, d)?;
                values.push(Vec::new());
            }
        }
        if random == 0 {
            if self.samples.is_some() || self.latin_hypercube {
                return Err(setting(format!(
                    "study `{}`: `samples` and `latin_hypercube` are for drawn axes",
                    self.name
                )));
            }
            return Ok(values);
        }
        let n = self.samples.filter(|n| *n > 0).ok_or_else(|| {
            setting(format!(
                "study `{}`: drawn axes need `samples` (the number of runs, > 0)",
                self.name
            ))
        })?;
        let mut rng = SplitMix64::new(self.seed);
        let units: Vec<Vec<f64>> = if self.latin_hypercube {
            latin_hypercube(n, self.axes.len(), &mut rng)
        } else {
            (0..n)
                .map(|_| (0..self.axes.len()).map(|_| rng.next_open01()).collect())
                .collect()
        };
        for (k, a) in self.axes.iter().enumerate() {
            if let Some(d) = a.draw {
                values[k] = units.iter().map(|u| d.at(u[k])).collect();
            }
        }
        Ok(values)
    }

    /// The study's runs on `base`: every scenario built and validated, so that a bad key or
    /// value is an error naming it before anything runs.
    pub fn runs(&self, base: &Scenario) -> Result<Vec<StudyRun>> {
        self.metrics()?;
        self.check_points()?;
        let values = self.axis_values()?;
        let random = self.axes.iter().any(|a| a.draw.is_some());
        let per_point = if random {
            values[0].len()
        } else {
            values.iter().map(Vec::len).product()
        };
        let points = self.points.len().max(1);
        let count = per_point * points;
        let mut table = toml::Value::try_from(base)
            .map_err(|e| setting(format!("study `{}`: the base scenario: {e}", self.name)))?;
        for (key, value) in &self.set {
            if !value.is_finite() {
                return Err(setting(format!("set `{key}`: {value} is not finite")));
            }
            set_key(&mut table, key, *value)
                .map_err(|e| setting(format!("study `{}`: set {e}", self.name)))?;
        }
        let mut runs = Vec::with_capacity(count);
        for index in 0..count {
            // The grid's coordinates of run `index`, the last axis fastest and the points
            // faster still; a random study's run takes one draw of every axis per point.
            let (axes_index, point) = (index / points, index % points);
            let mut rest = axes_index;
            let mut picks = vec![0; values.len()];
            if random {
                picks.fill(axes_index);
            } else {
                for (k, v) in values.iter().enumerate().rev() {
                    picks[k] = rest % v.len();
                    rest /= v.len();
                }
            }
            let mut t = table.clone();
            let mut parameters = Vec::with_capacity(values.len());
            for ((a, v), &p) in self.axes.iter().zip(&values).zip(&picks) {
                for key in std::iter::once(&a.key).chain(&a.also) {
                    set_key(&mut t, key, v[p]).map_err(|e| setting(format!("axis {e}")))?;
                }
                parameters.push((a.key.clone(), v[p]));
            }
            for (key, v) in self.points.get(point).into_iter().flatten() {
                set_key(&mut t, key, *v).map_err(|e| setting(format!("point {point}: {e}")))?;
                parameters.push((key.clone(), *v));
            }
            let mut scenario: Scenario = t
                .try_into()
                .map_err(|e| setting(format!("study `{}`, run {index}: {e}", self.name)))?;
            scenario.name = format!("{}_{index:04}", self.name);
            scenario.base_dir = base.base_dir.clone();
            scenario.validate().map_err(|e| {
                let set: Vec<String> = parameters
                    .iter()
                    .map(|(k, v)| format!("{k} = {v}"))
                    .collect();
                setting(format!(
                    "study `{}`, run {index} ({}): {e}",
                    self.name,
                    set.join(", ")
                ))
            })?;
            if let Some(why) = self.controller.missing(&scenario) {
                return Err(setting(format!("study `{}`: {why}", self.name)));
            }
            runs.push(StudyRun {
                index,
                parameters,
                scenario,
                controller: self.controller,
            });
        }
        Ok(runs)
    }
}

fn range_values(key: &str, r: Range) -> Result<Vec<f64>> {
    let ok = r.from.is_finite()
        && r.to.is_finite()
        && r.steps >= 2
        && (!r.log || (r.from > 0.0 && r.to > 0.0));
    if !ok {
        return Err(setting(format!(
            "axis `{key}`: a range needs finite ends, steps ≥ 2, and ends > 0 when log (got {r:?})"
        )));
    }
    let n = (r.steps - 1) as f64;
    Ok((0..r.steps)
        .map(|i| {
            let s = i as f64 / n;
            // The ends exactly as given.
            if i == 0 {
                r.from
            } else if i == r.steps - 1 {
                r.to
            } else if r.log {
                (r.from.ln() + s * (r.to.ln() - r.from.ln())).exp()
            } else {
                r.from + s * (r.to - r.from)
            }
        })
        .collect())
}

fn check_draw(key: &str, d: Draw) -> Result<()> {
    let ok = match d {
        Draw::Uniform { low, high } => low.is_finite() && high.is_finite() && high > low,
        Draw::Normal { mean, std } => mean.is_finite() && std.is_finite() && std > 0.0,
        Draw::Integer { low, high } => {
            low <= high && low.unsigned_abs() < 1 << 52 && high.unsigned_abs() < 1 << 52
        }
    };
    if ok {
        Ok(())
    } else {
        Err(setting(format!(
            "axis `{key}`: a uniform draw needs finite low < high, a normal one a finite mean and std > 0, an integer one low ≤ high (got {d:?})"
        )))
    }
}

/// Sets the number at the dotted `key` (`a.b.c`, `a.b[i]`, `a.b[i][j]`) of a scenario's table to `value`:
/// the key must exist and hold a number (an integer key takes only integral values). The
/// errors name the key and what the table has there (the caller says whether it is an axis or
/// a `set` entry).
fn set_key(table: &mut toml::Value, key: &str, value: f64) -> std::result::Result<(), String> {
    let mut here = table;
    let mut path = String::new();
    for part in key.split('.') {
        // `name`, or `name[i]`, `name[i][j]`, …
        let (name, indexes) = match part.split_once('[') {
            Some((name, rest)) => {
                let indexes = rest
                    .strip_suffix(']')
                    .map(|r| r.split("][").map(str::parse::<usize>).collect::<Vec<_>>())
                    .and_then(|r| {
                        r.into_iter()
                            .collect::<std::result::Result<Vec<_>, _>>()
                            .ok()
                    })
                    .ok_or_else(|| format!("`{key}`: `{part}` is not `name[index]`"))?;
                (name, indexes)
            }
            None => (part, Vec::new()),
        };
        let keys = |t: &toml::value::Table| t.keys().cloned().collect::<Vec<_>>().join(", ");
        here = match here {
            toml::Value::Table(t) => {
                let known = keys(t);
                t.get_mut(name).ok_or_else(|| {
                    format!(
                        "`{key}`: the scenario has no `{name}`{} (it has: {known})",
                        if path.is_empty() {
                            String::new()
                        } else {
                            format!(" in `{path}`")
                        }
                    )
                })?
            }
            _ => return Err(format!("`{key}`: `{path}` is a value, not a table")),
        };
        if !path.is_empty() {
            path.push('.');
        }
        path.push_str(name);
        for i in indexes {
            here = match here {
                toml::Value::Array(a) => {
                    let len = a.len();
                    a.get_mut(i)
                        .ok_or_else(|| format!("`{key}`: `{path}` has {len} entries"))?
                }
                _ => return Err(format!("`{key}`: `{path}` is not a list")),
            };
            path.push_str(&format!("[{i}]"));
        }
    }
    match here {
        toml::Value::Float(x) => *x = value,
        toml::Value::Integer(x) => {
            if value.fract() != 0.0 || value.abs() > 9.0e15 {
                return Err(format!(
                    "`{key}`: an integer setting, and {value} is not an integer"
                ));
            }
            *x = value as i64;
        }
        other => {
            return Err(format!(
                "`{key}`: not a number (it is {})",
                other.type_str()
            ))
        }
    }
    Ok(())
}
