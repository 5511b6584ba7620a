//! What skinning costs per frame: a synthetic character — a tube of 50,000 vertices
//! along a chain of 100 joints, each vertex blended between its two nearest joints, the
//! chain curling over a 2 s animation — rendered while the animation plays, against the
//! same tube drawn still (not skinned). GPU timestamps, medians of n frames:
//! `cargo run --release --example skinning_cost -- [FRAMES] [WIDTHxHEIGHT]`.

use combustion::renderer::{FrameInputs, PassTimings, Readback};
use combustion::scene::motion::{
    Animation, Channel, Interpolation, LocalTransform, Node, Property, Sampler, Skin, SkinWeights,
};
use combustion::scene::{builtin_scene, Mesh, NodeLink, Object, Scene, Vertex};
use combustion::{Headless, HeadlessDesc};
use glam::{Mat4, Quat, Vec3};

/// Joints along the chain.
const JOINTS: usize = 100;
/// Rings of vertices along the tube and vertices around each ring (250 × 200 = 50,000).
const RINGS: usize = 250;
const AROUND: usize = 200;
/// The tube's length and radius, metres.
const LENGTH: f32 = 3.0;
const RADIUS: f32 = 0.08;

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// The tube along +y from the origin, skinned to the chain, and the scene around it.
fn character() -> Scene {
    let mut vertices = Vec::with_capacity(RINGS * AROUND);
    let mut influences = Vec::with_capacity(RINGS * AROUND);
    let spacing = LENGTH / JOINTS as f32;
    for ring in 0..RINGS {
        let y = LENGTH * ring as f32 / (RINGS - 1) as f32;
        for k in 0..AROUND {
            let angle = std::f32::consts::TAU * k as f32 / AROUND as f32;
            let normal = Vec3::new(angle.cos(), 0.0, angle.sin());
            vertices.push(Vertex {
                position: (normal * RADIUS + Vec3::Y * y).to_array(),
                normal: normal.to_array(),
                tangent: [0.0, 1.0, 0.0, 1.0],
                uv: [k as f32 / AROUND as f32, y / LENGTH],
                uv1: [0.0; 2],
                color: [1.0; 4],
            });
            // Between joint j (at j · spacing) and j + 1.
            let at = (y / spacing).min(JOINTS as f32 - 1.0);
            let j = (at.floor() as usize).min(JOINTS - 2);
            let f = (at - j as f32).clamp(0.0, 1.0);
            influences.push([(j as u32, 1.0 - f), (j as u32 + 1, f)]);
        }
    }
    let weights = SkinWeights::from_influences(influences);
    let mut indices = Vec::new();
    for ring in 0..RINGS - 1 {
        for k in 0..AROUND {
            let a = (ring * AROUND + k) as u32;
            let b = (ring * AROUND + (k + 1) % AROUND) as u32;
            let (c, d) = (a + AROUND as u32, b + AROUND as u32);
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    let mesh = Mesh {
        name: "tube".into(),
        vertices,
        indices,
        skin: Some(weights),
        ..Mesh::default()
    };
    let mut scene = builtin_scene("spheres").expect("a built-in scene");
    scene.meshes = vec![mesh];
    scene.objects = vec![Object {
        node: Some(NodeLink {
            node: 0,
            offset: Mat4::IDENTITY,
        }),
        ..Object::casting_shadows(0, 0, Mat4::from_translation(Vec3::new(0.0, -1.5, 0.0)))
    }];
    // Node 0 holds the mesh; nodes 1..=100 are the chain, each a child of the one before.
    let mut nodes = vec![Node {
        name: Some("tube".into()),
        parent: None,
        local: LocalTransform::IDENTITY,
        skin: Some(0),
        weights: Vec::new(),
    }];
    for j in 0..JOINTS {
        let translation = if j == 0 {
            Vec3::new(0.0, -1.5, 0.0)
        } else {
            Vec3::Y * spacing
        };
        nodes.push(Node {
            name: Some(format!("joint {j}")),
            parent: (j > 0).then_some(j),
            local: LocalTransform::Trs {
                translation,
                rotation: Quat::IDENTITY,
                scale: Vec3::ONE,
            },
            skin: None,
            weights: Vec::new(),
        });
    }
    let inverse_bind = (0..JOINTS)
        .map(|j| Mat4::from_translation(-Vec3::Y * spacing * j as f32))
        .collect();
    // Each joint bends about z and x, out of phase along the chain, over 2 s.
    let times: Vec<f32> = (0..=8).map(|k| k as f32 * 0.25).collect();
    let mut samplers = Vec::new();
    let mut channels = Vec::new();
    for j in 0..JOINTS {
        let phase = j as f32 * 0.2;
        let values = times
            .iter()
            .flat_map(|t| {
                let a = (std::f32::consts::PI * t + phase).sin();
                (Quat::from_rotation_z(0.03 * a) * Quat::from_rotation_x(0.02 * a)).to_array()
            })
            .collect();
        samplers.push(Sampler {
            interpolation: Interpolation::Linear,
            times: times.clone(),
            values,
        });
        channels.push(Channel {
            node: j + 1,
            property: Property::Rotation,
            sampler: j,
        });
    }
    scene.motion = combustion::scene::Motion {
        nodes,
        skins: vec![Skin {
            name: Some("chain".into()),
            joints: (1..=JOINTS).collect(),
            inverse_bind,
        }],
        animations: vec![Animation {
            name: Some("curl".into()),
            samplers,
            channels,
        }],
    };
    scene.name = "synthetic character".into();
    scene
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN)
}

fn run() -> Result<(), combustion::Error> {
    let mut args = std::env::args().skip(1);
    let frames: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(30);
    let (width, height) = args
        .next()
        .and_then(|a| {
            let (w, h) = a.split_once('x')?;
            Some((w.parse().ok()?, h.parse().ok()?))
        })
        .unwrap_or((1280u32, 720u32));
    let skinned = character();
    skinned.validate()?;
    // The same tube, still: posed once on the CPU at rest and drawn as a plain mesh.
    let still = skinned.posed(&skinned.pose_objects(&skinned.motion.rest_pose()));
    let mut headless = Headless::new(&HeadlessDesc::from_env(false)?)?;
    let renderer = headless.renderer();
    let mut rows = Vec::new();
    for (label, scene) in [("skinned, playing", &skinned), ("still", &still)] {
        let gpu = renderer.upload(scene)?;
        renderer.render(&gpu, width, height, Readback::default())?;
        renderer.take_completed_timings();
        for i in 0..frames {
            let time = (i as f32 / 30.0) % 2.0;
            let pose = (label != "still").then(|| scene.pose_at(0, time).expect("the curl"));
            let inputs = FrameInputs {
                pose: pose.as_ref(),
                ..FrameInputs::of_scene(&gpu, 1.0)
            };
            renderer.submit_offscreen_with(&gpu, &inputs, width, height)?;
        }
        renderer.finish_offscreen()?;
        let timings = renderer.take_completed_timings();
        let pass = |name: &str| {
            median(
                timings
                    .iter()
                    .filter_map(|t| t.passes.iter().find(|p| p.name == name))
                    .map(|p| p.ms)
                    .collect(),
            )
        };
        rows.push((
            label,
            pass(PassTimings::DEFORM),
            pass(PassTimings::GBUFFER),
            median(timings.iter().map(|t| t.total_ms).collect()),
            timings.len(),
        ));
    }
    println!(
        "{} vertices, {JOINTS} joints, 2 influences each, {width}x{height}, medians in ms:",
        RINGS * AROUND
    );
    println!(
        "{:<18} {:>8} {:>8} {:>8} {:>4}",
        "", "deform", "gbuffer", "total", "n"
    );
    for (label, deform, gbuffer, total, n) in rows {
        println!("{label:<18} {deform:>8.2} {gbuffer:>8.2} {total:>8.2} {n:>4}");
    }
    Ok(())
}
