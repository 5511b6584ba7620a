//! Fuzzes the criteria parser (`diff --criteria`, batch manifests), each accepted term's
//! echo, and the check against arbitrary measurements (see `common/criteria.rs`).

#![no_main]

#[path = "../common/criteria.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::parse_and_check(data));
