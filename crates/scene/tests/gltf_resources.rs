//! Issue 9, resource use: each distinct image source is decoded once under a total
//! decoded-pixel budget; only regular files of a bounded size are read (a FIFO would
//! block, /dev/zero would never end); counts the renderer cannot take are refused first.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use combustion_scene::gltf::{import, ImportOptions};
use serde_json::json;

fn temp_dir(name: &str) -> PathBuf {
    super::support::temp_dir("resources", name)
}

/// A 4×4 grey PNG.
fn small_png() -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, 4, 4);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&[128u8; 4 * 4 * 4]).unwrap();
    drop(writer);
    bytes
}

/// `dir/scene.gltf`: one triangle drawn `materials` times (one primitive per material),
/// material i textured by image i, every image the same PNG in buffer view 1 of
/// `buffer_uri` (written to `dir/scene.bin` unless `write_buffer` is false).
fn write_scene(dir: &Path, materials: usize, buffer_uri: &str, write_buffer: bool) -> PathBuf {
    let positions: Vec<u8> = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    let png = small_png();
    let mut data = positions.clone();
    data.extend_from_slice(&png);
    // Padding no view covers, so the buffer (16 KiB) is larger than the glTF file.
    data.resize(data.len() + 16 * 1024, 0);
    if write_buffer {
        std::fs::write(dir.join("scene.bin"), &data).unwrap();
    }
    let primitives: Vec<_> = (0..materials)
        .map(|m| json!({ "attributes": { "POSITION": 0 }, "material": m }))
        .collect();
    let gltf = json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": primitives }],
        "materials": (0..materials)
            .map(|m| json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": m } } }))
            .collect::<Vec<_>>(),
        "textures": (0..materials).map(|m| json!({ "source": m })).collect::<Vec<_>>(),
        "images": (0..materials)
            .map(|_| json!({ "bufferView": 1, "mimeType": "image/png" }))
            .collect::<Vec<_>>(),
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0, 0, 0], "max": [1, 1, 0] }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": positions.len() },
            { "buffer": 0, "byteOffset": positions.len(), "byteLength": png.len() },
        ],
        "buffers": [{ "byteLength": data.len(), "uri": buffer_uri }],
    });
    let path = dir.join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&gltf).unwrap()).unwrap();
    path
}

#[test]
fn one_image_source_is_decoded_once_and_the_budget_holds() {
    let dir = temp_dir("one-source");
    let path = write_scene(&dir, 300, "scene.bin", true);
    let (scene, _) = import(&path, &ImportOptions::default()).unwrap();
    assert_eq!(scene.materials.len(), 300);
    let first = scene.materials[0].base_color_texture.as_ref().unwrap();
    for m in &scene.materials {
        let t = m.base_color_texture.as_ref().unwrap();
        assert!(
            Arc::ptr_eq(&t.texture.image, &first.texture.image),
            "decoded again"
        );
    }
    assert_eq!(scene.texture_table().images.len(), 1);

    // 16 pixels, decoded once and held once (the scene's image is the decode itself):
    // 16 fit, 15 do not. Used in a linear slot as well (metallic-roughness), the image
    // is held a second time, in the other colour space: 32 fit, 31 do not.
    let two_spaces = dir.join("two-spaces.gltf");
    let mut root: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    root["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] =
        json!({ "index": 0 });
    std::fs::write(&two_spaces, root.to_string()).unwrap();
    for (file, budget, fits) in [
        (&path, 15, false),
        (&path, 16, true),
        (&two_spaces, 31, false),
        (&two_spaces, 32, true),
    ] {
        let options = ImportOptions {
            max_decoded_pixels: budget,
            ..ImportOptions::default()
        };
        match import(file, &options) {
            Ok(_) => assert!(fits, "{budget}"),
            Err(e) => {
                assert!(!fits, "{budget}: {e}");
                assert!(
                    e.to_string()
                        .contains(&format!("over the budget of {budget} for one scene")),
                    "{e}"
                );
            }
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// `dir/scene.gltf`: one triangle textured by `dir/texture.jpg`, which holds `image`.
fn write_textured_triangle(dir: &Path, image: &[u8]) -> PathBuf {
    std::fs::write(dir.join("texture.jpg"), image).unwrap();
    let path = dir.join("scene.gltf");
    std::fs::write(&path, super::support::textured_triangle("texture.jpg")).unwrap();
    path
}

/// The budget holds a decode under way, not only the pixels kept: a JPEG is admitted
/// only if its decoder's peak (4:4:4, 64×64 pixels: 3 planes of a byte a sample, the
/// coefficients of rows queued to the decoder's threads, 2 bytes a sample, and the RGB
/// output, 12 bytes a pixel; progressive, also every DCT coefficient until the last
/// scan, 18 bytes a pixel), counted as pixels of 4 bytes, fits beside the images already
/// held — refused before decoding otherwise, with the decoder's work named. Once
/// decoded, only its 4,096 pixels stay charged.
#[test]
fn a_decoders_work_counts_against_the_pixel_budget_before_it_decodes() {
    let dir = temp_dir("decoder-work");
    let pixels = 64 * 64;
    for (image, name, at_once) in [
        (
            include_bytes!("data/gradient-64-baseline-444.jpg").as_slice(),
            "baseline",
            pixels * 12 / 4,
        ),
        (
            include_bytes!("data/gradient-64-progressive-444.jpg").as_slice(),
            "progressive",
            pixels * 18 / 4,
        ),
    ] {
        let path = write_textured_triangle(&dir, image);
        for (budget, fits) in [(pixels, false), (at_once - 1, false), (at_once, true)] {
            let options = ImportOptions {
                max_decoded_pixels: budget,
                ..ImportOptions::default()
            };
            match import(&path, &options) {
                Ok((scene, _)) => {
                    assert!(fits, "{name}, {budget}");
                    let texture = scene.materials[0].base_color_texture.as_ref().unwrap();
                    assert_eq!(texture.texture.image.pixels.len() as u64, pixels * 4);
                }
                Err(e) => {
                    assert!(!fits, "{name}, {budget}: {e}");
                    let message = e.to_string();
                    for part in [
                        format!("decoding it (64×64, its decoder's work beside its {pixels} pixels) takes the room of {at_once} pixels at once"),
                        format!("over the budget of {budget} for one scene"),
                    ] {
                        assert!(message.contains(&part), "{name}, {budget}: {message}");
                    }
                }
            }
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn only_regular_files_of_a_bounded_size_are_read() {
    let dir = temp_dir("special");
    // A FIFO as the buffer: refused at once (reading it would block forever).
    let fifo = dir.join("pipe.bin");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let path = write_scene(&dir, 1, "pipe.bin", false);
    let error = import(&path, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("not a regular file"), "{error}");
    // A link to /dev/zero: refused (read, it would never end).
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.bin")).unwrap();
    let path = write_scene(&dir, 1, "zero.bin", false);
    let error = import(&path, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("not a regular file"), "{error}");
    // A regular buffer over the size limit, refused before it is read: the limit lies
    // between the glTF file's size and the buffer's.
    let path = write_scene(&dir, 1, "scene.bin", true);
    let gltf_size = std::fs::metadata(&path).unwrap().len();
    let buffer_size = std::fs::metadata(dir.join("scene.bin")).unwrap().len();
    assert!(gltf_size < 8 * 1024 && buffer_size > 16 * 1024);
    let small = ImportOptions {
        max_file_bytes: 8 * 1024,
        ..ImportOptions::default()
    };
    let error = import(&path, &small).unwrap_err().to_string();
    assert!(
        error.contains("scene.bin")
            && error.contains("more than the 8192 bytes a scene's file may have"),
        "{error}"
    );
    // The glTF file itself too.
    let tiny = ImportOptions {
        max_file_bytes: 16,
        ..ImportOptions::default()
    };
    let error = import(&path, &tiny).unwrap_err().to_string();
    assert!(
        error.contains("more than the 16 bytes a scene's file may have"),
        "{error}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn too_many_materials_are_refused_before_any_work() {
    // 70,000 materials, each used by a primitive of one mesh (the importer keeps the
    // used ones only, so unused ones would be no problem).
    let primitives: Vec<_> = (0..70_000)
        .map(|m| json!({ "attributes": { "POSITION": 0 }, "material": m }))
        .collect();
    let gltf = json!({
        "asset": { "version": "2.0" },
        "meshes": [{ "primitives": primitives }],
        "accessors": [{ "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0, 0, 0], "max": [0, 0, 0] }],
        "materials": vec![json!({}); 70_000],
    });
    let bytes = serde_json::to_vec(&gltf).unwrap();
    let error = combustion_scene::gltf::import_slice(&bytes, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("70000 materials"), "{error}");
}

/// A top-level array of more than 2²¹ entries is refused from a count taken before the
/// document's tree is built: 2²¹ + 1 empty nodes are 6 MB of JSON, which parsed would
/// take over a gigabyte.
#[test]
fn a_top_level_array_past_its_limit_is_refused_before_the_tree_is_built() {
    let dir = temp_dir("many-nodes");
    let path = dir.join("nodes.gltf");
    let count = (1usize << 21) + 1;
    let mut json = String::from(r#"{"asset":{"version":"2.0"},"nodes":["#);
    json += &vec!["{}"; count].join(",");
    json += "]}";
    std::fs::write(&path, json).unwrap();
    // (Not `unwrap_err`: a scene of two million nodes is no message to print.)
    let Err(error) = import(&path, &ImportOptions::default()) else {
        panic!("2²¹ + 1 nodes imported");
    };
    let message = error.to_string();
    assert!(
        message
            .contains("its `nodes` holds 2097153 entries, more than the 2097152 a file may have"),
        "{message}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}
