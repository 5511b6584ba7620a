//! Fuzzes `diff`'s image readers (PNG and OpenEXR, header first) and the comparison
//! (see `common/diff.rs`).

#![no_main]

#[path = "../common/diff.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::read_and_compare(data));
