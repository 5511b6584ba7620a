//! What the glTF fuzz targets do with one input, shared with the test that replays the
//! committed corpora (crates/scene/tests/fuzz_corpus.rs), so a replay runs exactly the
//! code the fuzzer ran.

#![allow(dead_code)] // each target uses one of the two

use combustion_scene::gltf::{
    import_slice, ImportError, ImportOptions, ImportProblem, ImportReport,
};
use combustion_scene::Scene;

/// The importer catches its own panics and returns them as `ImportProblem::Internal`
/// (a user gets an error, not an abort); for a fuzzer or a replay that is the crash it
/// looks for, so it panics again here.
pub fn imported(result: Result<(Scene, ImportReport), ImportError>) -> Option<Scene> {
    match result {
        Ok((scene, _report)) => Some(scene),
        Err(ImportError {
            problem: ImportProblem::Internal(message),
            ..
        }) => panic!("the importer panicked: {message}"),
        Err(_) => None,
    }
}

/// `data` wrapped in a well-formed GLB container: the first two bytes give the length of
/// the JSON chunk, the rest is the binary chunk, so that the mutator reaches the JSON and
/// accessor code behind a valid container.
fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.len() + pad(bin.len());
    let total = 12 + 8 + json_len + if bin.is_empty() { 0 } else { 8 + bin_len };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.resize(out.len() + pad(json.len()), b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
        out.resize(out.len() + pad(bin.len()), 0);
    }
    out
}

/// `gltf_import`: the importer on the input as it is (JSON, or GLB when it starts with
/// the magic) and on the input wrapped in a GLB container.
pub fn import_both_ways(data: &[u8]) {
    let options = ImportOptions {
        // Keep decoded images small so each run stays fast.
        max_image_dimension: 256,
        ..ImportOptions::default()
    };
    imported(import_slice(data, &options));
    if data.len() >= 2 {
        let split = (usize::from(u16::from_le_bytes([data[0], data[1]])) + 2).min(data.len());
        imported(import_slice(
            &glb(&data[2..split], &data[split..]),
            &options,
        ));
    }
}

/// `gltf_import_validate`: import, then `Scene::validate` (the renderer's own check),
/// `features`, `texture_table` and `world_bounds` on every scene the importer accepts —
/// an accepted scene must validate or say why, never panic.
pub fn import_and_validate(data: &[u8]) {
    let options = ImportOptions {
        max_image_dimension: 256,
        max_decoded_pixels: 1 << 20,
        ..ImportOptions::default()
    };
    if let Some(scene) = imported(import_slice(data, &options)) {
        let _ = scene.validate();
        let _ = scene.features();
        let _ = scene.texture_table();
        let _ = scene.world_bounds();
    }
}
