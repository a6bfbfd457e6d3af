//! `house`: the house's own rules, checked by `cargo test -p house` (see `tests/house.rs`): no
//! module of any crate imports itself around a loop, each crate depends only on the crates below it
//! (ARCHITECTURE.md's layers), and every test file of the workspace is registered. The library is
//! empty; it exists because Cargo builds no package without a library or a binary.
#![deny(missing_docs)]
