//! Fuzzes `bench --against`'s reader of an earlier report.csv and the report's CSV
//! quoting (see `common/report_csv.rs`).

#![no_main]

#[path = "../common/report_csv.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::parse_and_round_trip(data));
