//! Unifies the features of the dependencies shared by pvfc's builds (see `Cargo.toml`). It
//! has no code.

#![no_std]
