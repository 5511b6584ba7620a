//! Temporal anti-aliasing (`temporal-anti-aliasing`) on lavapipe with validation, in
//! motion: along a camera path, each frame against a 16×16-supersampled frame of the same
//! instant (box-filtered radiance through the same output transform), by mean FLIP,
//! beside FXAA and none; and on a still camera, its frames converge.

use crate::common;

use combustion::renderer::{AntiAliasing, Frame, FrameInputs, Readback, ToneMapping};
use combustion::scene::{builtin_scene, Camera, ObjectPoses, Scene};

const IMAGES: Readback = Readback::IMAGES;

/// How a sequence is smoothed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    None,
    Fxaa,
    Taa,
}

/// The camera of frame `i` of a path orbiting `scene`'s target by 0.4° a frame (a slow
/// pan: 12°/s at 30 frames a second).
fn orbit(scene: &Scene, i: usize) -> Camera {
    let camera = scene.camera;
    let offset = camera.position - camera.target;
    let angle = (0.4 * i as f32).to_radians();
    let rotation = glam::Quat::from_rotation_y(angle);
    Camera {
        position: camera.target + rotation * offset,
        ..camera
    }
}

/// The camera and pose of each instant of a sequence.
type Instants = Vec<(Camera, Option<ObjectPoses>)>;

/// Frames of `scene` at `instants` at `size`, smoothed by `method` (one renderer, frame
/// after frame, so temporal anti-aliasing keeps its history).
fn sequence(
    scene: &Scene,
    instants: &[(Camera, Option<ObjectPoses>)],
    size: (u32, u32),
    method: Method,
) -> Vec<Frame> {
    let mut settings = common::exact_f32();
    if method == Method::Taa {
        let taa = combustion::renderer::optional_pass("temporal-anti-aliasing").unwrap();
        settings.shading.optional_passes = settings.shading.optional_passes.with(taa, true);
    }
    let mut headless = common::lavapipe(settings);
    let mut frames = Vec::new();
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(scene).unwrap();
        for (camera, pose) in instants {
            let inputs = FrameInputs {
                camera: *camera,
                pose: pose.as_ref(),
                anti_aliasing: if method == Method::Fxaa {
                    AntiAliasing::Fxaa
                } else {
                    AntiAliasing::None
                },
                ..FrameInputs::of_scene(&gpu, 1.0)
            };
            frames.push(
                renderer
                    .render_with(&gpu, &inputs, size.0, size.1, IMAGES)
                    .unwrap(),
            );
        }
    }
    common::finish(headless);
    frames
}

/// Each instant's 16×16-supersampled radiance: rendered 16 times as wide and high from
/// the same camera in the same pose, box-filtered per pixel.
fn reference(
    scene: &Scene,
    instants: &[(Camera, Option<ObjectPoses>)],
    size: (u32, u32),
) -> Vec<Vec<[f32; 3]>> {
    const F: u32 = 16;
    let mut headless = common::lavapipe(common::exact_f32());
    let mut out = Vec::new();
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(scene).unwrap();
        for (camera, pose) in instants {
            let inputs = FrameInputs {
                camera: *camera,
                pose: pose.as_ref(),
                ..FrameInputs::of_scene(&gpu, 1.0)
            };
            let large = renderer
                .render_with(&gpu, &inputs, size.0 * F, size.1 * F, IMAGES)
                .unwrap();
            let (w, f) = (size.0 as usize, F as usize);
            let mut radiance = Vec::with_capacity((size.0 * size.1) as usize);
            for y in 0..size.1 as usize {
                for x in 0..w {
                    let mut sum = [0.0f64; 3];
                    for sy in 0..f {
                        for sx in 0..f {
                            let p = large.hdr[(y * f + sy) * w * f + x * f + sx];
                            for c in 0..3 {
                                sum[c] += f64::from(p[c]);
                            }
                        }
                    }
                    radiance.push(sum.map(|s| (s / (f * f) as f64) as f32));
                }
            }
            out.push(radiance);
        }
    }
    common::finish(headless);
    out
}

/// The mean FLIP of frames `measured` of `scene` at `instants` against their
/// 16×16-supersampled references, for none, FXAA and temporal anti-aliasing.
fn mean_flips(
    what: &str,
    scene: &Scene,
    instants: &Instants,
    measured: std::ops::Range<usize>,
    size: (u32, u32),
) -> [f64; 3] {
    let references = reference(scene, &instants[measured.clone()], size);
    [Method::None, Method::Fxaa, Method::Taa].map(|method| {
        let frames = sequence(scene, instants, size, method);
        let flips: Vec<f64> = measured
            .clone()
            .zip(&references)
            .map(|(i, radiance)| {
                combustion::report::flip_against_radiance(
                    &frames[i],
                    radiance,
                    1.0,
                    ToneMapping::Exponential,
                )
            })
            .collect();
        let mean = flips.iter().sum::<f64>() / flips.len() as f64;
        eprintln!("{what}, {method:?}: mean FLIP {mean:.5} (frames {measured:?}: {flips:.4?})");
        mean
    })
}

/// On a camera path over the sphere grid (a slow orbit, 0.4° a frame; frames 8 to 23
/// measured, the history warmed up), the mean FLIP of each frame against its
/// 16×16-supersampled reference is lower with temporal anti-aliasing than with FXAA and
/// than with none (measured: 0.0281 against 0.0434 and 0.0372).
#[test]
fn temporal_anti_aliasing_is_closer_to_supersampling_along_a_camera_path() {
    let scene = builtin_scene("spheres").unwrap();
    let instants: Instants = (0..24).map(|i| (orbit(&scene, i), None)).collect();
    let [none, fxaa, taa] = mean_flips("camera path", &scene, &instants, 8..24, (96, 54));
    assert!(taa < fxaa, "TAA {taa} against FXAA {fxaa}");
    assert!(taa < none, "TAA {taa} against none {none}");
}

/// An animated model (Khronos BoxAnimated, its first animation at 30 frames a second,
/// from 0.5 s; ../shared) under a still camera: temporal anti-aliasing is closer to the
/// 16×16-supersampled frames than FXAA and none (the object's motion from its
/// transforms, frame to frame).
#[test]
fn temporal_anti_aliasing_is_closer_to_supersampling_on_an_animated_model() {
    let Some(dir) = common::shared_gltf_samples() else {
        return;
    };
    let scene = combustion::SceneSource::File(dir.join("BoxAnimated/glTF-Binary/BoxAnimated.glb"))
        .load()
        .unwrap();
    let instants: Instants = (0..24)
        .map(|i| {
            let pose = scene.pose_at(0, 0.5 + i as f32 / 30.0).unwrap();
            (scene.camera, Some(pose))
        })
        .collect();
    let [none, fxaa, taa] = mean_flips("animated model", &scene, &instants, 8..24, (96, 54));
    assert!(taa < fxaa, "TAA {taa} against FXAA {fxaa}");
    assert!(taa < none, "TAA {taa} against none {none}");
}

/// On a still camera its frames settle: the mean difference of the display codes between
/// consecutive frames (the jitter moves every frame's samples) is smaller over frames 16
/// to 23 than over frames 1 to 8, and its mean FLIP against the 16×16-supersampled frame
/// is below the unsmoothed frame's.
#[test]
fn temporal_anti_aliasing_settles_on_a_still_camera() {
    let scene = builtin_scene("spheres").unwrap();
    let instants: Instants = (0..24).map(|_| (scene.camera, None)).collect();
    let frames = sequence(&scene, &instants, (96, 54), Method::Taa);
    let change = |range: std::ops::Range<usize>| {
        let mut sum = 0.0;
        let mut count = 0usize;
        for i in range {
            for (a, b) in frames[i - 1].ldr.iter().zip(&frames[i].ldr) {
                sum += (0..3).map(|c| f64::from(a[c].abs_diff(b[c]))).sum::<f64>();
                count += 3;
            }
        }
        sum / count as f64
    };
    let (early, late) = (change(1..9), change(16..24));
    let reference = &reference(&scene, &instants[23..24], (96, 54))[0];
    let plain = &sequence(&scene, &instants[..1], (96, 54), Method::None)[0];
    let flip = |frame: &Frame| {
        combustion::report::flip_against_radiance(frame, reference, 1.0, ToneMapping::Exponential)
    };
    eprintln!(
        "frame-to-frame change: frames 1-8 {early:.4} codes, 16-23 {late:.4}; FLIP at frame 23 {:.4} against none's {:.4}",
        flip(&frames[23]),
        flip(plain)
    );
    assert!(late < early, "{late} against {early}");
    assert!(flip(&frames[23]) < flip(plain));
}

/// A skinned and a morphed sphere (the test scene, its animation over 2 s sped up four
/// times: the skinned sphere bends, the morphed one swells) under a still camera: the
/// motion vectors follow each vertex from its previous pose, and temporal anti-aliasing
/// is closer to the 16×16-supersampled frames than FXAA and none.
#[test]
fn temporal_anti_aliasing_follows_skins_and_morphs() {
    let scene = common::deformed_spheres();
    let instants: Instants = (0..24)
        .map(|i| {
            let pose = scene.pose_at(0, 4.0 * i as f32 / 30.0 % 2.0).unwrap();
            (scene.camera, Some(pose))
        })
        .collect();
    let [none, fxaa, taa] = mean_flips("skins and morphs", &scene, &instants, 8..24, (96, 54));
    assert!(taa < fxaa, "TAA {taa} against FXAA {fxaa}");
    assert!(taa < none, "TAA {taa} against none {none}");
}

/// The camera's resources alternated past the retire delay, two rounds, validation on:
/// temporal anti-aliasing (the motion vectors, their depth, the two histories, the slot's
/// previous transforms and vertex bases, the renderer's previous pose, replaced by a larger
/// one when a larger deformed scene comes), bloom (its levels, its sums) and the auto
/// exposure (the shared histogram and state, the frame-end copy), each on the spheres,
/// the deformed spheres and the glass, with frames that have none of them between. Every
/// binding is written every frame (`SetWriter::apply` checks it in debug builds), no
/// frame holds a non-finite pixel, every metered frame's exposure is finite, and each
/// configuration renders the same bytes, frame for frame, in its second round as in its
/// first (the history starts again, the jitter from its first element).
#[test]
fn camera_passes_alternate_past_the_retire_delay() {
    use combustion::renderer::{optional_pass, AutoExposure, OptionalPasses};
    use common::FRAMES_PAST_THE_RETIRE_DELAY;
    let taa = OptionalPasses::NONE.with(optional_pass("temporal-anti-aliasing").unwrap(), true);
    let bloom = OptionalPasses::NONE.with(optional_pass("bloom").unwrap(), true);
    let both = taa.with(optional_pass("bloom").unwrap(), true);
    let grid = common::with_coarse_grid_spheres(builtin_scene("spheres").unwrap());
    let deformed = common::deformed_spheres();
    let mut larger = common::deformed_spheres();
    larger.objects.extend(deformed.objects.clone());
    let glass = builtin_scene("glass").unwrap();
    let mut headless = common::lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let gpus = [&grid, &deformed, &glass, &larger].map(|s| renderer.upload(s).unwrap());
        // (scene, passes, auto exposure)
        let configurations = [
            (0, taa, false),
            (1, taa, false),
            (0, OptionalPasses::NONE, false),
            (2, both, true),
            (1, OptionalPasses::NONE, true),
            (3, taa, false),
            (0, bloom, true),
            (1, both, false),
            (2, OptionalPasses::NONE, false),
        ];
        let mut first: Vec<Vec<Vec<[f32; 4]>>> = vec![Vec::new(); configurations.len()];
        for round in 0..2 {
            for (config, &(scene, passes, metered)) in configurations.iter().enumerate() {
                let shading = combustion::renderer::ShadingOptions {
                    optional_passes: passes,
                    ..renderer.shading()
                };
                renderer.set_shading(shading, &gpus.each_ref()).unwrap();
                let gpu = &gpus[scene];
                let pose = gpu.scene().pose_at(0, 0.7);
                let inputs = FrameInputs {
                    pose: pose.as_ref().filter(|_| scene == 1 || scene == 3),
                    auto_exposure: metered.then(AutoExposure::default),
                    ..FrameInputs::of_scene(gpu, 1.0)
                };
                for i in 0..FRAMES_PAST_THE_RETIRE_DELAY {
                    let frame = renderer.render_with(gpu, &inputs, 80, 48, IMAGES).unwrap();
                    assert_eq!(frame.non_finite_pixels(), 0, "configuration {config}");
                    if metered {
                        let exposure = renderer.last_metered_exposure().unwrap().exposure;
                        assert!(exposure.is_finite() && exposure > 0.0, "{exposure}");
                    }
                    if round == 0 {
                        first[config].push(frame.hdr);
                    } else {
                        assert!(
                            first[config][i] == frame.hdr,
                            "configuration {config}, frame {i}: another image in round 2"
                        );
                    }
                }
            }
        }
        // Temporal frames differ from frame to frame (the jitter), then settle.
        assert!(first[0][0] != first[0][1]);
    }
    common::finish(headless);
}
