//! Every file in `tests/bad-gltf/` (made by its `generate.py`, one defect each, named for
//! it) is refused with an error that names the file and the problem, without panicking.

use std::path::{Path, PathBuf};

use combustion_scene::gltf::{import, import_slice, ImportError, ImportOptions, ImportReport};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/bad-gltf")
}

/// (file, words the error must contain).
const EXPECTED: &[(&str, &[&str])] = &[
    ("empty-file.gltf", &["malformed JSON", "truncated"]),
    (
        "animation-key-count-overflows.gltf",
        &["animation 0: sampler 0", "more than this file may ask for"],
    ),
    ("truncated-json.gltf", &["malformed JSON", "truncated"]),
    ("garbled-json.gltf", &["malformed JSON", "line 1"]),
    ("not-gltf-2.gltf", &["asset.version is `1.0`"]),
    ("truncated.glb", &["malformed GLB", "truncated", "declares"]),
    ("glb-version-1.glb", &["malformed GLB", "version 1"]),
    (
        "glb-first-chunk-not-json.glb",
        &["malformed GLB", "first chunk is `XXXX`"],
    ),
    (
        "glb-unpadded-json-chunk.glb",
        &[
            "malformed GLB",
            "chunk 0 (`JSON`) is 29 bytes, not a multiple of 4",
        ],
    ),
    (
        "glb-missing-bin-chunk.glb",
        &["buffer 0", "binary chunk", "has none"],
    ),
    (
        "missing-buffer-file.gltf",
        &["cannot read `missing-buffer.bin`"],
    ),
    ("short-buffer.gltf", &["buffer 0", "is short"]),
    (
        "buffer-view-out-of-range.gltf",
        &["buffer view 2", "exceeds buffer 0"],
    ),
    (
        "accessor-out-of-range.gltf",
        &["POSITION", "accessor 0", "30 elements"],
    ),
    (
        "index-out-of-range.gltf",
        &["mesh 0 primitive 0", "index 7 is out of range"],
    ),
    (
        "accessor-index-missing.gltf",
        &["invalid glTF", "POSITION", "Index out of bounds"],
    ),
    (
        "wrong-accessor-type.gltf",
        &["accessor 0 is VEC2", "expected 3"],
    ),
    (
        "missing-position.gltf",
        &["invalid glTF", "attributes[\"POSITION\"]: Missing data"],
    ),
    (
        "mismatched-attribute-counts.gltf",
        &["NORMAL has 2 elements but POSITION has 3"],
    ),
    ("nan-position.gltf", &["POSITION of vertex 1 is not finite"]),
    (
        "infinite-position.gltf",
        &["POSITION of vertex 2 is not finite"],
    ),
    (
        "all-degenerate-triangles.gltf",
        &["all 1 triangles are degenerate"],
    ),
    (
        "line-loop-index-out-of-range.gltf",
        &["mesh 0 primitive 0", "index 7 is out of range"],
    ),
    (
        "line-strip-of-one-index.gltf",
        &["mesh 0 primitive 0", "has no line segments"],
    ),
    ("nan-point.gltf", &["POSITION of vertex 1 is not finite"]),
    (
        "undecodable-png.gltf",
        &["image 0 (`texture`)", "undecodable PNG"],
    ),
    (
        "unsupported-image-format.gltf",
        &["image 0", "not a PNG, JPEG or WebP", "image/gif"],
    ),
    (
        "huge-image.gltf",
        &["image 0", "20000×20000", "limit of 8192"],
    ),
    ("image-over-limit.gltf", &["image 0", "16×16", "limit of 8"]),
    (
        "uri-leaves-folder.gltf",
        &["`../outside.bin` refused", "leaves the scene's folder"],
    ),
    (
        "uri-absolute-path.gltf",
        &["`/etc/hostname` refused", "absolute paths"],
    ),
    ("uri-file-scheme.gltf", &["refused", "`file:` URIs"]),
    (
        "uri-http-scheme.gltf",
        &["refused", "`https:` scheme is not supported"],
    ),
    ("uri-bad-base64.gltf", &["refused", "invalid base64"]),
    (
        "unsupported-required-extension.gltf",
        &["requires the extension `KHR_draco_mesh_compression`"],
    ),
    ("node-cycle.gltf", &["node 0", "cycle"]),
    (
        "optics-unknown-metal.gltf",
        &[
            "material 0 (`grey`)",
            "COMBUSTION_materials_optics",
            "unknown metal `unobtainium`",
        ],
    ),
    (
        "optics-spectrum-outside-folder.gltf",
        &["material 0", "leaves the scene's folder"],
    ),
    (
        "anisotropy-strength-not-a-number.gltf",
        &[
            "KHR_materials_anisotropy",
            "anisotropyStrength must be a number",
        ],
    ),
    ("camera-zero-fov.gltf", &["camera 0", "yfov 0"]),
    (
        "light-negative-intensity.gltf",
        &["light 0", "non-negative"],
    ),
    (
        "object-overflows-f32.gltf",
        &["node 0 (`huge`)", "beyond what f32 can hold"],
    ),
];

fn options_for(file: &str) -> ImportOptions {
    ImportOptions {
        max_image_dimension: if file == "image-over-limit.gltf" {
            8
        } else {
            8192
        },
        ..ImportOptions::default()
    }
}

#[test]
fn every_bad_file_gives_its_error() {
    let mut failures = Vec::new();
    for (file, needles) in EXPECTED {
        let path = corpus().join(file);
        assert!(
            path.is_file(),
            "{} is missing; run tests/bad-gltf/generate.py",
            path.display()
        );
        match import(&path, &options_for(file)) {
            Ok(_) => failures.push(format!("{file}: imported without error")),
            Err(e) => {
                let message = e.to_string();
                eprintln!("{message}");
                if !message.contains(file) {
                    failures.push(format!(
                        "{file}: the error does not name the file: {message}"
                    ));
                }
                for needle in *needles {
                    if !message.contains(needle) {
                        failures.push(format!("{file}: expected `{needle}` in: {message}"));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

/// No file in the corpus goes untested.
#[test]
fn every_file_in_the_corpus_is_expected() {
    for entry in std::fs::read_dir(corpus()).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if name.ends_with(".gltf") || name.ends_with(".glb") {
            assert!(
                EXPECTED.iter().any(|(f, _)| *f == name),
                "{name} has no expected error in crates/scene/tests/bad_gltf.rs"
            );
        }
    }
}

/// The same bytes from memory: external URIs cannot be resolved at all, and nothing
/// panics; prefixes of every bad file (truncation at any point) are refused too.
#[test]
fn bad_files_from_memory_and_truncated_never_panic() {
    for (file, _) in EXPECTED {
        let bytes = std::fs::read(corpus().join(file)).unwrap();
        assert!(import_slice(&bytes, &options_for(file)).is_err(), "{file}");
        let step = (bytes.len() / 64).max(1);
        for cut in (0..bytes.len()).step_by(step) {
            let _ = import_slice(&bytes[..cut], &options_for(file));
        }
    }
}

/// Degenerate triangles alone are dropped with a warning, not an error.
#[test]
fn some_degenerate_triangles_are_dropped_with_a_warning() {
    // Three vertices, six u16 indices: (0 1 2) and (0 0 1).
    let mut root = one_triangle_file(&[0, 1, 2, 0, 0, 1]);
    root["bufferViews"][2]["byteLength"] = 12.into();
    root["accessors"][2]["count"] = 6.into();
    let (scene, report) =
        import_slice(root.to_string().as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(scene.meshes[0].indices, vec![0, 1, 2]);
    assert_eq!(report.degenerate_triangles, 1);
    assert!(
        report.warnings.iter().any(|w| w.contains("degenerate")),
        "{report}"
    );
}

/// The views a file offers: every perspective camera placed in the scene, in (camera,
/// node) order; orthographic and unplaced cameras left out; each the camera the importer
/// gives when asked for it by index.
#[test]
fn placed_perspective_cameras_are_listed_in_order() {
    let mut root = one_triangle_file(&[0, 1, 2]);
    let perspective = |name: &str| {
        serde_json::json!({ "name": name, "type": "perspective",
            "perspective": { "yfov": 0.8, "znear": 0.1, "zfar": 100.0 } })
    };
    root["cameras"] = serde_json::json!([
        perspective("front"),
        { "type": "orthographic", "orthographic": { "xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0 } },
        perspective("unplaced"),
        perspective("side"),
    ]);
    root["nodes"] = serde_json::json!([
        { "mesh": 0 },
        { "camera": 3, "translation": [5.0, 0.0, 0.0] },
        { "camera": 1, "translation": [0.0, 5.0, 0.0] },
        { "camera": 0, "translation": [0.0, 0.0, 5.0] },
    ]);
    root["scenes"][0]["nodes"] = serde_json::json!([0, 1, 2, 3]);
    let bytes = root.to_string();
    let (scene, report) = import_slice(bytes.as_bytes(), &ImportOptions::default()).unwrap();
    let listed: Vec<_> = report
        .scene_cameras
        .iter()
        .map(|c| {
            (
                c.index,
                c.node,
                c.name.as_deref(),
                c.camera.position.to_array(),
            )
        })
        .collect();
    assert_eq!(
        listed,
        vec![
            (0, 3, Some("front"), [0.0, 0.0, 5.0]),
            (3, 1, Some("side"), [5.0, 0.0, 0.0]),
        ]
    );
    assert_eq!(scene.camera, report.scene_cameras[0].camera);
    let options = ImportOptions {
        camera: Some(3),
        ..ImportOptions::default()
    };
    let (side, _) = import_slice(bytes.as_bytes(), &options).unwrap();
    assert_eq!(side.camera, report.scene_cameras[1].camera);
}

/// The corpus's index-out-of-range.gltf made valid: three vertices (positions and
/// normals) in an embedded buffer, with `indices` (u16) after them.
fn one_triangle_file(indices: &[u16]) -> serde_json::Value {
    let base = corpus().join("index-out-of-range.gltf");
    let mut root: serde_json::Value =
        serde_json::from_slice(&std::fs::read(base).unwrap()).unwrap();
    let data: Vec<u8> = [
        0f32, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 1., 0., 0., 1.,
    ]
    .iter()
    .flat_map(|x| x.to_le_bytes())
    .chain(indices.iter().flat_map(|x| x.to_le_bytes()))
    .collect();
    let uri = format!("data:application/octet-stream;base64,{}", base64(&data));
    root["buffers"][0] = serde_json::json!({ "byteLength": data.len(), "uri": uri });
    root
}

fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            out.push(if k <= c.len() {
                T[((n >> (18 - 6 * k)) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    out
}

/// Appends `bytes` to `root` as a buffer of its own (a data URI) with one buffer view
/// over all of it, `byteStride` `stride` if given; returns the view's index.
fn add_buffer_view(root: &mut serde_json::Value, bytes: &[u8], stride: Option<usize>) -> usize {
    let uri = format!("data:application/octet-stream;base64,{}", base64(bytes));
    let buffers = root["buffers"].as_array_mut().unwrap();
    buffers.push(serde_json::json!({ "byteLength": bytes.len(), "uri": uri }));
    let buffer = buffers.len() - 1;
    let mut view = serde_json::json!({ "buffer": buffer, "byteLength": bytes.len() });
    if let Some(stride) = stride {
        view["byteStride"] = serde_json::json!(stride);
        view["target"] = serde_json::json!(34962);
    }
    let views = root["bufferViews"].as_array_mut().unwrap();
    views.push(view);
    views.len() - 1
}

/// Unknown optional extensions are a warning and listed in the report.
#[test]
fn unknown_optional_extension_is_reported() {
    let bytes = std::fs::read(corpus().join("unsupported-required-extension.gltf")).unwrap();
    let mut root: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    root.as_object_mut().unwrap().remove("extensionsRequired");
    let (_, report) = import_slice(root.to_string().as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(
        report.extensions_ignored,
        vec!["KHR_draco_mesh_compression".to_owned()]
    );
    assert!(report
        .warnings
        .iter()
        .any(|w| w.contains("KHR_draco_mesh_compression")));
}

/// alphaMode and alphaCutoff (glTF: a cutoff of at least 0, read in MASK mode only):
/// MASK keeps its cutoff (0.5 when absent); a negative or non-finite cutoff is a one-line
/// error naming the material; a cutoff above 1 (a material no alpha reaches) is a
/// warning; BLEND (drawn blended by the forward pass) keeps its alpha with no warning;
/// OPAQUE ignores alpha, with no warning.
#[test]
fn alpha_modes_are_read_and_bad_cutoffs_refused() {
    use combustion_scene::AlphaMode;
    let with_material = |material: serde_json::Value| {
        let mut root = one_triangle_file(&[0, 1, 2]);
        root["materials"] = serde_json::json!([material]);
        root["meshes"][0]["primitives"][0]["material"] = serde_json::json!(0);
        import_slice(root.to_string().as_bytes(), &ImportOptions::default())
    };
    let read = |material: serde_json::Value| {
        let (scene, report) = with_material(material).unwrap();
        (
            scene.materials[0].alpha_mode,
            scene.materials[0].alpha,
            report.warnings,
        )
    };
    let factor = |a: f32| serde_json::json!({ "baseColorFactor": [1.0, 1.0, 1.0, a] });
    let (mode, alpha, warnings) = read(serde_json::json!({
        "alphaMode": "MASK", "pbrMetallicRoughness": factor(0.25)
    }));
    assert_eq!((mode, alpha), (AlphaMode::Mask { cutoff: 0.5 }, 0.25));
    assert!(warnings.is_empty(), "{warnings:?}");
    let (mode, _, _) = read(serde_json::json!({ "alphaMode": "MASK", "alphaCutoff": 0.0 }));
    assert_eq!(mode, AlphaMode::Mask { cutoff: 0.0 });
    let (mode, _, warnings) = read(serde_json::json!({ "alphaMode": "MASK", "alphaCutoff": 1.5 }));
    assert_eq!(mode, AlphaMode::Mask { cutoff: 1.5 });
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("alphaCutoff 1.5 is above 1")),
        "{warnings:?}"
    );
    let (mode, alpha, warnings) = read(serde_json::json!({
        "alphaMode": "OPAQUE", "alphaCutoff": 0.7, "pbrMetallicRoughness": factor(0.1)
    }));
    assert_eq!((mode, alpha), (AlphaMode::Opaque, 0.1));
    assert!(warnings.is_empty(), "{warnings:?}");
    let (mode, alpha, warnings) = read(serde_json::json!({
        "alphaMode": "BLEND", "pbrMetallicRoughness": factor(0.3)
    }));
    assert_eq!((mode, alpha), (AlphaMode::Blend, 0.3));
    assert!(warnings.is_empty(), "{warnings:?}");
    let error = with_material(serde_json::json!({ "alphaMode": "MASK", "alphaCutoff": -0.5 }))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("material 0") && error.contains("alphaCutoff") && !error.contains('\n'),
        "{error}"
    );
}

/// The one-triangle file whose one material has these `extensions`, imported.
fn with_extensions(
    extensions: serde_json::Value,
) -> Result<(combustion_scene::Scene, ImportReport), ImportError> {
    let mut root = one_triangle_file(&[0, 1, 2]);
    root["materials"] = serde_json::json!([{ "extensions": extensions }]);
    root["meshes"][0]["primitives"][0]["material"] = serde_json::json!(0);
    import_slice(root.to_string().as_bytes(), &ImportOptions::default())
}

/// The one-triangle file whose material has `extensions` is refused with a one-line
/// error naming material 0 and holding `expected`.
fn refused_in_one_line(extensions: serde_json::Value, expected: &str) {
    let error = with_extensions(extensions).unwrap_err().to_string();
    assert!(error.contains(expected), "{error}");
    assert!(error.contains("material 0"), "{error}");
    assert!(!error.contains('\n'), "one line: {error}");
}

/// KHR_materials_transmission and KHR_materials_volume: the factors within glTF's
/// ranges are read (a volume of thickness 0 is thin-walled: none; no attenuation
/// distance is infinite); a transmission factor outside [0, 1], a negative thickness, an
/// attenuation distance of 0 or below and an attenuation colour outside [0, 1] are
/// one-line errors naming the extension and the material, as are a texture that does
/// not exist and a textureInfo that is not an object.
#[test]
fn transmission_and_volume_are_read_and_out_of_range_values_refused() {
    let (scene, report) = with_extensions(serde_json::json!({
        "KHR_materials_transmission": { "transmissionFactor": 0.8 },
        "KHR_materials_volume": {
            "thicknessFactor": 0.25, "attenuationDistance": 2.0,
            "attenuationColor": [0.9, 0.5, 0.1]
        }
    }))
    .unwrap();
    let material = &scene.materials[0];
    assert_eq!(material.transmission, 0.8);
    assert_eq!(
        material.volume,
        Some(combustion_scene::Volume {
            thickness: 0.25,
            attenuation_distance: 2.0,
            attenuation_color: [0.9, 0.5, 0.1],
        })
    );
    assert!(report.warnings.is_empty(), "{report}");
    assert_eq!(scene.features().transmissive, 1);
    let (scene, _) = with_extensions(serde_json::json!({
        "KHR_materials_transmission": { "transmissionFactor": 1.0 },
        "KHR_materials_volume": { "thicknessFactor": 0.0 }
    }))
    .unwrap();
    assert_eq!(scene.materials[0].volume, None, "thickness 0: thin-walled");
    let (scene, _) = with_extensions(serde_json::json!({
        "KHR_materials_volume": { "thicknessFactor": 1.0 }
    }))
    .unwrap();
    let volume = scene.materials[0].volume.unwrap();
    assert_eq!(volume.attenuation_distance, f32::INFINITY);
    assert_eq!(volume.absorption(), [0.0; 3]);
    for (extensions, expected) in [
        (
            serde_json::json!({
                "KHR_materials_transmission": { "transmissionTexture": { "index": 7 } }
            }),
            "transmission texture 7 does not exist (0 textures)",
        ),
        (
            serde_json::json!({
                "KHR_materials_volume": { "thicknessFactor": 1.0, "thicknessTexture": 3 }
            }),
            "thicknessTexture must be a JSON object",
        ),
        (
            serde_json::json!({ "KHR_materials_transmission": { "transmissionFactor": 1.5 } }),
            "KHR_materials_transmission: transmissionFactor must lie in [0, 1], found 1.5",
        ),
        (
            serde_json::json!({ "KHR_materials_transmission": { "transmissionFactor": "all" } }),
            "transmissionFactor must be a number",
        ),
        (
            serde_json::json!({ "KHR_materials_volume": { "thicknessFactor": -1.0 } }),
            "KHR_materials_volume: thicknessFactor must be at least 0, found -1",
        ),
        (
            serde_json::json!({ "KHR_materials_volume": { "attenuationDistance": 0.0 } }),
            "attenuationDistance must be above 0, found 0",
        ),
        (
            serde_json::json!({
                "KHR_materials_volume": { "attenuationColor": [1.0, 2.0, 0.5] }
            }),
            "attenuationColor must lie in [0, 1], found (1, 2, 0.5)",
        ),
    ] {
        refused_in_one_line(extensions, expected);
    }
}

/// KHR_materials_clearcoat: the factors are read (absent: 0, so a coat of no weight is
/// none; the normal texture's scale 1), and a factor outside [0, 1], a texture that does
/// not exist or a scale that is not a number are one-line errors naming the extension
/// and the material; the textures of a coat of weight 0 are not read.
#[test]
fn clearcoat_is_read_and_out_of_range_values_refused() {
    let (scene, report) = with_extensions(serde_json::json!({
        "KHR_materials_clearcoat": { "clearcoatFactor": 0.75, "clearcoatRoughnessFactor": 0.2 }
    }))
    .unwrap();
    let material = &scene.materials[0];
    assert_eq!(
        (material.clearcoat, material.clearcoat_roughness),
        (0.75, 0.2)
    );
    assert_eq!(material.clearcoat_normal_scale, 1.0);
    assert!(material.is_coated());
    assert!(report.warnings.is_empty(), "{report}");
    assert_eq!(scene.features().coated, 1);
    let (scene, _) = with_extensions(serde_json::json!({
        "KHR_materials_clearcoat": { "clearcoatRoughnessFactor": 0.5,
                                     "clearcoatTexture": { "index": 9 } }
    }))
    .unwrap();
    assert!(
        !scene.materials[0].is_coated(),
        "no factor: weight 0, no coat"
    );
    assert!(scene.materials[0].clearcoat_texture.is_none());
    for (extensions, expected) in [
        (
            serde_json::json!({ "KHR_materials_clearcoat": { "clearcoatFactor": 1.5 } }),
            "KHR_materials_clearcoat: clearcoatFactor must lie in [0, 1], found 1.5",
        ),
        (
            serde_json::json!({
                "KHR_materials_clearcoat": { "clearcoatFactor": 1.0, "clearcoatRoughnessFactor": -0.1 }
            }),
            "clearcoatRoughnessFactor must lie in [0, 1], found -0.1",
        ),
        (
            serde_json::json!({
                "KHR_materials_clearcoat": { "clearcoatFactor": 1.0,
                                             "clearcoatNormalTexture": { "index": 4 } }
            }),
            "clearcoat normal texture 4 does not exist (0 textures)",
        ),
        (
            serde_json::json!({
                "KHR_materials_clearcoat": { "clearcoatFactor": 1.0,
                    "clearcoatNormalTexture": { "index": 0, "scale": "big" } }
            }),
            "clearcoatNormalTexture.scale must be a number",
        ),
        (
            serde_json::json!({ "KHR_materials_clearcoat": [1] }),
            "KHR_materials_clearcoat",
        ),
    ] {
        refused_in_one_line(extensions, expected);
    }
}

/// KHR_materials_sheen: colour and roughness read (absent: black, no sheen, and 0);
/// out-of-range values and a texture that does not exist are one-line errors naming
/// the extension and the material.
#[test]
fn sheen_is_read_and_out_of_range_values_refused() {
    let (scene, report) = with_extensions(serde_json::json!({
        "KHR_materials_sheen": { "sheenColorFactor": [0.5, 0.25, 1.0], "sheenRoughnessFactor": 0.3 }
    }))
    .unwrap();
    let material = &scene.materials[0];
    assert_eq!(material.sheen_color, [0.5, 0.25, 1.0]);
    assert_eq!(material.sheen_roughness, 0.3);
    assert!(
        material.has_sheen() && report.warnings.is_empty(),
        "{report}"
    );
    assert_eq!(scene.features().sheen, 1);
    let (scene, _) = with_extensions(
        serde_json::json!({ "KHR_materials_sheen": { "sheenRoughnessFactor": 1.0 } }),
    )
    .unwrap();
    assert!(!scene.materials[0].has_sheen(), "black: no sheen");
    for (extensions, expected) in [
        (
            serde_json::json!({ "KHR_materials_sheen": { "sheenColorFactor": [2.0, 0.0, 0.0] } }),
            "KHR_materials_sheen: sheenColorFactor must lie in [0, 1]",
        ),
        (
            serde_json::json!({ "KHR_materials_sheen": { "sheenRoughnessFactor": -1.0 } }),
            "sheenRoughnessFactor must lie in [0, 1], found -1",
        ),
        (
            serde_json::json!({ "KHR_materials_sheen": { "sheenColorFactor": [1.0, 1.0, 1.0],
                                                         "sheenColorTexture": { "index": 3 } } }),
            "sheen colour texture 3 does not exist (0 textures)",
        ),
    ] {
        refused_in_one_line(extensions, expected);
    }
}

/// KHR_materials_iridescence: the factor, the film's IOR and thickness range read (the
/// extension's defaults where absent: IOR 1.3, 100 to 400 nm); a factor of 0 is no film;
/// out-of-range values and a texture that does not exist are one-line errors naming the
/// extension and the material.
#[test]
fn iridescence_is_read_and_out_of_range_values_refused() {
    let (scene, report) = with_extensions(serde_json::json!({
        "KHR_materials_iridescence": { "iridescenceFactor": 0.75, "iridescenceIor": 1.8,
                                       "iridescenceThicknessMaximum": 550 }
    }))
    .unwrap();
    let material = &scene.materials[0];
    let film = material.iridescence.unwrap();
    assert_eq!(
        (
            film.factor,
            film.ior,
            film.thickness_min_nm,
            film.thickness_max_nm
        ),
        (0.75, 1.8, 100.0, 550.0)
    );
    assert!(
        material.is_iridescent() && report.warnings.is_empty(),
        "{report}"
    );
    assert_eq!(scene.features().iridescent, 1);
    let (scene, _) =
        with_extensions(serde_json::json!({ "KHR_materials_iridescence": {} })).unwrap();
    assert!(!scene.materials[0].is_iridescent(), "factor 0: no film");
    for (extensions, expected) in [
        (
            serde_json::json!({ "KHR_materials_iridescence": { "iridescenceFactor": 1.5 } }),
            "KHR_materials_iridescence: iridescenceFactor must lie in [0, 1], found 1.5",
        ),
        (
            serde_json::json!({ "KHR_materials_iridescence": { "iridescenceFactor": 1, "iridescenceIor": 0.5 } }),
            "iridescenceIor must be at least 1, found 0.5",
        ),
        (
            serde_json::json!({ "KHR_materials_iridescence": { "iridescenceFactor": 1,
                                                               "iridescenceThicknessMinimum": -5 } }),
            "iridescenceThicknessMinimum must lie in [0, 100000] nm, found -5",
        ),
        (
            serde_json::json!({ "KHR_materials_iridescence": { "iridescenceFactor": 1,
                                                               "iridescenceThicknessMaximum": 1e9 } }),
            "iridescenceThicknessMaximum must lie in [0, 100000] nm, found 1e9",
        ),
        (
            serde_json::json!({ "KHR_materials_iridescence": { "iridescenceFactor": 1,
                                                               "iridescenceThicknessTexture": { "index": 2 } } }),
            "iridescence thickness texture 2 does not exist (0 textures)",
        ),
        (
            serde_json::json!({ "KHR_materials_iridescence": { "iridescenceFactor": "much" } }),
            "iridescenceFactor must be a number",
        ),
    ] {
        refused_in_one_line(extensions, expected);
    }
}

/// A data URI of an RGBA8 WebP (lossless).
fn webp_uri(width: u32, height: u32, rgba: &[u8]) -> String {
    let mut bytes = Vec::new();
    image_webp::WebPEncoder::new(&mut bytes)
        .encode(rgba, width, height, image_webp::ColorType::Rgba8)
        .unwrap();
    format!("data:image/webp;base64,{}", base64(&bytes))
}

/// EXT_texture_webp: a texture's WebP image is read in place of its fallback `source`,
/// or alone where the file requires the extension and gives none; an optional
/// KHR_texture_basisu leaves the fallback; a texture with no image it can read is a
/// one-line error; a WebP larger than the importer's limit is refused before its
/// pixels are decoded.
#[test]
fn webp_textures_are_read() {
    let pixels = [
        200u8, 100, 50, 255, 0, 0, 0, 128, 10, 20, 30, 40, 255, 255, 255, 255,
    ];
    let with = |images: serde_json::Value, texture: serde_json::Value, options: &ImportOptions| {
        let mut root = one_triangle_file(&[0, 1, 2]);
        root["extensionsUsed"] = serde_json::json!(["EXT_texture_webp"]);
        root["images"] = images;
        root["textures"] = serde_json::json!([texture]);
        root["materials"] =
            serde_json::json!([{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } }]);
        root["meshes"][0]["primitives"][0]["material"] = serde_json::json!(0);
        import_slice(root.to_string().as_bytes(), options)
    };
    let webp = serde_json::json!({ "uri": webp_uri(2, 2, &pixels) });
    let png = serde_json::json!({ "uri": png_uri(1, 1, &[9, 9, 9, 255]) });
    // Required: no fallback.
    let (scene, report) = with(
        serde_json::json!([webp]),
        serde_json::json!({ "extensions": { "EXT_texture_webp": { "source": 0 } } }),
        &ImportOptions::default(),
    )
    .unwrap();
    assert!(report.warnings.is_empty(), "{report}");
    let image = &scene.materials[0]
        .base_color_texture
        .as_ref()
        .unwrap()
        .texture
        .image;
    assert_eq!((image.width, image.height), (2, 2));
    assert_eq!(image.pixels, pixels, "lossless: the pixels as encoded");
    // The base colour image a texture of the PNG (0) and the WebP (1) gives.
    let base_colour_of = |texture: serde_json::Value| {
        let (scene, _) = with(
            serde_json::json!([png, webp]),
            texture,
            &ImportOptions::default(),
        )
        .unwrap();
        let texture = scene.materials[0].base_color_texture.clone().unwrap();
        texture.texture.image
    };
    // Optional, beside a PNG fallback: the WebP is read.
    let image = base_colour_of(
        serde_json::json!({ "source": 0, "extensions": { "EXT_texture_webp": { "source": 1 } } }),
    );
    assert_eq!(image.pixels, pixels);
    // KHR_texture_basisu (KTX2) is not read: an optional one leaves its texture the
    // fallback image, as the specification allows (a file requiring it is refused, as
    // any unsupported required extension).
    let image = base_colour_of(
        serde_json::json!({ "source": 0, "extensions": { "KHR_texture_basisu": { "source": 1 } } }),
    );
    assert_eq!(image.pixels, [9, 9, 9, 255]);
    // No image at all.
    let error = with(
        serde_json::json!([webp]),
        serde_json::json!({}),
        &ImportOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("texture 0 has no image") && !error.contains('\n'),
        "{error}"
    );
    // Too large for the limit: refused by its header.
    let small = ImportOptions {
        max_image_dimension: 1,
        ..ImportOptions::default()
    };
    let error = with(
        serde_json::json!([webp]),
        serde_json::json!({ "extensions": { "EXT_texture_webp": { "source": 0 } } }),
        &small,
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("2×2") || error.contains("2x2"), "{error}");
}

/// A data URI of an RGBA8 PNG.
fn png_uri(width: u32, height: u32, rgba: &[u8]) -> String {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder
            .write_header()
            .unwrap()
            .write_image_data(rgba)
            .unwrap();
    }
    format!("data:image/png;base64,{}", base64(&bytes))
}

/// KHR_materials_pbrSpecularGlossiness is converted to metallic-roughness at import: a
/// dielectric (specular 0.04) keeps its diffuse colour as base colour with metalness 0,
/// a metal (diffuse black) gets its specular colour with metalness 1 and a conductor
/// from it, roughness is 1 − glossiness; with textures, texel by texel into a base
/// colour image (the diffuse's alpha) and a metallic-roughness image, factors folded
/// in. Factors outside [0, 1] and textures read at different coordinates are one-line
/// errors.
#[test]
fn specular_glossiness_is_converted_to_metallic_roughness() {
    let ext =
        |sg: serde_json::Value| serde_json::json!({ "KHR_materials_pbrSpecularGlossiness": sg });
    let (scene, report) = with_extensions(ext(serde_json::json!({
        "diffuseFactor": [0.5, 0.25, 0.1, 0.8], "specularFactor": [0.04, 0.04, 0.04],
        "glossinessFactor": 0.6
    })))
    .unwrap();
    assert!(report.warnings.is_empty(), "{report}");
    let m = &scene.materials[0];
    for (got, want) in m.base_color.iter().zip([0.5, 0.25, 0.1]) {
        assert!((got - want).abs() < 1e-6, "{:?}", m.base_color);
    }
    assert_eq!((m.metalness, m.alpha), (0.0, 0.8));
    assert!((m.roughness - 0.4).abs() < 1e-6);
    let (scene, _) = with_extensions(ext(serde_json::json!({
        "diffuseFactor": [0.0, 0.0, 0.0, 1.0], "specularFactor": [0.9, 0.6, 0.5]
    })))
    .unwrap();
    let m = &scene.materials[0];
    assert!((m.metalness - 1.0).abs() < 1e-6, "{}", m.metalness);
    for (got, want) in m.base_color.iter().zip([0.9, 0.6, 0.5]) {
        assert!((got - want).abs() < 1e-5, "{:?}", m.base_color);
    }
    assert!(m.conductor_from_base_color && m.roughness == 0.0);

    // Textures: a dielectric texel (specular code 56, 0.0395 linear; glossiness 0.6)
    // and a metal one (diffuse black, half alpha; a copper-like specular).
    let diffuse = png_uri(2, 1, &[200, 100, 50, 255, 0, 0, 0, 128]);
    let specular = png_uri(2, 1, &[56, 56, 56, 153, 242, 209, 197, 255]);
    let textured = |specular_info: serde_json::Value| {
        let mut root = one_triangle_file(&[0, 1, 2]);
        root["images"] = serde_json::json!([{ "uri": diffuse }, { "uri": specular }]);
        root["textures"] = serde_json::json!([{ "source": 0 }, { "source": 1 }]);
        root["materials"] = serde_json::json!([{ "extensions": ext(serde_json::json!({
            "diffuseTexture": { "index": 0 }, "specularGlossinessTexture": specular_info
        })) }]);
        root["meshes"][0]["primitives"][0]["material"] = serde_json::json!(0);
        import_slice(root.to_string().as_bytes(), &ImportOptions::default())
    };
    let (scene, _) = textured(serde_json::json!({ "index": 1 })).unwrap();
    let m = &scene.materials[0];
    let base = m.base_color_texture.as_ref().unwrap().texture.image.clone();
    let metal_rough = m
        .metallic_roughness_texture
        .as_ref()
        .unwrap()
        .texture
        .image
        .clone();
    assert_eq!((base.width, base.height), (2, 1));
    assert_eq!(base.color_space, combustion_scene::ColorSpace::Srgb);
    assert_eq!(
        metal_rough.color_space,
        combustion_scene::ColorSpace::Linear
    );
    let near = |got: &[u8], want: &[u8]| {
        got.iter()
            .zip(want)
            .all(|(g, w)| (i32::from(*g) - i32::from(*w)).abs() <= 1)
    };
    // texel 0: the diffuse colour (× (1 − 0.0395)/0.96, within a code), metal 0, rough 0.4
    assert!(
        near(&base.pixels[..4], &[200, 100, 50, 255]),
        "{:?}",
        base.pixels
    );
    assert!(
        near(&metal_rough.pixels[..4], &[0, 102, 0, 255]),
        "{:?}",
        metal_rough.pixels
    );
    // texel 1: the specular colour, metal 1, rough 0, the diffuse's alpha
    assert!(
        near(&base.pixels[4..], &[242, 209, 197, 128]),
        "{:?}",
        base.pixels
    );
    assert!(
        near(&metal_rough.pixels[4..], &[0, 0, 255, 255]),
        "{:?}",
        metal_rough.pixels
    );
    assert_eq!(
        (m.base_color, m.metalness, m.roughness, m.alpha),
        ([1.0; 3], 1.0, 1.0, 1.0)
    );

    let error = textured(serde_json::json!({ "index": 1, "texCoord": 1 }))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("different texture coordinates") && !error.contains('\n'),
        "{error}"
    );
    for (sg, expected) in [
        (
            serde_json::json!({ "diffuseFactor": [2.0, 0.5, 0.5, 1.0] }),
            "diffuseFactor must lie in [0, 1]",
        ),
        (
            serde_json::json!({ "glossinessFactor": "shiny" }),
            "glossinessFactor must be a number",
        ),
        (
            serde_json::json!({ "specularFactor": [0.5, 0.5] }),
            "specularFactor must be an array of 3 numbers",
        ),
    ] {
        refused_in_one_line(ext(sg), expected);
    }
}

/// COLOR_0 (glTF: VEC3 or VEC4 of floats, normalised unsigned bytes or normalised
/// unsigned shorts): each form is read into `Vertex::color` (VEC3 with alpha 1); a
/// colour of integers that are not normalised, or of two components, is a one-line
/// error naming COLOR_0; float components above 1 are clamped with a warning.
#[test]
fn vertex_colours_are_read_in_every_allowed_form() {
    let with_colors =
        |component: u32, normalized: bool, ty: &str, stride: usize, bytes: Vec<u8>| {
            let mut root = one_triangle_file(&[0, 1, 2]);
            let view = add_buffer_view(&mut root, &bytes, Some(stride));
            let accessor = root["accessors"].as_array().unwrap().len();
            root["accessors"]
                .as_array_mut()
                .unwrap()
                .push(serde_json::json!({
                    "bufferView": view, "componentType": component, "normalized": normalized,
                    "count": 3, "type": ty
                }));
            root["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
                serde_json::json!(accessor);
            import_slice(root.to_string().as_bytes(), &ImportOptions::default())
        };
    let colors_of = |scene: &combustion_scene::Scene| -> Vec<[f32; 4]> {
        let mesh = &scene.meshes[0];
        mesh.indices
            .iter()
            .map(|&i| mesh.vertices[i as usize].color)
            .collect()
    };
    let floats = |values: &[f32]| {
        values
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect::<Vec<u8>>()
    };
    // VEC4 floats.
    let rgba = [
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, 0.5],
        [0.0, 0.0, 1.0, 0.25],
    ];
    let (scene, report) =
        with_colors(5126, false, "VEC4", 16, floats(rgba.as_flattened())).unwrap();
    assert_eq!(colors_of(&scene), rgba.to_vec());
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    // VEC3 normalised bytes (each element padded to 4 bytes): alpha 1.
    let bytes = vec![255, 0, 0, 0, 0, 255, 0, 0, 0, 0, 51, 0];
    let (scene, _) = with_colors(5121, true, "VEC3", 4, bytes).unwrap();
    assert_eq!(
        colors_of(&scene),
        vec![
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 1.0],
            [0.0, 0.0, 0.2, 1.0]
        ]
    );
    // VEC4 normalised shorts.
    let shorts: Vec<u8> = [65535u16, 0, 0, 65535, 0, 65535, 0, 32768, 0, 0, 65535, 0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let (scene, _) = with_colors(5123, true, "VEC4", 8, shorts).unwrap();
    assert_eq!(colors_of(&scene)[1], [0.0, 1.0, 0.0, 32768.0 / 65535.0]);
    // Not allowed: bytes that are not normalised, two components.
    for (component, normalized, ty, stride, bytes, words) in [
        (5121, false, "VEC4", 4, vec![255u8; 12], "normalised"),
        (5126, false, "VEC2", 8, floats(&[0.5; 6]), "VEC2"),
    ] {
        let error = with_colors(component, normalized, ty, stride, bytes)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("COLOR_0") && error.contains(words) && !error.contains('\n'),
            "{error}"
        );
    }
    // Floats above 1: clamped, with a warning.
    let (scene, report) = with_colors(5126, false, "VEC4", 16, floats(&[1.5; 12])).unwrap();
    assert_eq!(colors_of(&scene), vec![[1.0; 4]; 3]);
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("COLOR_0") && w.contains("clamped")),
        "{:?}",
        report.warnings
    );
}

/// KHR_materials_unlit: an (empty) object marks the material unlit, also when the file
/// requires the extension; anything else in its place is a one-line error naming it;
/// `save_gltf` writes it back.
#[test]
fn unlit_materials_are_read_and_written() {
    let with_unlit = |unlit: serde_json::Value, required: bool| {
        let mut root = one_triangle_file(&[0, 1, 2]);
        root["materials"] = serde_json::json!([{ "extensions": { "KHR_materials_unlit": unlit } }]);
        root["meshes"][0]["primitives"][0]["material"] = serde_json::json!(0);
        root["extensionsUsed"] = serde_json::json!(["KHR_materials_unlit"]);
        if required {
            root["extensionsRequired"] = serde_json::json!(["KHR_materials_unlit"]);
        }
        import_slice(root.to_string().as_bytes(), &ImportOptions::default())
    };
    for required in [false, true] {
        let (scene, report) = with_unlit(serde_json::json!({}), required).unwrap();
        assert!(scene.materials[0].unlit);
        assert!(report.warnings.is_empty(), "{:?}", report.warnings);
        assert_eq!(scene.features().unlit, 1);
    }
    let error = with_unlit(serde_json::json!(true), false)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("KHR_materials_unlit") && !error.contains('\n'),
        "{error}"
    );
    // Written back.
    let (scene, _) = with_unlit(serde_json::json!({}), false).unwrap();
    let dir = std::env::temp_dir().join(format!("combustion-unlit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("unlit.gltf");
    combustion_scene::gltf::save_gltf(&scene, &path).unwrap();
    let (again, _) = combustion_scene::gltf::import(&path, &ImportOptions::default()).unwrap();
    assert!(again.materials[0].unlit);
    let _ = std::fs::remove_dir_all(dir);
}

/// EXT_mesh_gpu_instancing: the node's mesh is placed once per instance, at the node's
/// transform × the instance's TRS (a missing attribute is the identity's), one object
/// after another; attributes of different counts, a non-finite value, a zero rotation or
/// no attribute at all are one-line errors naming the node and the extension.
#[test]
fn gpu_instances_are_placed_and_bad_ones_refused() {
    let with_instances = |attributes: serde_json::Value, data: &[f32], extra: &[(&str, u32)]| {
        let mut root = one_triangle_file(&[0, 1, 2]);
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = add_buffer_view(&mut root, &bytes, None);
        let mut offset = 0u32;
        for (ty, count) in extra {
            let size = if *ty == "VEC4" { 16 } else { 12 };
            root["accessors"]
                .as_array_mut()
                .unwrap()
                .push(serde_json::json!({
                    "bufferView": view, "byteOffset": offset, "componentType": 5126,
                    "count": count, "type": ty
                }));
            offset += size * count;
        }
        root["nodes"][0]["extensions"] =
            serde_json::json!({ "EXT_mesh_gpu_instancing": { "attributes": attributes } });
        root["extensionsUsed"] = serde_json::json!(["EXT_mesh_gpu_instancing"]);
        root["extensionsRequired"] = serde_json::json!(["EXT_mesh_gpu_instancing"]);
        import_slice(root.to_string().as_bytes(), &ImportOptions::default())
    };
    // Two instances: translations (1,0,0) and (0,2,0); the second scaled by 3 and turned
    // a quarter about z.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let data = [
        1.0, 0.0, 0.0, 0.0, 2.0, 0.0, // TRANSLATION (accessor 3)
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, s, s, // ROTATION (accessor 4)
        1.0, 1.0, 1.0, 3.0, 3.0, 3.0, // SCALE (accessor 5)
    ];
    let layout = [("VEC3", 2), ("VEC4", 2), ("VEC3", 2)];
    let all = serde_json::json!({ "TRANSLATION": 3, "ROTATION": 4, "SCALE": 5 });
    let (scene, report) = with_instances(all, &data, &layout).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.objects[0].mesh, scene.objects[1].mesh);
    let p = |o: usize, v: glam::Vec3| scene.objects[o].transform.transform_point3(v);
    assert!((p(0, glam::Vec3::X) - glam::Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
    assert!((p(1, glam::Vec3::X) - glam::Vec3::new(0.0, 5.0, 0.0)).length() < 1e-5);
    // Translation alone.
    let (scene, _) =
        with_instances(serde_json::json!({ "TRANSLATION": 3 }), &data, &layout).unwrap();
    assert_eq!(scene.objects.len(), 2);
    // Refused.
    let mut zero_rotation = data;
    zero_rotation[6..10].copy_from_slice(&[0.0; 4]);
    let mut infinite = data;
    infinite[0] = f32::INFINITY;
    for (attributes, data, layout, words) in [
        (
            serde_json::json!({ "TRANSLATION": 3, "ROTATION": 4 }),
            data.to_vec(),
            vec![("VEC3", 2), ("VEC4", 1), ("VEC3", 2)],
            "different counts",
        ),
        (
            serde_json::json!({ "TRANSLATION": 3, "ROTATION": 4 }),
            zero_rotation.to_vec(),
            layout.to_vec(),
            "unit quaternion",
        ),
        (
            serde_json::json!({ "TRANSLATION": 3 }),
            infinite.to_vec(),
            layout.to_vec(),
            "not finite",
        ),
        (
            serde_json::json!({}),
            data.to_vec(),
            layout.to_vec(),
            "names none",
        ),
    ] {
        let error = with_instances(attributes, &data, &layout)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("EXT_mesh_gpu_instancing")
                && error.contains(words)
                && !error.contains('\n'),
            "{error}"
        );
    }
}

/// KHR_mesh_quantization, required: positions as normalised shorts scaled back by the
/// node (the extension's usual form), normals as normalised bytes and coordinates as
/// normalised unsigned shorts are read as the numbers they stand for.
#[test]
fn quantized_attributes_are_read_as_their_values() {
    let mut root = one_triangle_file(&[0, 1, 2]);
    // Three vertices: positions (i16 normalised, each element padded to 8 bytes),
    // normals (i8 normalised, padded to 4), coordinates (u16 normalised).
    let positions: [[i16; 4]; 3] = [[0, 0, 0, 0], [32767, 0, 0, 0], [0, 32767, 0, 0]];
    let normals: [[i8; 4]; 3] = [[0, 0, 127, 0]; 3];
    let uvs: [[u16; 2]; 3] = [[0, 0], [65535, 0], [0, 32768]];
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bytes.extend(normals.iter().flatten().map(|&x| x as u8));
    bytes.extend(uvs.iter().flatten().flat_map(|x| x.to_le_bytes()));
    let uri = format!("data:application/octet-stream;base64,{}", base64(&bytes));
    root["buffers"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({ "byteLength": bytes.len(), "uri": uri }));
    let views = root["bufferViews"].as_array().unwrap().len();
    for (offset, length, stride) in [(0, 24, 8), (24, 12, 4), (36, 12, 4)] {
        root["bufferViews"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!({
                "buffer": 1, "byteOffset": offset, "byteLength": length, "byteStride": stride,
                "target": 34962
            }));
    }
    let accessors = root["accessors"].as_array().unwrap().len();
    for (k, (component, ty, min, max)) in [
        (5122, "VEC3", [0.0, 0.0, 0.0], [1.0, 1.0, 0.0]),
        (5120, "VEC3", [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
        (5123, "VEC2", [0.0, 0.0, 0.0], [1.0, 1.0, 0.0]),
    ]
    .into_iter()
    .enumerate()
    {
        let mut accessor = serde_json::json!({
            "bufferView": views + k, "componentType": component, "normalized": true,
            "count": 3, "type": ty
        });
        if k == 0 {
            accessor["min"] = serde_json::json!(min);
            accessor["max"] = serde_json::json!(max);
        }
        root["accessors"].as_array_mut().unwrap().push(accessor);
    }
    let attributes = &mut root["meshes"][0]["primitives"][0]["attributes"];
    attributes["POSITION"] = serde_json::json!(accessors);
    attributes["NORMAL"] = serde_json::json!(accessors + 1);
    attributes["TEXCOORD_0"] = serde_json::json!(accessors + 2);
    root["nodes"][0]["scale"] = serde_json::json!([2.0, 2.0, 2.0]);
    root["extensionsUsed"] = serde_json::json!(["KHR_mesh_quantization"]);
    root["extensionsRequired"] = serde_json::json!(["KHR_mesh_quantization"]);
    let (scene, report) = import_slice(root.to_string().as_bytes(), &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let mesh = &scene.meshes[scene.objects[0].mesh];
    let vertex = |i: usize| mesh.vertices[mesh.indices[i] as usize];
    assert_eq!(vertex(1).position, [1.0, 0.0, 0.0]);
    assert_eq!(vertex(2).position, [0.0, 1.0, 0.0]);
    assert_eq!(vertex(0).normal, [0.0, 0.0, 1.0]);
    assert_eq!(vertex(1).uv, [1.0, 0.0]);
    assert_eq!(vertex(2).uv, [0.0, 32768.0 / 65535.0]);
    let placed = scene.objects[0]
        .transform
        .transform_point3(glam::Vec3::from(vertex(1).position));
    assert_eq!(placed, glam::Vec3::new(2.0, 0.0, 0.0));
}

/// Numbers in the importer's messages are written short (`3e38`, not 39 digits) and in
/// parentheses (not a Rust array's `[…]` debug form).
#[test]
fn numbers_in_messages_are_written_short() {
    refused_in_one_line(
        serde_json::json!({ "KHR_materials_sheen": { "sheenRoughnessFactor": 3e38 } }),
        "sheenRoughnessFactor must lie in [0, 1], found 3e38",
    );
    refused_in_one_line(
        serde_json::json!({ "KHR_materials_sheen": { "sheenColorFactor": [0.5, 2.0, 3e38] } }),
        "sheenColorFactor must lie in [0, 1], found (0.5, 2, 3e38)",
    );
    refused_in_one_line(
        serde_json::json!({ "KHR_materials_volume": { "thicknessFactor": -1e-30 } }),
        "thicknessFactor must be at least 0, found -1e-30",
    );
}
