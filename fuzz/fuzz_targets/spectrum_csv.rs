//! Fuzzes the spectral-table parser and the RGB band means (see `common/spectrum.rs`).

#![no_main]

#[path = "../common/spectrum.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::parse_and_reduce(data));
