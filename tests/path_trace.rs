//! The GPU path tracer (`--path-trace on`: the lighting pass tracing paths by ray
//! queries, passes/path_trace.rs) against the f64 path tracer
//! (`combustion_reference::path`, which shares nothing with it but the scene): per pixel,
//! the difference of their means over its combined standard error. The ray-query tests
//! fail, not skip, on a lavapipe without ray queries (Mesa < 24.1).

use combustion::renderer::{optional_pass, OptionalPasses, Readback, RendererSettings};
use combustion::scene::{builtin_scene, Scene};
use combustion_optics::environment::Estimate;
use combustion_reference::path::{PathTracer, PathTracing};
use combustion_reference::shading::SceneShading;
use combustion_reference::SceneBvh;

use crate::common::exact_f32;

/// The spread f32 arithmetic adds to an estimate, relative to it and at least (W·sr⁻¹·m⁻²)
/// (the lighting pass's f32 terms against f64: a direct light's term alone has no
/// sampling noise to hide it).
const FLOAT_SPREAD: (f64, f64) = (2e-3, 1e-5);

const IMAGES: Readback = Readback::IMAGES;

/// `exact_f32` settings with the frame path traced, paths of at most `depth` surfaces.
fn path_traced_settings(depth: u32) -> RendererSettings {
    let mut settings = exact_f32();
    let pass = optional_pass("path-trace").expect("the renderer declares it");
    settings.shading.optional_passes = OptionalPasses::NONE.with(pass, true);
    settings.shading.path_depth = depth;
    settings
}

/// Each pixel's mean over `frames` path-traced frames of successive seeds (each the mean
/// of `PATHS_PER_FRAME` paths), with its standard error from their spread.
fn gpu_frames(
    scene: &Scene,
    (width, height): (u32, u32),
    frames: u32,
    depth: u32,
    pose: Option<&combustion::scene::ObjectPoses>,
) -> Vec<Estimate> {
    let mut headless = crate::common::lavapipe(path_traced_settings(depth));
    let mut averaged = combustion::frame_mean::FrameMean::new((width * height) as usize);
    {
        let renderer = headless.renderer();
        let gpu_scene = renderer.upload(scene).expect("upload");
        let inputs = crate::common::frame_inputs(scene, &scene.lights);
        for seed in 0..frames {
            let seeded = combustion::renderer::FrameInputs {
                environment_seed: seed,
                pose,
                ..inputs
            };
            let frame = renderer
                .render_with(&gpu_scene, &seeded, width, height, IMAGES)
                .expect("render");
            averaged.add(&frame.hdr);
        }
    }
    crate::common::finish(headless);
    averaged
        .mean()
        .iter()
        .zip(averaged.standard_errors())
        .map(|(mean, standard_error)| Estimate {
            mean: *mean,
            standard_error,
        })
        .collect()
}

/// The f64 path tracer's frame with `samples` paths a pixel of at most `depth` surfaces,
/// `None` where the pixel is
/// not compared: where its ray meets nothing, and at silhouettes — pixels whose four
/// neighbours' rays do not all meet the same object, or whose surface is seen within 84°
/// of grazing (n·v < 0.1): there f32 and f64 rays may meet different facets, or one a
/// surface the other misses.
fn f64_frame(
    scene: &Scene,
    (width, height): (u32, u32),
    samples: u32,
    depth: u32,
) -> Vec<Option<Estimate>> {
    let bvh = SceneBvh::new(scene);
    let casters = SceneBvh::shadow_casters(scene);
    let shading = SceneShading::new(scene, &bvh, &scene.lights, width, height);
    let tracing = PathTracing {
        samples,
        max_depth: depth,
        ..PathTracing::default()
    };
    let frame = PathTracer::new(&shading, &casters, tracing).render(2);
    let object = |x: i64, y: i64| {
        (x >= 0 && y >= 0 && x < i64::from(width) && y < i64::from(height))
            .then(|| shading.surface(x as u32, y as u32))
            .flatten()
            .map(|s| s.hit.object)
    };
    frame
        .into_iter()
        .enumerate()
        .map(|(i, estimate)| {
            let (x, y) = ((i as u32 % width) as i64, (i as u32 / width) as i64);
            let surface = shading.surface(x as u32, y as u32)?;
            let interior = [(1, 0), (-1, 0), (0, 1), (0, -1)]
                .iter()
                .all(|(dx, dy)| object(x + dx, y + dy) == Some(surface.hit.object))
                && surface.n.dot(surface.v) >= 0.1;
            estimate.filter(|_| interior)
        })
        .collect()
}

/// The agreement of two frames: per pixel and channel z = (a − b)/√(σa² + σb² + f²) over
/// the pixels both show (f: [`FLOAT_SPREAD`]); the mean z², how many beyond |z| = 6, and
/// each frame's sum with the combined standard error of their difference and its f32
/// bound.
struct Agreement {
    compared: usize,
    mean_square: f64,
    beyond_six: usize,
    means: (f64, f64),
    mean_error: f64,
    /// The f32 spread's bound on the sums' difference: the pixels' (every one of the same
    /// sign at worst).
    float_spread: f64,
    /// The GPU frame's mean standard error per compared channel (its noise).
    gpu_error: f64,
}

fn agreement(gpu: &[Estimate], reference: &[Option<Estimate>]) -> Agreement {
    let (mut z_squares, mut beyond, mut sums, mut variance) = (0.0, 0usize, (0.0, 0.0), 0.0);
    let mut float_spread = 0.0;
    let mut gpu_errors = 0.0;
    let mut compared = 0usize;
    for (g, r) in gpu.iter().zip(reference) {
        let Some(r) = r else {
            continue;
        };
        for c in 0..3 {
            let floor = (FLOAT_SPREAD.0 * g.mean[c].abs().max(r.mean[c].abs())).max(FLOAT_SPREAD.1);
            let spread =
                (g.standard_error[c].powi(2) + r.standard_error[c].powi(2) + floor * floor).sqrt();
            sums.0 += g.mean[c];
            sums.1 += r.mean[c];
            variance += g.standard_error[c].powi(2) + r.standard_error[c].powi(2);
            float_spread += floor;
            gpu_errors += g.standard_error[c];
            if spread > 0.0 {
                let z = (g.mean[c] - r.mean[c]) / spread;
                z_squares += z * z;
                beyond += usize::from(z.abs() > 6.0);
                compared += 1;
            }
        }
    }
    Agreement {
        compared,
        mean_square: z_squares / compared as f64,
        beyond_six: beyond,
        means: (sums.0, sums.1),
        mean_error: variance.sqrt(),
        float_spread,
        gpu_error: gpu_errors / compared.max(1) as f64,
    }
}

/// The GPU path tracer agrees with the f64 one on `scenes` at 40×30: 64 frames of
/// `PATHS_PER_FRAME` paths against 256 paths of the f64 tracer, per pixel. Their means
/// differ by their combined standard errors — mean z² at most 1.6 (1 where the sampling
/// noise dominates; less where the f32 spread of deterministic direct light does), no
/// channel beyond |z| = 6 (for normal errors about one false failure in 500 million
/// channels; these tests compare 28,071) — and the frames' sums within four combined
/// standard errors of each other, plus the f32 spread of each pixel (where the light is
/// deterministic: a convex object under a sun has no noise to hide its rounding).
fn agrees_on(scenes: &[&str]) {
    agrees_at_depth(
        scenes,
        combustion::renderer::ShadingOptions::DEFAULT.path_depth,
    );
}

/// [`agrees_on`] with paths of at most `depth` surfaces on both sides.
fn agrees_at_depth(scenes: &[&str], depth: u32) {
    for &name in scenes {
        agrees_on_scene(name, &builtin_scene(name).unwrap(), (40, 30), depth);
    }
}

/// [`agrees_at_depth`] on one scene (`name` for the messages) at `size`.
fn agrees_on_scene(name: &str, scene: &Scene, size: (u32, u32), depth: u32) {
    agrees_posed(name, scene, None, size, depth);
}

/// [`agrees_on_scene`] with the GPU's frames of `scene` in `pose` (none: at rest) and the
/// f64 frame of `reference` (the scene in that pose).
fn agrees_posed(
    name: &str,
    reference: &Scene,
    posed: Option<(&Scene, &combustion::scene::ObjectPoses)>,
    size: (u32, u32),
    depth: u32,
) {
    agrees_with_budget(name, reference, posed, size, depth, (64, 256));
}

/// [`agrees_posed`] with `budget`: the GPU's frames and the f64 tracer's paths a pixel.
fn agrees_with_budget(
    name: &str,
    reference: &Scene,
    posed: Option<(&Scene, &combustion::scene::ObjectPoses)>,
    size: (u32, u32),
    depth: u32,
    (frames, samples): (u32, u32),
) {
    {
        let gpu = match posed {
            Some((scene, pose)) => gpu_frames(scene, size, frames, depth, Some(pose)),
            None => gpu_frames(reference, size, frames, depth, None),
        };
        let reference = f64_frame(reference, size, samples, depth);
        let a = agreement(&gpu, &reference);
        println!(
            "{name}, depth {depth}: {} channels, mean z² {:.3}, beyond |z| = 6: {}, sums {:.4} (GPU) against {:.4} (f64) ± {:.4}; the GPU's mean standard error {:.3e}",
            a.compared, a.mean_square, a.beyond_six, a.means.0, a.means.1, a.mean_error, a.gpu_error
        );
        assert!(a.compared > 90, "{name}: {} channels compared", a.compared);
        assert!(a.mean_square < 1.6, "{name}: mean z² {:.3}", a.mean_square);
        assert_eq!(a.beyond_six, 0, "{name}: channels beyond |z| = 6");
        assert!(
            (a.means.0 - a.means.1).abs() < 4.0 * a.mean_error + a.float_spread,
            "{name}: sums {} against {} ± {} (f32: {})",
            a.means.0,
            a.means.1,
            a.mean_error,
            a.float_spread
        );
    }
}

/// Light that bounces: the closed box with its coloured walls, gold sphere and emitter
/// found only by paths; the resting sphere and box under the studio; the room lit
/// through its window; a spot light in a closed room; a point light among spheres on a
/// floor; the performance grid on its floor under a low sun.
#[test]
fn the_gpu_path_tracer_agrees_with_the_f64_one_where_light_bounces() {
    agrees_on(&[
        "cornell-box",
        "resting",
        "room",
        "spot-box",
        "point-among",
        "grid-sun",
    ]);
}

/// `--path-depth`: paths of one surface (direct light alone: the emitter and the
/// environment found by the last surface's sampled direction) and of two, on both sides.
#[test]
fn the_gpu_path_tracer_agrees_with_the_f64_one_at_each_depth() {
    for depth in [1, 2] {
        agrees_at_depth(&["cornell-box", "resting"], depth);
    }
}

/// Light through glass: a solid glass ball and slab (volumes: refracted in, reflected
/// inside, let out by the Fresnel equations) and thin-walled spheres from smooth to rough,
/// in air and under water.
#[test]
fn the_gpu_path_tracer_agrees_with_the_f64_one_through_glass() {
    agrees_on(&["glass", "glass-underwater"]);
}

/// The material terms: plastics, measured metals and anisotropic aluminium, clear coats,
/// sheens, thin films, specular strength and colour, the diffuse models, the hard cases,
/// each in air and (where the scene exists) under water, lit by lights or the studio.
#[test]
fn the_gpu_path_tracer_agrees_with_the_f64_one_on_every_lobe() {
    // Smooth metals and plastics under the studio's soft boxes: the light a diffuse
    // surface gets by way of a mirror-like sphere (a caustic, which neither tracer
    // samples directly) comes in rare bright paths, and 64 frames against 256 paths
    // understate both estimates' errors (GPU 85.96, f64 83.87 ± 0.61; with 512 frames
    // against 4,096 paths, 84.76 against 84.69 ± 0.18): this scene takes four times the
    // budget on each side.
    agrees_with_budget(
        "spheres-studio",
        &builtin_scene("spheres-studio").unwrap(),
        None,
        (40, 30),
        combustion::renderer::ShadingOptions::DEFAULT.path_depth,
        (256, 1024),
    );
    agrees_on(&[
        "spheres",
        "gold-copper",
        "gold-copper-underwater",
        "clearcoat",
        "clearcoat-underwater",
        "sheen",
        "iridescence",
        "specular",
        "dielectrics",
        "diffuse-models",
        "hard-cases",
        "underwater",
        "underwater-in-air",
        "grid-7x7",
    ]);
}

/// Textures, read by a path's hits at their finest level on both sides: the builtin
/// normal-mapped spheres (a steep bump map whose shading normals face away from the
/// eye), and — with ../shared — Khronos models with base colour, metallic–roughness and
/// normal maps, mirrored tangent frames, vertex colours, a second coordinate set and
/// blended and cut-out textures, each under its own lights or a sun (environment
/// removed, as the end-to-end comparison lights them), at 80×60 (their details are
/// small in the frame).
#[test]
fn the_gpu_path_tracer_agrees_with_the_f64_one_on_textures() {
    let depth = combustion::renderer::ShadingOptions::DEFAULT.path_depth;
    agrees_at_depth(&["normal-mapped"], depth);
    let Some(root) = crate::common::shared_gltf_samples() else {
        return;
    };
    for model in [
        "BoxTextured",
        "Avocado",
        "NormalTangentMirrorTest",
        "VertexColorTest",
        "AlphaBlendModeTest",
    ] {
        let path = crate::common::sample_model_path(&root, model);
        let scene = combustion::SceneSource::File(path).load().unwrap();
        let scene = crate::end_to_end::lit_for_comparison(scene);
        agrees_on_scene(model, &scene, (80, 60), depth);
    }
}

/// Skinned and morphed objects are met in their pose: a bent skinned sphere and a morphed
/// one on a floor under a sun, path traced in their pose at 1.3 s against the f64 tracer
/// on the scene baked in that pose (their shapes, shadows and what bounces off them).
#[test]
fn the_gpu_path_tracer_meets_deformed_objects_in_their_pose() {
    agrees_at_1_3_s(
        "deformed spheres in their pose",
        &crate::common::deformed_spheres_on_a_floor(),
    );
}

/// [`agrees_posed`] on `scene`'s first animation at 1.3 s, at 80 × 60 and the default
/// depth, against the f64 tracer on the scene baked in that pose.
fn agrees_at_1_3_s(name: &str, scene: &Scene) {
    scene.validate().unwrap();
    let pose = scene.pose_at(0, 1.3).unwrap();
    let still = scene.posed(&pose);
    agrees_posed(
        name,
        &still,
        Some((scene, &pose)),
        (80, 60),
        combustion::renderer::ShadingOptions::DEFAULT.path_depth,
    );
}

/// A skinned or morphed object that blocks no light is met by paths in its pose too: the
/// morphed sphere of [`the_gpu_path_tracer_meets_deformed_objects_in_their_pose`] made of
/// thin smooth glass (transmissive: seen by paths alone, refracting the floor and the
/// bent sphere behind it), against the f64 tracer on the scene baked in its pose.
#[test]
fn the_gpu_path_tracer_meets_deformed_glass_in_its_pose() {
    let mut scene = crate::common::deformed_spheres_on_a_floor();
    scene.materials.push(combustion::scene::Material {
        name: "thin glass".into(),
        base_color: [1.0; 3],
        roughness: 0.05,
        dielectric_ior: 1.5,
        transmission: 1.0,
        ..combustion::scene::Material::default()
    });
    // The morphed sphere (the skinned one is first, the floor last).
    scene.objects[1].material = scene.materials.len() - 1;
    agrees_at_1_3_s("deformed glass in its pose", &scene);
}

/// Lights with a size: next-event estimation's shadow ray towards one point of the disc
/// (or cone) the f64 reference samples for the light's visible fraction — a point light of
/// radius 0.3 m among spheres on a floor, and the grid under a sun of 3° (their
/// penumbrae wide at this size); the lights' shading stays their centre's, on both sides.
#[test]
fn the_gpu_path_tracer_agrees_with_the_f64_one_under_lights_with_a_size() {
    use combustion::scene::Light;
    let depth = combustion::renderer::ShadingOptions::DEFAULT.path_depth;
    for name in ["point-among", "grid-sun"] {
        let mut scene = builtin_scene(name).unwrap();
        for light in &mut scene.lights {
            match light {
                Light::Point { radius, .. } | Light::Spot { radius, .. } => *radius = 0.3,
                Light::Directional {
                    angular_diameter, ..
                } => *angular_diameter = 3f32.to_radians(),
            }
        }
        scene.validate().unwrap();
        agrees_on_scene(
            &format!("{name}, lights with a size"),
            &scene,
            (40, 30),
            depth,
        );
    }
}

/// Path-traced frames averaged on the GPU while nothing changes
/// (`RendererSettings::accumulate_paths`, the viewer's): a still view's k-th frame is the
/// mean of the frames of seeds 0 to k − 1 rendered one by one (to f32 rounding of the
/// running mean), a moved camera starts again with the one frame of seed 0 from there,
/// and so does a changed light; `Renderer::accumulated_paths` counts the paths a pixel.
#[test]
fn accumulated_frames_are_the_mean_of_successive_seeds_and_start_again_on_change() {
    use combustion::renderer::{FrameInputs, Renderer};
    use combustion::scene::Light;
    let (width, height) = (32, 24);
    let scene = builtin_scene("point-among").unwrap();
    let mut moved = scene.camera;
    moved.position += glam::Vec3::new(0.3, 0.1, 0.0);
    let mut brighter = scene.lights.clone();
    for light in &mut brighter {
        if let Light::Point { intensity, .. } = light {
            *intensity = intensity.map(|i| 2.0 * i);
        }
    }
    assert_ne!(
        brighter, scene.lights,
        "the scene has point lights to change"
    );
    let inputs = crate::common::frame_inputs(&scene, &scene.lights);
    let frame = |renderer: &mut Renderer,
                 gpu: &combustion::renderer::GpuScene,
                 inputs: &FrameInputs<'_>,
                 seed: u32| {
        let seeded = FrameInputs {
            environment_seed: seed,
            ..*inputs
        };
        renderer
            .render_with(gpu, &seeded, width, height, IMAGES)
            .expect("render")
            .hdr
    };
    let still = inputs;
    let from_moved = FrameInputs {
        camera: moved,
        ..inputs
    };
    let relit = FrameInputs {
        lights: &brighter,
        ..from_moved
    };
    // Each seed's frame alone.
    let frames = 6;
    let (singles, moved_single, relit_singles) = {
        let mut headless = crate::common::lavapipe(path_traced_settings(4));
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).expect("upload");
        let singles: Vec<_> = (0..frames)
            .map(|seed| frame(renderer, &gpu, &still, seed))
            .collect();
        let moved_single = frame(renderer, &gpu, &from_moved, 0);
        let relit_singles: Vec<_> = (0..2)
            .map(|seed| frame(renderer, &gpu, &relit, seed))
            .collect();
        drop(gpu);
        crate::common::finish(headless);
        (singles, moved_single, relit_singles)
    };
    // The mean of `frames` against an accumulated frame: each channel within f32 rounding
    // of the running mean; returns how many channels differ from the last frame alone.
    let agrees = |accumulated: &[[f32; 4]], frames: &[Vec<[f32; 4]>], what: &str| {
        let mut mean = combustion::frame_mean::FrameMean::new(accumulated.len());
        for f in frames {
            mean.add(f);
        }
        let mut unlike_last = 0;
        for (i, (a, m)) in accumulated.iter().zip(mean.mean()).enumerate() {
            for c in 0..3 {
                let tolerance = 1e-6 * m[c].abs().max(1e-3) * frames.len() as f64;
                assert!(
                    (f64::from(a[c]) - m[c]).abs() <= tolerance,
                    "{what}: pixel {i} channel {c}: accumulated {} against the mean {} of {} frames",
                    a[c],
                    m[c],
                    frames.len()
                );
                unlike_last += usize::from(a[c] != frames[frames.len() - 1][i][c]);
            }
        }
        unlike_last
    };
    let mut settings = path_traced_settings(4);
    settings.accumulate_paths = true;
    let mut headless = crate::common::lavapipe(settings);
    let renderer = headless.renderer();
    let gpu = renderer.upload(&scene).expect("upload");
    assert_eq!(renderer.accumulated_paths(), 0);
    for k in 1..=frames as usize {
        let accumulated = frame(renderer, &gpu, &still, 0);
        let unlike_last = agrees(&accumulated, &singles[..k], &format!("still, frame {k}"));
        if k > 1 {
            // Averaging, not the last frame's paths shown alone.
            assert!(
                unlike_last >= 100,
                "still, frame {k}: only {unlike_last} channels differ from the last frame alone"
            );
        }
        assert_eq!(
            renderer.accumulated_paths(),
            k as u64 * u64::from(combustion::renderer::PATHS_PER_FRAME)
        );
    }
    // Frames equal bit for bit (else how many channels differ).
    let same = |a: &[[f32; 4]], b: &[[f32; 4]], what: &str| {
        let differ = a
            .iter()
            .zip(b)
            .flat_map(|(p, q)| p.iter().zip(q))
            .filter(|(x, y)| x.to_bits() != y.to_bits())
            .count();
        assert_eq!(differ, 0, "{what}: channels that differ");
    };
    // A moved camera: its first frame is its seed 0 alone, bit for bit.
    same(
        &frame(renderer, &gpu, &from_moved, 0),
        &moved_single,
        "moved",
    );
    assert_eq!(
        renderer.accumulated_paths(),
        u64::from(combustion::renderer::PATHS_PER_FRAME)
    );
    // A changed light likewise, then its history goes on.
    same(
        &frame(renderer, &gpu, &relit, 0),
        &relit_singles[0],
        "relit",
    );
    let accumulated = frame(renderer, &gpu, &relit, 0);
    agrees(&accumulated, &relit_singles, "relit, frame 2");
    drop(gpu);
    crate::common::finish(headless);
}

/// The accumulation's history images, alternated with frames that have none past the
/// retire delay: path-traced frames of resting at two sizes and plain frames between
/// them, two rounds, validation on. Each path-traced run starts its history again (its
/// shading or size changed) and renders, frame for frame, the same bytes in its second
/// round as in its first, after its images were retired and made again.
#[test]
fn accumulated_frames_alternate_past_the_retire_delay() {
    use crate::common::FRAMES_PAST_THE_RETIRE_DELAY;
    let mut settings = path_traced_settings(4);
    settings.accumulate_paths = true;
    let traced = settings.shading.optional_passes;
    let resting = builtin_scene("resting").unwrap();
    let mut headless = crate::common::lavapipe(settings);
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&resting).expect("upload");
        // (passes, size)
        let configurations = [
            (traced, (48, 32)),
            (OptionalPasses::NONE, (48, 32)),
            (traced, (40, 24)),
            (OptionalPasses::NONE, (40, 24)),
        ];
        let mut first: Vec<Vec<Vec<[f32; 4]>>> = vec![Vec::new(); configurations.len()];
        for round in 0..2 {
            for (config, &(passes, (w, h))) in configurations.iter().enumerate() {
                let shading = combustion::renderer::ShadingOptions {
                    optional_passes: passes,
                    ..renderer.shading()
                };
                renderer.set_shading(shading, &[&gpu]).expect("set shading");
                for k in 0..FRAMES_PAST_THE_RETIRE_DELAY {
                    let frame = renderer.render(&gpu, w, h, IMAGES).expect("frame");
                    assert_eq!(frame.non_finite_pixels(), 0);
                    let paths = renderer.accumulated_paths();
                    let expected = if passes == traced {
                        (k as u64 + 1) * u64::from(combustion::renderer::PATHS_PER_FRAME)
                    } else {
                        0
                    };
                    assert_eq!(paths, expected, "configuration {config}, frame {k}");
                    if round == 0 {
                        first[config].push(frame.hdr);
                    } else {
                        assert!(
                            first[config][k] == frame.hdr,
                            "configuration {config}, frame {k}, round {round}"
                        );
                    }
                }
            }
        }
    }
    crate::common::finish(headless);
}
