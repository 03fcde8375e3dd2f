//! One version everywhere: the workspace's `[workspace.package] version` (this crate's
//! `CARGO_PKG_VERSION`) is every crate's, the Python wheel's (maturin reads it: the wheel's
//! version is dynamic), the CMake package's (its CMakeLists.txt reads Cargo.toml) and the
//! CHANGELOG's first release section's. `pvfc --version` (crates/pvfc-cli/tests/version.rs),
//! `pvfc_version()` and the header's `PVFC_VERSION_*` (crates/pvfc-c/tests/abi.rs),
//! `pvfc.__version__` (crates/pvfc-py/tests/test_version.py) and the installed CMake package
//! (scripts/test.sh) are checked where they are built.

use std::path::Path;

fn read(relative: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(relative);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The `[package]` (or `[workspace.package]`) table's lines of a Cargo.toml.
fn package_table(manifest: &str) -> Vec<&str> {
    manifest
        .lines()
        .skip_while(|l| !matches!(l.trim(), "[package]" | "[workspace.package]"))
        .skip(1)
        .take_while(|l| !l.starts_with('['))
        .collect()
}

#[test]
fn every_crate_takes_the_workspace_version_and_rust_version() {
    let root = read("Cargo.toml");
    let declared = package_table(&root);
    assert!(
        declared.contains(&format!("version = \"{}\"", env!("CARGO_PKG_VERSION")).as_str()),
        "[workspace.package] version is not {}",
        env!("CARGO_PKG_VERSION")
    );
    assert!(
        declared.iter().any(|l| l.starts_with("rust-version = ")),
        "[workspace.package] declares no rust-version"
    );
    for krate in [
        "pvfc-core",
        "pvfc-control",
        "pvfc-sim",
        "pvfc-cli",
        "pvfc-c",
        "pvfc-py",
        "workspace-hack",
    ] {
        let manifest = read(&format!("crates/{krate}/Cargo.toml"));
        let table = package_table(&manifest);
        for key in ["version.workspace = true", "rust-version.workspace = true"] {
            assert!(
                table.contains(&key),
                "crates/{krate}/Cargo.toml: `{key}` missing from [package]"
            );
        }
    }
    // The workspace's own dependencies on its crates ask for this version.
    let dependencies = root
        .lines()
        .skip_while(|l| l.trim() != "[workspace.dependencies]")
        .take_while(|l| !l.starts_with("[workspace.lints"));
    for line in dependencies.filter(|l| l.starts_with("pvfc-")) {
        assert!(
            line.contains(&format!("version = \"{}\"", env!("CARGO_PKG_VERSION"))),
            "Cargo.toml: `{line}` does not ask for version {}",
            env!("CARGO_PKG_VERSION")
        );
    }
}

#[test]
fn the_wheel_and_the_cmake_package_read_the_workspace_version() {
    let pyproject = read("crates/pvfc-py/pyproject.toml");
    let project: Vec<&str> = pyproject
        .lines()
        .skip_while(|l| l.trim() != "[project]")
        .skip(1)
        .take_while(|l| !l.starts_with('['))
        .collect();
    assert!(
        project.contains(&"dynamic = [\"version\"]"),
        "pyproject.toml: the version is not dynamic"
    );
    assert!(
        !project.iter().any(|l| l.starts_with("version")),
        "pyproject.toml: [project] sets a version of its own"
    );
    let cmake = read("crates/pvfc-c/CMakeLists.txt");
    assert!(
        cmake.contains("file(READ \"${PVFC_WORKSPACE}/Cargo.toml\"")
            && cmake.contains(
                "project(pvfc VERSION ${CMAKE_MATCH_1}.${CMAKE_MATCH_2}.${CMAKE_MATCH_3}"
            ),
        "crates/pvfc-c/CMakeLists.txt does not take its version from Cargo.toml"
    );
}

#[test]
fn the_changelog_first_release_is_this_version() {
    let changelog = read("CHANGELOG.md");
    let first = changelog
        .lines()
        .find(|l| l.starts_with("## [") && !l.starts_with("## [Unreleased]"))
        .expect("CHANGELOG.md has no release section (`## [X.Y.Z] - date`)");
    assert!(
        first.starts_with(&format!("## [{}] - ", env!("CARGO_PKG_VERSION"))),
        "CHANGELOG.md's first release section is `{first}`, not version {}",
        env!("CARGO_PKG_VERSION")
    );
}
