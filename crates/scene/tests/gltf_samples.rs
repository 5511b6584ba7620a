//! The Khronos glTF sample models in `../shared/data/gltf` (beside the workspace; not part
//! of the repository) must import. Skipped, with a note, when the folder is absent —
//! unless `COMBUSTION_REQUIRE_SHARED` is set (CI sets it), which makes its absence a
//! failure.

use std::path::{Path, PathBuf};

use combustion_scene::gltf::{import, CameraSource, ImportOptions};
use combustion_scene::{Scene, TextureSlot};

#[path = "../../../tests/common/shared_data.rs"]
mod shared_data;

fn samples() -> Option<PathBuf> {
    shared_data::shared_gltf_samples()
}

fn load(dir: &Path, relative: &str) -> Scene {
    let path = dir.join(relative);
    let (scene, report) =
        import(&path, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("{report}\n{}", scene.features());
    scene.validate().unwrap();
    assert!(!scene.objects.is_empty(), "{relative}: no objects");
    scene
}

/// What tests/sample-models.txt says of `model`: `Some(None)` imports, `Some(Some(ext))`
/// is refused for requiring `ext`, `None` is not listed.
fn expected_outcome(model: &str) -> Option<Option<String>> {
    let list = include_str!("../../../tests/sample-models.txt");
    list.lines()
        .filter(|l| !l.starts_with('#'))
        .find_map(
            |line| match line.split_whitespace().collect::<Vec<_>>()[..] {
                [name, "imports"] if name == model => Some(None),
                [name, "refused", extension] if name == model => Some(Some(extension.to_owned())),
                _ => None,
            },
        )
}

/// Every .gltf and .glb in the folder imports, or is refused with the required
/// extension tests/sample-models.txt names for it.
#[test]
fn every_sample_model_imports_or_is_refused_as_listed() {
    let Some(dir) = samples() else { return };
    let mut count = 0;
    for model in std::fs::read_dir(&dir).unwrap() {
        let model = model.unwrap().path();
        let name = model.file_name().unwrap().to_string_lossy().into_owned();
        for variant in ["glTF", "glTF-Binary", "glTF-Embedded"] {
            let Ok(entries) = std::fs::read_dir(model.join(variant)) else {
                continue;
            };
            for entry in entries {
                let path = entry.unwrap().path();
                let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
                if ext != "gltf" && ext != "glb" {
                    continue;
                }
                let relative = path
                    .strip_prefix(&dir)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                match expected_outcome(&name) {
                    None => panic!("{relative}: {name} has no line in tests/sample-models.txt"),
                    Some(None) => {
                        load(&dir, &relative);
                    }
                    Some(Some(extension)) => {
                        let error = import(&path, &ImportOptions::default())
                            .map(|_| ())
                            .expect_err(&format!(
                                "{relative} imported; the list says it is refused"
                            ));
                        let text = error.to_string();
                        assert!(
                            text.contains(&format!("requires the extension `{extension}`")),
                            "{relative}: {text}"
                        );
                    }
                }
                count += 1;
            }
        }
    }
    assert!(count >= 10, "only {count} sample files found");
}

/// The framing camera of a file without one sees the whole scene as drawn at rest: every
/// vertex of every deformed model's posed meshes (skins by their rest joints, morphs at
/// their default weights) projects inside the image, for the deformed sample models that
/// have no camera of their own. Framed by their undeformed vertices, SimpleMorph's
/// morphed tip fell outside the image.
#[test]
fn framing_cameras_see_deformed_models_as_drawn() {
    let Some(dir) = samples() else { return };
    let mut checked = Vec::new();
    for relative in [
        "SimpleMorph/glTF/SimpleMorph.gltf",
        "SimpleSkin/glTF/SimpleSkin.gltf",
        "RiggedSimple/glTF-Binary/RiggedSimple.glb",
        "RiggedFigure/glTF-Binary/RiggedFigure.glb",
        "CesiumMan/glTF-Binary/CesiumMan.glb",
        "AnimatedMorphCube/glTF-Binary/AnimatedMorphCube.glb",
        "MorphPrimitivesTest/glTF-Binary/MorphPrimitivesTest.glb",
    ] {
        let (scene, report) = import(&dir.join(relative), &ImportOptions::default()).unwrap();
        if report.camera != CameraSource::Framing {
            continue;
        }
        let drawn = scene.as_drawn(None);
        let view_projection = scene.camera.view_projection(1.0);
        let mut outside = 0;
        let mut total = 0;
        for object in &drawn.objects {
            for v in &drawn.meshes[object.mesh].vertices {
                let world = object
                    .transform
                    .transform_point3(glam::Vec3::from(v.position));
                let clip = view_projection * world.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                total += 1;
                if !(clip.w > 0.0 && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0) {
                    outside += 1;
                }
            }
        }
        assert_eq!(
            outside, 0,
            "{relative}: {outside} of {total} vertices outside the view"
        );
        checked.push(relative);
    }
    assert!(checked.len() >= 3, "{checked:?}");
}

/// The three forms of BoxTextured give the same scene (apart from the name).
#[test]
fn box_textured_forms_agree() {
    let Some(dir) = samples() else { return };
    let gltf = load(&dir, "BoxTextured/glTF/BoxTextured.gltf");
    let glb = load(&dir, "BoxTextured/glTF-Binary/BoxTextured.glb");
    let embedded = load(&dir, "BoxTextured/glTF-Embedded/BoxTextured.gltf");
    for other in [&glb, &embedded] {
        assert_eq!(gltf.meshes, other.meshes);
        assert_eq!(gltf.objects, other.objects);
        assert_eq!(gltf.materials.len(), other.materials.len());
        let (a, b) = (&gltf.materials[0], &other.materials[0]);
        let (ta, tb) = (
            a.base_color_texture.as_ref().unwrap(),
            b.base_color_texture.as_ref().unwrap(),
        );
        assert_eq!(ta.texture.image.pixels, tb.texture.image.pixels);
        assert_eq!(ta.texture.sampler, tb.texture.sampler);
    }
    let features = gltf.features();
    assert_eq!(features.texture_count(TextureSlot::BaseColor), 1);
}

fn load_with_report(dir: &Path, relative: &str) -> (Scene, combustion_scene::gltf::ImportReport) {
    import(&dir.join(relative), &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// KHR_materials_anisotropy is read from the raw extension JSON: strength, rotation and
/// texture, in both forms of the file.
#[test]
fn anisotropy_rotation_test_has_its_anisotropy() {
    let Some(dir) = samples() else { return };
    for relative in [
        "AnisotropyRotationTest/glTF/AnisotropyRotationTest.gltf",
        "AnisotropyRotationTest/glTF-Binary/AnisotropyRotationTest.glb",
    ] {
        let (scene, report) = load_with_report(&dir, relative);
        assert!(report
            .extensions_used
            .contains(&"KHR_materials_anisotropy".to_owned()));
        assert!(
            report.extensions_ignored.is_empty(),
            "{:?}",
            report.extensions_ignored
        );
        let find = |name: &str| {
            scene
                .materials
                .iter()
                .find(|m| m.name == name)
                .unwrap_or_else(|| panic!("{relative}: no material `{name}`"))
        };
        let plain = find("Aniso Tangents");
        assert_eq!(
            (plain.anisotropy_strength, plain.anisotropy_rotation),
            (0.5, 0.0)
        );
        assert!(plain.anisotropy_texture.is_none());
        let rotated = find("Aniso Tan + Rotation");
        assert_eq!(rotated.anisotropy_strength, 0.5);
        assert!((rotated.anisotropy_rotation - std::f32::consts::FRAC_PI_6).abs() < 1e-6);
        let textured = find("Aniso Tan + Texture");
        let texture = textured
            .anisotropy_texture
            .as_ref()
            .expect("anisotropy texture");
        assert_eq!(
            texture.texture.image.color_space,
            combustion_scene::ColorSpace::Linear
        );
        let both = find("Aniso Tan + Rotation + Texture");
        assert!((both.anisotropy_rotation - 0.349_065_85).abs() < 1e-6);
        assert!(both.anisotropy_texture.is_some());
        assert!(scene.features().anisotropic >= 4);
        assert_eq!(report.camera, CameraSource::Framing);
    }
}

/// AnisotropyStrengthTest: strengths 0 … 1 in sixths on 49 spheres sharing one set of
/// accessors (so one mesh); the label has no TANGENT and no anisotropy, so it gets the
/// reference frame of its normals rather than MikkTSpace.
#[test]
fn anisotropy_strength_test_has_its_strengths() {
    let Some(dir) = samples() else { return };
    for relative in [
        "AnisotropyStrengthTest/glTF/AnisotropyStrengthTest.gltf",
        "AnisotropyStrengthTest/glTF-Binary/AnisotropyStrengthTest.glb",
    ] {
        let (scene, report) = load_with_report(&dir, relative);
        let mut strengths: Vec<f32> = scene
            .materials
            .iter()
            .map(|m| m.anisotropy_strength)
            .collect();
        strengths.sort_by(f32::total_cmp);
        strengths.dedup();
        assert_eq!(strengths.len(), 7, "{strengths:?}");
        assert_eq!((strengths[0], strengths[6]), (0.0, 1.0));
        assert_eq!(
            (scene.meshes.len(), report.generated_tangents),
            (2, 0),
            "{report}"
        );
        for mesh in &scene.meshes {
            for v in &mesh.vertices {
                let t = glam::Vec3::from_slice(&v.tangent[..3]);
                assert!(
                    (t.length() - 1.0).abs() < 1e-3,
                    "{}: tangent {:?}",
                    mesh.name,
                    v.tangent
                );
                assert!(v.tangent[3] == 1.0 || v.tangent[3] == -1.0);
            }
        }
    }
}

/// KHR_materials_specular factors, colours (also above 1) and textures are stored, and
/// imported without a warning (they are shaded).
#[test]
fn specular_test_has_its_specular() {
    let Some(dir) = samples() else { return };
    let (scene, report) = load_with_report(&dir, "SpecularTest/glTF/SpecularTest.gltf");
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert!(scene.materials.iter().any(|m| m.has_specular()));
    let find = |name: &str| scene.materials.iter().find(|m| m.name == name).unwrap();
    assert_eq!(find("M1.1_specFac").specular_factor, 0.0);
    assert_eq!(find("M1.3_specFac").specular_factor, 0.212231);
    assert!(find("M2_SpecTex").specular_texture.is_some());
    assert_eq!(
        find("M5.4_yellowFac").specular_color_factor,
        [0.520996, 0.520996, 0.0]
    );
    assert_eq!(find("M7.5_HDR").specular_color_factor, [25.0; 3]);
    let colour = find("M6_yellowTex")
        .specular_color_texture
        .as_ref()
        .unwrap();
    assert_eq!(
        colour.texture.image.color_space,
        combustion_scene::ColorSpace::Srgb
    );
    assert!(scene.features().specular >= 20);
}

/// Metals without textures: each metal's conductor is derived from its base colour.
#[test]
fn metal_rough_spheres_are_base_colour_conductors() {
    let Some(dir) = samples() else { return };
    let (scene, report) = load_with_report(
        &dir,
        "MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf",
    );
    let features = scene.features();
    assert!(features.conductors_from_base_color > 50, "{features}");
    assert_eq!(features.conductors, 0);
    for m in scene.materials.iter().filter(|m| m.metalness > 0.0) {
        assert!(m.conductor_from_base_color);
        let expected = combustion_scene::conductor_from_reflectivity(m.base_color);
        assert_eq!(m.conductor, expected);
    }
    assert!(report.objects >= 98, "{report}");
}

/// MeshPrimitiveModes: one mesh per glTF mode, each on the same seven vertices (a hexagon
/// and its centre). Points and lines are kept with their topology — a line loop closed,
/// a strip joined — and drawn with an unlit copy of their material; the triangle modes
/// become triangle lists.
#[test]
fn mesh_primitive_modes_keep_their_points_and_lines() {
    use combustion_scene::Topology;
    let Some(dir) = samples() else { return };
    let (scene, report) = load_with_report(&dir, "MeshPrimitiveModes/glTF/MeshPrimitiveModes.gltf");
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let shapes: Vec<(Topology, usize)> = scene
        .meshes
        .iter()
        .map(|m| (m.topology, m.primitive_count()))
        .collect();
    assert_eq!(
        shapes,
        [
            (Topology::Points, 7),    // indices 0–6
            (Topology::Lines, 6),     // 0-1, 0-2, …, 0-6
            (Topology::Lines, 7),     // the loop 0-1, …, 5-6 and 6-0
            (Topology::Lines, 6),     // the strip 0-1, …, 5-6
            (Topology::Triangles, 6), // the hexagon as a list
            (Topology::Triangles, 4), // a strip of 6 indices
            (Topology::Triangles, 6), // a fan of 8 indices
        ]
    );
    assert_eq!(scene.meshes[0].indices, [0, 1, 2, 3, 4, 5, 6]);
    assert_eq!(
        scene.meshes[2].indices,
        [0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 0]
    );
    assert_eq!(
        scene.meshes[3].indices,
        [0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6]
    );
    // The strokes keep the file's seven vertices as they are.
    for mesh in &scene.meshes[..4] {
        assert_eq!(mesh.vertices.len(), 7, "{}", mesh.name);
        assert_eq!(mesh.vertices, scene.meshes[0].vertices);
    }
    // No materials in the file: the triangles use glTF's default material, the points
    // and lines its unlit copy (white).
    assert_eq!(scene.materials.len(), 2);
    for object in &scene.objects {
        let strokes = scene.meshes[object.mesh].topology != Topology::Triangles;
        let material = &scene.materials[object.material];
        assert_eq!(material.unlit, strokes, "{}", material.name);
        assert_eq!(material.base_color, [1.0; 3]);
    }
    assert_eq!(report.triangles, 16);
}
