//! The crate's integration tests, one test binary: each file below is a module, so the
//! crate and its dependencies are linked once, not once per file (docs/build.md, "Build cost").
//! `cargo nextest run` still runs each test in its own process; a test's name is its
//! file's, then its own.

mod common;

mod coat;
mod f32_accuracy;
mod glsl_mirror;
mod hard_cases;
mod identities;
mod sheen;
mod specular;
mod thin_film;
