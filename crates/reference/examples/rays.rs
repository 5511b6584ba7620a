//! Build time and ray throughput of the reference hierarchy, single-threaded:
//! `cargo run --release -p combustion-reference --example rays [FILE.gltf|FILE.glb ...]`.
//!
//! For each built-in scene measured ("grid-7x7", "spheres") and each glTF file given
//! (by default, whichever of a few Khronos sample models exist under
//! ../shared/data/gltf), it prints the triangle count, the build time, and the rate of
//! closest-hit rays (from the scene's camera through a grid of directions, and from
//! random points in the scene's box in random directions) and of any-hit rays
//! (shadow segments between random points). Timings only: nothing is asserted.

use std::path::{Path, PathBuf};
use std::time::Instant;

use combustion_reference::{Ray, SceneBvh};
use combustion_scene::{builtin_scene, Scene};

const RAYS: usize = 400_000;

fn main() {
    let mut scenes: Vec<(String, Scene)> = ["grid-7x7", "spheres"]
        .iter()
        .map(|name| {
            let scene = builtin_scene(name).expect("a built-in scene");
            (format!("builtin:{name}"), scene)
        })
        .collect();
    let mut files: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    if files.is_empty() {
        let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/gltf");
        for model in [
            "Sponza/glTF/Sponza.gltf",
            "SpecGlossVsMetalRough/glTF-Binary/SpecGlossVsMetalRough.glb",
            "IridescenceLamp/glTF-Binary/IridescenceLamp.glb",
            "SheenCloth/glTF/SheenCloth.gltf",
            "GlassHurricaneCandleHolder/glTF-Binary/GlassHurricaneCandleHolder.glb",
        ] {
            let path = shared.join(model);
            if path.is_file() {
                files.push(path);
            }
        }
    }
    for path in files {
        let options = combustion_scene::gltf::ImportOptions::default();
        match combustion_scene::gltf::import(&path, &options) {
            Ok((scene, _report)) => scenes.push((path.display().to_string(), scene)),
            Err(error) => println!("{}: not imported: {error}", path.display()),
        }
    }
    println!(
        "{:<44} {:>9} {:>9} {:>12} {:>9} {:>12} {:>12}",
        "scene", "triangles", "build ms", "camera Mr/s", "hit %", "random Mr/s", "shadow Mr/s"
    );
    for (name, scene) in &scenes {
        measure(name, scene);
    }
}

fn measure(name: &str, scene: &Scene) {
    let start = Instant::now();
    let bvh = SceneBvh::new(scene);
    let build = start.elapsed().as_secs_f64();
    let Some((min, max)) = bvh.bounds() else {
        println!("{name}: no triangles");
        return;
    };
    let mut random = XorShift(0x9e37_79b9_7f4a_7c15);
    let point_in_box =
        |random: &mut XorShift| [0, 1, 2].map(|k| min[k] + (max[k] - min[k]) * random.next_f64());

    // Primary rays: the camera's position through a square grid of directions about
    // its view direction (no projection needed to measure throughput).
    let camera = &scene.camera;
    let eye = camera.position.as_dvec3();
    let forward = (camera.target.as_dvec3() - eye).normalize_or_zero();
    let right = forward.cross(glam::DVec3::Y).normalize_or_zero();
    let up = right.cross(forward);
    let side = (RAYS as f64).sqrt() as usize;
    let camera_rays: Vec<Ray> = (0..side * side)
        .map(|i| {
            let x = (i % side) as f64 / side as f64 * 2.0 - 1.0;
            let y = (i / side) as f64 / side as f64 * 2.0 - 1.0;
            Ray::new(
                eye.to_array(),
                (forward + 0.6 * (x * right + y * up)).to_array(),
            )
        })
        .collect();
    let random_rays: Vec<Ray> = (0..RAYS)
        .map(|_| {
            let origin = point_in_box(&mut random);
            let direction = [0; 3].map(|_| random.next_f64() * 2.0 - 1.0);
            Ray::new(origin, direction)
        })
        .collect();
    let shadow_rays: Vec<Ray> = (0..RAYS)
        .map(|_| Ray::through(point_in_box(&mut random), point_in_box(&mut random)))
        .collect();

    let rate = |rays: &[Ray], cast: &dyn Fn(&Ray) -> bool| {
        let start = Instant::now();
        let hits = rays.iter().filter(|ray| cast(ray)).count();
        let seconds = start.elapsed().as_secs_f64();
        (rays.len() as f64 / seconds / 1e6, hits)
    };
    let (camera_rate, camera_hits) = rate(&camera_rays, &|ray| {
        bvh.closest_hit(ray, 0.0, f64::INFINITY).is_some()
    });
    let (random_rate, _) = rate(&random_rays, &|ray| {
        bvh.closest_hit(ray, 0.0, f64::INFINITY).is_some()
    });
    let (shadow_rate, _) = rate(&shadow_rays, &|ray| bvh.any_hit(ray, 0.0, 1.0));
    let short_name: String = name
        .chars()
        .rev()
        .take(44)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    println!(
        "{:<44} {:>9} {:>9.1} {:>12.2} {:>9.1} {:>12.2} {:>12.2}",
        short_name,
        bvh.triangle_count(),
        build * 1e3,
        camera_rate,
        100.0 * camera_hits as f64 / camera_rays.len() as f64,
        random_rate,
        shadow_rate
    );
}

/// xorshift64: deterministic ray sets.
struct XorShift(u64);

impl XorShift {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
