//! The hierarchy answers exactly what a loop over every triangle answers, and a closed
//! mesh lets no ray through.

use crate::common::{place, scene_of, welded_uv_sphere, Random};
use combustion_reference::{Ray, SceneBvh, TriangleTest, WorldTriangle};
use combustion_scene::{builtin_scene, Mesh, BUILTIN_SCENES};
use glam::{DVec3, Mat4, Quat, Vec3};

/// A hit as the brute force lists it: (t, object, triangle, barycentrics).
type BruteHit = (f64, usize, usize, [f64; 2]);

/// Triangles per block of [`brute_force_hits`]: 2 048 of 88 bytes (180 KB) stay in a
/// core's cache while every ray passes over them.
const TRIANGLES_PER_BLOCK: usize = 2048;

/// For each (ray, t_min) of `rays`, every hit beyond t_min over every triangle, sorted by
/// t and then (object, triangle): the closest hit below any t_max is the first entry
/// with t < t_max (the triangle test's interval check is `t_min < t < t_max` on the same
/// computed t, so one pass serves every t_max). The loop runs block of triangles by
/// block, every ray over each block: the same tests as ray by ray, without reading the
/// whole scene from memory again for each ray (the sphere grid's 216 576 triangles are
/// 19 MB).
fn brute_force_hits(triangles: &[WorldTriangle], rays: &[(&Ray, f64)]) -> Vec<Vec<BruteHit>> {
    let tests: Vec<TriangleTest> = rays.iter().map(|(ray, _)| TriangleTest::new(ray)).collect();
    let mut hits: Vec<Vec<BruteHit>> = vec![Vec::new(); rays.len()];
    for block in triangles.chunks(TRIANGLES_PER_BLOCK) {
        for ((test, &(_, t_min)), hits) in tests.iter().zip(rays).zip(&mut hits) {
            hits.extend(block.iter().filter_map(|triangle| {
                test.intersect(&triangle.vertices, t_min, f64::INFINITY)
                    .map(|(t, barycentrics)| (t, triangle.object, triangle.triangle, barycentrics))
            }));
        }
    }
    for hits in &mut hits {
        hits.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    }
    hits
}

/// `rays` random rays against `bvh` and a brute-force loop: half from points in and
/// around the scene's box in random directions (random lengths), half aimed at a
/// random point of a random triangle; t_min 0 or a random positive value; t_max
/// unbounded, random, exactly the brute-force hit's t, or just beyond it. Returns how
/// many rays hit. The rays are shared between two threads.
fn compare_with_brute_force(label: &str, bvh: &SceneBvh, rays: usize, seed: u64) -> usize {
    let triangles = bvh.triangles();
    let (min, max) = bvh.bounds().expect("a scene with triangles");
    let (min, max) = (DVec3::from(min), DVec3::from(max));
    let extent = (max - min).max(DVec3::splat(1e-3));
    let mut random = Random::new(seed);
    let mut cases = Vec::with_capacity(rays);
    for k in 0..rays {
        let origin = DVec3::new(
            random.range(min.x - 0.2 * extent.x, max.x + 0.2 * extent.x),
            random.range(min.y - 0.2 * extent.y, max.y + 0.2 * extent.y),
            random.range(min.z - 0.2 * extent.z, max.z + 0.2 * extent.z),
        );
        let direction = if k % 2 == 0 {
            random.direction() * random.range(0.01, 10.0)
        } else {
            let triangle = &triangles[random.below(triangles.len())];
            let (mut b1, mut b2) = (random.unit(), random.unit());
            if b1 + b2 > 1.0 {
                (b1, b2) = (1.0 - b1, 1.0 - b2);
            }
            let [p0, p1, p2] = triangle.vertices.map(DVec3::from);
            let target = p0 + b1 * (p1 - p0) + b2 * (p2 - p0);
            (target - origin) * random.range(0.5, 2.0)
        };
        let ray = Ray::new(origin.to_array(), direction.to_array());
        let t_min = if k % 3 == 0 {
            random.range(0.0, 0.5)
        } else {
            0.0
        };
        let t_random = random.range(t_min, t_min + 3.0);
        cases.push((k, ray, t_min, t_random));
    }
    let check = |(k, ray, t_min, t_random): &(usize, Ray, f64, f64), hits: &[BruteHit]| -> bool {
        let (k, t_min) = (*k, *t_min);
        let mut limits = vec![f64::INFINITY, *t_random];
        if let Some(&(t, ..)) = hits.first() {
            limits.push(t);
            limits.push(t * (1.0 + 1e-9));
        }
        for t_max in limits {
            let expected = hits.iter().find(|hit| hit.0 < t_max).copied();
            let found = bvh.closest_hit(ray, t_min, t_max);
            match (expected, found) {
                (None, None) => {}
                (Some((t, object, triangle, barycentrics)), Some(hit)) => {
                    assert!(
                        (hit.t - t).abs() <= 1e-12 * t.abs(),
                        "{label} ray {k}: t {} against {t}",
                        hit.t
                    );
                    assert_eq!(
                        (hit.object, hit.triangle),
                        (object, triangle),
                        "{label} ray {k} ({ray:?}, t in ({t_min}, {t_max}))"
                    );
                    assert_eq!(hit.barycentrics, barycentrics, "{label} ray {k}");
                }
                (expected, found) => panic!(
                    "{label} ray {k} ({ray:?}, t in ({t_min}, {t_max})): brute force {expected:?}, hierarchy {found:?}"
                ),
            }
            assert_eq!(
                bvh.any_hit(ray, t_min, t_max),
                expected.is_some(),
                "{label} ray {k}: any_hit, t in ({t_min}, {t_max})"
            );
        }
        !hits.is_empty()
    };
    let check_all = |cases: &[(usize, Ray, f64, f64)]| {
        let rays: Vec<(&Ray, f64)> = cases
            .iter()
            .map(|(_, ray, t_min, _)| (ray, *t_min))
            .collect();
        let hits = brute_force_hits(triangles, &rays);
        cases
            .iter()
            .zip(&hits)
            .filter(|(case, hits)| check(case, hits))
            .count()
    };
    let (first, second) = cases.split_at(rays / 2);
    std::thread::scope(|scope| {
        let other = scope.spawn(|| check_all(second));
        let here = check_all(first);
        here + other.join().expect("the other half of the rays")
    })
}

#[test]
fn every_built_in_scene_agrees_with_brute_force() {
    let mut seen: Vec<(&str, Vec<WorldTriangle>)> = Vec::new();
    for (i, name) in BUILTIN_SCENES.iter().enumerate() {
        let scene = builtin_scene(name).unwrap();
        let bvh = SceneBvh::new(&scene);
        if let Some(same) = seen
            .iter()
            .find(|(_, triangles)| triangles == bvh.triangles())
        {
            // The hierarchy is deterministic: the same triangles, the same answers.
            println!("{name}: the geometry of {}, not cast again", same.0);
            continue;
        }
        // The hierarchy holds every triangle of every object.
        let expected: usize = scene
            .objects
            .iter()
            .map(|o| scene.meshes[o.mesh].indices.len() / 3)
            .sum();
        assert_eq!(bvh.triangle_count(), expected, "{name}");
        let rays = 2000;
        let hits = compare_with_brute_force(name, &bvh, rays, 1000 + i as u64);
        println!(
            "{name}: {} triangles, {hits} of {rays} rays hit",
            bvh.triangle_count()
        );
        assert!(hits > rays / 4, "{name}: only {hits} hits");
        seen.push((name, bvh.triangles().to_vec()));
    }
}

/// A soup of random triangles of every size (slivers, huge ones, duplicates sharing a
/// position under two identities, axis-aligned ones) and some that cannot be hit.
#[test]
fn a_random_triangle_soup_agrees_with_brute_force() {
    let mut random = Random::new(42);
    let mut triangles = Vec::new();
    for i in 0..3000 {
        let center = DVec3::new(
            random.range(-10.0, 10.0),
            random.range(-10.0, 10.0),
            random.range(-10.0, 10.0),
        );
        let size = match i % 10 {
            0 => random.range(2.0, 8.0),
            1..=3 => random.range(1e-3, 1e-2),
            _ => random.range(0.05, 1.0),
        };
        let mut vertices = [0; 3].map(|_| (center + random.direction() * size).to_array());
        if i % 17 == 0 {
            // axis-aligned: flat boxes
            for v in &mut vertices {
                v[1] = center.y;
            }
        }
        if i % 29 == 0 {
            // a sliver: the third vertex almost on the first edge
            let [p0, p1, _] = vertices.map(DVec3::from);
            vertices[2] = (p0 + 0.5 * (p1 - p0) + DVec3::splat(1e-9)).to_array();
        }
        triangles.push(WorldTriangle {
            object: i / 100,
            triangle: i % 100,
            vertices,
        });
        if i % 50 == 0 {
            // the same triangle again under a larger identity: every hit a tie
            triangles.push(WorldTriangle {
                object: 1000 + i,
                triangle: 0,
                vertices,
            });
        }
    }
    let proper = triangles.len();
    // Improper triangles are left out.
    triangles.push(WorldTriangle {
        object: 9999,
        triangle: 0,
        vertices: [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
    });
    triangles.push(WorldTriangle {
        object: 9999,
        triangle: 1,
        vertices: [[0.0; 3], [f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]],
    });
    let bvh = SceneBvh::from_triangles(triangles);
    assert_eq!(bvh.triangle_count(), proper);
    let hits = compare_with_brute_force("soup", &bvh, 4000, 7);
    println!("soup: {proper} triangles, {hits} of 4000 rays hit");
}

/// Rays from the centre of a closed UV sphere (moved and turned) towards every vertex
/// and every edge's midpoint all hit it, at t = 1: `Mesh::uv_sphere` as it is (whose
/// seam and south pole vertices are not exactly where those of angle 0 are, the f32
/// angles 2π and π being off by an ulp), and welded (every seam and pole vertex at one
/// position, a mesh closed by shared positions, which watertightness is about).
#[test]
fn rays_at_the_vertices_and_edges_of_a_closed_sphere_never_miss() {
    for (segments, rings, welded) in [
        (64, 32, false),
        (256, 128, false),
        (7, 5, true),
        (64, 32, true),
        (256, 128, true),
    ] {
        let mesh = if welded {
            welded_uv_sphere(1.5, segments, rings)
        } else {
            Mesh::uv_sphere("sphere", 1.5, segments, rings)
        };
        let transform = Mat4::from_rotation_translation(
            Quat::from_euler(glam::EulerRot::XYZ, 0.4, -1.2, 0.7),
            Vec3::new(3.25, -1.5, 20.125),
        );
        let bvh = SceneBvh::new(&scene_of(vec![mesh.clone()], &[(0, transform)]));
        let center = place(transform, [0.0; 3]);
        let mut targets: Vec<DVec3> = mesh
            .vertices
            .iter()
            .map(|v| place(transform, v.position))
            .collect();
        for triangle in mesh.indices.chunks_exact(3) {
            for k in 0..3 {
                let a = place(transform, mesh.vertices[triangle[k] as usize].position);
                let b = place(
                    transform,
                    mesh.vertices[triangle[(k + 1) % 3] as usize].position,
                );
                targets.push((a + b) / 2.0);
            }
        }
        let mut misses = 0;
        for target in &targets {
            let ray = Ray::new(center.to_array(), (*target - center).to_array());
            match bvh.closest_hit(&ray, 0.0, f64::INFINITY) {
                Some(hit) => assert!((hit.t - 1.0).abs() < 1e-6, "t {} at {target}", hit.t),
                None => misses += 1,
            }
            assert!(bvh.any_hit(&ray, 0.0, f64::INFINITY));
        }
        assert_eq!(
            misses,
            0,
            "{segments}×{rings} (welded: {welded}): {misses} of {} rays missed",
            targets.len()
        );
    }
}

#[test]
fn hits_report_the_object_triangle_point_and_front_normal() {
    // Two planes: one lifted to y = 1, one mirrored (a negative x scale reverses its
    // winding: it faces down) at y = 3; a mesh index out of range and an object naming
    // no mesh are left out.
    let mut broken = Mesh::plane("broken", 1.0);
    broken.indices.extend_from_slice(&[0, 1, 99]);
    let lifted = Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0));
    let mirrored = Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0))
        * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let scene = scene_of(
        vec![Mesh::plane("ground", 4.0), broken],
        &[
            (0, lifted),
            (7, Mat4::IDENTITY),
            (0, mirrored),
            (1, Mat4::IDENTITY),
        ],
    );
    let bvh = SceneBvh::new(&scene);
    assert_eq!(bvh.triangle_count(), 2 + 2 + 2);
    let down = Ray::new([0.5, 2.0, -0.25], [0.0, -2.0, 0.0]);
    let hit = bvh.closest_hit(&down, 0.0, f64::INFINITY).unwrap();
    assert_eq!(hit.object, 0);
    assert!((hit.t - 0.5).abs() < 1e-15);
    assert_eq!(hit.normal, [0.0, 1.0, 0.0]);
    // The barycentrics give the point back from the mesh's own vertices.
    let mesh = &scene.meshes[0];
    let corner = |k: usize| {
        place(
            lifted,
            mesh.vertices[mesh.indices[3 * hit.triangle + k] as usize].position,
        )
    };
    let [b1, b2] = hit.barycentrics;
    let point = (1.0 - b1 - b2) * corner(0) + b1 * corner(1) + b2 * corner(2);
    assert!(
        (point - DVec3::from(down.at(hit.t))).length() < 1e-15,
        "{point}"
    );
    // Upwards, the mirrored plane is hit from its (world-space) front: its normal is
    // now −y, facing the ray.
    let up = Ray::new([0.5, 2.0, -0.25], [0.0, 1.0, 0.0]);
    let hit = bvh.closest_hit(&up, 0.0, f64::INFINITY).unwrap();
    assert_eq!((hit.object, hit.t), (2, 1.0));
    assert_eq!(hit.normal, [0.0, -1.0, 0.0]);
    // The plain plane in object 3 (mesh 1) sits at y = 0 below the first.
    let hit = bvh.closest_hit(&down, 0.5, f64::INFINITY).unwrap();
    assert_eq!((hit.object, hit.t), (3, 1.0));
    // Nothing is hit beyond everything, nor in an empty interval.
    assert!(bvh.closest_hit(&down, 1.0, f64::INFINITY).is_none());
    assert!(!bvh.any_hit(&down, 0.3, 0.3));
    assert!(!bvh.any_hit(&down, 0.0, f64::NAN));
    // A scene without objects, and rays that are not rays.
    let empty = SceneBvh::new(&scene_of(vec![], &[]));
    assert_eq!((empty.triangle_count(), empty.bounds()), (0, None));
    assert!(empty.closest_hit(&down, 0.0, f64::INFINITY).is_none());
    for bad in [
        Ray::new([0.5, 2.0, 0.0], [0.0; 3]),
        Ray::new([f64::NAN; 3], [0.0, -1.0, 0.0]),
        Ray::new([0.5, 2.0, 0.0], [f64::INFINITY, -1.0, 0.0]),
    ] {
        assert!(
            bvh.closest_hit(&bad, 0.0, f64::INFINITY).is_none(),
            "{bad:?}"
        );
        assert!(!bvh.any_hit(&bad, 0.0, f64::INFINITY), "{bad:?}");
    }
}
