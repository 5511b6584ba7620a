//! Fuzzes the camera path parser and the cameras of every path it accepts (see
//! `common/camera_path.rs`).

#![no_main]

#[path = "../common/camera_path.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::parse_and_follow(data));
