//! Fuzzes the environment image readers, Radiance `.hdr` and OpenEXR (see
//! `common/environment.rs`).

#![no_main]

#[path = "../common/environment.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::decode(data));
