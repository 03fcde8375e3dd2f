//! Puts the memory layout of QEMU's RISC-V `virt` machine (`../memory/riscv-virt.x`) as
//! `memory.x` where the linker (riscv-rt's `link.x`) finds it.
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("../memory/riscv-virt.x", out.join("memory.x"))
        .expect("examples/firmware/memory/riscv-virt.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=../memory/riscv-virt.x");
}
