//! Names the shared library for the dynamic linker (its soname): `libpvfc_c.so.0.MINOR` before
//! 1.0, when a minor version may change the ABI, `libpvfc_c.so.MAJOR` after. A program linked
//! against one version then never loads an incompatible one; the CMake package installs the
//! file as `libpvfc_c.so.MAJOR.MINOR.PATCH` with the soname and `libpvfc_c.so` as links.

fn main() {
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if os == "linux" || os == "freebsd" || os == "android" {
        let major = env!("CARGO_PKG_VERSION_MAJOR");
        let minor = env!("CARGO_PKG_VERSION_MINOR");
        let soname = if major == "0" {
            format!("libpvfc_c.so.0.{minor}")
        } else {
            format!("libpvfc_c.so.{major}")
        };
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,{soname}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
