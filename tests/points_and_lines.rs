//! Points and lines (`Topology::Points`, `Topology::Lines`; glTF modes 0–3) drawn into
//! the G-buffer by pipelines of their own, checked by hand: a horizontal segment along a
//! row of pixel centres covers exactly that row between its ends, a point at a pixel
//! centre exactly that pixel, each showing its unlit material's base colour × its vertex
//! colour; they cast no shadow and change no other pixel, a scene without them builds
//! no pipeline for them, and the end-to-end comparison counts their pixels apart.

use crate::common;

use combustion::renderer::gbuffer::srgb_to_linear;
use combustion::scene::{Camera, Light, Material, Mesh, Object, Scene, Topology, Vertex};
use glam::{Mat4, Vec3};

/// Odd, so that the image's centre row and column are pixel centres.
const SIZE: u32 = 65;
/// The strokes' height above the plane (the camera is 3 m above it).
const STROKE_HEIGHT: f32 = 1.0;

/// Colours that are exact 8-bit sRGB codes, so the G-buffer stores them without loss.
fn exact(codes: [u8; 3]) -> [f32; 3] {
    codes.map(|c| srgb_to_linear(f64::from(c) / 255.0) as f32)
}

/// A grey plane at y = 0 lit obliquely (so a surface above it would cast a shadow on
/// it), seen straight down from 3 m.
fn plane() -> Scene {
    common::plane_from_above(
        "plane",
        Material {
            base_color: exact([128, 128, 128]),
            ..Material::default()
        },
        vec![Light::Directional {
            direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
            irradiance: [2.0; 3],
            casts_shadows: true,
            angular_diameter: 0.0,
        }],
    )
}

/// One pixel's width at the strokes' distance from the camera (metres).
fn pixel_at_strokes(camera: &Camera) -> f32 {
    let distance = camera.position.y - STROKE_HEIGHT;
    2.0 * distance * (camera.vertical_fov / 2.0).tan() / SIZE as f32
}

/// Where `p` lands in the framebuffer (x right, y down, pixel centres at k + ½).
fn framebuffer(camera: &Camera, p: Vec3) -> [f32; 2] {
    let clip = camera.view_projection(1.0) * p.extend(1.0);
    let ndc = [clip.x / clip.w, clip.y / clip.w];
    ndc.map(|c| (c + 1.0) / 2.0 * SIZE as f32)
}

/// The pixel whose centre `p` lands on (checked to be within 1/100 pixel of it).
fn pixel_of(camera: &Camera, p: Vec3) -> (u32, u32) {
    let [x, y] = framebuffer(camera, p);
    for c in [x, y] {
        assert!(
            (c - c.floor() - 0.5).abs() < 0.01,
            "{p} lands at ({x}, {y}), not at a pixel centre"
        );
    }
    (x as u32, y as u32)
}

/// The colours of the segment's and the points' vertices.
const LINE_COLOR: [u8; 3] = [255, 64, 0];
const POINT_COLOR: [u8; 3] = [0, 128, 255];

/// `plane()` with a segment 30 pixels long along the centre row and five points at pixel
/// centres, STROKE_HEIGHT above the plane, each of an unlit material of base colour 1
/// (the glTF importer's for points and lines) and coloured by its vertices.
fn with_strokes() -> (Scene, [Vec3; 2], Vec<Vec3>) {
    let mut scene = plane();
    let s = pixel_at_strokes(&scene.camera);
    let at = |i: f32, j: f32| Vec3::new(i * s, STROKE_HEIGHT, j * s);
    let ends = [at(-15.0, 0.0), at(15.0, 0.0)];
    let points: Vec<Vec3> = [
        (-20.0, -20.0),
        (5.0, -10.0),
        (0.0, 10.0),
        (12.0, 12.0),
        (25.0, 3.0),
    ]
    .into_iter()
    .map(|(i, j)| at(i, j))
    .collect();
    let vertex = |p: Vec3, codes: [u8; 3]| {
        let [r, g, b] = exact(codes);
        Vertex {
            position: p.to_array(),
            normal: [0.0, 1.0, 0.0],
            tangent: [1.0, 0.0, 0.0, 1.0],
            color: [r, g, b, 1.0],
            ..Vertex::default()
        }
    };
    scene.meshes.push(Mesh {
        name: "segment".into(),
        vertices: ends.iter().map(|&p| vertex(p, LINE_COLOR)).collect(),
        indices: vec![0, 1],
        topology: Topology::Lines,
        ..Mesh::default()
    });
    scene.meshes.push(Mesh {
        name: "points".into(),
        vertices: points.iter().map(|&p| vertex(p, POINT_COLOR)).collect(),
        indices: (0..points.len() as u32).collect(),
        topology: Topology::Points,
        ..Mesh::default()
    });
    let strokes = Material::default().for_points_and_lines();
    assert!(strokes.unlit);
    scene.materials.push(Material {
        base_color: [1.0; 3],
        ..strokes
    });
    for mesh in [1, 2] {
        scene.objects.push(Object {
            mesh,
            material: 1,
            transform: Mat4::IDENTITY,
            casts_shadows: true,
            node: None,
        });
    }
    scene.validate().expect("a valid scene");
    (scene, ends, points)
}

/// Mesh `mesh` of `scene` made a small triangle (0.1 m sides) at its first vertex.
fn as_triangle(scene: &mut Scene, mesh: usize) {
    let mesh = &mut scene.meshes[mesh];
    mesh.vertices = vec![mesh.vertices[0]; 3];
    mesh.vertices[1].position[0] += 0.1;
    mesh.vertices[2].position[2] += 0.1;
    mesh.indices = vec![0, 1, 2];
    mesh.topology = Topology::Triangles;
}

/// The material index the G-buffer stores at (x, y), None for the background.
fn material_at(frame: &combustion::renderer::Frame, x: u32, y: u32) -> Option<u16> {
    let texel =
        &frame.gbuffer.as_ref().expect("G-buffer read back").texels[(y * frame.width + x) as usize];
    (texel.depth < 1.0).then_some(texel.material_direction[0])
}

fn assert_radiance(frame: &combustion::renderer::Frame, x: u32, y: u32, codes: [u8; 3]) {
    let got = frame.hdr[(y * frame.width + x) as usize];
    let want = exact(codes);
    for c in 0..3 {
        assert!(
            (got[c] - want[c]).abs() <= 1e-6 + 1e-4 * want[c],
            "pixel ({x}, {y}): radiance {got:?}, the unlit colour is {want:?}"
        );
    }
}

#[test]
fn a_segment_covers_its_row_and_a_point_its_pixel_in_their_unlit_colour() {
    let (scene, ends, points) = with_strokes();
    let frame = common::render_with_lights(&scene, &scene.lights, SIZE, SIZE);
    let (x0, row) = pixel_of(&scene.camera, ends[0]);
    let (x1, row1) = pixel_of(&scene.camera, ends[1]);
    assert_eq!(row, row1);
    let (x0, x1) = (x0.min(x1), x0.max(x1));
    // Every column strictly between the ends (a segment's last pixel is left to the
    // rasteriser's rule): the row and nothing above or below it.
    for x in x0 + 1..x1 {
        assert_eq!(material_at(&frame, x, row), Some(1), "column {x}");
        assert_radiance(&frame, x, row, LINE_COLOR);
        for y in [row - 1, row + 1] {
            assert_eq!(
                material_at(&frame, x, y),
                Some(0),
                "({x}, {y}) beside the segment"
            );
        }
    }
    // Each point: its pixel, none of its eight neighbours.
    let point_pixels: Vec<(u32, u32)> =
        points.iter().map(|&p| pixel_of(&scene.camera, p)).collect();
    for &(x, y) in &point_pixels {
        assert_eq!(material_at(&frame, x, y), Some(1), "point at ({x}, {y})");
        assert_radiance(&frame, x, y, POINT_COLOR);
        for (dx, dy) in [
            (-1, -1),
            (0, -1),
            (1, -1),
            (-1, 0),
            (1, 0),
            (-1, 1),
            (0, 1),
            (1, 1),
        ] {
            let (nx, ny) = ((x as i32 + dx) as u32, (y as i32 + dy) as u32);
            if ny == row && (x0..=x1).contains(&nx) {
                continue;
            }
            assert_eq!(
                material_at(&frame, nx, ny),
                Some(0),
                "({nx}, {ny}) beside a point"
            );
        }
    }
    // Nothing else: the segment's pixels (its ends at most one more each) and the points'.
    let stroke_pixels = (0..SIZE * SIZE)
        .filter(|i| material_at(&frame, i % SIZE, i / SIZE) == Some(1))
        .count();
    let inner = (x1 - x0 - 1) as usize;
    assert!(
        (inner + points.len()..=inner + 2 + points.len()).contains(&stroke_pixels),
        "{stroke_pixels} pixels show the strokes; the segment covers {inner} between its ends and there are {} points",
        points.len()
    );
}

/// Points and lines have no surface: the plane is lit the same, bit for bit, wherever
/// they do not cover it (no shadow, nothing else drawn), though the light is oblique and
/// every object casts shadows — where a triangle in the segment's place does shadow it.
#[test]
fn points_and_lines_cast_no_shadow_and_change_no_other_pixel() {
    let settings = common::exact_f32();
    let settings = combustion::renderer::RendererSettings {
        shading: combustion::renderer::ShadingOptions {
            shadows: Some(Default::default()),
            ..settings.shading
        },
        ..settings
    };
    let (scene, _, _) = with_strokes();
    let bare = plane();
    let with = common::render_with_lights_in(&scene, &scene.lights, SIZE, SIZE, settings);
    let without = common::render_with_lights_in(&bare, &bare.lights, SIZE, SIZE, settings);
    let mut covered = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            if material_at(&with, x, y) == Some(1) {
                covered += 1;
                continue;
            }
            let i = (y * SIZE + x) as usize;
            assert_eq!(with.hdr[i], without.hdr[i], "({x}, {y})");
        }
    }
    assert!(covered > 30, "{covered} stroke pixels");
    // The control: a small triangle at the segment's end casts a shadow on the plane.
    let mut shadowing = scene.clone();
    as_triangle(&mut shadowing, 1);
    let control =
        common::render_with_lights_in(&shadowing, &shadowing.lights, SIZE, SIZE, settings);
    let shadowed = (0..(SIZE * SIZE) as usize)
        .filter(|&i| {
            let (x, y) = (i as u32 % SIZE, i as u32 / SIZE);
            material_at(&control, x, y) == Some(0) && control.hdr[i] != without.hdr[i]
        })
        .count();
    assert!(
        shadowed > 0,
        "the triangle casts no shadow: the check above proves nothing"
    );
}

/// A scene without points or lines builds no pipeline for them: the same scene with a
/// triangle in place of each (the same materials and vertex colours, so the same
/// G-buffer and lighting variants otherwise) builds one pipeline fewer per kind.
#[test]
fn only_scenes_with_points_or_lines_build_their_pipelines() {
    let pipelines = |scene: &Scene| {
        let mut headless = common::lavapipe(common::exact_f32());
        let built = {
            let renderer = headless.renderer();
            let gpu = renderer.upload(scene).expect("upload");
            renderer.prepare(&gpu).expect("prepare");
            renderer.stats().pipelines_built
        };
        common::finish(headless);
        built
    };
    let (strokes, _, _) = with_strokes();
    let mut lines_only = strokes.clone();
    as_triangle(&mut lines_only, 2);
    let mut points_only = strokes.clone();
    as_triangle(&mut points_only, 1);
    let mut neither = lines_only.clone();
    as_triangle(&mut neither, 1);
    let base = pipelines(&neither);
    assert_eq!(pipelines(&lines_only), base + 1);
    assert_eq!(pipelines(&points_only), base + 1);
    assert_eq!(pipelines(&strokes), base + 2);
}

/// The f64 end-to-end reference has no surface to hit for points and lines: their
/// pixels are counted apart, and the plane around them compares as before.
#[test]
fn the_end_to_end_comparison_counts_stroke_pixels_apart() {
    use combustion::end_to_end::SceneReference;
    use combustion::reference::SceneBvh;
    let (scene, _, _) = with_strokes();
    let frame = common::render_with_lights(&scene, &scene.lights, SIZE, SIZE);
    let bvh = SceneBvh::new(&scene);
    let precision = combustion::end_to_end::precision_of(common::exact_f32().gbuffer);
    let reference = SceneReference::new(&scene, &bvh, &scene.lights, (SIZE, SIZE), precision, 2);
    let summary = reference.compare(&frame).summary();
    let stroke_pixels = (0..SIZE * SIZE)
        .filter(|i| material_at(&frame, i % SIZE, i / SIZE) == Some(1))
        .count();
    assert_eq!(summary.strokes, stroke_pixels);
    assert_eq!(summary.away, 0, "{summary:?}");
    assert_eq!(
        summary.compared + summary.strokes + summary.silhouette,
        (SIZE * SIZE) as usize,
        "{summary:?}"
    );
}

/// Frames alternate between a scene with points and lines (its own G-buffer variant and
/// stroke pipelines) and one without, 20 frames each (past the 16-frame retire delay),
/// twice round, under validation: the strokes are drawn in every frame of theirs and
/// never in the other's.
#[test]
fn frames_with_and_without_points_and_lines_alternate() {
    let (strokes, _, _) = with_strokes();
    let bare = plane();
    let mut headless = common::lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let scenes = [
            renderer.upload(&strokes).expect("upload"),
            renderer.upload(&bare).expect("upload"),
        ];
        common::alternate_scenes_past_the_retire_delay(
            renderer,
            &scenes,
            ((SIZE, SIZE), combustion::renderer::Readback::ALL),
            |gpu| common::frame_inputs(gpu.scene(), &gpu.scene().lights),
            |index, frame| {
                let stroke_pixels = (0..SIZE * SIZE)
                    .filter(|i| material_at(frame, i % SIZE, i / SIZE) == Some(1))
                    .count();
                assert_eq!(stroke_pixels > 30, index == 0, "{stroke_pixels}");
            },
        );
    }
    common::finish(headless);
}
