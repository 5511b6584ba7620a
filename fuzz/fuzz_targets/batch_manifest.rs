//! Fuzzes `combustion batch`'s manifest parser, its split into shards and the merge of
//! shards' results (see `common/batch_manifest.rs`).

#![no_main]

#[path = "../common/batch_manifest.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::parse_and_merge(data));
