//! Forms of a scenario file that still read but are deprecated, and the message that names
//! each ([`Scenario::deprecations`](super::Scenario::deprecations)): the command prints them
//! as warnings, the Python package raises `DeprecationWarning`s.

use super::plant::inferred_kind;
use super::ContourSpec;
use serde::de::IgnoredAny;
use serde::Deserialize;

/// The keys of a scenario that tell its form, every other key ignored.
#[derive(Default, Deserialize)]
#[serde(default)]
struct Probe {
    plant: Option<PlantProbe>,
    contour: Option<serde_json::Value>,
}

#[derive(Default, Deserialize)]
#[serde(default)]
struct PlantProbe {
    kind: Option<IgnoredAny>,
    urdf: Option<IgnoredAny>,
    rigid_body: Option<IgnoredAny>,
}

impl Probe {
    fn messages(self) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(p) = self.plant {
            if p.kind.is_none() {
                let kind = inferred_kind(p.urdf.is_some(), p.rigid_body.is_some()).key();
                out.push(format!(
                    "plant: the robot's kind is inferred from which keys are set (deprecated); say it: kind = \"{kind}\""
                ));
            }
            if p.rigid_body.is_some() {
                out.push(
                    "plant.rigid_body: deprecated; write the inertia as plant.inertia beside kind = \"rigid_body\""
                        .into(),
                );
            }
        }
        if self.contour.as_ref().is_some_and(ContourSpec::before_kinds) {
            out.push(
                "contour: keys directly under [contour] (amplitude, periods, phase, offset, period, spacing, a waypoints array) are deprecated; write one table named for the contour's kind: [contour.lissajous], [contour.waypoints] (points, spacing), [contour.ellipse], or period and spacing inside [contour.cartesian]"
                    .into(),
            );
        }
        out
    }
}

/// The deprecated forms in a scenario's TOML text (none if it does not parse: the parse
/// error is the reader's to report).
pub fn in_toml(text: &str) -> Vec<String> {
    toml::from_str::<Probe>(text)
        .map(Probe::messages)
        .unwrap_or_default()
}

/// The deprecated forms in a scenario given as JSON (a Python dict).
pub fn in_json(text: &str) -> Vec<String> {
    serde_json::from_str::<Probe>(text)
        .map(Probe::messages)
        .unwrap_or_default()
}
