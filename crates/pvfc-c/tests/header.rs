//! The committed header `include/pvfc.h` is what cbindgen generates from the crate now
//! (regenerate it with `PVFC_BLESS=1 cargo test -p pvfc-c --test header`).

use std::path::Path;

#[test]
fn the_header_is_fresh() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let generated = String::from_utf8(generated).expect("UTF-8");
    let path = dir.join("include/pvfc.h");
    if std::env::var_os("PVFC_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("write include/pvfc.h");
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/pvfc.h is stale: regenerate it with `PVFC_BLESS=1 cargo test -p pvfc-c --test header`"
    );
}
