//! The runs of a reproduction, kept by name: each run's scenario and trace, and the URDF
//! arms' systems built for them, so that the claims, the figures and the logs read the same
//! runs.

use pvfc_sim::error::{Result, SimError};
use pvfc_sim::scenario::preset_id::PresetId;
use pvfc_sim::scenario::{ArmSystem, Scenario, System};
use pvfc_sim::trace::metrics::{contact_summary, mean_potential_over_pass, ContactSummary};
use pvfc_sim::trace::Trace;
use std::borrow::Cow;
use std::collections::BTreeMap;

/// The runs of a reproduction: scenario and trace by name.
#[derive(Clone, Debug, Default)]
pub struct Runs {
    /// Scenario and trace, by the scenario's name (the timed baseline as `NAME-timed`).
    pub runs: BTreeMap<String, (Scenario, Trace)>,
    /// The scenarios' systems, built once per scenario, by the scenario's name.
    pub systems: BTreeMap<String, System>,
}

impl Runs {
    /// The system of scenario `s`: the one built for its runs, or built now if these runs did
    /// not keep it.
    pub fn system(&self, s: &Scenario) -> Result<Cow<'_, System>> {
        Ok(match self.systems.get(&s.name) {
            Some(sys) => Cow::Borrowed(sys),
            None => Cow::Owned(System::build(s)?),
        })
    }

    /// The system of scenario `s`, a serial chain's (an error naming the run for another
    /// kind of robot).
    pub fn chain_system(&self, s: &Scenario) -> Result<Cow<'_, ArmSystem>> {
        match self.systems.get(&s.name) {
            Some(System::SerialChain(sys)) => Ok(Cow::Borrowed(&**sys)),
            Some(_) => Err(SimError::Setting(format!(
                "run `{}` is not a serial chain's",
                s.name
            ))),
            None => Ok(Cow::Owned(ArmSystem::build(s)?)),
        }
    }

    /// The scenario and trace of a preset's run.
    pub fn run(&self, id: PresetId) -> Result<&(Scenario, Trace)> {
        self.named(&id.name())
    }

    /// The trace of a preset's run.
    pub fn trace(&self, id: PresetId) -> Result<&Trace> {
        Ok(&self.run(id)?.1)
    }

    /// The trace of a preset's timed baseline (`NAME-timed`).
    pub fn timed(&self, id: PresetId) -> Result<&Trace> {
        Ok(&self.named(&id.timed_name())?.1)
    }

    /// A run by its name, for runs that are not presets.
    pub fn named(&self, name: &str) -> Result<&(Scenario, Trace)> {
        self.runs
            .get(name)
            .ok_or_else(|| SimError::Setting(format!("run `{name}` is missing")))
    }

    pub(crate) fn mean_u(&self, id: PresetId) -> Result<f64> {
        let (s, t) = self.run(id)?;
        mean_potential_over_pass(t, s.contour.period()).ok_or_else(|| no_pass(id))
    }

    /// The peaks of `U` over the last pass of a preset's run
    /// ([`potential_peaks`](pvfc_sim::trace::metrics::potential_peaks), above `fraction` of
    /// its largest value).
    pub(crate) fn potential_peaks(&self, id: PresetId, fraction: f64) -> Result<usize> {
        let (s, t) = self.run(id)?;
        pvfc_sim::trace::metrics::potential_peaks(t, s.contour.period(), fraction)
            .ok_or_else(|| no_pass(id))
    }

    /// The contact summary of a preset's run.
    pub fn summary(&self, id: PresetId) -> Result<ContactSummary> {
        summarize(self.trace(id)?, &id.name())
    }

    /// The contact summary of a preset's timed baseline.
    pub fn timed_summary(&self, id: PresetId) -> Result<ContactSummary> {
        summarize(self.timed(id)?, &id.timed_name())
    }
}

fn summarize(t: &Trace, name: &str) -> Result<ContactSummary> {
    contact_summary(t)
        .ok_or_else(|| SimError::Setting(format!("run `{name}` has no contact columns")))
}

/// The error of a run too short for a measure over one pass of its contour.
fn no_pass(id: PresetId) -> SimError {
    SimError::Setting(format!("run `{id}` does not cover one pass of the contour"))
}
