//! Things that move, on the GPU: a frame's pose (`FrameInputs::pose`) places the scene's
//! objects through the per-frame path; checked against the still scene in that pose and
//! refused when it does not fit the scene.

use crate::common;

use combustion::renderer::{
    FrameInputs, Readback, RenderError, RendererSettings, ShadingOptions, ShadowSettings,
};
use combustion::scene::ObjectPoses;
use common::{animated_grid, finish, lavapipe};

const W: u32 = 96;
const H: u32 = 64;

fn with_shadows() -> RendererSettings {
    RendererSettings {
        shading: ShadingOptions {
            shadows: Some(ShadowSettings::DEFAULT),
            ..ShadingOptions::DEFAULT
        },
        ..common::exact_f32()
    }
}

/// A frame posed by the pose of the animation at a time is, bit for bit, the frame of
/// the still scene in that pose (`Scene::posed`: the objects' transforms replaced),
/// shadows included, at four times through the animation and past its end; frames in a
/// new pose differ from the rest (the test sees the motion), and the shadow maps follow
/// the pose (rendered again when it changes, also where the scene's box and so the
/// cascades stay, in frames recorded back to back in one renderer).
#[test]
fn a_posed_frame_is_the_still_scene_in_that_pose() {
    let scene = animated_grid();
    let mut headless = lavapipe(with_shadows());
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let rest = renderer.render(&gpu, W, H, Readback::ALL).unwrap();
        // The posed frames one after another (the shadow maps kept from frame to frame
        // only while the pose stays), then the still scenes.
        let times = [0.0, 0.5, 1.3, 2.5, 2.5];
        let mut poses: Vec<ObjectPoses> = times
            .iter()
            .map(|&t| scene.pose_at(0, t).unwrap())
            .collect();
        // The last, a host's own: sphere 10 moved 0.3 m within the scene's box (the
        // cascades, fitted to the box, stay where they were: only the pose says the
        // maps must be rendered again).
        poses[4].transforms[10].w_axis.x += 0.3;
        let posed: Vec<_> = poses
            .iter()
            .map(|pose| common::render_posed(renderer, &gpu, Some(pose), (W, H)))
            .collect();
        for ((time, pose), posed) in times.iter().zip(&poses).zip(&posed) {
            let still = renderer.upload(&scene.posed(pose)).unwrap();
            let expected = renderer.render(&still, W, H, Readback::ALL).unwrap();
            let differing = common::hdr_pixels_differing(posed, &expected);
            assert_eq!(
                differing, 0,
                "t = {time}: {differing} pixels differ from the still scene's"
            );
            let moved = common::hdr_pixels_differing(posed, &rest);
            eprintln!("t = {time}: {moved} pixels differ from the rest pose's");
            if *time > 0.0 {
                assert!(
                    moved > 100,
                    "t = {time}: the pose moved only {moved} pixels"
                );
            }
        }
    }
    finish(headless);
}

/// A pose that does not fit the scene is refused with its reason, before anything is
/// recorded: too few transforms, a non-finite transform, a skin count that differs. A
/// singular transform (a node scaled to 0, as files hide objects) is accepted: the
/// object is not drawn.
#[test]
fn a_pose_that_does_not_fit_the_scene_is_refused() {
    let scene = animated_grid();
    let mut headless = lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let good = scene.pose_objects(&scene.motion.rest_pose());
        let mut cases: Vec<(ObjectPoses, &str)> = Vec::new();
        let mut short = good.clone();
        short.transforms.pop();
        cases.push((short, "transforms and"));
        let mut nan = good.clone();
        nan.transforms[0].w_axis.x = f32::NAN;
        cases.push((nan, "object 0's transform is not finite"));
        let mut skins = good.clone();
        skins.joints.push(vec![glam::Mat4::IDENTITY]);
        cases.push((skins, "1 joint lists for 0 skins"));
        for (pose, expected) in cases {
            let inputs = FrameInputs {
                pose: Some(&pose),
                ..FrameInputs::of_scene(&gpu, 1.0)
            };
            let error = renderer
                .render_with(&gpu, &inputs, W, H, Readback::ALL)
                .unwrap_err();
            assert!(
                matches!(&error, RenderError::InvalidPose(m) if m.contains(expected)),
                "expected `{expected}`: {error}"
            );
        }
        // The renderer goes on as before; a sphere scaled to 0 is not drawn: the frame is
        // the one without it.
        let mut hidden = good.clone();
        hidden.transforms[3] = glam::Mat4::from_scale(glam::Vec3::ZERO);
        let frame = common::render_posed(renderer, &gpu, Some(&hidden), (W, H));
        assert_eq!(frame.non_finite_pixels(), 0);
        let mut without = scene.clone();
        without.objects.remove(3);
        let without = renderer.upload(&without).unwrap();
        let expected = renderer.render(&without, W, H, Readback::ALL).unwrap();
        assert_eq!(common::hdr_pixels_differing(&frame, &expected), 0);
    }
    finish(headless);
}

/// The deformed sample models (skins, morph targets) and the file of each.
const DEFORMED_SAMPLES: [&str; 7] = [
    "CesiumMan/glTF-Binary/CesiumMan.glb",
    "RiggedFigure/glTF-Binary/RiggedFigure.glb",
    "RiggedSimple/glTF-Binary/RiggedSimple.glb",
    "SimpleSkin/glTF/SimpleSkin.gltf",
    "AnimatedMorphCube/glTF-Binary/AnimatedMorphCube.glb",
    "SimpleMorph/glTF/SimpleMorph.gltf",
    "MorphPrimitivesTest/glTF-Binary/MorphPrimitivesTest.glb",
];

/// The scenes with deformed objects: the synthetic one always, the sample models when
/// `../shared` is beside the workspace.
fn deformed_scenes() -> Vec<(String, combustion::scene::Scene)> {
    let mut scenes = vec![("deformed spheres".to_owned(), common::deformed_spheres())];
    if let Some(dir) = common::shared_gltf_samples() {
        for relative in DEFORMED_SAMPLES {
            let scene = combustion::SceneSource::File(dir.join(relative))
                .load()
                .unwrap();
            scenes.push((relative.to_owned(), scene));
        }
    }
    scenes
}

/// The GPU morphs and skins every vertex of every deformed object where the f64 pose
/// (`combustion_reference::pose`, from the scene alone) puts it, read back after frames
/// at rest and at 0, 37 % and 100 % of the first animation: positions to a few f32
/// roundings of the model's size, normals and tangents to a few roundings of a unit
/// vector.
#[test]
fn the_gpus_posed_vertices_are_the_f64_pose() {
    use combustion::reference::pose::posed_objects;
    use glam::{DVec3, Vec3};
    let mut headless = lavapipe(common::exact_f32());
    for (name, scene) in deformed_scenes() {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let duration = scene.motion.animations.first().map(|a| a.duration());
        let mut times = vec![None];
        if let Some(d) = duration {
            times.extend([0.0, 0.37 * d, d].map(Some));
        }
        let (mut worst_position, mut worst_direction, mut vertices) = (0.0f64, 0.0f64, 0);
        for time in times {
            let pose = time.map(|t| scene.pose_at(0, t).unwrap());
            common::render_posed(renderer, &gpu, pose.as_ref(), (W, H));
            let read = renderer.read_posed_vertices(&gpu).unwrap();
            assert!(!read.is_empty(), "{name}: no deformed object");
            let expected = posed_objects(&scene, time.map(|t| (0, f64::from(t))));
            let rest = scene.pose_objects(&scene.motion.rest_pose());
            let poses = pose.as_ref().unwrap_or(&rest);
            let extent = expected
                .iter()
                .flatten()
                .map(|v| v.position.abs().max_element())
                .fold(0.0f64, f64::max);
            for (object, posed) in &read {
                // A morphed object's vertices stay in its own space: placed here in f64.
                let transform = poses.transforms[*object].as_dmat4();
                for (v, (got, want)) in posed.iter().zip(&expected[*object]).enumerate() {
                    let position = transform.transform_point3(Vec3::from(got.position).as_dvec3());
                    let error = (position - want.position).length() / extent;
                    assert!(
                        error < 32.0 * f64::from(f32::EPSILON),
                        "{name} at {time:?}: object {object} vertex {v} is {error:.2e} of the extent from the f64 pose"
                    );
                    worst_position = worst_position.max(error);
                    let linear = glam::DMat3::from_mat4(transform);
                    for (got, want, normal) in [
                        (Vec3::from(got.normal), want.normal, true),
                        (Vec3::from_slice(&got.tangent[..3]), want.tangent, false),
                    ] {
                        if want == DVec3::ZERO {
                            continue;
                        }
                        let m = if normal {
                            linear.inverse().transpose()
                        } else {
                            linear
                        };
                        let got = (m * got.as_dvec3()).normalize();
                        worst_direction = worst_direction.max((got - want).length());
                    }
                    vertices += 1;
                }
            }
        }
        eprintln!(
            "{name}: {vertices} posed vertices; position error ≤ {worst_position:.2e} of the extent, direction error ≤ {worst_direction:.2e}"
        );
        assert!(
            worst_direction < 128.0 * f64::from(f32::EPSILON),
            "{name}: a normal or tangent is {worst_direction:.2e} from the f64 pose's"
        );
    }
    finish(headless);
}

/// A pose that changes nothing draws the rest mesh bit for bit: the skinned sphere with
/// one influence of weight 1 per vertex and every joint matrix the identity, its morphed
/// neighbour at weight 0, renders exactly as the same meshes neither skinned nor morphed
/// (the skinned one placed by the identity).
#[test]
fn a_pose_that_changes_nothing_draws_the_rest_mesh_exactly() {
    use combustion::scene::motion::SkinWeights;
    let mut scene = common::deformed_spheres();
    let skinned = scene.objects.len() - 2;
    let mesh = scene.objects[skinned].mesh;
    let count = scene.meshes[mesh].vertices.len();
    scene.meshes[mesh].skin = Some(SkinWeights {
        offsets: (0..=count as u32).collect(),
        joints: scene.meshes[mesh]
            .vertices
            .iter()
            .map(|v| u32::from(v.position[1] > 0.0))
            .collect(),
        weights: vec![1.0; count],
    });
    let mut pose = scene.pose_objects(&scene.motion.rest_pose());
    for joints in &mut pose.joints {
        joints.fill(glam::Mat4::IDENTITY);
    }
    let mut still = scene.clone();
    for object in &mut still.objects {
        object.node = None;
    }
    still.objects[skinned].transform = glam::Mat4::IDENTITY;
    still.objects[skinned + 1].transform = pose.transforms[skinned + 1];
    still.meshes[mesh].skin = None;
    let morphed = still.objects[skinned + 1].mesh;
    still.meshes[morphed].morph_targets.clear();
    let mut headless = lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let posed = common::render_posed(renderer, &gpu, Some(&pose), (W, H));
        let still = renderer.upload(&still).unwrap();
        let expected = renderer.render(&still, W, H, Readback::ALL).unwrap();
        let differing = common::hdr_pixels_differing(&posed, &expected);
        assert_eq!(
            differing, 0,
            "{differing} pixels differ from the rest meshes'"
        );
        let lit = expected.hdr.iter().filter(|p| p[0] > 0.0).count();
        assert!(lit > 500, "only {lit} pixels lit");
    }
    finish(headless);
}

/// A joint scaled to 0 hides what it carries (as rigs hide parts), and one flattened
/// flattens it, with no NaN anywhere: the normals of a singular joint sum come from its
/// cofactors (finite where the inverse is not), and a vertex collapsed to a point keeps
/// its own. The sphere's upper half rides joint 1: scaled to 0 it collapses into a point
/// (the blended middle stretches to it); flattened along the joint's y it becomes a
/// disc, whose normals point along y.
#[test]
fn a_joint_scaled_to_zero_or_flattened_poses_without_a_nan() {
    let scene = common::deformed_spheres();
    let skinned = scene.objects.len() - 2;
    let rest_vertices = &scene.meshes[scene.objects[skinned].mesh].vertices;
    let at_rest = scene.pose_objects(&scene.motion.rest_pose());
    let joint = at_rest.joints[0][1];
    let with_joint_scaled = |scale: glam::Vec3| {
        let mut pose = at_rest.clone();
        pose.joints[0][1] = joint * glam::Mat4::from_scale(scale);
        pose
    };
    let mut headless = lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let mut frames = Vec::new();
        for (label, pose) in [
            ("at rest", at_rest.clone()),
            ("scaled to 0", with_joint_scaled(glam::Vec3::ZERO)),
            (
                "flattened",
                with_joint_scaled(glam::Vec3::new(1.0, 0.0, 1.0)),
            ),
        ] {
            let frame = common::render_posed(renderer, &gpu, Some(&pose), (W, H));
            assert_eq!(frame.non_finite_pixels(), 0, "{label}");
            for (object, vertices) in renderer.read_posed_vertices(&gpu).unwrap() {
                for (v, posed) in vertices.iter().enumerate() {
                    let n = glam::Vec3::from(posed.normal);
                    assert!(
                        n.is_finite() && n != glam::Vec3::ZERO,
                        "{label}: object {object} vertex {v}: normal {n}"
                    );
                    // The flattened disc (the vertices on joint 1 alone) faces along y.
                    if label == "flattened"
                        && object == skinned
                        && rest_vertices[v].position[1] > 0.2
                    {
                        assert!(n.normalize().y.abs() > 0.9999, "vertex {v}: normal {n}");
                    }
                }
            }
            frames.push(frame);
        }
        for (i, label) in [(1, "scaled to 0"), (2, "flattened")] {
            let changed = common::hdr_pixels_differing(&frames[0], &frames[i]);
            assert!(changed > 50, "{label}: {changed} pixels changed");
        }
    }
    finish(headless);
}

/// An object whose node is scaled to 0 at rest (it appears when its animation grows it)
/// uploads, is not drawn at rest — the frame is the one without it, bit for bit, with no
/// NaN — and is drawn once the animation has grown it.
#[test]
fn an_object_scaled_to_zero_at_rest_appears_when_its_animation_grows_it() {
    use combustion::scene::motion::LocalTransform;
    let mut scene = animated_grid();
    // Sphere 1 (object 1, node 2): scaled to 0 at rest; its animation scales it 1 → 1.6.
    if let LocalTransform::Trs { scale, .. } = &mut scene.motion.nodes[2].local {
        *scale = glam::Vec3::ZERO;
    }
    let rest = scene.pose_objects(&scene.motion.rest_pose());
    scene.objects[1].transform = rest.transforms[1];
    scene.validate().unwrap();
    let mut without = scene.clone();
    without.objects.remove(1);
    let mut headless = lavapipe(common::exact_f32());
    {
        let renderer = headless.renderer();
        let gpu = renderer.upload(&scene).unwrap();
        let at_rest = renderer.render(&gpu, W, H, Readback::ALL).unwrap();
        assert_eq!(at_rest.non_finite_pixels(), 0);
        let without = renderer.upload(&without).unwrap();
        let expected = renderer.render(&without, W, H, Readback::ALL).unwrap();
        assert_eq!(common::hdr_pixels_differing(&at_rest, &expected), 0);
        let pose = scene.pose_at(0, 1.0).unwrap();
        let grown = common::render_posed(renderer, &gpu, Some(&pose), (W, H));
        let appeared = common::hdr_pixels_differing(&grown, &at_rest);
        assert!(appeared > 20, "the grown sphere changed {appeared} pixels");
    }
    finish(headless);
}
