#![deny(clippy::arithmetic_side_effects)]
//! [`Scene`] → `.gltf` + `.bin` + PNG images, such that importing the result gives the
//! same scene (see `docs/gltf.md`, "Writing").

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use serde_json::{json, Map, Value};

use super::error::{SaveError, SaveProblem};
use super::image::encode_png;
use super::optics_ext::diffuse_model_name;
use super::{OPTICS_EXTENSION, SHADOW_EXTENSION};
use crate::{
    AlphaMode, Filter, Light, Material, Sampler, Scene, TextureRef, TextureSlot, WrapMode,
};

fn num(x: f32) -> Value {
    // The exact binary value as f64: reads back as the same f32 through any parser.
    Value::from(f64::from(x))
}

fn nums(xs: &[f32]) -> Value {
    Value::Array(xs.iter().map(|&x| num(x)).collect())
}

struct Bin {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    fn push(&mut self, bytes: &[u8], target: u32) -> usize {
        while self.data.len() % 4 != 0 {
            self.data.push(0);
        }
        self.views.push(json!({
            "buffer": 0,
            "byteOffset": self.data.len(),
            "byteLength": bytes.len(),
            "target": target,
        }));
        self.data.extend_from_slice(bytes);
        // The view just pushed.
        self.views.len().saturating_sub(1)
    }

    fn floats<const N: usize>(&mut self, values: &[[f32; N]], with_bounds: bool) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let view = self.push(&bytes, 34962);
        let ty = match N {
            2 => "VEC2",
            3 => "VEC3",
            _ => "VEC4",
        };
        let mut accessor = json!({
            "bufferView": view,
            "componentType": 5126,
            "count": values.len(),
            "type": ty,
        });
        if with_bounds {
            let mut lo = [f32::INFINITY; N];
            let mut hi = [f32::NEG_INFINITY; N];
            for v in values {
                for c in 0..N {
                    lo[c] = lo[c].min(v[c]);
                    hi[c] = hi[c].max(v[c]);
                }
            }
            accessor["min"] = nums(&lo);
            accessor["max"] = nums(&hi);
        }
        self.accessors.push(accessor);
        // The accessor just pushed.
        self.accessors.len().saturating_sub(1)
    }

    fn indices(&mut self, indices: &[u32]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.push(&bytes, 34963);
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": 5125,
            "count": indices.len(),
            "type": "SCALAR",
        }));
        self.accessors.len().saturating_sub(1)
    }
}

fn sampler_json(s: &Sampler) -> Value {
    let filter = |f: Filter| match f {
        Filter::Nearest => 9728,
        Filter::Linear => 9729,
    };
    let min = match (s.min_filter, s.mipmap_filter) {
        (f, None) => filter(f),
        (Filter::Nearest, Some(Filter::Nearest)) => 9984,
        (Filter::Linear, Some(Filter::Nearest)) => 9985,
        (Filter::Nearest, Some(Filter::Linear)) => 9986,
        (Filter::Linear, Some(Filter::Linear)) => 9987,
    };
    let wrap = |w: WrapMode| match w {
        WrapMode::Repeat => 10497,
        WrapMode::MirroredRepeat => 33648,
        WrapMode::ClampToEdge => 33071,
    };
    json!({
        "magFilter": filter(s.mag_filter),
        "minFilter": min,
        "wrapS": wrap(s.wrap_u),
        "wrapT": wrap(s.wrap_v),
    })
}

/// Node matrix whose -Z axis is exactly `direction` (not normalised) and whose X and Y
/// axes are unit and orthogonal to it, translated to `position`.
fn aim_matrix(position: Vec3, direction: Vec3) -> Mat4 {
    let z = -direction.normalize();
    let x = super::geometry::reference_tangent(z);
    let y = z.cross(x);
    Mat4::from_cols(
        x.extend(0.0),
        y.extend(0.0),
        (-direction).extend(0.0),
        position.extend(1.0),
    )
}

/// The KHR_lights_punctual colour and intensity giving `power` exactly: intensity is the
/// power of two at or above the largest channel, so colour ∈ [0, 1] and
/// colour × intensity reproduces `power` bit for bit.
fn color_intensity(power: [f32; 3]) -> ([f32; 3], f32) {
    let max = power.iter().copied().fold(0.0f32, f32::max);
    if max <= 0.0 {
        return ([0.0; 3], 1.0);
    }
    let mut scale = 2f32.powi(max.log2().ceil() as i32);
    while scale < max {
        scale *= 2.0;
    }
    (power.map(|p| p / scale), scale)
}

/// A textureInfo: the texture's index, its texCoord (when not 0) and its
/// KHR_texture_transform (when not the identity).
fn texture_info_json(index: usize, texture: Option<&TextureRef>) -> Value {
    let mut info = json!({ "index": index });
    if let Some(t) = texture {
        if t.tex_coord != 0 {
            info["texCoord"] = json!(t.tex_coord);
        }
        if !t.transform.is_identity() {
            info["extensions"] = json!({ "KHR_texture_transform": {
                "offset": nums(&t.transform.offset),
                "rotation": num(t.transform.rotation),
                "scale": nums(&t.transform.scale),
            } });
        }
    }
    info
}

fn material_json(m: &Material, texture_of: &dyn Fn(TextureSlot) -> Option<usize>) -> Value {
    let defaults = Material::default();
    let slots = m.texture_slots();
    let reference =
        |slot: TextureSlot| slots.iter().find(|(s, _)| *s == slot).and_then(|(_, t)| *t);
    let info = |slot| texture_of(slot).map(|index| texture_info_json(index, reference(slot)));
    let mut pbr = json!({
        "baseColorFactor": nums(&[m.base_color[0], m.base_color[1], m.base_color[2], m.alpha]),
        "metallicFactor": num(m.metalness),
        "roughnessFactor": num(m.roughness),
    });
    if let Some(t) = info(TextureSlot::BaseColor) {
        pbr["baseColorTexture"] = t;
    }
    if let Some(t) = info(TextureSlot::MetallicRoughness) {
        pbr["metallicRoughnessTexture"] = t;
    }
    let mut out = json!({
        "name": m.name,
        "pbrMetallicRoughness": pbr,
        "emissiveFactor": nums(&m.emissive_factor),
        "doubleSided": m.double_sided,
    });
    match m.alpha_mode {
        AlphaMode::Opaque => {}
        AlphaMode::Mask { cutoff } => {
            out["alphaMode"] = json!("MASK");
            out["alphaCutoff"] = num(cutoff);
        }
        AlphaMode::Blend => out["alphaMode"] = json!("BLEND"),
    }
    if let Some(mut t) = info(TextureSlot::Normal) {
        t["scale"] = num(m.normal_scale);
        out["normalTexture"] = t;
    }
    if let Some(mut t) = info(TextureSlot::Occlusion) {
        t["strength"] = num(m.occlusion_strength);
        out["occlusionTexture"] = t;
    }
    if let Some(t) = info(TextureSlot::Emissive) {
        out["emissiveTexture"] = t;
    }
    let mut extensions = Map::new();
    if m.dielectric_ior != defaults.dielectric_ior {
        extensions.insert(
            "KHR_materials_ior".into(),
            json!({ "ior": num(m.dielectric_ior) }),
        );
    }
    if m.emissive_strength != defaults.emissive_strength {
        extensions.insert(
            "KHR_materials_emissive_strength".into(),
            json!({ "emissiveStrength": num(m.emissive_strength) }),
        );
    }
    let specular_texture = info(TextureSlot::Specular);
    let specular_color_texture = info(TextureSlot::SpecularColor);
    if m.specular_factor != defaults.specular_factor
        || m.specular_color_factor != defaults.specular_color_factor
        || specular_texture.is_some()
        || specular_color_texture.is_some()
    {
        let mut specular = json!({
            "specularFactor": num(m.specular_factor),
            "specularColorFactor": nums(&m.specular_color_factor),
        });
        if let Some(t) = specular_texture {
            specular["specularTexture"] = t;
        }
        if let Some(t) = specular_color_texture {
            specular["specularColorTexture"] = t;
        }
        extensions.insert("KHR_materials_specular".into(), specular);
    }
    let anisotropy_texture = info(TextureSlot::Anisotropy);
    if m.anisotropy_strength != 0.0 || m.anisotropy_rotation != 0.0 || anisotropy_texture.is_some()
    {
        let mut anisotropy = json!({
            "anisotropyStrength": num(m.anisotropy_strength),
            "anisotropyRotation": num(m.anisotropy_rotation),
        });
        if let Some(t) = anisotropy_texture {
            anisotropy["anisotropyTexture"] = t;
        }
        extensions.insert("KHR_materials_anisotropy".into(), anisotropy);
    }
    if m.unlit {
        extensions.insert("KHR_materials_unlit".into(), json!({}));
    }
    let transmission_texture = info(TextureSlot::Transmission);
    if m.transmission != defaults.transmission || transmission_texture.is_some() {
        let mut t = json!({ "transmissionFactor": num(m.transmission) });
        if let Some(texture) = transmission_texture {
            t["transmissionTexture"] = texture;
        }
        extensions.insert("KHR_materials_transmission".into(), t);
    }
    if let Some(volume) = &m.volume {
        let mut v = json!({
            "thicknessFactor": num(volume.thickness),
            "attenuationColor": nums(&volume.attenuation_color),
        });
        if let Some(texture) = info(TextureSlot::Thickness) {
            v["thicknessTexture"] = texture;
        }
        // JSON has no infinity: glTF's default (absent) stands for it.
        if volume.attenuation_distance.is_finite() {
            v["attenuationDistance"] = num(volume.attenuation_distance);
        }
        extensions.insert("KHR_materials_volume".into(), v);
    }
    if m.is_coated() {
        let mut coat = json!({
            "clearcoatFactor": num(m.clearcoat),
            "clearcoatRoughnessFactor": num(m.clearcoat_roughness),
        });
        if let Some(t) = info(TextureSlot::Clearcoat) {
            coat["clearcoatTexture"] = t;
        }
        if let Some(t) = info(TextureSlot::ClearcoatRoughness) {
            coat["clearcoatRoughnessTexture"] = t;
        }
        if let Some(mut t) = info(TextureSlot::ClearcoatNormal) {
            t["scale"] = num(m.clearcoat_normal_scale);
            coat["clearcoatNormalTexture"] = t;
        }
        extensions.insert("KHR_materials_clearcoat".into(), coat);
    }
    if m.has_sheen() {
        let mut sheen = json!({
            "sheenColorFactor": nums(&m.sheen_color),
            "sheenRoughnessFactor": num(m.sheen_roughness),
        });
        if let Some(t) = info(TextureSlot::SheenColor) {
            sheen["sheenColorTexture"] = t;
        }
        if let Some(t) = info(TextureSlot::SheenRoughness) {
            sheen["sheenRoughnessTexture"] = t;
        }
        extensions.insert("KHR_materials_sheen".into(), sheen);
    }
    if let Some(film) = m.film() {
        let mut iridescence = json!({
            "iridescenceFactor": num(film.factor),
            "iridescenceIor": num(film.ior),
            "iridescenceThicknessMinimum": num(film.thickness_min_nm),
            "iridescenceThicknessMaximum": num(film.thickness_max_nm),
        });
        if let Some(t) = info(TextureSlot::Iridescence) {
            iridescence["iridescenceTexture"] = t;
        }
        if let Some(t) = info(TextureSlot::IridescenceThickness) {
            iridescence["iridescenceThicknessTexture"] = t;
        }
        extensions.insert("KHR_materials_iridescence".into(), iridescence);
    }
    let mut conductor = json!({
        "eta": nums(&m.conductor.eta),
        "k": nums(&m.conductor.k),
    });
    if m.conductor_from_base_color {
        conductor["fromBaseColor"] = Value::Bool(true);
    }
    let mut optics = json!({
        "conductor": conductor,
        "polarisationWeight": num(m.polarisation_weight),
        "diffuseModel": diffuse_model_name(m.diffuse_model),
    });
    if let Some(ior) = m.outside_ior {
        optics["outsideIor"] = num(ior);
    }
    extensions.insert(OPTICS_EXTENSION.into(), optics);
    out["extensions"] = Value::Object(extensions);
    out
}

/// Writes `scene` as `path` (a `.gltf` JSON file) with its geometry in `STEM.bin` and its
/// images as `STEM_N.png` beside it. Every material carries `COMBUSTION_materials_optics`
/// with its exact optical constants, so [`super::import`] gives back an identical scene
/// (meshes and materials in scene order) as long as every mesh and material is used by
/// an object and no object's transform mirrors (negative determinant; glTF flips the
/// winding of those). Meshes no object uses are not written. Objects are written where
/// they are, without the nodes they hang from; skins, morph targets and animations are
/// not written: a scene with any is refused (save [`Scene::posed`] of a pose for a
/// still copy).
pub fn save_gltf(scene: &Scene, path: &Path) -> Result<(), SaveError> {
    let fail = |file: &Path, problem| SaveError {
        file: file.to_path_buf(),
        problem,
    };
    scene
        .validate()
        .map_err(|e| fail(path, SaveProblem::Scene(e)))?;
    // What would be lost: an object's skin or morph targets, or an animation of the
    // nodes objects hang from.
    let moving = scene.objects.iter().any(|o| {
        let mesh = &scene.meshes[o.mesh];
        mesh.skin.is_some()
            || !mesh.morph_targets.is_empty()
            || (o.node.is_some() && !scene.motion.animations.is_empty())
    });
    if moving {
        return Err(fail(
            path,
            SaveProblem::Unsupported(
                "the scene's skins, morph targets and animations cannot be written yet; save Scene::posed of a pose for a still copy".into(),
            ),
        ));
    }
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| {
            fail(
                path,
                SaveProblem::Unsupported("the path has no file name".into()),
            )
        })?;
    let dir = path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let bin_name = format!("{stem}.bin");

    let mut bin = Bin {
        data: Vec::new(),
        views: Vec::new(),
        accessors: Vec::new(),
    };
    // Geometry of every used mesh.
    let used_meshes: BTreeSet<usize> = scene.objects.iter().map(|o| o.mesh).collect();
    let mut mesh_attributes = vec![None; scene.meshes.len()];
    for &i in &used_meshes {
        let mesh = &scene.meshes[i];
        if mesh.indices.is_empty() || mesh.vertices.is_empty() {
            return Err(fail(
                path,
                SaveProblem::Unsupported(format!(
                    "mesh {i} (`{}`) has no {}",
                    mesh.name,
                    mesh.topology.name()
                )),
            ));
        }
        let positions: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.position).collect();
        let normals: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.normal).collect();
        let tangents: Vec<[f32; 4]> = mesh.vertices.iter().map(|v| v.tangent).collect();
        let uvs: Vec<[f32; 2]> = mesh.vertices.iter().map(|v| v.uv).collect();
        let mut attributes = json!({
            "POSITION": bin.floats(&positions, true),
            "NORMAL": bin.floats(&normals, false),
            "TANGENT": bin.floats(&tangents, false),
            "TEXCOORD_0": bin.floats(&uvs, false),
        });
        // Set 1 only where it differs from set 0 (the importer copies set 0 otherwise).
        if mesh.vertices.iter().any(|v| v.uv1 != v.uv) {
            let uvs1: Vec<[f32; 2]> = mesh.vertices.iter().map(|v| v.uv1).collect();
            attributes["TEXCOORD_1"] = json!(bin.floats(&uvs1, false));
        }
        // Colours only where some vertex is not white (the importer's default).
        if mesh.has_colors() {
            let colors: Vec<[f32; 4]> = mesh.vertices.iter().map(|v| v.color).collect();
            attributes["COLOR_0"] = json!(bin.floats(&colors, false));
        }
        let indices = bin.indices(&mesh.indices);
        mesh_attributes[i] = Some((attributes, indices));
    }

    // Images, samplers, textures.
    let table = scene.texture_table();
    let mut images = Vec::new();
    for (i, image) in table.images.iter().enumerate() {
        let file_name = format!("{stem}_{i}.png");
        let file = dir.join(&file_name);
        let png = encode_png(image.width, image.height, &image.pixels)
            .map_err(|e| fail(&file, SaveProblem::Png(e)))?;
        std::fs::write(&file, png).map_err(|e| fail(&file, SaveProblem::Io(e)))?;
        images.push(json!({ "name": image.name, "uri": file_name, "mimeType": "image/png" }));
    }
    let mut samplers: Vec<Sampler> = Vec::new();
    let mut textures = Vec::new();
    for entry in &table.textures {
        let sampler = match samplers.iter().position(|s| *s == entry.sampler) {
            Some(i) => i,
            None => {
                samplers.push(entry.sampler);
                samplers.len().saturating_sub(1)
            }
        };
        textures.push(json!({ "sampler": sampler, "source": entry.image }));
    }

    let materials: Vec<Value> = scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let slots = table.material_textures[i];
            let texture_of = |slot: TextureSlot| {
                TextureSlot::ALL
                    .iter()
                    .position(|&s| s == slot)
                    .and_then(|k| slots[k])
            };
            material_json(m, &texture_of)
        })
        .collect();

    // One glTF mesh per (mesh, material) pair, in mesh order, sharing the accessors.
    let pairs: BTreeSet<(usize, usize)> =
        scene.objects.iter().map(|o| (o.mesh, o.material)).collect();
    let pairs: Vec<(usize, usize)> = pairs.into_iter().collect();
    let meshes: Vec<Value> = pairs
        .iter()
        .map(|&(mesh, material)| {
            let (attributes, indices) = mesh_attributes[mesh].clone().unwrap_or_default();
            json!({
                "name": scene.meshes[mesh].name,
                "primitives": [{
                    "attributes": attributes,
                    "indices": indices,
                    "material": material,
                    "mode": match scene.meshes[mesh].topology {
                        crate::Topology::Points => 0,
                        crate::Topology::Lines => 1,
                        crate::Topology::Triangles => 4,
                    },
                }],
            })
        })
        .collect();

    let mut nodes = Vec::new();
    // Whether COMBUSTION_shadows is written (an object or a light that differs from the
    // defaults).
    let mut writes_shadows = false;
    for (i, object) in scene.objects.iter().enumerate() {
        let mesh = pairs
            .iter()
            .position(|&p| p == (object.mesh, object.material))
            .unwrap_or(0);
        let mut node = json!({
            "name": format!("object {i}"),
            "mesh": mesh,
            "matrix": nums(&object.transform.to_cols_array()),
        });
        if !object.casts_shadows {
            node["extensions"] = json!({ SHADOW_EXTENSION: { "castsShadows": false } });
            writes_shadows = true;
        }
        nodes.push(node);
    }
    let mut lights = Vec::new();
    for (i, light) in scene.lights.iter().enumerate() {
        let (kind, matrix, power, spot, range) = match light {
            Light::Point {
                position,
                intensity,
                range,
                ..
            } => (
                "point",
                Mat4::from_translation(*position),
                intensity,
                None,
                *range,
            ),
            Light::Directional {
                direction,
                irradiance,
                ..
            } => (
                "directional",
                aim_matrix(Vec3::ZERO, *direction),
                irradiance,
                None,
                None,
            ),
            Light::Spot {
                position,
                direction,
                intensity,
                inner_cone,
                outer_cone,
                range,
                ..
            } => (
                "spot",
                aim_matrix(*position, *direction),
                intensity,
                Some(
                    json!({ "innerConeAngle": num(*inner_cone), "outerConeAngle": num(*outer_cone) }),
                ),
                *range,
            ),
        };
        let (color, intensity) = color_intensity(*power);
        let mut light = json!({ "type": kind, "color": nums(&color), "intensity": num(intensity) });
        if let Some(spot) = spot {
            light["spot"] = spot;
        }
        if let Some(range) = range {
            light["range"] = num(range);
        }
        // Shadows: written where they differ from the defaults (casting, no size).
        let (size_name, size) = match scene.lights[i] {
            Light::Directional {
                angular_diameter, ..
            } => ("angularDiameter", angular_diameter),
            Light::Point { radius, .. } | Light::Spot { radius, .. } => ("radius", radius),
        };
        let casts = scene.lights[i].casts_shadows();
        if !casts || size != 0.0 {
            let mut ext = json!({ "castsShadows": casts });
            if size != 0.0 {
                ext[size_name] = num(size);
            }
            light["extensions"] = json!({ SHADOW_EXTENSION: ext });
            writes_shadows = true;
        }
        lights.push(light);
        nodes.push(json!({
            "name": format!("light {i}"),
            "matrix": nums(&matrix.to_cols_array()),
            "extensions": { "KHR_lights_punctual": { "light": i } },
        }));
    }
    let camera = &scene.camera;
    let forward = (camera.target - camera.position).normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    let view = Mat4::from_cols(
        right.extend(0.0),
        up.extend(0.0),
        (-forward).extend(0.0),
        camera.position.extend(1.0),
    );
    nodes.push(json!({
        "name": "camera",
        "camera": 0,
        "matrix": nums(&view.to_cols_array()),
        "extras": { "combustion": {
            "target": nums(&camera.target.to_array()),
            "up": nums(&camera.up.to_array()),
        } },
    }));

    let mut used = vec![OPTICS_EXTENSION.to_owned()];
    if scene.materials.iter().any(|m| {
        m.texture_slots()
            .iter()
            .any(|(_, t)| t.is_some_and(|t| !t.transform.is_identity()))
    }) {
        used.push("KHR_texture_transform".into());
    }
    for material in &materials {
        if let Some(ext) = material["extensions"].as_object() {
            for name in ext.keys() {
                if !used.contains(name) {
                    used.push(name.clone());
                }
            }
        }
    }
    let mut root_extensions = json!({ OPTICS_EXTENSION: { "outsideIor": num(scene.outside_ior) } });
    if writes_shadows {
        used.push(SHADOW_EXTENSION.into());
    }
    if !lights.is_empty() {
        used.push("KHR_lights_punctual".into());
        root_extensions["KHR_lights_punctual"] = json!({ "lights": lights });
    }
    used.sort();
    let mut root = json!({
        "asset": { "version": "2.0", "generator": concat!("Combustion ", env!("CARGO_PKG_VERSION")) },
        "extensionsUsed": used,
        "extensions": root_extensions,
        "scene": 0,
        "scenes": [{ "name": scene.name, "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "cameras": [{
            "type": "perspective",
            "perspective": {
                "yfov": num(camera.vertical_fov),
                "znear": num(camera.near),
                "zfar": num(camera.far),
            },
        }],
        "materials": materials,
        "meshes": meshes,
        "accessors": bin.accessors,
        "bufferViews": bin.views,
        "buffers": [{ "uri": bin_name, "byteLength": bin.data.len() }],
    });
    if !images.is_empty() {
        root["images"] = Value::Array(images);
        root["samplers"] = Value::Array(samplers.iter().map(sampler_json).collect());
        root["textures"] = Value::Array(textures);
    }
    let bin_path = dir.join(&bin_name);
    std::fs::write(&bin_path, &bin.data).map_err(|e| fail(&bin_path, SaveProblem::Io(e)))?;
    let mut text = serde_json::to_string_pretty(&root)
        .map_err(|e| fail(path, SaveProblem::Unsupported(e.to_string())))?;
    text.push('\n');
    std::fs::write(path, text).map_err(|e| fail(path, SaveProblem::Io(e)))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_power_splits_exactly() {
        for power in [
            [60.0, 60.0, 60.0],
            [12.0, 13.0, 15.0],
            [0.6, 0.58, 0.55],
            [0.0; 3],
            [1e-3, 7.7, 1e6],
        ] {
            let (color, intensity) = color_intensity(power);
            assert!(color.iter().all(|c| (0.0..=1.0).contains(c)), "{color:?}");
            assert_eq!(color.map(|c| c * intensity), power);
        }
    }

    #[test]
    fn aim_matrix_points_minus_z_along_the_direction() {
        let d = Vec3::new(-0.3, -1.0, -0.4);
        let m = aim_matrix(Vec3::ONE, d);
        assert_eq!(-m.z_axis.truncate(), d);
        assert!(m.determinant() > 0.0);
    }
}
