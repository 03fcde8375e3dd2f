//! Puts the STM32F405's memory layout (`../memory/netduinoplus2.x`) as `memory.x` where the linker (cortex-m-rt's `link.x`) finds it.
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("../memory/netduinoplus2.x", out.join("memory.x"))
        .expect("examples/firmware/memory/netduinoplus2.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=../memory/netduinoplus2.x");
}
