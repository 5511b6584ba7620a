//! Light visibility against configurations whose answer is known exactly.

use crate::common::{box_mesh, grid_mesh, place, quads_mesh, scene_of, Random};
use combustion_reference::visibility::{shadow_ray_origin, surface_offset};
use combustion_reference::SceneBvh;
use combustion_scene::{Light, Mesh};
use glam::{DVec3, Mat4, Quat, Vec3};

fn directional(towards_light: DVec3) -> Light {
    Light::Directional {
        direction: (-towards_light).as_vec3(),
        irradiance: [1.0; 3],
        casts_shadows: true,
        angular_diameter: 0.0,
    }
}

fn point_light(position: DVec3) -> Light {
    Light::Point {
        position: position.as_vec3(),
        intensity: [1.0; 3],
        range: None,
        casts_shadows: true,
        radius: 0.0,
    }
}

/// A sphere of radius r centred at height h above the plane y = 0, lit by a
/// directional light at elevation e: its shadow on the plane is the ellipse centred
/// h/tan(e) from the sphere's foot along the light's horizontal direction of travel,
/// with semi-axes r across and r/sin(e) along it.
///
/// The tessellated sphere (`segments` around, `rings` pole to pole) is the convex
/// polytope inscribed in the sphere; each of its faces is a planar isosceles trapezoid
/// (or a triangle at a pole) spanning Δφ = 2π/segments and Δθ = π/rings, whose plane
/// is at distance r·cos(Δθ/2)/√(cos²θm + sin²θm/cos²(Δφ/2)) ≥ r·cos(Δφ/2)·cos(Δθ/2)
/// from the centre (θm its middle polar angle). So the polytope lies between the balls
/// of radius r_in = r·cos(π/segments)·cos(π/(2·rings)) and r, and its shadow between
/// those balls' ellipses; with the vertices' f32 rounding, r_in·(1 − 1e-6) and
/// r·(1 + 1e-6). Every grid point outside that band must be classified as the
/// ellipses say, without exception; points inside the band are counted, not judged.
///
/// The shadow ray starts `eps` = surface_offset(point) above the plane: the same line
/// as the ray from the plane point moved by eps·cot(e) towards the light's travel, so
/// that is the point classified.
#[test]
fn a_spheres_shadow_on_a_plane_is_the_analytic_ellipse() {
    let (r, h) = (1.0_f64, 2.5_f64);
    let (segments, rings) = (256_u32, 128_u32);
    let sphere = Mesh::uv_sphere("sphere", r as f32, segments, rings);
    let scene = scene_of(
        vec![sphere, Mesh::plane("ground", 80.0)],
        &[
            (0, Mat4::from_translation(Vec3::new(0.0, h as f32, 0.0))),
            (1, Mat4::IDENTITY),
        ],
    );
    let bvh = SceneBvh::new(&scene);
    let r_in = r
        * (std::f64::consts::PI / segments as f64).cos()
        * (std::f64::consts::PI / (2.0 * rings as f64)).cos()
        * (1.0 - 1e-6);
    let r_out = r * (1.0 + 1e-6);
    let azimuth = 0.52_f64; // not along an axis
    let horizontal = DVec3::new(azimuth.cos(), 0.0, azimuth.sin()); // towards the light
    let across = DVec3::new(-azimuth.sin(), 0.0, azimuth.cos());
    for elevation_degrees in [35.0_f64, 10.0] {
        let e = elevation_degrees.to_radians();
        let towards_light = e.cos() * horizontal + e.sin() * DVec3::Y;
        let light = directional(towards_light);
        // The light's horizontal direction of travel is −horizontal.
        let shadow_center = -h / e.tan() * horizontal;
        let inside = |p: DVec3, radius: f64| {
            let q = p - shadow_center;
            let along = q.dot(horizontal) * e.sin() / radius;
            let side = q.dot(across) / radius;
            along * along + side * side < 1.0
        };
        let (n_along, n_across) = (400, 200);
        let (mut shadowed, mut in_band, mut wrong) = (0, 0, Vec::new());
        for i in 0..n_along {
            for j in 0..n_across {
                let a = 1.3 * r / e.sin() * (2.0 * (i as f64 + 0.5) / n_along as f64 - 1.0);
                let b = 1.3 * r * (2.0 * (j as f64 + 0.5) / n_across as f64 - 1.0);
                let point = shadow_center + a * horizontal + b * across;
                let eps = surface_offset(point.to_array());
                let classified = point - eps / e.tan() * horizontal;
                let visibility = bvh.light_visibility(point.to_array(), [0.0, 1.0, 0.0], &light);
                assert!(visibility == 0.0 || visibility == 1.0);
                shadowed += (visibility == 0.0) as usize;
                if inside(classified, r_in) {
                    if visibility != 0.0 {
                        wrong.push((point, "lit inside the inner ellipse"));
                    }
                } else if !inside(classified, r_out) {
                    if visibility != 1.0 {
                        wrong.push((point, "shadowed outside the outer ellipse"));
                    }
                } else {
                    in_band += 1;
                }
            }
        }
        let expected_area_fraction = std::f64::consts::PI / 4.0 / (1.3 * 1.3);
        println!(
            "elevation {elevation_degrees}°: {shadowed} of {} points shadowed (analytic {:.0}), {in_band} within the tessellation band (r_in = {r_in:.7}), {} misclassified",
            n_along * n_across,
            expected_area_fraction * (n_along * n_across) as f64,
            wrong.len()
        );
        assert!(
            wrong.is_empty(),
            "elevation {elevation_degrees}°: {:?}",
            &wrong[..wrong.len().min(5)]
        );
    }
}

/// A point light inside a closed box (six quads, turned and moved) is seen from every
/// point inside and from no point outside (offset normals towards the light); from a
/// point on a face, the offset normal picks the side.
#[test]
fn a_point_light_in_a_closed_box_is_seen_only_from_inside() {
    let transform = Mat4::from_rotation_translation(
        Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.3, 0.2),
        Vec3::new(10.0, 2.0, -4.0),
    );
    let bvh = SceneBvh::new(&scene_of(vec![box_mesh(1.0)], &[(0, transform)]));
    let to_world = |p: DVec3| transform.as_dmat4().transform_point3(p);
    let light_local = DVec3::new(0.13, -0.21, 0.37);
    let light_world = to_world(light_local);
    let light = point_light(light_world);
    // The light is placed in f32: work with that position.
    let light_at = match light {
        Light::Point { position, .. } => position.as_dvec3(),
        _ => unreachable!(),
    };
    let mut random = Random::new(3);
    let (mut inside_points, mut outside_points) = (0, 0);
    while inside_points + outside_points < 4000 {
        let local = DVec3::new(
            random.range(-4.0, 4.0),
            random.range(-4.0, 4.0),
            random.range(-4.0, 4.0),
        );
        let distance = local.abs().max_element();
        if (0.98..=1.02).contains(&distance) {
            continue;
        }
        let point = to_world(local);
        let towards_light = (light_at - point).to_array();
        let visibility = bvh.light_visibility(point.to_array(), towards_light, &light);
        if distance < 1.0 {
            inside_points += 1;
            assert_eq!(visibility, 1.0, "inside at {local}");
        } else {
            outside_points += 1;
            assert_eq!(visibility, 0.0, "outside at {local}");
        }
    }
    // Points on the faces: the inward normal sees the light, the outward one does not.
    for _ in 0..500 {
        let axis = random.below(3);
        let sign = if random.unit() < 0.5 { -1.0 } else { 1.0 };
        let mut local = DVec3::new(
            random.range(-0.99, 0.99),
            random.range(-0.99, 0.99),
            random.range(-0.99, 0.99),
        );
        local[axis] = sign;
        let mut outward = DVec3::ZERO;
        outward[axis] = sign;
        let point = to_world(local).to_array();
        let outward = transform.as_dmat4().transform_vector3(outward);
        assert_eq!(
            bvh.light_visibility(point, (-outward).to_array(), &light),
            1.0
        );
        assert_eq!(bvh.light_visibility(point, outward.to_array(), &light), 0.0);
    }
}

/// Shadow rays aimed exactly through the edges, corners and face diagonals of a closed
/// axis-aligned box (a light at its centre) are blocked: no crack between its faces.
#[test]
fn rays_through_a_boxes_edges_and_corners_are_blocked() {
    let bvh = SceneBvh::new(&scene_of(vec![box_mesh(1.0)], &[(0, Mat4::IDENTITY)]));
    let light = point_light(DVec3::ZERO);
    let mut through = Vec::new();
    let steps = [-1.0, -0.5, -0.25, 0.0, 0.3, 0.5, 1.0];
    for &a in &steps {
        for &b in &steps {
            // A point of every face (on the diagonals where |a| = |b|), edge (|a| or |b|
            // = 1) and corner (both).
            for axis in 0..3 {
                for sign in [-1.0, 1.0] {
                    let mut p = DVec3::ZERO;
                    p[axis] = sign;
                    p[(axis + 1) % 3] = a;
                    p[(axis + 2) % 3] = b;
                    through.push(p);
                }
            }
        }
    }
    for p in through {
        for scale in [1.5, 2.0, 3.0, 10.0] {
            let point = p * scale;
            let visibility = bvh.light_visibility(point.to_array(), (-point).to_array(), &light);
            assert_eq!(visibility, 0.0, "through {p} from {point}");
            assert!(!bvh.segment_visible(point.to_array(), [0.0; 3]), "{point}");
        }
    }
}

/// A light grazing a plane at 85° from its normal does not shadow the plane itself,
/// across ±1000 m (a tilted, moved 64 × 64 grid: points rounded to f32 and pushed along
/// the normal by 1e-6 of their distance from the origin, as from a depth buffer), nor
/// the points of a sphere's faces lit within 85° of their normal.
#[test]
fn grazing_light_does_not_shadow_the_lit_surface_at_any_scale() {
    let transform = Mat4::from_rotation_translation(
        Quat::from_euler(glam::EulerRot::XYZ, 0.35, 0.8, -0.2),
        Vec3::new(300.0, -50.0, 200.0),
    );
    let plane = grid_mesh(2000.0, 64);
    let bvh = SceneBvh::new(&scene_of(vec![plane], &[(0, transform)]));
    let normal = transform.as_dmat4().transform_vector3(DVec3::Y).normalize();
    let tangent = transform.as_dmat4().transform_vector3(DVec3::X).normalize();
    let bitangent = normal.cross(tangent);
    let mut random = Random::new(11);
    let grazing = 85.0_f64.to_radians();
    for _ in 0..5000 {
        let local = [
            random.range(-999.0, 999.0) as f32,
            0.0,
            random.range(-999.0, 999.0) as f32,
        ];
        let exact = place(transform, local);
        let error = exact.length() * 1e-6 * random.range(-1.0, 1.0);
        let point = (exact.as_vec3().as_dvec3() + error * normal).to_array();
        let azimuth = random.range(0.0, std::f64::consts::TAU);
        let towards_light = grazing.cos() * normal
            + grazing.sin() * (azimuth.cos() * tangent + azimuth.sin() * bitangent);
        let visibility =
            bvh.light_visibility(point, normal.to_array(), &directional(towards_light));
        assert_eq!(visibility, 1.0, "at {point:?} towards {towards_light}");
        assert!(surface_offset(point) >= 1e-4);
    }

    // A sphere far from the origin; points on its faces (f64, and rounded to f32),
    // offset along each face's normal, lit within 85° of it: a convex surface never
    // shadows a point from a direction its face looks towards.
    let center = Vec3::new(-700.0, 40.0, 650.0);
    let sphere = Mesh::uv_sphere("sphere", 3.0, 64, 32);
    let bvh = SceneBvh::new(&scene_of(
        vec![sphere],
        &[(0, Mat4::from_translation(center))],
    ));
    for _ in 0..5000 {
        let triangle = bvh.triangles()[random.below(bvh.triangle_count())];
        let [p0, p1, p2] = triangle.vertices.map(DVec3::from);
        let (mut b1, mut b2) = (random.unit(), random.unit());
        if b1 + b2 > 1.0 {
            (b1, b2) = (1.0 - b1, 1.0 - b2);
        }
        let exact = p0 + b1 * (p1 - p0) + b2 * (p2 - p0);
        let face_normal = DVec3::from(triangle.normal());
        let (t, b) = {
            let t = (p1 - p0).normalize();
            (t, face_normal.cross(t))
        };
        let angle = random.range(0.0, grazing);
        let azimuth = random.range(0.0, std::f64::consts::TAU);
        let towards_light =
            angle.cos() * face_normal + angle.sin() * (azimuth.cos() * t + azimuth.sin() * b);
        for point in [exact, exact.as_vec3().as_dvec3()] {
            let visibility = bvh.light_visibility(
                point.to_array(),
                face_normal.to_array(),
                &directional(towards_light),
            );
            assert_eq!(visibility, 1.0, "at {point} towards {towards_light}");
            // and a point light 10 m away in that direction
            let lamp = point_light(point + 10.0 * towards_light);
            assert_eq!(
                bvh.light_visibility(point.to_array(), face_normal.to_array(), &lamp),
                1.0
            );
        }
    }
}

/// A disc light of radius R facing down at height H above the point (0, 0, 0), with a
/// blocker at mid height: nothing, all, half, and a chord's segment blocked.
#[test]
fn a_disc_lights_visible_fraction_is_the_blocked_areas_complement() {
    let (radius, height) = (0.5_f64, 2.0_f64);
    let center = [0.0, height, 0.0];
    let n = 32_u32;
    let samples = f64::from(n * n);
    // The module's bound: M ≤ 1 + 1.25·ℓ·n cells crossed by a boundary of ℓ radii,
    // σ ≤ √M/(2N), |error| ≤ M/N.
    let bounds = |chord_in_radii: f64| {
        let crossed = 1.0 + 1.25 * chord_in_radii * f64::from(n);
        (crossed.sqrt() / (2.0 * samples), crossed / samples)
    };
    let blocker = |x0: f32, x1: f32| {
        let y = (height / 2.0) as f32;
        quads_mesh(
            "blocker",
            &[[[x0, y, -2.0], [x0, y, 2.0], [x1, y, 2.0], [x1, y, -2.0]]],
        )
    };
    // Blockers are turned about the vertical axis through the point, so that their
    // edge does not fall on the samples' grid lines (the concentric map takes the
    // square's middle lines to the disc's axes, where a half would be exact).
    let turn = Mat4::from_rotation_y(0.5);
    let fraction = |meshes: Vec<Mesh>| {
        let objects: Vec<(usize, Mat4)> = (0..meshes.len()).map(|i| (i, turn)).collect();
        let bvh = SceneBvh::new(&scene_of(meshes, &objects));
        bvh.disc_visibility(
            [0.0; 3],
            [0.0, 1.0, 0.0],
            center,
            [0.0, -1.0, 0.0],
            radius,
            n,
        )
    };
    // The floor the point lies on, and no blocker: exactly 1.
    assert_eq!(fraction(vec![Mesh::plane("floor", 10.0)]), 1.0);
    // A blocker covering the disc's whole projection: exactly 0.
    assert_eq!(
        fraction(vec![Mesh::plane("floor", 10.0), blocker(-1.0, 1.0)]),
        0.0
    );
    // Half: the blocker's edge (x = 0) projects onto the disc's diameter.
    let half = fraction(vec![blocker(-1.0, 0.0)]);
    let (sigma, hard) = bounds(2.0);
    println!("half-covered disc: {half} (exact 0.5; σ ≤ {sigma:.4}, |error| ≤ {hard:.4})");
    assert!((half - 0.5).abs() <= 4.0 * sigma, "{half}");
    // A chord: the edge at x = a projects from the ray origin (0, eps, 0) to
    // x = a·(H − eps)/(H/2 − eps) on the disc's plane, d = x/R of the radius; the
    // visible part is the segment beyond it, (acos d − d·√(1 − d²))/π of the disc.
    let a = 0.125_f64;
    let eps = surface_offset([0.0; 3]);
    let d = a * (height - eps) / (height / 2.0 - eps) / radius;
    let exact = (d.acos() - d * (1.0 - d * d).sqrt()) / std::f64::consts::PI;
    let chord = fraction(vec![blocker(-1.0, a as f32)]);
    let (sigma, hard) = bounds(2.0 * (1.0 - d * d).sqrt());
    println!("chord-covered disc: {chord} (exact {exact:.5}; σ ≤ {sigma:.4}, |error| ≤ {hard:.4})");
    assert!(
        (chord - exact).abs() <= 4.0 * sigma,
        "{chord} against {exact}"
    );
    // The same call gives the same answer.
    assert_eq!(chord, fraction(vec![blocker(-1.0, a as f32)]));
}

/// A sun of angular diameter 10° straight up, a blocker at height 1 (turned about the
/// vertical axis, as for the disc): nothing, all, and half of its directions blocked.
#[test]
fn a_suns_visible_fraction_is_the_blocked_cones_complement() {
    let n = 32_u32;
    let blocker = |x0: f32, x1: f32| {
        quads_mesh(
            "blocker",
            &[[
                [x0, 1.0, -5.0],
                [x0, 1.0, 5.0],
                [x1, 1.0, 5.0],
                [x1, 1.0, -5.0],
            ]],
        )
    };
    let turn = Mat4::from_rotation_y(0.5);
    let visible = |meshes: Vec<Mesh>| {
        let objects: Vec<(usize, Mat4)> = (0..meshes.len()).map(|i| (i, turn)).collect();
        let bvh = SceneBvh::new(&scene_of(meshes, &objects));
        bvh.sun_visibility(
            [0.0; 3],
            [0.0, 1.0, 0.0],
            [0.0, 2.0, 0.0],
            10f64.to_radians(),
            n,
        )
    };
    assert_eq!(visible(vec![Mesh::plane("floor", 10.0)]), 1.0);
    assert_eq!(visible(vec![blocker(-5.0, 5.0)]), 0.0);
    let half = visible(vec![blocker(-5.0, 0.0)]);
    let crossed = 1.0 + 1.25 * 2.0 * f64::from(n);
    let sigma = crossed.sqrt() / (2.0 * f64::from(n * n));
    println!("half-covered sun: {half} (σ ≤ {sigma:.4})");
    assert!((half - 0.5).abs() <= 4.0 * sigma, "{half}");
    // Zero diameter: the single direction's answer.
    let bvh = SceneBvh::new(&scene_of(vec![blocker(-5.0, 0.0)], &[(0, Mat4::IDENTITY)]));
    let up = |x: f64| bvh.sun_visibility([x, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0], 0.0, 4);
    assert_eq!((up(-0.5), up(0.5)), (0.0, 1.0));
}

#[test]
fn the_offset_rule_is_relative_with_a_floor_of_one_metre() {
    assert_eq!(surface_offset([0.0, 0.2, -0.5]), 1e-4);
    assert_eq!(surface_offset([0.0, -2000.0, 3.0]), 0.2);
    assert_eq!(
        shadow_ray_origin([1.0, 0.0, 0.0], [0.0, 5.0, 0.0]),
        [1.0, 1e-4, 0.0]
    );
    assert_eq!(
        shadow_ray_origin([1.0, 0.0, 0.0], [0.0; 3]),
        [1.0, 0.0, 0.0]
    );
    assert_eq!(
        shadow_ray_origin([1.0, 0.0, 0.0], [f64::NAN; 3]),
        [1.0, 0.0, 0.0]
    );
}
