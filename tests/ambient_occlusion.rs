//! The ambient-occlusion pass (`--environment-occlusion gtao`) against exact visibility: the
//! floor beside a sphere resting on it, lit by a uniform environment, has the radiance
//! ρL(1 − F), F the form factor from the floor point to the sphere (1 at the contact) —
//! without occlusion the floor is ρL everywhere. A floor alone occludes nothing; frames
//! without the option run nothing of it.

use combustion::renderer::{optional_pass, OptionalPasses, Readback, RendererSettings};
use combustion::scene::{Camera, Environment, Material, Mesh, Object, Scene};
use glam::{DVec3, DVec4, Mat4, Vec3};

use crate::common::{exact_f32, render};

const RHO: f64 = 0.8;
const IMAGES: Readback = Readback::IMAGES;
const RADIUS: f64 = 1.0;
const WIDTH: u32 = 640;
const HEIGHT: u32 = 360;

/// A Lambertian floor (ρ = 0.8, IOR 1: no specular lobe) and, with `sphere`, a sphere of
/// radius 1 resting on it at the origin, both under a uniform environment of radiance 1.
fn resting_sphere(sphere: bool) -> Scene {
    let lambert = Material {
        name: "lambert".into(),
        base_color: [RHO as f32; 3],
        roughness: 1.0,
        dielectric_ior: 1.0,
        ..Material::default()
    };
    let mut objects = vec![Object {
        mesh: 0,
        material: 0,
        transform: Mat4::IDENTITY,
        casts_shadows: true,
        node: None,
    }];
    if sphere {
        objects.push(Object {
            mesh: 1,
            material: 0,
            transform: Mat4::from_translation(Vec3::new(0.0, RADIUS as f32, 0.0)),
            casts_shadows: true,
            node: None,
        });
    }
    Scene {
        name: "resting-sphere".into(),
        meshes: vec![
            Mesh::plane("floor", 16.0),
            Mesh::uv_sphere("sphere", RADIUS as f32, 128, 64),
        ],
        materials: vec![lambert],
        objects,
        lights: Vec::new(),
        camera: Camera {
            position: Vec3::new(0.0, 3.5, 6.0),
            target: Vec3::new(0.0, 0.4, 0.0),
            up: Vec3::Y,
            vertical_fov: 45f32.to_radians(),
            near: 0.1,
            far: 100.0,
        },
        outside_ior: 1.0,
        environment: Some(Environment::Uniform([1.0; 3])),
        motion: Default::default(),
    }
}

/// `exact_f32` settings with the ambient-occlusion pass on or off.
fn settings(occlusion: bool) -> RendererSettings {
    with_pass("ambient-occlusion", occlusion)
}

/// `exact_f32` settings with the optional pass `name` on or off.
fn with_pass(name: &str, on: bool) -> RendererSettings {
    let mut settings = exact_f32();
    let pass = optional_pass(name).expect("the renderer declares it");
    settings.shading.optional_passes = OptionalPasses::NONE.with(pass, on);
    settings
}

/// The form factor from a floor point at distance `d` from the contact to the sphere
/// resting there: (R/D)² cos θ with D the distance to its centre and cos θ = R/D (the
/// sphere lies wholly above the floor's horizon).
fn form_factor(d: f64) -> f64 {
    (RADIUS / (d * d + RADIUS * RADIUS).sqrt()).powi(3)
}

/// The floor pixels whose centre sees the floor (not the sphere), at least a pixel from
/// the sphere's outline, with their distance from the contact (in radii).
fn floor_pixels(scene: &Scene) -> Vec<(usize, f64)> {
    let inverse = scene
        .camera
        .view_projection(WIDTH as f32 / HEIGHT as f32)
        .as_dmat4()
        .inverse();
    let ray = |x: f64, y: f64| {
        let at = |z: f64| {
            let p = inverse
                * DVec4::new(
                    x / f64::from(WIDTH) * 2.0 - 1.0,
                    y / f64::from(HEIGHT) * 2.0 - 1.0,
                    z,
                    1.0,
                );
            p.truncate() / p.w
        };
        let near = at(0.0);
        (near, (at(1.0) - near).normalize())
    };
    let centre = DVec3::new(0.0, RADIUS, 0.0);
    let hits_sphere = |x: f64, y: f64| {
        let (o, d) = ray(x, y);
        let oc = o - centre;
        let b = oc.dot(d);
        b * b - (oc.length_squared() - RADIUS * RADIUS) >= 0.0 && b < 0.0
    };
    let mut out = Vec::new();
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let (fx, fy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            let near_outline = [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0), (0.0, 0.0)]
                .iter()
                .any(|(dx, dy)| hits_sphere(fx + dx, fy + dy));
            let (o, d) = ray(fx, fy);
            if near_outline || d.y >= 0.0 {
                continue;
            }
            let floor = o + d * (-o.y / d.y);
            if floor.x.abs() < 7.5 && floor.z.abs() < 7.5 {
                let distance = (floor.x * floor.x + floor.z * floor.z).sqrt() / RADIUS;
                out.push((y as usize * WIDTH as usize + x as usize, distance));
            }
        }
    }
    out
}

/// The mean relative error of the floor's radiance (green) against ρL(1 − F), over the
/// pixels whose distance from the contact lies in `range` (radii): (signed, absolute,
/// pixels).
fn floor_error(
    hdr: &[[f32; 4]],
    pixels: &[(usize, f64)],
    range: std::ops::Range<f64>,
) -> (f64, f64, usize) {
    let errors: Vec<f64> = pixels
        .iter()
        .filter(|(_, d)| range.contains(d))
        .map(|&(i, d)| {
            let exact = RHO * (1.0 - form_factor(d));
            (f64::from(hdr[i][1]) - exact) / exact
        })
        .collect();
    let n = errors.len() as f64;
    (
        errors.iter().sum::<f64>() / n,
        errors.iter().map(|e| e.abs()).sum::<f64>() / n,
        errors.len(),
    )
}

/// The bounds the pass holds on the floor beside the resting sphere, as measured at
/// 640×360 (2 slices of 8 steps a side, turned per pixel over 4×4 blocks; 8 slices
/// measured the same to the third digit): (range of
/// distances from the contact in radii, largest |mean relative error|, largest mean
/// |relative error|). Measured: the ring −0.067 (|.| 0.078), within three radii −0.026
/// (|.| 0.035), beyond +0.006 (|.| 0.019); without occlusion +0.66, +0.17 and +0.017.
const FLOOR_BOUNDS: [(std::ops::Range<f64>, f64, f64); 3] = [
    (0.25..1.5, 0.08, 0.09),
    (0.0..3.0, 0.03, 0.04),
    (3.0..6.0, 0.012, 0.022),
];

/// Where `hdr`'s floor is beyond [`FLOOR_BOUNDS`] (none: within every bound).
fn beyond_floor_bounds(hdr: &[[f32; 4]], pixels: &[(usize, f64)], label: &str) -> Vec<String> {
    let mut beyond = Vec::new();
    for (range, mean_bound, abs_bound) in FLOOR_BOUNDS {
        let (mean, abs, n) = floor_error(hdr, pixels, range.clone());
        println!(
            "{label}: {n} floor pixels {range:?} radii from the contact: mean relative error {mean:+.4}, mean |relative error| {abs:.4}"
        );
        assert!(n > 1000, "{n} floor pixels in {range:?}");
        if mean.abs() > mean_bound || abs > abs_bound {
            beyond.push(format!(
                "{range:?}: {mean:+.4} (bound ±{mean_bound}), |.| {abs:.4} (bound {abs_bound})"
            ));
        }
    }
    beyond
}

/// With the pass, the floor's radiance follows ρL(1 − F) within the bounds; without it
/// (the same check on the same scene) it is 66 % too bright in the ring beside the
/// contact.
#[test]
fn the_floor_beside_a_resting_sphere_darkens_as_its_form_factor_says() {
    let scene = resting_sphere(true);
    let pixels = floor_pixels(&scene);
    let on = render(&scene, WIDTH, HEIGHT, settings(true), IMAGES);
    let beyond = beyond_floor_bounds(&on.hdr, &pixels, "with ambient occlusion");
    assert!(
        beyond.is_empty(),
        "beyond the bounds: {}",
        beyond.join("; ")
    );
    let off = render(&scene, WIDTH, HEIGHT, settings(false), IMAGES);
    let beyond = beyond_floor_bounds(&off.hdr, &pixels, "without");
    assert_eq!(beyond.len(), 3, "without occlusion: {}", beyond.join("; "));
    let (ring, _, _) = floor_error(&off.hdr, &pixels, 0.25..1.5);
    assert!(ring > 0.5, "without occlusion the ring is {ring:+.3} off");
}

/// A floor alone occludes nothing: every floor pixel keeps the radiance it has without
/// the pass (no surface occludes itself: its samples lie on its tangent plane; and the
/// slices' sum is taken over the same sum unoccluded, so the quadrature's error cancels —
/// it was 0.9 % at the grazing far end before).
#[test]
fn a_floor_alone_occludes_nothing() {
    let scene = resting_sphere(false);
    let pixels = floor_pixels(&scene);
    let on = render(&scene, WIDTH, HEIGHT, settings(true), IMAGES);
    let off = render(&scene, WIDTH, HEIGHT, settings(false), IMAGES);
    let errors: Vec<f64> = pixels
        .iter()
        .map(|&(i, _)| f64::from(on.hdr[i][1]) / f64::from(off.hdr[i][1]) - 1.0)
        .collect();
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let worst = errors.iter().fold(0.0f64, |w, e| w.max(e.abs()));
    println!(
        "{} floor pixels: mean relative error {mean:+.2e}, largest {worst:.2e}",
        errors.len()
    );
    assert!(
        mean.abs() < 1e-4 && worst < 1e-3,
        "mean {mean:+.2e}, largest {worst:.2e}"
    );
}

/// Frames without the option, and frames with it in a scene without an environment (the
/// light it would occlude), do not run the pass.
#[test]
fn only_frames_that_ask_with_an_environment_run_it() {
    let name = "ambient occlusion";
    let scene = resting_sphere(true);
    let off = render(&scene, 64, 36, settings(false), IMAGES);
    assert!(
        !off.timings.names().contains(&name),
        "{:?}",
        off.timings.names()
    );
    let on = render(&scene, 64, 36, settings(true), IMAGES);
    assert!(
        on.timings.names().contains(&name),
        "{:?}",
        on.timings.names()
    );
    let unlit = Scene {
        environment: None,
        ..scene
    };
    let dark = render(&unlit, 64, 36, settings(true), IMAGES);
    assert!(
        !dark.timings.names().contains(&name),
        "{:?}",
        dark.timings.names()
    );
}

/// Ray-traced occlusion: the floor beside the resting sphere within 1 % of ρL(1 − F) in
/// the mean over each range (64 cosine-distributed rays a pixel, traced against the
/// scene's acceleration structures on lavapipe's ray queries; the per-pixel noise
/// averages out over the thousands of pixels of a range).
#[test]
fn ray_traced_occlusion_gives_the_floor_its_form_factor() {
    let scene = resting_sphere(true);
    let pixels = floor_pixels(&scene);
    let traced = render(
        &scene,
        WIDTH,
        HEIGHT,
        with_pass("ray-traced-occlusion", true),
        IMAGES,
    );
    assert!(
        traced.timings.names().contains(&"ray-traced occlusion"),
        "lavapipe has no ray queries here (Mesa 24.1 or later has them; bash scripts/dev.sh test installs it): {:?}",
        traced.timings.names()
    );
    // Each range within 1 % in the mean. The 366 pixels nearest the contact are printed,
    // not bounded: their mean moves by a few per cent between sample seeds (−0.3 % and
    // −2.7 % seen), more than their standard error says — the per-pixel turns of one
    // stratified pattern are not independent enough for so few pixels.
    for (range, one_percent) in [
        (0.25..0.5, false),
        (0.25..1.5, true),
        (0.0..3.0, true),
        (3.0..6.0, true),
    ] {
        let errors: Vec<f64> = pixels
            .iter()
            .filter(|(_, d)| range.contains(d))
            .map(|&(i, d)| {
                let exact = RHO * (1.0 - form_factor(d));
                (f64::from(traced.hdr[i][1]) - exact) / exact
            })
            .collect();
        let n = errors.len() as f64;
        let mean = errors.iter().sum::<f64>() / n;
        let spread = (errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let standard_error = spread / n.sqrt();
        println!(
            "ray-traced: {n} floor pixels {range:?} radii from the contact: mean relative error {mean:+.4} (standard error {standard_error:.4})"
        );
        if one_percent {
            assert!(
                mean.abs() < 0.01,
                "{range:?}: mean relative error {mean:+.4}"
            );
        } else {
            assert!(
                mean.abs() < 4.0 * standard_error,
                "{range:?}: mean relative error {mean:+.4}, standard error {standard_error:.4}"
            );
        }
    }
}

/// A device created without ray queries (as on one that has none) renders frames that
/// ask for ray-traced occlusion with the raster paths: no error, no pass, the image of
/// a frame without it, nothing from the validation layer.
#[test]
fn without_ray_queries_the_traced_pass_is_left_out() {
    use combustion::vk::{DeviceDesc, DeviceSelector, RayQueries};
    use combustion::{Headless, HeadlessDesc};
    let scene = resting_sphere(true);
    let mut headless = Headless::new(&HeadlessDesc {
        device: DeviceDesc {
            selector: DeviceSelector::NameContains("llvmpipe".into()),
            validation: true,
            synchronization_validation: true,
            ray_queries: RayQueries::Off,
            ..DeviceDesc::default()
        },
        settings: with_pass("ray-traced-occlusion", true),
    })
    .expect("lavapipe with validation");
    let frame = {
        let renderer = headless.renderer();
        assert!(!renderer.device().ray_queries());
        let gpu_scene = renderer.upload(&scene).expect("upload");
        renderer.render(&gpu_scene, 64, 36, IMAGES).expect("render")
    };
    crate::common::finish(headless);
    assert!(
        !frame.timings.names().contains(&"ray-traced occlusion"),
        "{:?}",
        frame.timings.names()
    );
    let plain = render(&scene, 64, 36, settings(false), IMAGES);
    assert_eq!(frame.hdr, plain.hdr);
}

/// What the traced rays let through: a sphere that casts no shadows, and a glass sphere
/// (transmission 1), occlude nothing — every floor pixel keeps the radiance of the frame
/// without occlusion, bit for bit (its visibility is exactly 1).
#[test]
fn objects_that_cast_nothing_and_glass_occlude_nothing_traced() {
    let base = resting_sphere(true);
    let pixels = floor_pixels(&base);
    let mut no_shadow = base.clone();
    no_shadow.objects[1].casts_shadows = false;
    let mut glass = base.clone();
    glass.materials.push(Material {
        name: "glass".into(),
        transmission: 1.0,
        dielectric_ior: 1.5,
        roughness: 0.0,
        ..Material::default()
    });
    glass.objects[1].material = 1;
    for (what, scene) in [("casts no shadows", no_shadow), ("glass", glass)] {
        let plain = render(&scene, WIDTH, HEIGHT, settings(false), IMAGES);
        let traced = render(
            &scene,
            WIDTH,
            HEIGHT,
            with_pass("ray-traced-occlusion", true),
            IMAGES,
        );
        assert!(traced.timings.names().contains(&"ray-traced occlusion"));
        let differing = pixels
            .iter()
            .filter(|&&(i, _)| traced.hdr[i] != plain.hdr[i])
            .count();
        assert_eq!(differing, 0, "{what}: floor pixels occluded");
    }
}

/// Inside a closed sphere (double-sided, seen from its centre) the environment reaches
/// nothing: with ray-traced occlusion every pixel is black.
#[test]
fn inside_a_closed_sphere_is_black_traced() {
    let mut scene = resting_sphere(true);
    scene.objects.remove(0);
    scene.materials[0].double_sided = true;
    scene.camera.position = Vec3::new(0.0, RADIUS as f32, 0.0);
    scene.camera.target = Vec3::new(0.0, RADIUS as f32, -1.0);
    scene.camera.near = 0.01;
    let traced = render(
        &scene,
        64,
        36,
        with_pass("ray-traced-occlusion", true),
        IMAGES,
    );
    let plain = render(&scene, 64, 36, settings(false), IMAGES);
    let largest =
        |f: &combustion::renderer::Frame| f.hdr.iter().map(|p| p[1]).fold(0.0f32, f32::max);
    println!(
        "inside: largest radiance {} traced, {} without",
        largest(&traced),
        largest(&plain)
    );
    assert!(largest(&plain) > 0.5, "without occlusion the inside is lit");
    assert_eq!(largest(&traced), 0.0, "with it, black");
}

/// Frames of other sample seeds (`FrameInputs::environment_seed`) trace other rays, and
/// their mean converges: over the ring beside the contact, the mean |relative error| of
/// 8 frames averaged is below half of one frame's (1/√8 ≈ 0.35 of it for independent
/// noise); seed 0 is the frame without a seed, bit for bit.
#[test]
fn traced_frames_of_other_seeds_average_towards_the_form_factor() {
    let scene = resting_sphere(true);
    let pixels = floor_pixels(&scene);
    let mut headless = crate::common::lavapipe(with_pass("ray-traced-occlusion", true));
    let (first, unseeded, mean) = {
        let renderer = headless.renderer();
        let gpu_scene = renderer.upload(&scene).expect("upload");
        let inputs = crate::common::frame_inputs(&scene, &scene.lights);
        let frames: Vec<_> = (0..8)
            .map(|seed| {
                let seeded = combustion::renderer::FrameInputs {
                    environment_seed: seed,
                    ..inputs
                };
                renderer
                    .render_with(&gpu_scene, &seeded, WIDTH, HEIGHT, IMAGES)
                    .expect("render")
            })
            .collect();
        let unseeded = renderer
            .render(&gpu_scene, WIDTH, HEIGHT, IMAGES)
            .expect("render");
        // The structures' memory is counted: the sphere's and the floor's, and a top
        // level per frame slot.
        let bytes = renderer.stats().acceleration_structure_bytes;
        println!("acceleration structures: {bytes} bytes");
        assert!(bytes > 0);
        let mean: Vec<[f32; 4]> = (0..frames[0].hdr.len())
            .map(|i| {
                let sum = frames.iter().map(|f| f.hdr[i][1]).sum::<f32>();
                [0.0, sum / frames.len() as f32, 0.0, 1.0]
            })
            .collect();
        (frames[0].hdr.clone(), unseeded.hdr, mean)
    };
    crate::common::finish(headless);
    let differing = first.iter().zip(&unseeded).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "seed 0 is the unseeded frame");
    let (_, one, _) = floor_error(&first, &pixels, 0.25..1.5);
    let (mean_error, averaged, _) = floor_error(&mean, &pixels, 0.25..1.5);
    println!("ring: mean |relative error| one frame {one:.4}, 8 frames {averaged:.4} (mean {mean_error:+.4})");
    assert!(
        averaged < 0.5 * one,
        "one frame {one:.4}, 8 averaged {averaged:.4}"
    );
}

/// builtin:resting's geometry (its sphere, box and floor made Lambertian, ρ = 0.8, IOR 1)
/// under a uniform environment (radiance 1) against the f64 reference with the
/// environment's visibility (`ReferenceShading::with_environment_visibility`: 24²
/// stratified cosine rays a pixel against the scene's triangles, the same definition as
/// the passes'), every 4th pixel of 160×90, the channels summed: the traced pass (8 seeds
/// averaged) within 1 % in the mean; the screen-space pass's error stated; without
/// occlusion the same check fails.
#[test]
fn resting_against_the_reference_with_environment_visibility() {
    // Lambertian: the visibility alone. Then its plastics as built: the visibility
    // applied as the split sum applies occlusion (diffuse × V, the specular lobe × the
    // specular occlusion at its α), against the oracle's integral so occluded — before the
    // passes switched the specular occlusion on (it followed glTF occlusion textures
    // alone) the traced frame was +10 % off there.
    for (lambert, bound) in [(true, 0.01), (false, 0.02)] {
        let (none, _, traced) = resting_against_reference(lambert);
        assert!(
            traced.0.abs() < bound,
            "ray-traced: mean relative error {:+.4}",
            traced.0
        );
        assert!(
            none.0 > 0.05,
            "without occlusion: mean relative error {:+.4}",
            none.0
        );
    }
}

/// builtin:resting under a uniform environment of radiance 1 (its materials made
/// Lambertian, ρ = 0.8 and IOR 1, with `lambert`) against the f64 reference with the
/// environment's visibility, every 4th pixel of 160×90, the channels summed: (signed
/// mean, mean magnitude) of the relative error without occlusion, with the screen-space
/// pass and with the traced pass (8 seeds averaged).
fn resting_against_reference(lambert: bool) -> ((f64, f64), (f64, f64), (f64, f64)) {
    use combustion::renderer::reference::ReferenceShading;
    let (w, h) = (160u32, 90u32);
    let mut scene = combustion::scene::builtin_scene("resting").unwrap();
    scene.environment = Some(Environment::Uniform([1.0; 3]));
    for material in scene.materials.iter_mut().filter(|_| lambert) {
        *material = Material {
            name: material.name.clone(),
            base_color: [RHO as f32; 3],
            roughness: 1.0,
            dielectric_ior: 1.0,
            ..Material::default()
        };
    }
    let bvh = std::sync::Arc::new(combustion::reference::SceneBvh::shadow_casters(&scene));
    let inputs = crate::common::frame_inputs(&scene, &[]);
    let reference =
        ReferenceShading::new(&scene, &inputs, w, h).with_environment_visibility(bvh, 24);
    let measure = |name: &str, settings: RendererSettings, seeds: u32| {
        let against = against_reference(&scene, &reference, (w, h), name, settings, seeds);
        (against.mean, against.magnitude)
    };
    let label = if lambert { "Lambertian" } else { "as built" };
    let none = measure(&format!("{label}, no occlusion"), settings(false), 1);
    let screen = measure(&format!("{label}, screen-space"), settings(true), 1);
    let traced = measure(
        &format!("{label}, ray-traced, 8 seeds"),
        with_pass("ray-traced-occlusion", true),
        8,
    );
    (none, screen, traced)
}

/// How far a frame is from its reference ([`against_reference`]).
struct Against {
    /// The signed mean of the per-pixel relative errors.
    mean: f64,
    /// The mean of their magnitudes.
    magnitude: f64,
    /// The relative error of the mean radiance (what scenes with black pixels, where a
    /// relative error has no meaning, are measured by).
    of_mean: f64,
}

/// `scene` (lit by its environment alone) rendered at `size` with `settings`, the mean
/// of the frames of `seeds` sample seeds, against `reference` (made for that frame) at
/// every 4th pixel, the channels summed (a blue plastic's green alone is near black),
/// printed under `name`.
fn against_reference(
    scene: &Scene,
    reference: &combustion::renderer::reference::ReferenceShading,
    size: (u32, u32),
    name: &str,
    settings: RendererSettings,
    seeds: u32,
) -> Against {
    let pairs = radiance_pairs(scene, reference, size, settings, seeds);
    let n = pairs.len() as f64;
    // Per pixel where the reference is not black (a relative error has no meaning there).
    let errors: Vec<f64> = pairs
        .iter()
        .filter(|(_, exact)| *exact > 0.0)
        .map(|(gpu, exact)| (gpu - exact) / exact)
        .collect();
    let lit = errors.len() as f64;
    let mean = errors.iter().sum::<f64>() / lit;
    let magnitude = errors.iter().map(|e| e.abs()).sum::<f64>() / lit;
    let (gpu, exact) = pairs
        .iter()
        .fold((0.0, 0.0), |(g, e), (gpu, exact)| (g + gpu, e + exact));
    let of_mean = (gpu - exact) / exact;
    println!(
        "{name}: {n} pixels ({lit} not black in the reference), mean relative error {mean:+.4}, mean |relative error| {magnitude:.4}; mean radiance {:.4} against {:.4}: {of_mean:+.4}",
        gpu / n,
        exact / n
    );
    Against {
        mean,
        magnitude,
        of_mean,
    }
}

/// The (frame, reference) radiance pairs of [`against_reference`], the channels summed.
fn radiance_pairs(
    scene: &Scene,
    reference: &combustion::renderer::reference::ReferenceShading,
    (w, h): (u32, u32),
    settings: RendererSettings,
    seeds: u32,
) -> Vec<(f64, f64)> {
    let inputs = crate::common::frame_inputs(scene, &[]);
    let environment = scene.environment.clone().unwrap();
    let mut headless = crate::common::lavapipe(settings);
    let frames: Vec<_> = {
        let renderer = headless.renderer();
        let gpu_scene = renderer.upload(scene).expect("upload");
        (0..seeds)
            .map(|seed| {
                let seeded = combustion::renderer::FrameInputs {
                    environment_seed: seed,
                    ..inputs
                };
                renderer
                    .render_with(&gpu_scene, &seeded, w, h, Readback::ALL)
                    .expect("render")
            })
            .collect()
    };
    crate::common::finish(headless);
    let gbuffer = frames[0].gbuffer.as_ref().unwrap();
    let mut pairs = Vec::new();
    for y in (2..h).step_by(4) {
        for x in (2..w).step_by(4) {
            let i = (y * w + x) as usize;
            let Some(estimate) =
                reference.shade_environment(&gbuffer.texels[i], x, y, &environment, 1024)
            else {
                continue;
            };
            let gpu = frames
                .iter()
                .map(|f| f.hdr[i][..3].iter().map(|&c| f64::from(c)).sum::<f64>())
                .sum::<f64>()
                / f64::from(seeds);
            pairs.push((gpu, estimate.mean.iter().sum::<f64>()));
        }
    }
    pairs
}

/// builtin:room, a closed room with a window, under a uniform environment of radiance 1:
/// only the window lets the light in. Against the f64 reference with the environment's
/// visibility, the mean radiance over every 4th pixel of 160×90 (much of the room is
/// black: no per-pixel relative error there): the traced pass (16 seeds averaged) within
/// 3 %; without occlusion the room glows, several times too bright, and the screen-space
/// pass, which cannot see that the room is closed (what lies off screen occludes
/// nothing), is still far too bright.
#[test]
fn a_room_is_lit_through_its_window_alone() {
    use combustion::renderer::reference::ReferenceShading;
    let (w, h) = (160u32, 90u32);
    let mut scene = combustion::scene::builtin_scene("room").unwrap();
    scene.environment = Some(Environment::Uniform([1.0; 3]));
    let bvh = std::sync::Arc::new(combustion::reference::SceneBvh::shadow_casters(&scene));
    let inputs = crate::common::frame_inputs(&scene, &[]);
    let reference =
        ReferenceShading::new(&scene, &inputs, w, h).with_environment_visibility(bvh, 24);
    let measure = |name: &str, settings: RendererSettings, seeds: u32| {
        against_reference(&scene, &reference, (w, h), name, settings, seeds).of_mean
    };
    let none = measure("room, no occlusion", settings(false), 1);
    let screen = measure("room, screen-space", settings(true), 1);
    let traced = measure(
        "room, ray-traced, 16 seeds",
        with_pass("ray-traced-occlusion", true),
        16,
    );
    assert!(
        traced.abs() < 0.03,
        "ray-traced: mean relative error {traced:+.4}"
    );
    assert!(none > 2.0, "no occlusion: mean relative error {none:+.4}");
    assert!(
        screen > 1.0,
        "screen-space: mean relative error {screen:+.4}"
    );
}

/// Cut-outs let the environment through their holes: the cut-out panels
/// (assets/scenes/cutout: a lattice with 2×2-texel holes, a gradient cut at a threshold,
/// a panel cut everywhere) under a uniform environment, with ray-traced occlusion (8
/// seeds), against the f64 reference with the environment's visibility, whose rays test
/// each cut-out's alpha where they meet it: within 1 % in the mean over the floor and
/// panels seen at every 4th pixel of 160×90.
#[test]
fn cut_outs_let_the_environment_through_their_holes() {
    use combustion::renderer::reference::ReferenceShading;
    let (w, h) = (160u32, 90u32);
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/cutout/cutout.gltf");
    let mut scene = combustion::SceneSource::File(path).load().unwrap();
    scene.lights.clear();
    scene.environment = Some(Environment::Uniform([1.0; 3]));
    let bvh = std::sync::Arc::new(combustion::reference::SceneBvh::shadow_casters(&scene));
    let inputs = crate::common::frame_inputs(&scene, &[]);
    let reference =
        ReferenceShading::new(&scene, &inputs, w, h).with_environment_visibility(bvh, 24);
    let traced = against_reference(
        &scene,
        &reference,
        (w, h),
        "cut-outs, ray-traced, 8 seeds",
        with_pass("ray-traced-occlusion", true),
        8,
    )
    .mean;
    assert!(traced.abs() < 0.01, "mean relative error {traced:+.4}");
}

/// The sampled environment (`environment_samples`) with ray-traced occlusion traces each
/// of its directions against the scene, and so converges to the rendering equation's
/// direct environment light with the scene's geometry in the way: builtin:resting as
/// built (plastics) under the studio, 64 samples of each strategy a pixel over 8 seeds,
/// against the f64 reference that traces every direction its integral samples
/// (`ReferenceShading::with_traced_environment`, 1 024 samples of each strategy) at every
/// 4th pixel of 160×90. Without the visibility the same check fails: the sampled mode
/// alone converges to a world without geometry.
#[test]
fn the_sampled_environment_converges_with_the_scene_in_the_way() {
    use combustion::renderer::reference::ReferenceShading;
    let (w, h) = (160u32, 90u32);
    let scene = combustion::scene::builtin_scene("resting").unwrap();
    assert!(matches!(scene.environment, Some(Environment::Studio)));
    let bvh = std::sync::Arc::new(combustion::reference::SceneBvh::shadow_casters(&scene));
    let inputs = crate::common::frame_inputs(&scene, &[]);
    let reference = ReferenceShading::new(&scene, &inputs, w, h).with_traced_environment(bvh, 24);
    let sampled = |traced: bool| {
        let mut settings = with_pass("ray-traced-occlusion", traced);
        settings.shading.environment_samples = 64;
        settings
    };
    let traced = against_reference(
        &scene,
        &reference,
        (w, h),
        "sampled, traced directions, 8 seeds",
        sampled(true),
        8,
    )
    .mean;
    let untraced = against_reference(
        &scene,
        &reference,
        (w, h),
        "sampled, no visibility, 8 seeds",
        sampled(false),
        8,
    )
    .mean;
    assert!(
        traced.abs() < 0.01,
        "traced: mean relative error {traced:+.4}"
    );
    assert!(
        untraced > 0.05,
        "untraced: mean relative error {untraced:+.4}"
    );
}

/// A scene edited between traced frames is traced in its new shape: the sphere lifted a
/// radius off the floor leaves the floor beside where it rested brighter (beneath it, the
/// form factor falls from 1 to a quarter), frames before and after the edit with
/// validation silent.
#[test]
fn an_edited_scene_is_traced_in_its_new_shape() {
    let scene = resting_sphere(true);
    let pixels = floor_pixels(&scene);
    let ring = |hdr: &[[f32; 4]]| {
        let values: Vec<f64> = pixels
            .iter()
            .filter(|(_, d)| (0.25..1.0).contains(d))
            .map(|&(i, _)| f64::from(hdr[i][1]))
            .collect();
        values.iter().sum::<f64>() / values.len() as f64
    };
    let mut headless = crate::common::lavapipe(with_pass("ray-traced-occlusion", true));
    let (resting, lifted) = {
        let renderer = headless.renderer();
        let mut gpu = renderer.upload(&scene).expect("upload");
        let resting = renderer
            .render(&gpu, WIDTH, HEIGHT, IMAGES)
            .expect("render");
        renderer
            .edit_scene(&mut gpu, |scene| {
                scene.objects[1].transform =
                    Mat4::from_translation(Vec3::new(0.0, 2.0 * RADIUS as f32, 0.0));
            })
            .expect("edit");
        let lifted = renderer
            .render(&gpu, WIDTH, HEIGHT, IMAGES)
            .expect("render");
        (ring(&resting.hdr), ring(&lifted.hdr))
    };
    crate::common::finish(headless);
    println!("ring 0.25–1 radii: resting {resting:.4}, lifted {lifted:.4}");
    assert!(
        lifted > resting * 1.2,
        "resting {resting:.4}, lifted {lifted:.4}"
    );
}

/// The optional passes' images (screen-space and traced occlusion, traced shadows' light
/// bits), their lighting bindings (the traced scene and its cut-out tables, bound by the
/// lighting pass for the sampled environment) and the scenes' acceleration structures
/// (deformed objects' rebuilt each traced frame), alternated with frames that have none
/// of them, each for longer than the retire delay, two rounds, validation on: scenes lit
/// by an environment and not (the occlusion passes run only with one), the cut-out
/// panels under the studio with the sampled environment traced, common's deformed
/// spheres under the studio, the passes on and off; and path-traced frames (the surface
/// table bound in the lighting set, glass placed for paths alone) of the glass scene,
/// resting and the cut-outs between them; and traced reflections and refraction (the
/// surface and texture tables in the lighting and forward sets, the environment's
/// distribution) on the glass lit by the studio and not, resting and the deformed
/// spheres, between frames without them. Every binding is written every frame
/// (the placeholders where a pass did not run: `SetWriter::apply` checks it in debug
/// builds), and each configuration renders the same bytes in its second round as in its
/// first, after its images were retired and made again.
#[test]
fn optional_passes_alternate_past_the_retire_delay() {
    use crate::common::FRAMES_PAST_THE_RETIRE_DELAY;
    let all = [
        "ambient-occlusion",
        "ray-traced-occlusion",
        "ray-traced-shadows",
    ]
    .into_iter()
    .map(|name| optional_pass(name).expect("declared"))
    .fold(OptionalPasses::NONE, |set, pass| set.with(pass, true));
    let resting = combustion::scene::builtin_scene("resting").unwrap();
    let spot_box = combustion::scene::builtin_scene("spot-box").unwrap();
    let cutouts_path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/cutout/cutout.gltf");
    let mut cutouts = combustion::SceneSource::File(cutouts_path).load().unwrap();
    cutouts.environment = Some(Environment::Studio);
    let mut deformed = crate::common::deformed_spheres();
    deformed.environment = Some(Environment::Studio);
    let glass = combustion::scene::builtin_scene("glass").unwrap();
    // Path tracing: the surface table and, with glass, the instances paths alone see.
    let traced = OptionalPasses::NONE.with(optional_pass("path-trace").expect("declared"), true);
    // Traced reflections and refraction: the surface and texture tables in the lighting
    // set, the traced scene and those tables in the forward set.
    let rays = OptionalPasses::NONE
        .with(
            optional_pass("ray-traced-reflections").expect("declared"),
            true,
        )
        .with(
            optional_pass("ray-traced-refraction").expect("declared"),
            true,
        );
    let mut glass_lit = glass.clone();
    glass_lit.environment = Some(Environment::Studio);
    let mut settings = exact_f32();
    settings.shading.optional_passes = all;
    let mut headless = crate::common::lavapipe(settings);
    let (w, h) = (96, 64);
    {
        let renderer = headless.renderer();
        let gpus = [&resting, &spot_box, &cutouts, &deformed, &glass, &glass_lit]
            .map(|scene| renderer.upload(scene).expect("upload"));
        // (scene, passes, environment samples)
        let configurations = [
            (0, all, 0),
            (1, all, 0),
            (0, OptionalPasses::NONE, 0),
            (1, OptionalPasses::NONE, 0),
            (2, all, 16),
            (3, all, 0),
            (2, OptionalPasses::NONE, 16),
            (4, traced, 0),
            (0, traced, 0),
            (4, all, 0),
            (2, traced, 0),
            (4, OptionalPasses::NONE, 0),
            (5, rays, 0),
            (0, rays, 0),
            (4, rays, 0),
            (5, OptionalPasses::NONE, 0),
            (3, rays, 0),
            (5, traced, 0),
        ];
        let mut first: Vec<Option<Vec<[f32; 4]>>> = vec![None; configurations.len()];
        let mut ran: Vec<Vec<&'static str>> = vec![Vec::new(); configurations.len()];
        for round in 0..2 {
            for (config, &(scene, passes, samples)) in configurations.iter().enumerate() {
                let shading = combustion::renderer::ShadingOptions {
                    optional_passes: passes,
                    environment_samples: samples,
                    ..renderer.shading()
                };
                renderer
                    .set_shading(shading, &gpus.each_ref())
                    .expect("set shading");
                for _ in 0..FRAMES_PAST_THE_RETIRE_DELAY {
                    let frame = renderer.render(&gpus[scene], w, h, IMAGES).expect("frame");
                    assert_eq!(frame.non_finite_pixels(), 0);
                    if round == 0 {
                        ran[config] = frame.timings.names();
                    }
                    match &first[config] {
                        None => first[config] = Some(frame.hdr),
                        Some(hdr) => {
                            assert!(*hdr == frame.hdr, "configuration {config}, round {round}")
                        }
                    }
                }
            }
        }
        let has = |config: usize, pass: &str| ran[config].contains(&pass);
        // resting (an environment, no lights) with the passes: both occlusion passes and
        // the traced shadows; spot-box (lights, no environment): the traced shadows only.
        assert!(has(0, "ambient occlusion") && has(0, "ray-traced occlusion"));
        assert!(has(0, "ray-traced shadows") && has(1, "ray-traced shadows"));
        assert!(!has(1, "ambient occlusion") && !has(1, "ray-traced occlusion"));
        // The cut-outs' sampled environment and the deformed spheres trace too.
        assert!(has(4, "ray-traced occlusion") && has(5, "ray-traced occlusion"));
        assert!(has(5, "deform"), "{:?}", ran[5]);
        // Path-traced frames run the path trace pass (and no other that traces).
        for config in [7, 8, 10] {
            assert!(has(config, "path trace"), "{:?}", ran[config]);
            assert!(!has(config, "ray-traced occlusion"), "{:?}", ran[config]);
        }
        assert!(!has(9, "path trace") && !has(11, "path trace"));
        // Traced reflections where an environment lights the frame (the lit glass,
        // resting, the deformed spheres), traced refraction where there is glass.
        for config in [12, 13, 16] {
            assert!(has(config, "ray-traced reflections"), "{:?}", ran[config]);
        }
        assert!(!has(14, "ray-traced reflections"), "{:?}", ran[14]);
        for config in [12, 14] {
            assert!(has(config, "ray-traced refraction"), "{:?}", ran[config]);
        }
        assert!(!has(13, "ray-traced refraction") && !has(16, "ray-traced refraction"));
        assert!(has(17, "path trace") && !has(15, "ray-traced reflections"));
        for config in [2, 3, 6, 11] {
            assert!(
                !ran[config]
                    .iter()
                    .any(|p| p.contains("occlusion") || p.contains("ray-traced")),
                "{:?}",
                ran[config]
            );
        }
    }
    crate::common::finish(headless);
}

/// The viewer's error view (X) measures a frame whose environment the scene blocks
/// against the reference with the environment's visibility (the occlusion passes'
/// definition): builtin:resting with ray-traced occlusion is about as close to it as the
/// frame without occlusion is to the reference without — where, measured against the
/// unblocked environment, it would be several times further off.
#[test]
fn the_error_view_measures_occlusion_against_visibility() {
    let scene = combustion::scene::builtin_scene("resting").unwrap();
    let inputs = crate::common::frame_inputs(&scene, &[]);
    let mean_error = |settings: RendererSettings| {
        let mut headless = crate::common::lavapipe(settings);
        let summary = {
            let renderer = headless.renderer();
            let gpu = renderer.upload(&scene).unwrap();
            combustion::viewer::inspect::measure_error(
                renderer,
                &gpu,
                &inputs,
                (WIDTH / 4, HEIGHT / 4),
            )
            .unwrap()
        };
        crate::common::finish(headless);
        summary.mean_relative
    };
    let none = mean_error(settings(false));
    let traced = mean_error(with_pass("ray-traced-occlusion", true));
    println!("error view, mean relative error: no occlusion {none:.4}, ray-traced {traced:.4}");
    assert!(
        traced < 2.0 * none,
        "ray-traced {traced:.4}, none {none:.4}"
    );
}

/// The traced pass's split sum against the rendering equation with the scene in the way
/// (the f64 reference that traces every direction its integral samples,
/// `ReferenceShading::with_traced_environment`): builtin:resting as built under the
/// studio, 8 seeds, every 4th pixel of 160×90. The split sum applies one visibility to
/// the whole hemisphere, whichever part of the studio the scene hides: measured −2.1 % in
/// the mean, 5.5 % in magnitude, held within 3 % and 7 %; the screen-space pass's +0.36 %
/// and 8.4 % (one frame), held within 2 % and 10 %. (Looking the diffuse irradiance up
/// along the bent normal, the mean open direction, was tried for both: the traced pass
/// +1.8 % and 6.3 %; the screen-space pass, its bent normal by Jimenez et al.'s slice
/// integral, +3.9 % and 11.9 % — no closer either way; not kept.)
#[test]
fn traced_occlusion_against_the_rendering_equation() {
    use combustion::renderer::reference::ReferenceShading;
    let (w, h) = (160u32, 90u32);
    let scene = combustion::scene::builtin_scene("resting").unwrap();
    let bvh = std::sync::Arc::new(combustion::reference::SceneBvh::shadow_casters(&scene));
    let inputs = crate::common::frame_inputs(&scene, &[]);
    let reference = ReferenceShading::new(&scene, &inputs, w, h).with_traced_environment(bvh, 24);
    let Against {
        mean, magnitude, ..
    } = against_reference(
        &scene,
        &reference,
        (w, h),
        "ray-traced split sum against the rendering equation, 8 seeds",
        with_pass("ray-traced-occlusion", true),
        8,
    );
    let screen = against_reference(
        &scene,
        &reference,
        (w, h),
        "screen-space split sum against the rendering equation",
        settings(true),
        1,
    );
    assert!(mean.abs() < 0.03, "mean relative error {mean:+.4}");
    assert!(magnitude < 0.07, "mean |relative error| {magnitude:.4}");
    assert!(
        screen.mean.abs() < 0.02,
        "screen-space: {:+.4}",
        screen.mean
    );
    assert!(
        screen.magnitude < 0.10,
        "screen-space: {:.4}",
        screen.magnitude
    );
}
