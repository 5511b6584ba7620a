//! The f64 path tracer against what is known without it: the white furnace's closed form,
//! the one-bounce reference it must reduce to, its own standard errors, and light that
//! visibly bounces (a Cornell-type box's coloured walls tint its white floor).

use combustion_optics::environment::Estimate;
use combustion_reference::path::{PathTracer, PathTracing};
use combustion_reference::shading::SceneShading;
use combustion_reference::SceneBvh;
use combustion_scene::{builtin_scene, Camera, Material, Mesh, Object, Scene, Volume};
use glam::{Mat4, Vec3};

const THREADS: usize = 2;

/// `base` (its medium and motion) holding one sphere of `radius` at the origin, of
/// `material`, seen by `camera`, lit by `environment` alone.
fn lone_sphere(
    base: Scene,
    radius: f32,
    material: Material,
    camera: Camera,
    environment: Option<combustion_scene::Environment>,
) -> Scene {
    Scene {
        meshes: vec![Mesh::uv_sphere("sphere", radius, 48, 24)],
        materials: vec![material],
        objects: vec![Object {
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
            casts_shadows: true,
            node: None,
        }],
        lights: Vec::new(),
        camera,
        environment,
        ..base
    }
}

/// A camera at the centre of a closed sphere (radius 1) of one Lambertian material of
/// albedo `albedo` that emits radiance 1, double-sided so its inside is its front.
fn furnace(albedo: f32) -> Scene {
    let glowing = Material {
        name: "glowing white".into(),
        base_color: [albedo; 3],
        roughness: 1.0,
        dielectric_ior: 1.0,
        emissive_factor: [1.0; 3],
        emissive_strength: 1.0,
        double_sided: true,
        ..Material::default()
    };
    let camera = Camera {
        position: Vec3::ZERO,
        target: Vec3::new(0.3, 0.2, -1.0),
        up: Vec3::Y,
        vertical_fov: 90f32.to_radians(),
        near: 0.01,
        far: 10.0,
    };
    let base = builtin_scene("spheres").expect("built-in scene");
    lone_sphere(base, 1.0, glowing, camera, None)
}

/// The path-traced frame of `scene` at `width` × `height`.
fn path_traced(
    scene: &Scene,
    width: u32,
    height: u32,
    tracing: PathTracing,
) -> Vec<Option<Estimate>> {
    let bvh = SceneBvh::new(scene);
    let casters = SceneBvh::shadow_casters(scene);
    let shading = SceneShading::new(scene, &bvh, &scene.lights, width, height);
    PathTracer::new(&shading, &casters, tracing).render(THREADS)
}

/// Holds a furnace frame at `exact`: every pixel's green channel by its z-score (|z| < 5:
/// a false failure about once in 1.7 million pixels if the estimates are normal), and
/// the mean of the pixels `counted` by its own standard error (itself below 0.5 % of
/// `exact`, so that a bias of 2 % fails); `what` names the case in messages.
fn holds_furnace(
    frame: &[Option<Estimate>],
    exact: f64,
    counted: impl Fn(usize) -> bool,
    what: &str,
) {
    let (mut sum, mut variance, mut count) = (0.0, 0.0, 0.0);
    for (i, pixel) in frame.iter().enumerate() {
        let pixel = pixel.expect("every pixel sees the furnace's wall");
        let (mean, standard_error) = (pixel.mean[1], pixel.standard_error[1]);
        let z = (mean - exact) / standard_error;
        assert!(
            z.abs() < 5.0,
            "{what}, pixel {i}: {mean} ± {standard_error} against {exact} (z = {z:.2})"
        );
        if counted(i) {
            sum += mean;
            variance += standard_error * standard_error;
            count += 1.0;
        }
    }
    assert!(count > 30.0, "{what}: {count} pixels counted");
    let (mean, standard_error) = (sum / count, variance.sqrt() / count);
    println!("{what}: mean {mean:.5} ± {standard_error:.5} against {exact:.5} over {count} pixels");
    assert!(
        (mean - exact).abs() < 4.0 * standard_error && standard_error < 5e-3 * exact,
        "{what}: mean {mean} ± {standard_error} against {exact}"
    );
}

/// L = E + ρ L in a closed furnace of uniform emission E = 1: every pixel converges to
/// 1/(1 − ρ) ([`holds_furnace`]).
#[test]
fn white_furnace_every_pixel_is_emission_over_one_minus_albedo() {
    for albedo in [0.5f32, 0.8] {
        let scene = furnace(albedo);
        let tracing = PathTracing {
            samples: 1024,
            max_depth: 200,
            seed: 1,
        };
        let frame = path_traced(&scene, 16, 12, tracing);
        let exact = 1.0 / (1.0 - f64::from(albedo));
        // The walls are grey and every channel follows the same paths.
        for (i, pixel) in frame.iter().enumerate() {
            let mean = pixel.expect("every pixel sees the furnace's wall").mean;
            assert!(
                mean.iter().all(|&m| m == mean[0]),
                "pixel {i}: grey walls, grey paths"
            );
        }
        holds_furnace(&frame, exact, |_| true, &format!("albedo {albedo}"));
    }
}

/// A lossless dielectric in a furnace is invisible: a solid glass ball (index 1.5, smooth,
/// no absorption) inside the glowing sphere leaves every pixel at 1/(1 − ρ), the paths
/// that enter it refracted, reflected inside (totally past the critical angle) and let
/// out by the Fresnel equations' probabilities. The ball covers a sixth of the frame
/// (32 of 192 pixels; their mean 1.9975 ± 0.0064 when written); the check fails if the
/// exit's reflection is dropped or the entry's transmittance counted twice.
#[test]
fn a_glass_ball_in_the_white_furnace_disappears() {
    let albedo = 0.5f32;
    let mut scene = furnace(albedo);
    scene.meshes.push(Mesh::uv_sphere("ball", 0.25, 48, 24));
    scene.materials.push(Material {
        name: "glass".into(),
        base_color: [1.0; 3],
        roughness: 0.0,
        transmission: 1.0,
        volume: Some(Volume {
            thickness: 0.5,
            attenuation_distance: f32::INFINITY,
            attenuation_color: [1.0; 3],
        }),
        ..Material::default()
    });
    scene.objects.push(Object {
        mesh: 1,
        material: 1,
        transform: Mat4::from_translation(Vec3::new(0.15, 0.1, -0.5)),
        casts_shadows: true,
        node: None,
    });
    let frame = path_traced(
        &scene,
        16,
        12,
        PathTracing {
            samples: 4096,
            max_depth: 200,
            seed: 5,
        },
    );
    let exact = 1.0 / (1.0 - f64::from(albedo));
    let bvh = SceneBvh::new(&scene);
    let shading = SceneShading::new(&scene, &bvh, &scene.lights, 16, 12);
    let sees_the_ball = |i: usize| {
        let (x, y) = (i as u32 % 16, i as u32 / 16);
        !shading.blended_surfaces(x, y).is_empty()
    };
    holds_furnace(&frame, exact, sees_the_ball, "the glass ball");
}

/// With one surface lit (no bounce), a path is the one-bounce reference with exact
/// visibility: its emission and each light's direct term (in a closed room lit by a spot
/// light alone: no emitter or environment for the sampled direction to find).
#[test]
fn a_path_of_depth_one_is_the_one_bounce_reference() {
    let scene = builtin_scene("spot-box").unwrap();
    let (width, height) = (24, 18);
    let bvh = SceneBvh::new(&scene);
    let casters = SceneBvh::shadow_casters(&scene);
    let shading = SceneShading::new(&scene, &bvh, &scene.lights, width, height);
    let one_bounce =
        SceneShading::new(&scene, &bvh, &scene.lights, width, height).with_visibility(&casters);
    let tracing = PathTracing {
        samples: 2,
        max_depth: 1,
        seed: 3,
    };
    let tracer = PathTracer::new(&shading, &casters, tracing);
    let mut compared = 0;
    for y in 0..height {
        for x in 0..width {
            let (Some(traced), Some(reference)) = (tracer.pixel(x, y), one_bounce.pixel(x, y))
            else {
                continue;
            };
            assert_eq!(traced.mean, reference.radiance, "pixel ({x}, {y})");
            assert_eq!(
                traced.standard_error, [0.0; 3],
                "pixel ({x}, {y}): nothing sampled"
            );
            compared += 1;
        }
    }
    assert!(compared > width * height / 2, "{compared} pixels compared");
}

/// Two seeds' estimates of one frame differ by no more than their standard errors say:
/// z = (a − b)/√(σa² + σb²) has a mean square near 1 and few |z| > 4 (the standard
/// errors are honest, which every statistical test against this reference relies on).
#[test]
fn two_seeds_agree_within_their_standard_errors() {
    let scene = builtin_scene("cornell-box").unwrap();
    let frame = |seed| {
        path_traced(
            &scene,
            24,
            18,
            PathTracing {
                samples: 64,
                max_depth: 16,
                seed,
            },
        )
    };
    let (a, b) = (frame(11), frame(12));
    let mut z_squares = Vec::new();
    for (a, b) in a.iter().zip(&b) {
        let (a, b) = (a.expect("closed box"), b.expect("closed box"));
        for c in 0..3 {
            let spread = (a.standard_error[c].powi(2) + b.standard_error[c].powi(2)).sqrt();
            if spread > 0.0 {
                z_squares.push(((a.mean[c] - b.mean[c]) / spread).powi(2));
            }
        }
    }
    let n = z_squares.len() as f64;
    let mean_square = z_squares.iter().sum::<f64>() / n;
    let beyond_four = z_squares.iter().filter(|&&z2| z2 > 16.0).count();
    assert!(n > 1000.0, "{n} channels compared");
    assert!(
        (0.7..1.4).contains(&mean_square),
        "mean z² {mean_square:.3} over {n} channels (1 for honest standard errors)"
    );
    assert!(
        beyond_four <= 3,
        "{beyond_four} of {n} channels beyond |z| = 4"
    );
}

/// In the closed box, light bounces: every part of the frame is at least as bright as its
/// direct light (the one-bounce reference), and the white floor, neutral in direct light,
/// turns red beside the red wall and green beside the green one.
#[test]
fn bounced_light_tints_the_floor_by_the_walls_beside_it() {
    let scene = builtin_scene("cornell-box").unwrap();
    let (width, height) = (32, 24);
    let bvh = SceneBvh::new(&scene);
    let casters = SceneBvh::shadow_casters(&scene);
    let shading = SceneShading::new(&scene, &bvh, &scene.lights, width, height);
    let one_bounce =
        SceneShading::new(&scene, &bvh, &scene.lights, width, height).with_visibility(&casters);
    let traced = PathTracer::new(
        &shading,
        &casters,
        PathTracing {
            samples: 64,
            ..PathTracing::default()
        },
    )
    .render(THREADS);
    // (red − green)/(red + green) of the floor's mean, left and right of the centre.
    let mut floor = [[0.0; 3]; 2];
    let mut floor_direct = [[0.0; 3]; 2];
    let (mut added, mut added_variance) = (0.0, 0.0);
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            let traced = traced[i].expect("closed box");
            let surface = shading.surface(x, y).expect("closed box");
            let direct = one_bounce.pixel(x, y).expect("closed box").radiance;
            for (c, direct) in direct.iter().enumerate() {
                // Every path adds the direct light and what its bounces find (≥ 0).
                assert!(
                    traced.mean[c] >= direct * (1.0 - 1e-12),
                    "pixel ({x}, {y}): {} below its direct light {direct}",
                    traced.mean[c]
                );
                added += traced.mean[c] - direct;
                added_variance += traced.standard_error[c].powi(2);
            }
            if surface.hit.object == 0 && surface.hit.position[0].abs() > 0.3 {
                let side = usize::from(surface.hit.position[0] > 0.0);
                for c in 0..3 {
                    floor[side][c] += traced.mean[c];
                    floor_direct[side][c] += direct[c];
                }
            }
        }
    }
    let tint = |rgb: [f64; 3]| (rgb[0] - rgb[1]) / (rgb[0] + rgb[1]);
    assert!(
        added > 10.0 * added_variance.sqrt(),
        "bounces add {added} ± {} to the frame's sum",
        added_variance.sqrt()
    );
    for direct in floor_direct {
        assert!(
            tint(direct).abs() < 1e-9,
            "direct light on the white floor is neutral: {direct:?}"
        );
    }
    let (left, right) = (tint(floor[0]), tint(floor[1]));
    assert!(
        left > 0.05 && right < -0.05,
        "the floor's tint: {left:.3} by the red wall, {right:.3} by the green"
    );
}

/// Direct light from the environment, two ways: a path of depth 1 finds the studio by
/// the one direction it samples per path, the one-bounce reference integrates it with
/// each of its strategies per sample (combustion_optics' environment integral). On a lone
/// sphere (nothing in the way of its hemisphere) of each kind of lobe — red plastic and
/// gold of roughness 0.1, anisotropic aluminium, a coat of roughness 0.15 over red, cloth
/// with a sheen, black plastic under a 500 nm film — the two agree per pixel within their
/// combined standard errors (mean z² 1.10 over 1,080 channels when written).
#[test]
fn direct_environment_light_matches_the_environment_integral() {
    let (size, samples) = (10u32, 512u32);
    let mut z_squares = Vec::new();
    for (source, material) in [
        ("spheres", 0usize),
        ("spheres", 6),
        ("spheres", 20),
        ("clearcoat", 1),
        ("sheen", 1),
        ("iridescence", 2),
    ] {
        let from = builtin_scene(source).unwrap();
        let camera = Camera {
            position: Vec3::new(0.4, 0.6, 2.5),
            target: Vec3::ZERO,
            up: Vec3::Y,
            vertical_fov: 25f32.to_radians(),
            near: 0.1,
            far: 10.0,
        };
        let studio = Some(combustion_scene::Environment::Studio);
        let scene = lone_sphere(
            from.clone(),
            0.5,
            from.materials[material].clone(),
            camera,
            studio,
        );
        let bvh = SceneBvh::new(&scene);
        let casters = SceneBvh::shadow_casters(&scene);
        let shading = SceneShading::new(&scene, &bvh, &scene.lights, size, size);
        let integral =
            SceneShading::new(&scene, &bvh, &scene.lights, size, size).with_environment(samples);
        let tracer = PathTracer::new(
            &shading,
            &casters,
            PathTracing {
                samples,
                max_depth: 1,
                seed: 9,
            },
        );
        for y in 0..size {
            for x in 0..size {
                let (Some(traced), Some(surface)) = (tracer.pixel(x, y), integral.surface(x, y))
                else {
                    continue;
                };
                let estimate = integral.environment_estimate(&surface).expect("the studio");
                for c in 0..3 {
                    let spread = (traced.standard_error[c].powi(2)
                        + estimate.standard_error[c].powi(2))
                    .sqrt();
                    let z = (traced.mean[c] - estimate.mean[c] - surface.emitted[c]) / spread;
                    assert!(
                        z.abs() < 5.0,
                        "{source} material {material} pixel ({x}, {y}) channel {c}: traced {} ± {}, integral {} ± {}",
                        traced.mean[c],
                        traced.standard_error[c],
                        estimate.mean[c],
                        estimate.standard_error[c]
                    );
                    z_squares.push(z * z);
                }
            }
        }
    }
    let n = z_squares.len() as f64;
    let mean_square = z_squares.iter().sum::<f64>() / n;
    assert!(n > 500.0, "{n} channels compared");
    assert!(
        (0.6..1.6).contains(&mean_square),
        "mean z² {mean_square:.3} over {n} channels"
    );
}
