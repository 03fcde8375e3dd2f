//! Puts the memory layout of QEMU's machine `$PVFC_MACHINE` (`memory/$PVFC_MACHINE.x`; by
//! default `netduinoplus2`, the STM32F405; `scripts/cores.sh` builds for `microbit`,
//! `mps2-an500` and `mps2-an505`) where the linker (cortex-m-rt's `link.x`) finds it as
//! `memory.x`. (No `memory.x` lies in the package's directory: the linker would find it there
//! first.)
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let machine = env::var("PVFC_MACHINE").unwrap_or_else(|_| "netduinoplus2".to_string());
    let layout = format!("memory/{machine}.x");
    fs::copy(&layout, out.join("memory.x"))
        .expect("the machine's memory layout is in examples/firmware");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={layout}");
    println!("cargo:rerun-if-env-changed=PVFC_MACHINE");
}
