//! Fuzzes the whole path a file takes before the renderer sees it: import, then
//! `Scene::validate` and what the renderer asks of a scene (see `common/gltf.rs`).

#![no_main]

#[path = "../common/gltf.rs"]
mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| common::import_and_validate(data));
