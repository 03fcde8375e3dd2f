//! Empty: the build-dependencies only unify the features of the host's proc-macro crates.

fn main() {
    // Only this file reruns it: without the line cargo fingerprints every file of the
    // package by mtime, and a build of the same package from another copy (the sdist's)
    // would make the workspace's stale.
    println!("cargo:rerun-if-changed=build.rs");
}
