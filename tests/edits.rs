//! Scenes edited between frames (`Renderer::edit_scene`) without uploading them again:
//! only what an edit touches is rebuilt, frames in flight keep reading what they were
//! recorded with, and the edited scene renders exactly as a fresh upload of the same
//! scene does. Also: the pipeline cache survives a save and a load.

use crate::common;

use combustion::renderer::{Frame, Readback, Renderer, RendererSettings};
use combustion::scene::{builtin_scene, Light, Scene};
use glam::{Mat4, Vec3};

const W: u32 = 96;
const H: u32 = 64;
const IMAGES: Readback = Readback::IMAGES;

fn fresh(renderer: &mut Renderer, scene: &Scene) -> Frame {
    let gpu = renderer.upload(scene).unwrap();
    renderer.render(&gpu, W, H, IMAGES).unwrap()
}

fn assert_same(a: &Frame, b: &Frame, what: &str) {
    assert_eq!(a.ldr, b.ldr, "{what}: display images differ");
    let bits = |f: &Frame| {
        f.hdr
            .iter()
            .flat_map(|p| p.map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert!(bits(a) == bits(b), "{what}: HDR images differ");
}

/// Moves, recolours, removes and adds objects and lights between frames in flight; the
/// result is the same as uploading the edited scene.
#[test]
fn edits_between_frames_render_as_a_fresh_upload() {
    let mut headless = common::lavapipe(RendererSettings::default());
    let renderer = headless.renderer();
    let original = builtin_scene("spheres").unwrap();
    let mut gpu = renderer.upload(&original).unwrap();
    let before = renderer.render(&gpu, W, H, IMAGES).unwrap();
    // Frames in flight while the scene is edited: they must keep their own buffers.
    renderer.submit_offscreen(&gpu, W, H).unwrap();
    renderer.submit_offscreen(&gpu, W, H).unwrap();
    let pipelines = renderer.stats().pipelines_built;
    let report = renderer
        .edit_scene(&mut gpu, |scene| {
            scene.objects[0].transform =
                Mat4::from_translation(Vec3::new(0.2, 0.1, 0.0)) * scene.objects[0].transform;
            scene.materials[0].base_color = [0.1, 0.8, 0.2];
            scene.objects.pop();
            let mut copy = scene.objects[1].clone();
            copy.transform = Mat4::from_translation(Vec3::new(0.0, 0.0, 0.5)) * copy.transform;
            scene.objects.push(copy);
            scene.lights.push(Light::Point {
                position: Vec3::new(0.0, 2.0, 4.0),
                intensity: [3.0, 3.0, 3.0],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            });
        })
        .unwrap();
    assert!(
        report.tables && !report.geometry && !report.textures,
        "{report:?}"
    );
    assert_eq!(report.pipelines_built, 0);
    assert_eq!(renderer.stats().pipelines_built, pipelines);
    renderer.submit_offscreen(&gpu, W, H).unwrap();
    let edited_frame = renderer.render(&gpu, W, H, IMAGES).unwrap();
    let edited_scene = gpu.scene().clone();
    assert_ne!(edited_frame.ldr, before.ldr, "the edit shows");
    let reference = fresh(renderer, &edited_scene);
    assert_same(&edited_frame, &reference, "edited vs fresh upload");
    drop(gpu);
    common::finish(headless);
}

/// An edit that needs a shader feature the renderer has not built (an emissive
/// material) builds that variant's pipelines during the edit, never in a frame; an edit
/// of a mesh rebuilds the geometry; an invalid edit changes nothing.
#[test]
fn edits_build_only_what_they_need_and_invalid_edits_change_nothing() {
    let mut headless = common::lavapipe(RendererSettings::default());
    let renderer = headless.renderer();
    let mut gpu = renderer.upload(&builtin_scene("spheres").unwrap()).unwrap();
    let before = renderer.render(&gpu, W, H, IMAGES).unwrap();

    let error = renderer
        .edit_scene(&mut gpu, |scene| scene.objects[0].material = 10_000)
        .unwrap_err();
    assert!(error.to_string().contains("material"), "{error}");
    let after_error = renderer.render(&gpu, W, H, IMAGES).unwrap();
    assert_same(&before, &after_error, "after a refused edit");

    let report = renderer
        .edit_scene(&mut gpu, |scene| {
            scene.materials[0].emissive_factor = [1.0, 0.5, 0.25];
            scene.materials[0].emissive_strength = 2.0;
        })
        .unwrap();
    assert_eq!(
        report.pipelines_built, 3,
        "G-buffer and lighting of the emissive variant, and its lighting with the output folded in (into the display format)"
    );
    let emissive = renderer.render(&gpu, W, H, IMAGES).unwrap();
    let reference = fresh(renderer, &gpu.scene().clone());
    assert_same(&emissive, &reference, "emissive edit vs fresh upload");

    let report = renderer
        .edit_scene(&mut gpu, |scene| {
            for v in &mut scene.meshes[0].vertices {
                v.position = (Vec3::from(v.position) * 0.8).into();
            }
        })
        .unwrap();
    assert!(report.geometry && !report.textures, "{report:?}");
    let shrunk = renderer.render(&gpu, W, H, IMAGES).unwrap();
    let reference = fresh(renderer, &gpu.scene().clone());
    assert_same(&shrunk, &reference, "mesh edit vs fresh upload");
    drop(gpu);
    common::finish(headless);
}

/// The pipeline cache's contents can be saved and given to a new renderer; data from
/// elsewhere (here: garbage) is ignored rather than trusted.
#[test]
fn pipeline_cache_saves_and_loads() {
    let mut headless = common::lavapipe(RendererSettings::default());
    let device = headless.renderer().device().clone();
    let data = headless.renderer().pipeline_cache_data().unwrap();
    assert!(!data.is_empty());
    let scene = builtin_scene("spheres").unwrap();
    let expected = {
        let r = headless.renderer();
        let gpu = r.upload(&scene).unwrap();
        r.render(&gpu, W, H, IMAGES).unwrap()
    };
    for initial in [data.clone(), vec![0xAB; 64]] {
        let mut renderer =
            Renderer::with_pipeline_cache(device.clone(), RendererSettings::default(), &initial)
                .unwrap();
        let gpu = renderer.upload(&scene).unwrap();
        let frame = renderer.render(&gpu, W, H, IMAGES).unwrap();
        assert_same(&frame, &expected, "renderer with a loaded cache");
    }
    drop(device);
    common::finish(headless);
}

/// A scene whose first material samples a 32×32 base-colour image.
fn textured_spheres() -> Scene {
    use combustion::scene::{ColorSpace, Image, Sampler, Texture, TextureRef, UvTransform};
    let mut scene = builtin_scene("spheres").unwrap();
    let pixels = (0..32 * 32)
        .flat_map(|i| [(i % 32 * 8) as u8, (i / 32 * 8) as u8, 128, 255])
        .collect();
    scene.materials[0].base_color_texture = Some(TextureRef {
        texture: Texture {
            image: std::sync::Arc::new(Image {
                name: "gradient".into(),
                width: 32,
                height: 32,
                color_space: ColorSpace::Srgb,
                pixels,
            }),
            sampler: Sampler::default(),
        },
        tex_coord: 0,
        transform: UvTransform::default(),
    });
    scene
}

/// Issue 19, defect 6: edits upload only the items they add or change — an untextured
/// material added to a textured scene uploads no image (every texture was uploaded
/// again before), a mesh added uploads that mesh alone (all geometry before) — and the
/// report says exactly that; an edit of a scene without an environment reports no
/// environment bake (it said `true` before). Items are named by stable handles: an
/// object removed before another leaves the other's handle naming it, and an edit is
/// undone by handle. Each edited frame equals a fresh upload of the same scene.
#[test]
fn edits_upload_only_what_they_add_and_handles_stay_stable() {
    use combustion::renderer::{EditError, RenderError};
    use combustion::scene::Material;
    let mut headless = common::lavapipe(RendererSettings::default());
    let renderer = headless.renderer();
    let original = textured_spheres();
    let mut gpu = renderer.upload(&original).unwrap();
    let objects = gpu.object_ids().to_vec();
    assert_eq!(objects.len(), original.objects.len());

    // An untextured material, and an object using it with a mesh of its own.
    let started = std::time::Instant::now();
    let (added_material, report) = renderer
        .try_edit_scene(&mut gpu, |e| {
            Ok(e.add_material(Material {
                base_color: [0.9, 0.1, 0.1],
                ..Material::default()
            }))
        })
        .unwrap();
    eprintln!(
        "adding an untextured material: {:.1} ms, {report:?}",
        started.elapsed().as_secs_f64() * 1e3
    );
    assert_eq!(report.images_uploaded, 0, "{report:?}");
    assert!(
        !report.environment && report.meshes_uploaded == 0,
        "{report:?}"
    );
    let started = std::time::Instant::now();
    let ((added_mesh, added_object), report) = renderer
        .try_edit_scene(&mut gpu, |e| {
            let mesh = e.add_mesh(combustion::scene::Mesh::plane("floor", 3.0));
            let object = e.add_object(
                mesh,
                added_material,
                Mat4::from_translation(Vec3::new(0.0, -1.2, 0.0)),
            )?;
            Ok((mesh, object))
        })
        .unwrap();
    eprintln!(
        "adding a mesh and an object: {:.1} ms, {report:?}",
        started.elapsed().as_secs_f64() * 1e3
    );
    assert!(report.geometry && report.meshes_uploaded == 1, "{report:?}");
    assert!(
        !report.textures && report.images_uploaded == 0,
        "{report:?}"
    );
    let frame = renderer.render(&gpu, W, H, IMAGES).unwrap();
    let reference = fresh(renderer, &gpu.scene().clone());
    assert_same(
        &frame,
        &reference,
        "added mesh, material and object vs fresh upload",
    );

    // Removing the first object shifts every index; the handles still name the same
    // objects (the last original object keeps its transform under its handle).
    let last = *objects.last().unwrap();
    let last_transform = original.objects.last().unwrap().transform;
    let ((removed_mesh, removed_material, removed_transform), _) = renderer
        .try_edit_scene(&mut gpu, |e| e.remove_object(objects[0]))
        .unwrap();
    let index = gpu.object_ids().iter().position(|&id| id == last).unwrap();
    assert_eq!(index, original.objects.len() - 2);
    assert_eq!(gpu.scene().objects[index].transform, last_transform);
    // A material in use is refused, and the scene stays as it was.
    let before = gpu.scene().objects.len();
    let error = renderer
        .try_edit_scene(&mut gpu, |e| e.remove_material(added_material).map(|_| ()))
        .unwrap_err();
    assert!(
        matches!(
            error,
            RenderError::Edit(EditError::MaterialInUse { objects: 1, .. })
        ),
        "{error}"
    );
    assert_eq!(gpu.scene().objects.len(), before);
    // Undo every edit by handle: the first object back (at the end of the list: the
    // same image), the added object, material and mesh removed.
    let original_frame = fresh(renderer, &original);
    let (_, report) = renderer
        .try_edit_scene(&mut gpu, |e| {
            e.remove_object(added_object)?;
            e.remove_material(added_material)?;
            e.remove_mesh(added_mesh)?;
            e.add_object(removed_mesh, removed_material, removed_transform)
        })
        .unwrap();
    assert_eq!(report.meshes_uploaded, 0, "{report:?}");
    assert_eq!(gpu.scene().objects.len(), original.objects.len());
    assert_eq!(gpu.scene().materials.len(), original.materials.len());
    assert_eq!(gpu.scene().meshes.len(), original.meshes.len());
    let undone = renderer.render(&gpu, W, H, IMAGES).unwrap();
    assert_same(
        &undone,
        &original_frame,
        "every edit undone vs the original",
    );
    // A handle of a removed item is refused.
    let error = renderer
        .try_edit_scene(&mut gpu, |e| e.set_transform(added_object, Mat4::IDENTITY))
        .unwrap_err();
    assert!(
        matches!(error, RenderError::Edit(EditError::UnknownObject(_))),
        "{error}"
    );
    drop(gpu);
    common::finish(headless);
}
