//! The scene crate's f32 player and vertex posing against the f64 pose, on the Khronos
//! skinned, morphed and animated sample models (in `../shared/data/gltf`, beside the
//! workspace; skipped with a message where they are absent).

use std::path::{Path, PathBuf};

use combustion_reference::pose::{posed_objects, sample_f64, slerp_f64};
use combustion_scene::gltf::{import, ImportOptions};
use combustion_scene::motion::{pose_vertex, Interpolation, Sampler};
use combustion_scene::Scene;
use glam::{DQuat, DVec3, Quat, Vec3};

/// The skinned, morphed and animated sample models, by file.
const ANIMATED: [&str; 10] = [
    "AnimatedMorphCube/glTF-Binary/AnimatedMorphCube.glb",
    "AnimatedTriangle/glTF/AnimatedTriangle.gltf",
    "BoxAnimated/glTF-Binary/BoxAnimated.glb",
    "CesiumMan/glTF-Binary/CesiumMan.glb",
    "InterpolationTest/glTF-Binary/InterpolationTest.glb",
    "MorphPrimitivesTest/glTF-Binary/MorphPrimitivesTest.glb",
    "RiggedFigure/glTF-Binary/RiggedFigure.glb",
    "RiggedSimple/glTF-Binary/RiggedSimple.glb",
    "SimpleMorph/glTF/SimpleMorph.gltf",
    "SimpleSkin/glTF/SimpleSkin.gltf",
];

#[path = "../../../tests/common/shared_data.rs"]
mod shared_data;

fn samples() -> Option<PathBuf> {
    shared_data::shared_gltf_samples()
}

fn load(dir: &Path, relative: &str) -> Scene {
    import(&dir.join(relative), &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{relative}: {e}"))
        .0
}

/// The f32 player (sample, world transforms, joint matrices) and `pose_vertex` place
/// every vertex of every animated sample model where the f64 pose does, at rest and at
/// eleven times through each animation (and past its end), to a few f32 roundings of
/// the model's size; normals and tangents to a few f32 roundings of a unit vector.
#[test]
fn the_player_poses_every_vertex_as_the_f64_pose_does() {
    let Some(dir) = samples() else { return };
    for relative in ANIMATED {
        let scene = load(&dir, relative);
        let motion = &scene.motion;
        let morphed = scene.meshes.iter().any(|m| !m.morph_targets.is_empty());
        assert!(
            !motion.animations.is_empty() || morphed,
            "{relative}: neither an animation nor a morph target imported"
        );
        let rest = posed_objects(&scene, None);
        let extent = rest
            .iter()
            .flatten()
            .map(|v| v.position.abs().max_element())
            .fold(0.0f64, f64::max);
        let mut cases = vec![None];
        for (a, animation) in motion.animations.iter().enumerate() {
            let duration = animation.duration();
            for k in 0..=11 {
                cases.push(Some((a, f64::from(duration) * f64::from(k) / 10.0)));
            }
        }
        let (mut worst_position, mut worst_direction) = (0.0f64, 0.0f64);
        for case in cases {
            let pose = match case {
                Some((a, t)) => motion.sample(a, t as f32).unwrap(),
                None => motion.rest_pose(),
            };
            let poses = scene.pose_objects(&pose);
            let expected = posed_objects(&scene, case);
            for (o, object) in scene.objects.iter().enumerate() {
                let mesh = &scene.meshes[object.mesh];
                let joints = scene.object_joints(o, &poses);
                for (v, want) in expected[o].iter().enumerate() {
                    let got = pose_vertex(mesh, v, &poses.weights[o], joints, &poses.transforms[o]);
                    let position = (Vec3::from(got.position).as_dvec3() - want.position).length();
                    worst_position = worst_position.max(position / extent);
                    for (got, want) in [
                        (Vec3::from(got.normal), want.normal),
                        (Vec3::from_slice(&got.tangent[..3]), want.tangent),
                    ] {
                        if want != DVec3::ZERO {
                            worst_direction = worst_direction.max((got.as_dvec3() - want).length());
                        }
                    }
                }
            }
        }
        eprintln!(
            "{relative}: position error ≤ {worst_position:.2e} of the extent {extent:.3}, direction error ≤ {worst_direction:.2e}"
        );
        assert!(
            worst_position < 16.0 * f64::from(f32::EPSILON),
            "{relative}: a vertex is {worst_position:.2e} of the model's extent from the f64 pose"
        );
        assert!(
            worst_direction < 64.0 * f64::from(f32::EPSILON),
            "{relative}: a normal or tangent is {worst_direction:.2e} from the f64 pose's"
        );
    }
}

/// The player's samplers against the f64 ones and against hand computations: each
/// interpolation at its keys, between them, before and after them.
#[test]
fn samplers_interpolate_as_gltf_specifies() {
    let at = |sampler: &Sampler, time: f32| {
        let mut out = vec![0.0; sampler.width()];
        sampler.sample(time, false, &mut out);
        out
    };
    let keys = |interpolation, values: Vec<f32>| Sampler {
        interpolation,
        times: vec![1.0, 2.0, 4.0],
        values,
    };
    let step = keys(Interpolation::Step, vec![0.0, 10.0, 30.0]);
    let linear = keys(Interpolation::Linear, vec![0.0, 10.0, 30.0]);
    // Cubic: (in-tangent, value, out-tangent) per key.
    let cubic = keys(
        Interpolation::CubicSpline,
        vec![0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 2.0, 3.0, 0.0],
    );
    for (sampler, time, want) in [
        (&step, 0.0, 0.0),
        (&step, 1.0, 0.0),
        (&step, 1.999, 0.0),
        (&step, 2.0, 10.0),
        (&step, 3.5, 10.0),
        (&step, 9.0, 30.0),
        (&linear, 0.5, 0.0),
        (&linear, 1.25, 2.5),
        (&linear, 3.0, 20.0),
        (&linear, 4.0, 30.0),
        (&linear, 5.0, 30.0),
        // Hermite at s = ½ over [1, 2] (Δt 1): ½·0 + ⅛·1·1 + ½·1 − ⅛·1·0 = 0.625.
        (&cubic, 1.5, 0.625),
        // Over [2, 4] (Δt 2) at s = ½: ½·1 + ⅛·2·0 + ½·3 − ⅛·2·2 = 1.5.
        (&cubic, 3.0, 1.5),
        (&cubic, 4.0, 3.0),
        (&cubic, 0.0, 0.0),
    ] {
        let got = at(sampler, time)[0];
        assert!(
            (got - want).abs() <= 1e-6,
            "{:?} at {time}: {got}, expected {want}",
            sampler.interpolation
        );
        let f64_value = sample_f64(sampler, f64::from(time), 1, false)[0];
        assert!(
            (f64_value - f64::from(want)).abs() <= 1e-12,
            "f64 at {time}: {f64_value}"
        );
    }
    // Rotations: halfway from identity to 90° about z is 45°, and a key given as −q (the
    // same rotation) is reached along the shorter arc all the same.
    let quarter = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    for end in [quarter, -quarter] {
        let sampler = Sampler {
            interpolation: Interpolation::Linear,
            times: vec![0.0, 1.0],
            values: [Quat::IDENTITY.to_array(), end.to_array()].concat(),
        };
        let mut q = [0.0; 4];
        sampler.sample(0.5, true, &mut q);
        let angle = Quat::from_array(q).angle_between(Quat::IDENTITY);
        assert!(
            (angle - std::f32::consts::FRAC_PI_4).abs() < 1e-6,
            "{end:?}: halfway is {angle} rad from the start"
        );
        let f64_q = slerp_f64(DQuat::IDENTITY, end.as_dquat(), 0.5);
        // (The key is an f32 quaternion: its angle is 90° to about 1e-8.)
        assert!((f64_q.angle_between(DQuat::IDENTITY) - std::f64::consts::FRAC_PI_4).abs() < 1e-7);
    }
}

/// The file's bytes, its buffers' bytes (a GLB's binary chunk, or the files its URIs
/// name beside it) and its document, read by the gltf crate's own readers.
fn read_independently(path: &Path) -> (gltf::Document, Vec<Vec<u8>>) {
    let gltf = gltf::Gltf::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let buffers = gltf
        .document
        .buffers()
        .map(|buffer| match buffer.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().expect("the GLB's binary chunk"),
            gltf::buffer::Source::Uri(uri) => {
                std::fs::read(path.parent().unwrap().join(uri)).unwrap()
            }
        })
        .collect();
    (gltf.document, buffers)
}

/// What the importer read of every skin, morph target and animation of the sample
/// models is what the gltf crate's own readers read: each channel's node, property,
/// interpolation, key times and values (rotations normalised); each skin's joints and
/// inverse bind matrices; and each built vertex's joint influences and target
/// displacements are those of a vertex of the file at its position.
#[test]
fn the_imported_motion_is_what_the_file_holds() {
    use combustion_scene::motion::Property;
    use gltf::animation::util::ReadOutputs;
    let Some(dir) = samples() else { return };
    for relative in ANIMATED {
        let scene = load(&dir, relative);
        let motion = &scene.motion;
        let (document, buffers) = read_independently(&dir.join(relative));
        let data = |buffer: gltf::Buffer| Some(buffers[buffer.index()].as_slice());
        assert_eq!(
            document.animations().count(),
            motion.animations.len(),
            "{relative}"
        );
        for (animation, ours) in document.animations().zip(&motion.animations) {
            assert_eq!(
                animation.channels().count(),
                ours.channels.len(),
                "{relative}"
            );
            for (channel, our) in animation.channels().zip(&ours.channels) {
                let sampler = &ours.samplers[our.sampler];
                assert_eq!(channel.target().node().index(), our.node, "{relative}");
                assert_eq!(
                    format!("{:?}", channel.sampler().interpolation()).to_lowercase(),
                    format!("{:?}", sampler.interpolation).to_lowercase(),
                    "{relative}"
                );
                let reader = channel.reader(data);
                let times: Vec<f32> = reader.read_inputs().unwrap().collect();
                assert_eq!(times, sampler.times, "{relative}");
                let (property, values, normalised): (Property, Vec<f32>, bool) =
                    match reader.read_outputs().unwrap() {
                        ReadOutputs::Translations(v) => {
                            (Property::Translation, v.flatten().collect(), false)
                        }
                        ReadOutputs::Scales(v) => (Property::Scale, v.flatten().collect(), false),
                        ReadOutputs::Rotations(v) => {
                            (Property::Rotation, v.into_f32().flatten().collect(), true)
                        }
                        ReadOutputs::MorphTargetWeights(v) => {
                            (Property::Weights, v.into_f32().collect(), false)
                        }
                    };
                assert_eq!(property, our.property, "{relative}");
                assert_eq!(values.len(), sampler.values.len(), "{relative}");
                let cubic = sampler.interpolation == Interpolation::CubicSpline;
                if normalised && !cubic {
                    for (file, ours) in values.chunks(4).zip(sampler.values.chunks(4)) {
                        let file = Quat::from_slice(file).normalize();
                        assert!(
                            file.abs_diff_eq(Quat::from_slice(ours), 1e-7),
                            "{relative}: {file} against {ours:?}"
                        );
                    }
                } else {
                    assert_eq!(values, sampler.values, "{relative}");
                }
            }
        }
        assert_eq!(document.skins().count(), motion.skins.len(), "{relative}");
        for (skin, ours) in document.skins().zip(&motion.skins) {
            let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
            assert_eq!(joints, ours.joints, "{relative}");
            let matrices: Vec<glam::Mat4> = match skin.reader(data).read_inverse_bind_matrices() {
                Some(m) => m.map(|m| glam::Mat4::from_cols_array_2d(&m)).collect(),
                None => vec![glam::Mat4::IDENTITY; joints.len()],
            };
            assert_eq!(matrices, ours.inverse_bind, "{relative}");
        }
        // Every vertex of the file, by its position's bits: its influences (sorted, zero
        // weights left out) and its displacements per target.
        type Data = (Vec<(u32, u32)>, Vec<[[u32; 3]; 3]>);
        let mut by_position: std::collections::HashMap<[u32; 3], Vec<Data>> = Default::default();
        let bits = |v: [f32; 3]| v.map(f32::to_bits);
        for mesh in document.meshes() {
            for primitive in mesh.primitives() {
                let reader = primitive.reader(data);
                let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
                let mut influences = vec![Vec::new(); positions.len()];
                let mut set = 0;
                while let (Some(joints), Some(weights)) =
                    (reader.read_joints(set), reader.read_weights(set))
                {
                    for ((i, j), w) in joints.into_u16().enumerate().zip(weights.into_f32()) {
                        for (j, w) in j.iter().zip(w) {
                            if w != 0.0 {
                                influences[i].push((u32::from(*j), w.to_bits()));
                            }
                        }
                    }
                    set += 1;
                }
                let mut displacements = vec![Vec::new(); positions.len()];
                for (p, n, t) in reader.read_morph_targets() {
                    let mut lists: [Vec<[f32; 3]>; 3] = [
                        p.map_or(Vec::new(), Iterator::collect),
                        n.map_or(Vec::new(), Iterator::collect),
                        t.map_or(Vec::new(), Iterator::collect),
                    ];
                    for list in &mut lists {
                        list.resize(positions.len(), [0.0; 3]);
                    }
                    for (i, d) in displacements.iter_mut().enumerate() {
                        d.push([bits(lists[0][i]), bits(lists[1][i]), bits(lists[2][i])]);
                    }
                }
                for (i, p) in positions.iter().enumerate() {
                    influences[i].sort_unstable();
                    by_position
                        .entry(bits(*p))
                        .or_default()
                        .push((influences[i].clone(), displacements[i].clone()));
                }
            }
        }
        let mut checked = 0;
        for mesh in &scene.meshes {
            if mesh.skin.is_none() && mesh.morph_targets.is_empty() {
                continue;
            }
            for (v, vertex) in mesh.vertices.iter().enumerate() {
                let mut influences: Vec<(u32, u32)> = mesh.skin.as_ref().map_or(Vec::new(), |s| {
                    s.influences(v).map(|(j, w)| (j, w.to_bits())).collect()
                });
                influences.sort_unstable();
                let displacements: Vec<[[u32; 3]; 3]> = mesh
                    .morph_targets
                    .iter()
                    .map(|t| {
                        let d = |list: &[[f32; 3]]| bits(list.get(v).copied().unwrap_or([0.0; 3]));
                        [d(&t.positions), d(&t.normals), d(&t.tangents)]
                    })
                    .collect();
                let candidates = by_position
                    .get(&bits(vertex.position))
                    .map_or(&[][..], Vec::as_slice);
                assert!(
                    candidates.iter().any(|(i, d)| {
                        (mesh.skin.is_none() || *i == influences)
                            && (mesh.morph_targets.is_empty() || *d == displacements)
                    }),
                    "{relative}: mesh `{}` vertex {v} at {:?} has influences or displacements no vertex of the file there has",
                    mesh.name,
                    vertex.position
                );
                checked += 1;
            }
        }
        eprintln!("{relative}: {} animations, {} skins, {checked} deformed vertices as the file holds them", motion.animations.len(), motion.skins.len());
    }
}
