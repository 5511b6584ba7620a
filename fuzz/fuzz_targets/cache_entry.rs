//! Fuzzes the disk caches' reader and the checks of each kind's body (see
//! `common/cache_entry.rs`).

#![no_main]

#[path = "../common/cache_entry.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::load_and_check(data));
