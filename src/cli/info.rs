//! `combustion info`: what a scene holds and which renderer features it needs.

use combustion::scene::gltf::{self, ImportOptions};
use combustion::scene::{DiffuseModel, Environment, Light, Material, Mesh, Scene, Topology};
use combustion::vk::{DeviceDesc, DeviceSelector};
use combustion::{Error, SceneSource};

use super::*;
use super::{write_stdout, CliError};

/// `info SCENE`: what the scene holds and which renderer features it needs.
pub(crate) fn info(o: &InfoArgs) -> Result<(), CliError> {
    let scene = match &o.scene {
        SceneSource::Builtin(name) => {
            let scene = combustion::scene::builtin_scene(name).map_err(Error::from)?;
            outln!("scene: builtin:{name}");
            scene
        }
        SceneSource::File(path) => {
            let (mut scene, report) =
                gltf::import(path, &ImportOptions::default()).map_err(Error::from)?;
            outln!("{report}");
            if !scene.name.is_empty() {
                outln!("scene: {}", scene.name);
            }
            if scene.environment.is_none() {
                // What `render` does with the file (SceneSource::load).
                scene.environment = Some(Environment::Studio);
                if scene.lights.is_empty() {
                    outln!(
                        "note: the file has no lights; render lights it with the studio environment (--light-rig adds the camera-relative key and fill lights)"
                    );
                } else {
                    outln!(
                        "note: render lights the file with its {} lights and the studio environment (--environment none: its lights alone; --scene-lights off: the studio alone)",
                        scene.lights.len()
                    );
                }
            }
            scene
        }
    };
    scene.validate().map_err(Error::from)?;
    write_stdout(format_args!("{}", describe_scene(&scene)));
    if let Some(budget) = o.max_error {
        // What `render --max-error` would choose at the size asked (640×360 unless
        // told).
        let device = DeviceDesc {
            selector: DeviceSelector::from_env().map_err(Error::from)?,
            ..DeviceDesc::default()
        };
        let (width, height) = (o.width, o.height);
        // A side beyond the device's limit is refused before anything is measured.
        super::args::preflight_size(&device, width, height)?;
        let choice = combustion::report::choose(&o.scene, budget, width, height, 10, device)?;
        outln!("variant sets measured at {width}x{height} (10 frames each), fastest first:");
        write_stdout(format_args!("{}", choice.explain(budget)));
    }
    Ok(())
}

pub(crate) fn fmt3(v: [f32; 3]) -> String {
    format!("({}, {}, {})", v[0], v[1], v[2])
}

/// `x` to 3 decimals, for printing.
pub(crate) fn round3(x: f32) -> f32 {
    (x * 1000.0).round() / 1000.0
}

/// `, range R m` for a light with a range.
pub(crate) fn fmt_range(range: Option<f32>) -> String {
    range.map_or(String::new(), |r| format!(", range {r} m"))
}

pub(crate) fn fmt_vec(v: glam::Vec3) -> String {
    format!("({}, {}, {})", round3(v.x), round3(v.y), round3(v.z))
}

/// One line per material: what its optics are.
pub(crate) fn describe_material(m: &Material, outside_ior: f32) -> String {
    let diffuse = match m.diffuse_model {
        DiffuseModel::Lambert => "Lambert",
        DiffuseModel::OrenNayarQualitative => "Oren-Nayar qualitative",
        DiffuseModel::OrenNayarFull => "Oren-Nayar full",
    };
    let dielectric = format!(
        "dielectric η {} over base colour {} ({diffuse})",
        m.dielectric_ior,
        fmt3(m.base_color)
    );
    let conductor = if m.conductor_from_base_color {
        "conductor η+ik from the base colour".to_owned()
    } else {
        let r = |v: [f32; 3]| fmt3(v.map(|x| (x * 1e4).round() / 1e4));
        format!("conductor η {} k {}", r(m.conductor.eta), r(m.conductor.k))
    };
    let mut parts = vec![if m.metalness >= 1.0 {
        conductor
    } else if m.metalness <= 0.0 {
        dielectric
    } else {
        format!("metalness {}: {conductor}; {dielectric}", m.metalness)
    }];
    parts.push(format!("roughness {}", m.roughness));
    if m.anisotropy_strength > 0.0 {
        parts.push(format!(
            "anisotropy {} at {}°",
            m.anisotropy_strength,
            m.anisotropy_rotation.to_degrees()
        ));
    }
    if m.outside_ior.is_some() {
        parts.push(format!("outside IOR {outside_ior} (own)"));
    }
    if m.polarisation_weight != 0.5 {
        parts.push(format!("polarisation weight {}", m.polarisation_weight));
    }
    let textures: Vec<&str> = m
        .texture_slots()
        .iter()
        .filter(|(_, t)| t.is_some())
        .map(|(slot, _)| slot.name())
        .collect();
    if !textures.is_empty() {
        parts.push(format!("textures: {}", textures.join(", ")));
    }
    if m.unlit {
        parts.push("unlit (shows its base colour as radiance)".to_owned());
    }
    match m.alpha_mode {
        combustion::scene::AlphaMode::Opaque => {}
        combustion::scene::AlphaMode::Mask { cutoff } => parts.push(format!(
            "cut out where alpha (factor {}{}) < {cutoff}",
            m.alpha,
            if m.base_color_texture.is_some() {
                " × texture"
            } else {
                ""
            }
        )),
        combustion::scene::AlphaMode::Blend => {
            parts.push(format!("blended at alpha {} (drawn opaque)", m.alpha))
        }
    }
    parts.join(", ")
}

/// `, N line segments, M points` for the scene's meshes of points and lines (empty
/// without any).
fn strokes_of(scene: &Scene) -> String {
    let mut out = String::new();
    for topology in [Topology::Lines, Topology::Points] {
        let count: usize = scene
            .meshes
            .iter()
            .filter(|m| m.topology == topology)
            .map(Mesh::primitive_count)
            .sum();
        if count > 0 {
            out.push_str(&format!(", {count} {}", topology.name()));
        }
    }
    out
}

pub(crate) fn describe_scene(scene: &Scene) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let triangles: usize = scene.meshes.iter().map(Mesh::triangle_count).sum();
    let drawn: usize = scene
        .objects
        .iter()
        .map(|o| scene.meshes[o.mesh].triangle_count())
        .sum();
    let _ = writeln!(
        out,
        "meshes: {} ({triangles} triangles{}), objects: {} ({drawn} triangles drawn)",
        scene.meshes.len(),
        strokes_of(scene),
        scene.objects.len()
    );
    let _ = writeln!(out, "materials: {}", scene.materials.len());
    for (i, m) in scene.materials.iter().enumerate() {
        let _ = writeln!(
            out,
            "  {i}: {}: {}",
            m.name,
            describe_material(m, scene.outside_ior_of(m))
        );
    }
    let _ = writeln!(
        out,
        "environment: {}",
        scene
            .environment
            .as_ref()
            .map_or("none".into(), |e| e.name())
    );
    let _ = writeln!(out, "lights: {}", scene.lights.len());
    for light in &scene.lights {
        let _ = match light {
            Light::Point {
                position,
                intensity,
                range,
                ..
            } => writeln!(
                out,
                "  point at {}, intensity {} W/sr{}",
                fmt_vec(*position),
                fmt3(*intensity),
                fmt_range(*range)
            ),
            Light::Directional {
                direction,
                irradiance,
                ..
            } => writeln!(
                out,
                "  directional along {}, irradiance {} W/m²",
                fmt_vec(direction.normalize()),
                fmt3(*irradiance)
            ),
            Light::Spot {
                position,
                direction,
                intensity,
                inner_cone,
                outer_cone,
                range,
                ..
            } => writeln!(
                out,
                "  spot at {} along {}, intensity {} W/sr, cone {:.1}°–{:.1}°{}",
                fmt_vec(*position),
                fmt_vec(direction.normalize()),
                fmt3(*intensity),
                inner_cone.to_degrees(),
                outer_cone.to_degrees(),
                fmt_range(*range)
            ),
        };
    }
    let c = &scene.camera;
    let _ = writeln!(
        out,
        "camera: at {} looking at {}, vertical field of view {:.1}°, near {} far {}",
        fmt_vec(c.position),
        fmt_vec(c.target),
        c.vertical_fov.to_degrees(),
        round3(c.near),
        round3(c.far)
    );
    let _ = writeln!(out, "outside medium IOR: {}", scene.outside_ior);
    let _ = writeln!(out, "renderer features needed:");
    for line in scene.features().to_string().lines() {
        let _ = writeln!(out, "  {line}");
    }
    out
}
