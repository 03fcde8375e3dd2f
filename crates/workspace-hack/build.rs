//! Empty: the build-dependencies only unify the features of the host's proc-macro crates.

fn main() {}
