//! `pvfc --version` prints the workspace's version (tests/version.rs checks the others).

#[test]
fn pvfc_version_is_the_crate_version() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pvfc"))
        .arg("--version")
        .output()
        .expect("run pvfc --version");
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stdout).trim(),
        format!("pvfc {}", env!("CARGO_PKG_VERSION"))
    );
}
