//! Fuzzes the glTF importer from bytes: the input as it is, and wrapped in a well-formed
//! GLB container (see `common/gltf.rs`).

#![no_main]

#[path = "../common/gltf.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::import_both_ways(data));
