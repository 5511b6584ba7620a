//! glTF scenes on the GPU: every Khronos sample model in ../shared/data/gltf (when that
//! folder is present) and every scene in assets/scenes renders on lavapipe with no
//! validation message and no NaN/Inf pixel; the anisotropy test model's anisotropy
//! directions come out as its README says; emissive and base-colour-derived conductors
//! meet hand computations.

use crate::common;

use std::path::{Path, PathBuf};

use combustion::optics::fresnel::fresnel_conductor;
use combustion::renderer::gbuffer::{
    anisotropy_direction_decode, octahedral_decode, srgb_to_linear,
};
use combustion::renderer::gpu_types::conductor_from_base_color_table;
use combustion::renderer::{HdrFormat, Readback, RendererSettings, ShadingOptions};
use combustion::scene::{Material, Scene};
use combustion::SceneSource;
use glam::{Mat4, Vec3};

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The sample models tests/sample-models.txt lists as importing, or None (with a note)
/// when ../shared is not beside the workspace (a failure when CI requires it:
/// `common::REQUIRE_SHARED`). (Those refused, and models missing from
/// the list, are the importer's test: crates/scene/tests/gltf_samples.rs.)
fn sample_models() -> Option<Vec<PathBuf>> {
    let importing: Vec<&str> = include_str!("sample-models.txt")
        .lines()
        .filter_map(|line| line.strip_suffix(" imports"))
        .collect();
    let root = common::shared_gltf_samples()?;
    let mut files = Vec::new();
    for model in std::fs::read_dir(&root).unwrap() {
        let model = model.unwrap().path();
        let name = model.file_name().unwrap().to_string_lossy().into_owned();
        if !importing.contains(&name.as_str()) {
            continue;
        }
        for variant in ["glTF", "glTF-Binary", "glTF-Embedded"] {
            let Ok(entries) = std::fs::read_dir(model.join(variant)) else {
                continue;
            };
            for entry in entries {
                let path = entry.unwrap().path();
                if matches!(
                    path.extension().and_then(|e| e.to_str()),
                    Some("gltf" | "glb")
                ) {
                    files.push(path);
                }
            }
        }
    }
    files.sort();
    Some(files)
}

/// The scene in `path`, which must have lights or an environment (a file without lights
/// is lit by the default environment, the studio).
fn load_file(path: &Path) -> Scene {
    let scene = SceneSource::File(path.to_path_buf())
        .load()
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        !scene.lights.is_empty() || scene.environment.is_some(),
        "{}: neither lights nor an environment",
        path.display()
    );
    scene
}

/// Fails unless every pixel of `frame` (of the scene in `path`) is finite and more than
/// 100 are lit.
fn assert_clean(path: &Path, frame: &combustion::renderer::Frame) {
    let bad = frame
        .hdr
        .iter()
        .filter(|p| p.iter().any(|c| !c.is_finite()))
        .count();
    assert_eq!(bad, 0, "{}: {bad} NaN/Inf pixels", path.display());
    let lit = frame
        .hdr
        .iter()
        .filter(|p| p[0] + p[1] + p[2] > 0.0)
        .count();
    assert!(lit > 100, "{}: only {lit} lit pixels", path.display());
}

/// The scene in `path` rendered by a renderer of its own under validation (`common::exact_f32`),
/// checked by [`assert_clean`].
fn render_file(
    path: &Path,
    width: u32,
    height: u32,
    readback: Readback,
) -> combustion::renderer::Frame {
    let frame = common::render(
        &load_file(path),
        width,
        height,
        common::exact_f32(),
        readback,
    );
    assert_clean(path, &frame);
    frame
}

/// Every sample model, one after another in one renderer (as a viewer opening file
/// after file: each model's scene uploaded, rendered once and dropped before the next),
/// under validation: the log is read after each model, so a message names the model
/// that caused it; leaks are reported when the device is destroyed at the end, without
/// a model's name (the models go in the order the test prints them). A renderer of
/// its own per model took 34 s with Mesa's cache empty against 27 s.
///
/// And no pixel of a surface is exactly black where the scene lights it: each pixel
/// the G-buffer covers whose radiance is exactly 0 is shaded by the f64 reference
/// (`SceneShading`, the environment's integral included where the file is lit by one);
/// it counts unless the reference is black there too (below `RADIANCE_FLOOR`). Shading normals that face away
/// from the eye (interpolated at silhouettes, normal-mapped on folds) made such pixels
/// before every pass bent them towards it (`facing_view`): 93 pixels in 14 files (12
/// models) at this size then, 0 since.
#[test]
fn every_sample_model_renders_cleanly() {
    let Some(files) = sample_models() else { return };
    assert!(files.len() >= 5, "{files:?}");
    let (width, height) = (192, 144);
    let mut headless = common::lavapipe(common::exact_f32());
    let log = headless.validation_log();
    let mut black = Vec::new();
    for path in files {
        let scene = load_file(&path);
        let frame = {
            let renderer = headless.renderer();
            let gpu = renderer.upload(&scene).expect("upload");
            let readback = Readback {
                images: true,
                gbuffer: true,
            };
            renderer
                .render(&gpu, width, height, readback)
                .expect("render")
        };
        let messages = log.messages();
        assert!(
            messages.is_empty(),
            "{}: validation layer reported {} message(s):\n{}",
            path.display(),
            messages.len(),
            messages.join("\n")
        );
        assert_clean(&path, &frame);
        let lit_black = common::black_where_lit(&scene, &frame);
        eprintln!(
            "rendered {}: {} black pixels where the scene is lit",
            path.display(),
            lit_black.len()
        );
        if !lit_black.is_empty() {
            black.push((path, lit_black));
        }
    }
    common::finish(headless);
    let total: usize = black.iter().map(|(_, p)| p.len()).sum();
    assert!(
        black.is_empty(),
        "{total} pixels in {} files exactly black where the f64 reference is not:\n{}",
        black.len(),
        black
            .iter()
            .map(|(path, p)| format!(
                "{}: {} e.g. {:?}",
                path.display(),
                p.len(),
                &p[..p.len().min(4)]
            ))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// The sample models that ship lights render with shadows on (every light casts them,
/// glTF having no flag against it) with no validation message and no NaN, and their
/// frame runs the shadow pass.
#[test]
fn sample_models_with_lights_render_their_shadows() {
    let Some(files) = sample_models() else { return };
    let mut with_lights = 0;
    for path in files {
        // A glTF file's lights are KHR_lights_punctual's: a file that never names the
        // extension has none and is not imported here (its images decoded for nothing).
        let bytes = std::fs::read(&path).unwrap();
        let extension = b"KHR_lights_punctual";
        if !bytes.windows(extension.len()).any(|w| w == extension) {
            continue;
        }
        let scene = SceneSource::File(path.clone())
            .load()
            .unwrap_or_else(|e| panic!("{e}"));
        if scene.lights.is_empty() {
            continue;
        }
        with_lights += 1;
        let frame = common::render(
            &scene,
            96,
            72,
            RendererSettings {
                shading: ShadingOptions {
                    shadows: Some(combustion::renderer::ShadowSettings::DEFAULT),
                    ..ShadingOptions::DEFAULT
                },
                ..common::exact_f32()
            },
            Readback::IMAGES,
        );
        assert!(
            frame.hdr.iter().flatten().all(|c| c.is_finite()),
            "{}: a value is not finite",
            path.display()
        );
        assert!(
            frame.timings.ms("shadow maps").is_some(),
            "{}: no shadow pass",
            path.display()
        );
        eprintln!("rendered {} with shadows", path.display());
    }
    assert!(with_lights >= 1, "no sample model with lights found");
}

#[test]
fn every_authored_scene_renders_cleanly() {
    let dir = workspace().join("assets/scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let folder = entry.unwrap().path();
        let Ok(files) = std::fs::read_dir(&folder) else {
            continue;
        };
        for file in files {
            let path = file.unwrap().path();
            if path.extension().and_then(|e| e.to_str()) == Some("gltf") {
                render_file(&path, 96, 72, Readback::IMAGES);
                count += 1;
            }
        }
    }
    assert!(count >= 2, "authored scenes found: {count}");
}

/// AnisotropyRotationTest: every mesh's anisotropy — given by plain tangents, by tangents
/// tilted 30° and undone by `anisotropyRotation`, by the anisotropy texture, or by both —
/// must end up along the same horizontal direction (the model's README). Checked on the
/// G-buffer: the decoded direction of every anisotropic pixel lies within 10° of the
/// horizontal plane (the model's up axis is +y).
#[test]
fn anisotropy_rotation_model_is_horizontal_everywhere() {
    let Some(files) = sample_models() else { return };
    let path = files
        .iter()
        .find(|p| p.to_string_lossy().ends_with("AnisotropyRotationTest.glb"))
        .expect("AnisotropyRotationTest.glb");
    let frame = render_file(path, 320, 240, Readback::ALL);
    let (mut anisotropic, mut horizontal) = (0usize, 0usize);
    for texel in &frame.gbuffer.unwrap().texels {
        let [nx, ny, _, strength] = texel.normal_roughness_anisotropy;
        if texel.depth >= 1.0 || strength < 0.1 {
            continue; // background, or strength below 0.1
        }
        let n = octahedral_decode([nx, ny]);
        let d = anisotropy_direction_decode(n, texel.material_direction[1]);
        // Horizontal: no component along the model's up axis. The surfaces curve, so
        // the direction may point into the screen; it must not tilt.
        let along_up = d[1].abs();
        anisotropic += 1;
        if along_up < 10f64.to_radians().sin() {
            horizontal += 1;
        }
    }
    eprintln!("{horizontal} of {anisotropic} anisotropic pixels within 10° of horizontal");
    assert!(anisotropic > 2000, "{anisotropic}");
    // Quantisation of the stored angle (0.0014°) and of the normal are far below 10°;
    // texture filtering at the texture-driven meshes' seams may tilt a few pixels.
    assert!(
        horizontal as f64 > 0.98 * anisotropic as f64,
        "{horizontal} of {anisotropic}"
    );
}

/// An emissive surface with no light shows exactly its emitted radiance.
#[test]
fn emissive_plane_shows_its_radiance() {
    let emitted = [0.25f32, 1.5, 4.0];
    let frame = render_emissive_plane(emitted, HdrFormat::Rgba32Float);
    for pixel in &frame.hdr {
        // factor × strength is exact here (a power of two), and nothing else lights it.
        assert_eq!(&pixel[..3], &emitted[..], "{pixel:?} vs {emitted:?}");
    }
}

/// A plane emitting `emitted` (W·sr⁻¹·m⁻², factor × strength 2), no lights, seen from
/// above, rendered at 32×32 into `hdr`.
fn render_emissive_plane(emitted: [f32; 3], hdr: HdrFormat) -> combustion::renderer::Frame {
    let scene = common::plane_from_above(
        "emissive plane",
        Material {
            emissive_factor: [emitted[0] / 2.0, emitted[1] / 2.0, emitted[2] / 2.0],
            emissive_strength: 2.0,
            ..Material::default()
        },
        vec![],
    );
    let settings = RendererSettings {
        hdr_format: hdr,
        ..common::exact_f32()
    };
    common::render_images(&scene, 32, 32, settings)
}

/// Issue 9, "precision": the emissive target has the HDR image's format, so an f32 frame
/// keeps emission above f16's largest value (65504) and below its 11-bit step (1000.1 is
/// not 1000.0); an f16 frame rounds it as its own storage does.
#[test]
fn emission_keeps_the_frames_precision() {
    let emitted = [1000.1f32, 70000.0, 0.3];
    let f32_frame = render_emissive_plane(emitted, HdrFormat::Rgba32Float);
    for pixel in &f32_frame.hdr {
        for c in 0..3 {
            // factor × strength 2 undoes the halving exactly (a power of two)
            assert_eq!(pixel[c], emitted[c], "{pixel:?}");
        }
    }
    let f16_frame = render_emissive_plane(emitted, HdrFormat::Rgba16Float);
    for pixel in &f16_frame.hdr {
        // Vulkan lets a render-target write round to nearest or toward zero (lavapipe
        // truncates: 0.3 → 0.2998), so the bound is one step of 11 bits, 2⁻¹⁰ relative.
        // 1000.1 lies between the f16 neighbours 1000.0 and 1000.5: both roundings give
        // 1000.0; 70000 is beyond f16 (65504 when truncated, +∞ when rounded).
        assert_eq!(pixel[0], 1000.0, "{pixel:?}");
        assert!(pixel[1] >= 65504.0, "{pixel:?}");
        assert!((pixel[2] - 0.3).abs() <= 0.3 * 2f32.powi(-10), "{pixel:?}");
    }
}

/// The per-code table of conductors derived from a base colour reflects, at normal
/// incidence, exactly that base colour (Gulbrandsen's mapping is built to).
#[test]
fn conductor_table_reflects_its_base_colour_at_normal_incidence() {
    let table = conductor_from_base_color_table();
    let mut worst = 0.0f64;
    for (code, &[eta, k]) in table.iter().enumerate() {
        let r = srgb_to_linear(code as f64 / 255.0).min(0.999);
        let f0 = fresnel_conductor(1.0, 1.0, f64::from(eta), f64::from(k)).unpolarised();
        worst = worst.max((f0 - r).abs());
    }
    // The table holds f32 η, k: their rounding moves F0 by a few 1e-7.
    assert!(worst < 2e-6, "worst |F0 − r| = {worst:e}");
}

/// `scene` with every length multiplied by `s`: meshes, placements, camera, lights and
/// their ranges; point and spot intensities × s², so every irradiance, and so every
/// pixel's radiance, stays the same (radiometry has no length scale of its own).
fn scaled_world(scene: &Scene, s: f32) -> Scene {
    use combustion::scene::Light;
    let mut out = scene.clone();
    for object in &mut out.objects {
        object.transform = Mat4::from_scale(Vec3::splat(s)) * object.transform;
    }
    let camera = &mut out.camera;
    camera.position *= s;
    camera.target *= s;
    camera.near *= s;
    camera.far *= s;
    for light in &mut out.lights {
        match light {
            Light::Point {
                position,
                intensity,
                range,
                ..
            }
            | Light::Spot {
                position,
                intensity,
                range,
                ..
            } => {
                *position *= s;
                *intensity = intensity.map(|i| i * s * s);
                *range = range.map(|r| r * s);
            }
            Light::Directional { .. } => {}
        }
    }
    out
}

/// Issue 12, "any scale a file uses": a centimetre export (positions × 1e4 under a node
/// scale of 1e-4) imports as the same 1 m objects and renders as its metre twin, and the
/// whole world scaled to millimetres or to kilometres renders the same image. Identical
/// up to f32 rounding of positions (shading moves by ~1e-7 relative: at most one 8-bit
/// step) and the rasteriser's coverage of silhouette pixels, which the rounding can tip:
/// at most 0.2 % of the pixels may differ by more than one step.
#[test]
fn any_scale_renders_as_its_metre_twin() {
    use combustion::scene::gltf::save_gltf;
    let (width, height) = (192, 128);
    let allowed = (width * height) as usize / 500;
    let metre = combustion::scene::builtin_scene("spheres").unwrap();
    let render = |scene: &Scene| common::render_images(scene, width, height, common::exact_f32());
    let reference = render(&metre);

    // The centimetre export, through the importer.
    let mut centimetre = metre.clone();
    for mesh in &mut centimetre.meshes {
        for v in &mut mesh.vertices {
            v.position = v.position.map(|x| x * 1e4);
        }
    }
    for object in &mut centimetre.objects {
        object.transform *= Mat4::from_scale(Vec3::splat(1e-4));
    }
    let dir = std::env::temp_dir().join(format!("combustion-scale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut imported = Vec::new();
    for (name, scene) in [("metre", &metre), ("centimetre", &centimetre)] {
        let path = dir.join(format!("{name}.gltf"));
        save_gltf(scene, &path).unwrap();
        let loaded = SceneSource::File(path).load().unwrap();
        assert_eq!(
            loaded.objects.len(),
            metre.objects.len(),
            "{name}: every object kept"
        );
        imported.push(render(&loaded));
    }
    std::fs::remove_dir_all(&dir).unwrap();
    let apart = common::pixels_apart(&imported[0], &imported[1]);
    eprintln!("centimetre export against its metre twin: {apart} pixels apart");
    assert!(
        apart <= allowed,
        "{apart} pixels differ by more than one step"
    );

    // The whole world from millimetres to kilometres.
    for s in [1e-3, 1e3, 1e4] {
        let frame = render(&scaled_world(&metre, s));
        let apart = common::pixels_apart(&reference, &frame);
        eprintln!("world × {s}: {apart} pixels apart");
        assert!(
            apart <= allowed,
            "world × {s}: {apart} pixels differ by more than one step"
        );
    }
}

/// Edits of a textured, emissive sample model (LightsPunctualLamp, 6 images) upload
/// only what they add: an untextured material uploads no image, where every image was
/// uploaded again before issue 19's fix — the cost of that, measured here by an edit
/// that gives every texture a new image (an `Arc` of its own), is printed beside it.
/// Timings are printed, not asserted.
#[test]
fn edits_of_a_textured_sample_model_upload_no_image_they_do_not_add() {
    use std::time::Instant;
    let Some(files) = sample_models() else { return };
    let Some(path) = files
        .iter()
        .find(|p| p.to_string_lossy().contains("LightsPunctualLamp"))
    else {
        eprintln!("skipped: LightsPunctualLamp is not among the sample models");
        return;
    };
    let scene = SceneSource::File(path.clone()).load().unwrap();
    let images = scene.texture_table().images.len();
    assert!(images >= 2, "{images} images");
    let mut headless = common::lavapipe(RendererSettings::default());
    let renderer = headless.renderer();
    let mut gpu = renderer.upload(&scene).unwrap();
    let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
    let mut material_ms = Vec::new();
    let mut all_images_ms = Vec::new();
    for _ in 0..3 {
        let t = Instant::now();
        let report = renderer
            .edit_scene(&mut gpu, |s| s.materials.push(Material::default()))
            .unwrap();
        material_ms.push(ms(t));
        assert_eq!(report.images_uploaded, 0, "{report:?}");
        assert!(report.textures, "the texture sets follow the materials");
        let t = Instant::now();
        let report = renderer
            .edit_scene(&mut gpu, |s| {
                for m in &mut s.materials {
                    for t in [
                        &mut m.base_color_texture,
                        &mut m.metallic_roughness_texture,
                        &mut m.normal_texture,
                        &mut m.occlusion_texture,
                        &mut m.emissive_texture,
                        &mut m.anisotropy_texture,
                        &mut m.specular_texture,
                        &mut m.specular_color_texture,
                    ]
                    .into_iter()
                    .flatten()
                    {
                        // A new image (one texel changed, so it is not the same image).
                        let mut image = (*t.texture.image).clone();
                        image.pixels[0] ^= 1;
                        t.texture.image = std::sync::Arc::new(image);
                    }
                }
            })
            .unwrap();
        all_images_ms.push(ms(t));
        assert!(report.images_uploaded >= images, "{report:?}");
    }
    eprintln!(
        "LightsPunctualLamp ({images} images): adding an untextured material {:.1?} ms; an edit uploading every image again {:.1?} ms",
        material_ms, all_images_ms
    );
    renderer.render(&gpu, 64, 48, Readback::default()).unwrap();
    drop(gpu);
    common::finish(headless);
}

/// KHR_materials_unlit (the Khronos UnlitTest): every pixel of the unlit boxes is its
/// base colour, as the renderer's own f64 mirror of the lighting pass says from the
/// G-buffer (`ReferenceShading::shade`), whatever lights the frame.
#[test]
fn unlit_materials_show_their_base_colour() {
    use combustion::renderer::reference::{error_map, ReferenceShading};
    let Some(files) = sample_models() else { return };
    let path = files
        .iter()
        .find(|p| p.to_string_lossy().ends_with("UnlitTest.glb"))
        .expect("UnlitTest.glb");
    let mut scene = SceneSource::File(path.clone()).load().unwrap();
    assert_eq!(scene.features().unlit, 2, "{}", scene.features());
    // A light that would change every lit pixel.
    scene.environment = None;
    scene.lights.push(combustion::scene::Light::Directional {
        direction: Vec3::new(0.3, -1.0, -0.4).normalize(),
        irradiance: [5.0; 3],
        casts_shadows: false,
        angular_diameter: 0.0,
    });
    let (w, h) = (128, 96);
    let frame = common::render(&scene, w, h, common::exact_f32(), Readback::ALL);
    let inputs = common::frame_inputs(&scene, &scene.lights);
    let reference = ReferenceShading::new(&scene, &inputs, w, h);
    let map = error_map(&frame, &reference, 2);
    eprintln!(
        "UnlitTest: {} pixels, error mean {:.2e}, max {:.2e}",
        map.lit_pixels, map.mean_relative, map.max_relative
    );
    assert!(map.lit_pixels > 2000, "{}", map.lit_pixels);
    // The parity tests' f32 shading bound (the radiance is the stored base colour).
    assert!(map.max_relative < 1e-3, "max {:e}", map.max_relative);
}

/// SpecularTest (KHR_materials_specular) renders as its screenshot shows: its spheres,
/// black plastics of roughness 0 under the studio, differ by their specular factor and
/// colour. Per sphere (its pixels found by material in the G-buffer), the mean
/// radiance: factor 0 is exactly black (no specular lobe, a black diffuse); each row
/// brightens with its factor or colour (a colour of 0 keeps the grazing reflection, the
/// extension's f90 = factor); the yellow colours reflect more red and green than the
/// colour 0, and blue only at grazing as it does; colours above 1 brighten beyond the
/// plain plastic. Before the extension
/// was shaded every sphere was the plain plastic (factor 1, colour 1).
#[test]
fn specular_test_spheres_differ_as_its_screenshot_shows() {
    let Some(root) = common::shared_gltf_samples() else {
        return;
    };
    let scene = load_file(&root.join("SpecularTest/glTF/SpecularTest.gltf"));
    let mut headless = common::lavapipe(common::exact_f32());
    let frame = {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).expect("upload");
        let readback = Readback {
            images: true,
            gbuffer: true,
        };
        renderer.render(&gpu, 384, 288, readback).expect("render")
    };
    common::finish(headless);
    let gbuffer = frame.gbuffer.as_ref().expect("read back");
    let mean = |name: &str| -> [f64; 3] {
        let index = scene
            .materials
            .iter()
            .position(|m| m.name == name)
            .unwrap_or_else(|| panic!("SpecularTest has no {name}"));
        let pixels: Vec<[f32; 4]> = frame
            .hdr
            .iter()
            .zip(&gbuffer.texels)
            .filter(|(_, t)| t.depth < 1.0 && usize::from(t.material_direction[0]) == index)
            .map(|(hdr, _)| *hdr)
            .collect();
        assert!(pixels.len() > 50, "{name}: {} pixels", pixels.len());
        std::array::from_fn(|c| {
            pixels.iter().map(|p| f64::from(p[c])).sum::<f64>() / pixels.len() as f64
        })
    };
    let luminance = |m: [f64; 3]| 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2];
    assert_eq!(mean("M1.1_specFac"), [0.0; 3], "factor 0 reflects nothing");
    for row in [
        [
            "M1.1_specFac",
            "M1.2_specFac",
            "M1.3_specFac",
            "M1.4_specFac",
            "M1.5_specFac",
        ],
        [
            "M3.1_whiteFac",
            "M3.2_whiteFac",
            "M3.3_whiteFac",
            "M3.4_whiteFac",
            "M3.5_whiteFac",
        ],
        [
            "M5.1_yellowFac",
            "M5.2_yellowFac",
            "M5.3_yellowFac",
            "M5.4_yellowFac",
            "M5.5_yellowFac",
        ],
        ["M7.1_HDR", "M7.2_HDR", "M7.3_HDR", "M7.4_HDR", "M7.5_HDR"],
    ] {
        let means: Vec<f64> = row.iter().map(|name| luminance(mean(name))).collect();
        eprintln!("{row:?}: mean luminance {means:?}");
        assert!(
            means.windows(2).all(|w| w[0] < w[1]),
            "{row:?} does not brighten along the row: {means:?}"
        );
    }
    assert!(luminance(mean("M3.1_whiteFac")) > 0.0, "colour 0 keeps f90");
    let plain = luminance(mean("M3.5_whiteFac"));
    assert!(
        luminance(mean("M7.3_HDR")) > 2.0 * plain,
        "colour 5.4 against 1"
    );
    // Yellow: red and green rise along the row from the colour-0 sphere, blue stays at
    // its grazing reflection; white: blue rises as well.
    let (yellow_0, yellow_1) = (mean("M5.1_yellowFac"), mean("M5.5_yellowFac"));
    let (white_0, white_1) = (mean("M3.1_whiteFac"), mean("M3.5_whiteFac"));
    eprintln!("yellow {yellow_0:?} to {yellow_1:?}, white {white_0:?} to {white_1:?}");
    assert!(yellow_1[0] > 1.5 * yellow_0[0] && yellow_1[1] > 1.5 * yellow_0[1]);
    assert!(yellow_1[2] < 1.2 * yellow_0[2], "yellow reflects blue");
    assert!(white_1[2] > 1.5 * white_0[2], "white does not reflect blue");
}
