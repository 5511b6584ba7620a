//! The crate's integration tests, one test binary: each file below is a module, so the
//! crate and its dependencies are linked once, not once per file (docs/build.md, "Build cost").
//! `cargo nextest run` still runs each test in its own process; a test's name is its
//! file's, then its own.

mod common;

mod hierarchy;
mod path;
mod pose;
mod visibility;
