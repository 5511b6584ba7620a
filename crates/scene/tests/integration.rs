//! The crate's integration tests, one test binary: each file below is a module, so the
//! crate and its dependencies are linked once, not once per file (docs/build.md, "Build cost").
//! `cargo nextest run` still runs each test in its own process; a test's name is its
//! file's, then its own.

mod bad_gltf;
mod fuzz_corpus;
mod gltf_authored;
mod gltf_conductor;
mod gltf_resources;
mod gltf_samples;
mod gltf_validity;
mod memory_bounds;
mod support;
