//! Any text as a scenario file: a validated scenario (its system built) or an error naming
//! what is wrong; never a panic. Relative files are looked up in the repository's
//! `scenarios/` folder, as a shipped scenario's are.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pvfc_sim::scenario::Scenario;
use std::path::{Path, PathBuf};

fuzz_target!(|text: &str| {
    let base = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios"));
    let _ = Scenario::parse(text, Path::new("fuzz.toml"), base);
});
