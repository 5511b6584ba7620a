//! Fuzzes the whole path a file takes before the renderer sees it: import (as
//! `gltf_import` does) and then `Scene::validate`, the renderer's own check, on every
//! scene the importer accepts — an accepted scene must validate or say why, never panic.

#![no_main]

use combustion_scene::gltf::{import_slice, ImportOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let options = ImportOptions {
        max_image_dimension: 256,
        max_decoded_pixels: 1 << 20,
        ..ImportOptions::default()
    };
    if let Ok((scene, _report)) = import_slice(data, &options) {
        let _ = scene.validate();
        let _ = scene.features();
        let _ = scene.texture_table();
        let _ = scene.world_bounds();
    }
});
