//! Fuzzes animation sampling at arbitrary times on every scene the importer accepts, and
//! posing the scene in each finite pose (see `common/animation.rs`).

#![no_main]

#[path = "../common/gltf.rs"]
mod gltf;
#[path = "../common/animation.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::sample_animations(data));
