//! CPU mirrors of the structures in `shaders/include/gpu_types.glsl` and of the push
//! constants of the passes that do not generate theirs (`push_block!`). The size assertions below fail the build if a field is added on one
//! side only; the field order is the GLSL one.

use bytemuck::{Pod, Zeroable};
use combustion_scene::{Filter, Light, Material, Object, Scene, TEXTURE_SLOTS};
use glam::Mat4;

/// `MATERIAL_FLAG_*` in the shaders (generated `bindings/constants.glsl`).
pub const MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR: u32 = 1;
/// The material is unlit (KHR_materials_unlit): its pixels show their base colour as
/// radiance.
pub const MATERIAL_FLAG_UNLIT: u32 = 2;

/// `GpuMaterial` (std430, 912 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Linear base colour (rgb) and metalness (a).
    pub base_color_metalness: [f32; 4],
    /// Perceptual roughness, anisotropy strength, anisotropy rotation (radians) and the
    /// dielectric part's IOR.
    pub roughness_anisotropy_ior: [f32; 4],
    /// The conductor's η per channel (rgb) and the outside medium's IOR (a).
    pub conductor_eta_outside_ior: [f32; 4],
    /// The conductor's extinction coefficient k per channel (rgb) and the polarisation
    /// weight (a).
    pub conductor_k_polarisation: [f32; 4],
    /// The diffuse model (`DiffuseModel as u32`), the `MATERIAL_FLAG_*` bits, the occlusion
    /// strength's f32 bits, and 0.
    pub diffuse_model_flags: [u32; 4],
    /// Texture-array indices (-1: none) of the base colour, metallic–roughness, normal and
    /// occlusion slots.
    pub textures_base_mr_normal_occlusion: [i32; 4],
    /// Texture-array indices (-1: none) of the emissive, anisotropy, specular and
    /// specular colour slots (`TextureSlot::ALL` order).
    pub textures_emissive_anisotropy_specular: [i32; 4],
    /// Texture-array indices (-1: none) of the transmission and thickness slots, then -1,
    /// -1.
    pub textures_transmission_thickness: [i32; 4],
    /// Emitted radiance (rgb: the emissive factor × emissive strength, W·sr⁻¹·m⁻²) and the
    /// normal-map scale (a).
    pub emissive_normal_scale: [f32; 4],
    /// Per texture slot s (`TextureSlot::ALL` order): `[2s]` = (a, b, c, set),
    /// `[2s + 1]` = (d, e, f, 0): the slot samples at (a u + b v + c, d u + e v + f) of
    /// texture-coordinate set `set` (KHR_texture_transform; identity on set 0 by default).
    pub uv_transforms: [[f32; 4]; 2 * TEXTURE_SLOTS],
    /// The base colour factor's alpha (x), the cut-out threshold (y: glTF `alphaCutoff`
    /// of an [`combustion_scene::AlphaMode::Mask`] material, 0 otherwise), 1 in z where
    /// the base colour sampler picks the nearest mip level (0: blends two), w unused;
    /// read by the pipelines that test alpha (`ALPHA_MASK`).
    pub alpha_cutoff: [f32; 4],
    /// Per mip level of the base colour texture (`[level / 4][level % 4]`), the scale
    /// of its alpha that keeps a cut-out's coverage ([`combustion_scene::alpha_mip_scales`]);
    /// 1 for materials that are not cut-outs or whose sampler has no mipmap filter.
    pub alpha_mip_scales: [[f32; 4]; 4],
    /// x: KHR_materials_transmission's factor (0: opaque); y: KHR_materials_volume's
    /// thickness in the mesh's units (0: thin-walled); z, w: 0. Read by the forward
    /// pass's TRANSMISSION variant.
    pub transmission_thickness: [f32; 4],
    /// rgb: the volume's absorption coefficient σ (1/m, `Volume::absorption`; 0 without
    /// a volume or absorption); w: 0.
    pub absorption: [f32; 4],
    /// KHR_materials_clearcoat: the coat's weight (x, 0: no coat), perceptual roughness
    /// (y), IOR (z: [`combustion_scene::CLEARCOAT_IOR`]) and its normal map's scale (w).
    /// Read by the CLEARCOAT variants.
    pub clearcoat: [f32; 4],
    /// Texture-array indices (-1: none) of the clearcoat, clearcoat roughness and
    /// clearcoat normal slots, then -1.
    pub textures_clearcoat: [i32; 4],
    /// KHR_materials_sheen: the sheen's linear colour (rgb, black: no sheen) and
    /// perceptual roughness (a). Read by the SHEEN variants.
    pub sheen: [f32; 4],
    /// Texture-array indices (-1: none) of the sheen colour and sheen roughness slots,
    /// then -1, -1.
    pub textures_sheen: [i32; 4],
    /// KHR_materials_iridescence: the thin film's weight (x, 0: no film), IOR (y) and
    /// thickness range in nm (z: at the thickness texture's 0, w: at its 1 and without
    /// it). Read by the IRIDESCENCE variants.
    pub film: [f32; 4],
    /// Texture-array indices (-1: none) of the iridescence and iridescence thickness
    /// slots, then -1, -1.
    pub textures_film: [i32; 4],
    /// KHR_materials_specular: the specular colour factor (rgb, linear, may exceed 1) and
    /// the specular factor (a); (1, 1, 1, 1) is the plain dielectric. Its textures are the
    /// specular slots of `textures_emissive_anisotropy_specular`. Read by the SPECULAR
    /// variants.
    pub specular: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuMaterial>() == 912);

impl GpuMaterial {
    /// The table entry of `material`; `textures` are its texture-array indices per
    /// `TextureSlot::ALL` slot (-1: none).
    pub fn new(material: &Material, outside_ior: f32, textures: [i32; TEXTURE_SLOTS]) -> Self {
        let [r, g, b] = material.base_color;
        let [eta_r, eta_g, eta_b] = material.conductor.eta;
        let [k_r, k_g, k_b] = material.conductor.k;
        Self {
            base_color_metalness: [r, g, b, material.metalness],
            roughness_anisotropy_ior: [
                material.roughness,
                material.anisotropy_strength,
                material.anisotropy_rotation,
                material.dielectric_ior,
            ],
            conductor_eta_outside_ior: [eta_r, eta_g, eta_b, outside_ior],
            conductor_k_polarisation: [k_r, k_g, k_b, material.polarisation_weight],
            diffuse_model_flags: [
                material.diffuse_model as u32,
                if material.conductor_from_base_color {
                    MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR
                } else {
                    0
                } | if material.unlit {
                    MATERIAL_FLAG_UNLIT
                } else {
                    0
                },
                material.occlusion_strength.to_bits(),
                0,
            ],
            textures_base_mr_normal_occlusion: [textures[0], textures[1], textures[2], textures[3]],
            textures_emissive_anisotropy_specular: [
                textures[4],
                textures[5],
                textures[6],
                textures[7],
            ],
            textures_transmission_thickness: [textures[8], textures[9], -1, -1],
            emissive_normal_scale: {
                let e = material
                    .emissive_factor
                    .map(|c| c * material.emissive_strength);
                [e[0], e[1], e[2], material.normal_scale]
            },
            uv_transforms: {
                let mut rows = [[0.0; 4]; 2 * TEXTURE_SLOTS];
                for (s, (_, texture)) in material.texture_slots().iter().enumerate() {
                    let (transform, set) = texture
                        .map_or((combustion_scene::UvTransform::IDENTITY, 0), |t| {
                            (t.transform, t.tex_coord)
                        });
                    let [r0, r1] = transform.rows();
                    rows[2 * s] = [r0[0], r0[1], r0[2], set as f32];
                    rows[2 * s + 1] = [r1[0], r1[1], r1[2], 0.0];
                }
                rows
            },
            alpha_cutoff: [
                material.alpha,
                material.alpha_mode.cutoff().unwrap_or(0.0),
                match &material.base_color_texture {
                    Some(t) if t.texture.sampler.mipmap_filter == Some(Filter::Nearest) => 1.0,
                    _ => 0.0,
                },
                0.0,
            ],
            alpha_mip_scales: alpha_mip_scales_of(material),
            transmission_thickness: [
                material.transmission,
                material.volume.map_or(0.0, |v| v.thickness),
                0.0,
                0.0,
            ],
            absorption: {
                // An absorption too large for f32 (a colour of 0) stays finite: e^(−σ d)
                // is 0 at any thickness the shader sees either way.
                let [r, g, b] = material
                    .volume
                    .map_or([0.0; 3], |v| v.absorption())
                    .map(|s| s.min(f64::from(f32::MAX)) as f32);
                [r, g, b, 0.0]
            },
            clearcoat: [
                material.clearcoat,
                material.clearcoat_roughness,
                combustion_scene::CLEARCOAT_IOR,
                material.clearcoat_normal_scale,
            ],
            textures_clearcoat: [textures[10], textures[11], textures[12], -1],
            sheen: {
                let [r, g, b] = material.sheen_color;
                [r, g, b, material.sheen_roughness]
            },
            textures_sheen: [textures[13], textures[14], -1, -1],
            film: match material.film() {
                Some(f) => [f.factor, f.ior, f.thickness_min_nm, f.thickness_max_nm],
                None => [0.0, 1.0, 0.0, 0.0],
            },
            textures_film: [textures[15], textures[16], -1, -1],
            specular: {
                let [r, g, b] = material.specular_color_factor;
                [r, g, b, material.specular_factor]
            },
        }
    }

    /// Whether the conductor's η and k come from the base colour
    /// ([`MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR`]).
    pub fn conductor_from_base_color(&self) -> bool {
        self.diffuse_model_flags[1] & MATERIAL_FLAG_CONDUCTOR_FROM_BASE_COLOR != 0
    }

    /// The same entry with every texture slot empty (-1): what the environment bake
    /// reads of a material, whatever its textures' places in the texture array.
    pub fn without_textures(&self) -> Self {
        Self {
            textures_base_mr_normal_occlusion: [-1; 4],
            textures_emissive_anisotropy_specular: [-1; 4],
            textures_transmission_thickness: [-1; 4],
            textures_clearcoat: [-1; 4],
            textures_sheen: [-1; 4],
            textures_film: [-1; 4],
            ..*self
        }
    }

    /// Whether the material is unlit ([`MATERIAL_FLAG_UNLIT`]).
    pub fn unlit(&self) -> bool {
        self.diffuse_model_flags[1] & MATERIAL_FLAG_UNLIT != 0
    }
}

/// [`GpuMaterial::alpha_mip_scales`] of `material`.
fn alpha_mip_scales_of(material: &Material) -> [[f32; 4]; 4] {
    let mut rows = [[1.0; 4]; 4];
    let (Some(cutoff), Some(texture)) = (
        material.alpha_mode.cutoff(),
        material.base_color_texture.as_ref(),
    ) else {
        return rows;
    };
    if texture.texture.sampler.mipmap_filter.is_none() {
        return rows;
    }
    let scales = combustion_scene::alpha_mip_scales(&texture.texture.image, material.alpha, cutoff);
    for (level, scale) in scales.into_iter().enumerate().take(16) {
        rows[level / 4][level % 4] = scale;
    }
    rows
}

/// A vertex in the G-buffer pass's first vertex stream (48 bytes): `Vertex` without its
/// second coordinate set, which goes to a stream of its own (`Vertex::uv1`, 8 bytes)
/// read only by the TEXTURE_TRANSFORMS variant, so scenes that do not use it read no
/// more bytes per vertex than before it existed (the pass is vertex-bound on lavapipe).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuVertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// Object-space normal.
    pub normal: [f32; 3],
    /// Object-space tangent (xyz) and the bitangent's sign (w), as glTF stores it.
    pub tangent: [f32; 4],
    /// The first texture-coordinate set.
    pub uv: [f32; 2],
}
const _: () = assert!(std::mem::size_of::<GpuVertex>() == 48);

impl GpuVertex {
    /// The first stream's part of `v` (its `uv1` is uploaded separately).
    pub fn new(v: &combustion_scene::Vertex) -> Self {
        Self {
            position: v.position,
            normal: v.normal,
            tangent: v.tangent,
            uv: v.uv,
        }
    }
}

/// `GpuObject` (std430, 144 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuObject {
    /// Object-to-world matrix, column-major.
    pub model: [f32; 16],
    /// The inverse transpose of the model matrix's linear part, scaled by the inverse of its
    /// largest axis length (column-major): it maps normals to world directions (normalised
    /// in the shader).
    pub normal_matrix: [f32; 16],
    /// x: the index of the object's material in the material table; y: 1 if its mesh
    /// has vertex colours (stream 2), else 0; zw: 0.
    pub material_index: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuObject>() == 144);

impl GpuObject {
    /// The table entry of `object`: its transform, its normal matrix, its material index
    /// and whether its mesh has vertex colours (`has_colors`: `Mesh::has_colors`).
    pub fn new(object: &Object, has_colors: bool) -> Self {
        Self {
            model: [0.0; 16],
            normal_matrix: [0.0; 16],
            material_index: [object.material as u32, u32::from(has_colors), 0, 0],
        }
        .placed(&object.transform)
    }

    /// The same entry with the object placed by `transform` instead. A singular
    /// transform (an animation scaling a node to 0 to hide it) flattens the object to no
    /// area, so nothing of it is drawn: its normal matrix is left zero (not the inverse,
    /// which does not exist).
    pub fn placed(&self, transform: &glam::Mat4) -> Self {
        let normal = if combustion_scene::transform_is_degenerate(transform) {
            glam::Mat4::ZERO
        } else {
            normal_matrix(transform)
        };
        Self {
            model: transform.to_cols_array(),
            normal_matrix: normal.to_cols_array(),
            ..*self
        }
    }
}

/// The inverse transpose of `transform`'s linear part (normals, normalised in the
/// G-buffer shader, keep only its direction), computed from the transform divided by
/// its largest axis length: the same directions, but no determinant of a tiny (1e-13)
/// or huge scale under- or overflows f32 on the way.
fn normal_matrix(transform: &glam::Mat4) -> glam::Mat4 {
    let linear = glam::Mat3::from_mat4(*transform);
    let scale = [linear.x_axis, linear.y_axis, linear.z_axis]
        .map(glam::Vec3::length)
        .into_iter()
        .fold(0.0f32, f32::max);
    let unit = if scale > 0.0 && scale.is_finite() {
        linear * (1.0 / scale)
    } else {
        linear
    };
    glam::Mat4::from_mat3(unit.inverse().transpose())
}

/// `LIGHT_KIND_*` in the shaders (generated `bindings/constants.glsl`).
pub const LIGHT_KIND_DIRECTIONAL: f32 = 0.0;
/// `LIGHT_KIND_POINT`: a point light.
pub const LIGHT_KIND_POINT: f32 = 1.0;
/// `LIGHT_KIND_SPOT`: a spot light.
pub const LIGHT_KIND_SPOT: f32 = 2.0;

/// `GpuLight` (std430, 64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// Point and spot lights: the position (w = 1); directional lights: the unit direction
    /// the light travels in (w = 0).
    pub position_or_direction: [f32; 4],
    /// rgb: intensity (W·sr⁻¹, point and spot) or irradiance (W·m⁻², directional); a: the
    /// kind (`LIGHT_KIND_*`).
    pub power_kind: [f32; 4],
    /// Spot lights: the unit direction of the cone's axis (xyz; zero for other kinds).
    /// w: the light's size for its shadows' softness: the radius (metres) of a point or
    /// spot light, tan(angular diameter / 2) of a directional one; 0: none.
    pub spot_axis: [f32; 4],
    /// x, y: the spot cone's scale 1/(cos θ_inner − cos θ_outer) and offset
    /// −cos θ_outer · scale (zero for other kinds); z: 1/range² (0: no range); w: for a
    /// light casting shadows this frame, 1 + the index of its first shadow cascade
    /// (`GpuShadowCascade`), else 0.
    pub spot_cone: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuLight>() == 64);

impl GpuLight {
    /// The table entry of `light` (directions normalised; cone angles in radians, as
    /// [`combustion_scene::Light`] gives them).
    pub fn new(light: &Light) -> Self {
        let power = |p: &[f32; 3], kind| [p[0], p[1], p[2], kind];
        match light {
            Light::Point {
                position,
                intensity,
                range,
                radius,
                ..
            } => Self {
                position_or_direction: position.extend(1.0).to_array(),
                power_kind: power(intensity, LIGHT_KIND_POINT),
                spot_axis: [0.0, 0.0, 0.0, *radius],
                spot_cone: [0.0, 0.0, inverse_range_squared(*range), 0.0],
            },
            Light::Directional {
                direction,
                irradiance,
                angular_diameter,
                ..
            } => Self {
                position_or_direction: direction.normalize().extend(0.0).to_array(),
                power_kind: power(irradiance, LIGHT_KIND_DIRECTIONAL),
                spot_axis: [0.0, 0.0, 0.0, (angular_diameter * 0.5).tan()],
                ..Self::zeroed()
            },
            Light::Spot {
                position,
                direction,
                intensity,
                inner_cone,
                outer_cone,
                range,
                radius,
                ..
            } => {
                let scale = 1.0 / (inner_cone.cos() - outer_cone.cos()).max(1e-3);
                Self {
                    position_or_direction: position.extend(1.0).to_array(),
                    power_kind: power(intensity, LIGHT_KIND_SPOT),
                    spot_axis: direction.normalize().extend(*radius).to_array(),
                    spot_cone: [
                        scale,
                        -outer_cone.cos() * scale,
                        inverse_range_squared(*range),
                        0.0,
                    ],
                }
            }
        }
    }

    /// CPU mirror of `range_attenuation` (gpu_types.glsl) at squared distance `d2`, in
    /// f64: (max(0, 1 − (d²/r²)²))², or 1 for a light without range.
    pub fn range_attenuation(&self, d2: f64) -> f64 {
        let inverse_r2 = f64::from(self.spot_cone[2]);
        if inverse_r2 == 0.0 {
            return 1.0;
        }
        combustion_scene::range_window_of_squared(d2 * inverse_r2)
    }

    /// CPU mirror of `spot_attenuation` (gpu_types.glsl), in f64; 1 for other lights.
    pub fn attenuation(&self, l: [f64; 3]) -> f64 {
        if self.power_kind[3] != LIGHT_KIND_SPOT {
            return 1.0;
        }
        let axis = self.spot_axis.map(f64::from);
        let cos_axis = -(axis[0] * l[0] + axis[1] * l[1] + axis[2] * l[2]);
        let a = (cos_axis * f64::from(self.spot_cone[0]) + f64::from(self.spot_cone[1]))
            .clamp(0.0, 1.0);
        a * a
    }
}

/// 1/range² of a light with a range (its window, `range_attenuation`), 0 without.
fn inverse_range_squared(range: Option<f32>) -> f32 {
    range.map_or(0.0, |r| 1.0 / (r * r))
}

/// The material table of a scene, outside IORs resolved, texture slots from
/// `texture_indices` (per material; missing entries mean no textures).
pub fn material_table(scene: &Scene, texture_indices: &[[i32; TEXTURE_SLOTS]]) -> Vec<GpuMaterial> {
    scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let textures = texture_indices
                .get(i)
                .copied()
                .unwrap_or([-1; TEXTURE_SLOTS]);
            GpuMaterial::new(m, scene.outside_ior_of(m), textures)
        })
        .collect()
}

/// η, k of a conductor derived from its base colour, for every 8-bit code the G-buffer
/// can store (`conductor_from_base_color` materials, e.g. glTF metals): entry c is
/// `conductor_from_reflectivity(sRGB⁻¹(c/255))`. The lighting pass looks each channel up
/// by its stored code, so the per-pixel mapping is exact and costs one fetch.
pub fn conductor_from_base_color_table() -> &'static [[f32; 2]; 256] {
    static TABLE: std::sync::OnceLock<[[f32; 2]; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let mut table = [[0.0; 2]; 256];
        for (code, entry) in table.iter_mut().enumerate() {
            let r = crate::color::srgb_to_linear(code as f64 / 255.0) as f32;
            let ior = combustion_scene::conductor_from_reflectivity([r; 3]);
            *entry = [ior.eta[0], ior.k[0]];
        }
        table
    })
}

/// `GpuShadowCascade` (std430, 96 bytes): one shadow-map layer's placement
/// ([`crate::Cascade`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuShadowCascade {
    /// World space to the map's clip space (column-major): x, y in [−1, 1] across the
    /// map, depth in [0, 1] along the light.
    pub world_to_clip: [f32; 16],
    /// x: one texel's side in metres; y: metres along the light per unit of map depth;
    /// z: the end of the view slice it covers, metres from the eye; w: 0.
    pub texel_depth_slice: [f32; 4],
    /// xyz: a cascade's: the camera's unit view direction (the slices' distances are
    /// along it); zero for a local light's layer; w: the layer's index in its array of
    /// maps (the cascades' or the local lights').
    pub view_forward: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuShadowCascade>() == 96);

/// Push constants of the G-buffer pass (`GBufferPush` in gbuffer.vert).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GBufferPush {
    /// The camera's view-projection matrix, column-major.
    pub view_projection: [f32; 16],
    /// The index of the drawn object in the object table.
    pub object_index: u32,
    /// Padding to the GLSL block's size.
    pub _pad: [u32; 3],
}
const _: () = assert!(std::mem::size_of::<GBufferPush>() == 80);

/// Push constants of the forward pass (`ForwardPush` in forward.frag; its vertex stage,
/// gbuffer.vert, reads the first two members as its `GBufferPush`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ForwardPush {
    /// The camera's view-projection matrix, column-major.
    pub view_projection: [f32; 16],
    /// The index of the drawn object in the object table.
    pub object_index: u32,
    /// The frame's lights (every one is evaluated: the tile lists are culled against the
    /// opaque depth, which a blended surface in front of it is not within).
    pub light_count: u32,
    /// The drawn object's scale (the cube root of its transform's |determinant|): a
    /// volume's thickness, in the mesh's units, times this is its thickness in metres.
    pub object_scale: f32,
    /// The length of the diagonal of the drawn object's world-space box: the longest
    /// path through it (the VOLUME variant's rays look that far for where they leave).
    pub object_extent: f32,
    /// The eye's world position (w = 1).
    pub camera_position: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<ForwardPush>() == 96);
const _: () = assert!(
    std::mem::offset_of!(ForwardPush, object_index)
        == std::mem::offset_of!(GBufferPush, object_index)
);

/// Push constants of the lighting pass (`LightingPush` in lighting.frag).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LightingPush {
    /// The inverse of the camera's view-projection matrix, column-major (depth to world
    /// position).
    pub inverse_view_projection: [f32; 16],
    /// The eye's world position (w = 1).
    pub camera_position: [f32; 4],
    /// x: the frame's lights; y: the debug view (`DebugView as u32`); z: tiles across and
    /// w: the tile lists' stride in words (0 when the frame does not cull its lights).
    pub counts: [u32; 4],
    /// The background where no surface is: rgb a radiance, or w = 1: the environment's
    /// (frames with one).
    pub background: [f32; 4],
    /// x: the frame's environment sample seed (`FrameInputs::environment_seed`); y: the
    /// most surfaces a traced path lights (`ShadingOptions::path_depth`); z, w: the
    /// exposure (`f32` bits) and tone curve (`ToneMapping as u32`) of frames whose output
    /// is folded into the lighting pass ([`LightingPush::with_output`]).
    pub sampling: [u32; 4],
}
// 128 bytes: every Vulkan device takes that much (maxPushConstantsSize ≥ 128).
const _: () = assert!(std::mem::size_of::<LightingPush>() == 128);

impl LightingPush {
    /// `debug_view`: `DebugView as u32` (0: radiance).
    pub fn new(
        view_projection: Mat4,
        camera_position: glam::Vec3,
        light_count: u32,
        debug_view: u32,
    ) -> Self {
        Self {
            inverse_view_projection: view_projection.inverse().to_cols_array(),
            camera_position: camera_position.extend(1.0).to_array(),
            counts: [light_count, debug_view, 0, 0],
            background: [0.0; 4],
            sampling: [0; 4],
        }
    }

    /// The frame's sampled environment (and its paths) take the sample set of `seed`;
    /// its paths light at most `path_depth` surfaces.
    pub fn with_sampling(self, seed: u32, path_depth: u32) -> Self {
        Self {
            sampling: [seed, path_depth, 0, 0],
            ..self
        }
    }

    /// The frame's exposure and tone curve, for a frame whose output pass's work the
    /// lighting pass does (`OUTPUT_FOLDED`).
    pub fn with_output(self, exposure: f32, curve: u32) -> Self {
        let [seed, depth, _, _] = self.sampling;
        Self {
            sampling: [seed, depth, exposure.to_bits(), curve],
            ..self
        }
    }

    /// The frame shows `background` where no surface is.
    pub fn with_background(self, background: crate::Background) -> Self {
        Self {
            background: match background {
                crate::Background::None => [0.0; 4],
                crate::Background::Color([r, g, b]) => [r, g, b, 0.0],
                crate::Background::Environment => [0.0, 0.0, 0.0, 1.0],
            },
            ..self
        }
    }

    /// The lighting pass reads the tile lists of a culled frame: `tiles_x` tiles across,
    /// each list `stride` words long.
    pub fn with_tile_lists(self, tiles_x: u32, stride: u32) -> Self {
        Self {
            counts: [self.counts[0], self.counts[1], tiles_x, stride],
            ..self
        }
    }
}

/// Push constants of the tonemap pass (`TonemapPush` in tonemap.frag).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct TonemapPush {
    /// Multiplies radiance before the tone curve (and in linear outputs).
    pub exposure: f32,
    /// The tone curve (`ToneMapping as u32`).
    pub curve: u32,
    /// 1: the exposure is the auto exposure's (`exposure_state`), not `exposure`.
    pub metered: u32,
}

/// An environment's source radiance as the bake shaders evaluate it (`EnvironmentSource`
/// in environment.glsl): L(ω) = ground + (sky − ground)(1 + ω_y)/2 + Σ_i B_i max(0, ω·k_i)^p_i.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct EnvironmentSource {
    /// The sky's radiance (rgb, W·sr⁻¹·m⁻², straight up); a: 0.
    pub sky: [f32; 4],
    /// The ground's radiance (rgb, W·sr⁻¹·m⁻², straight down); a: 0.
    pub ground: [f32; 4],
    /// xyz: unit k_i.
    pub box_direction: [[f32; 4]; 2],
    /// rgb: B_i, a: p_i.
    pub box_radiance_exponent: [[f32; 4]; 2],
}

impl EnvironmentSource {
    /// The source of `environment`: uniform (sky = ground), the studio's gradient and two
    /// boxes, or, for an image (read from its own texture instead), zero radiance.
    pub fn new(environment: &combustion_scene::Environment) -> Self {
        use combustion_scene::Environment;
        let rgb = |c: [f64; 3], a: f64| [c[0] as f32, c[1] as f32, c[2] as f32, a as f32];
        match environment {
            Environment::Uniform(l) => Self {
                sky: [l[0], l[1], l[2], 0.0],
                ground: [l[0], l[1], l[2], 0.0],
                box_direction: [[0.0, 1.0, 0.0, 0.0]; 2],
                box_radiance_exponent: [[0.0, 0.0, 0.0, 1.0]; 2],
            },
            // Read from the equirectangular image instead.
            Environment::Image(_) => Self::new(&Environment::Uniform([0.0; 3])),
            Environment::Studio => {
                let boxes = combustion_scene::STUDIO_BOXES;
                let unit = |k: [f64; 3]| {
                    let len = (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt();
                    rgb(k.map(|c| c / len), 0.0)
                };
                Self {
                    sky: rgb(combustion_scene::STUDIO_SKY, 0.0),
                    ground: rgb(combustion_scene::STUDIO_GROUND, 0.0),
                    box_direction: [unit(boxes[0].0), unit(boxes[1].0)],
                    box_radiance_exponent: [
                        rgb(boxes[0].1, boxes[0].2),
                        rgb(boxes[1].1, boxes[1].2),
                    ],
                }
            }
        }
    }
}

/// How environment_radiance.comp makes a level of the radiance cube
/// ([`EnvironmentRadiancePush::mode`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadianceMode {
    /// Evaluate the analytic source at each texel's centre (level 0).
    Analytic = 0,
    /// The mean of the four texels of the level before (levels above 0).
    Reduce = 1,
    /// Average the equirectangular image over each texel (level 0).
    Equirect = 2,
}

/// Push constants of environment_radiance.comp (`EnvironmentRadiancePush`): one level of
/// the radiance cube.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct EnvironmentRadiancePush {
    /// The environment's analytic source radiance ([`RadianceMode::Analytic`]).
    pub source: EnvironmentSource,
    /// Texels per side of the level.
    pub size: u32,
    /// How the level is made (`RadianceMode as u32`).
    pub mode: u32,
    /// [`RadianceMode::Reduce`]: the level read (the one before).
    pub source_level: u32,
    /// [`RadianceMode::Equirect`]: n, for n × n samples of the image per texel.
    pub samples_across: u32,
}
const _: () = assert!(std::mem::size_of::<EnvironmentRadiancePush>() == 112);

/// Push constants of environment_prefilter.comp (`EnvironmentPrefilterPush`): one level
/// of the GGX-prefiltered specular cube.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct EnvironmentPrefilterPush {
    /// Texels per side of the level.
    pub size: u32,
    /// GGX samples per texel.
    pub samples: u32,
    /// Texels per side of the radiance cube's level 0.
    pub radiance_size: u32,
    /// The level's perceptual roughness r (0: a copy of the radiance cube's level 0).
    pub roughness: f32,
}
const _: () = assert!(std::mem::size_of::<EnvironmentPrefilterPush>() == 16);

/// Push constants of environment_irradiance.comp (`EnvironmentIrradiancePush`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct EnvironmentIrradiancePush {
    /// Texels per side of the irradiance cube.
    pub size: u32,
    /// The radiance cube's level summed over.
    pub source_level: u32,
    /// Texels per side of that level.
    pub source_size: u32,
}
const _: () = assert!(std::mem::size_of::<EnvironmentIrradiancePush>() == 12);

/// Push constants of environment_albedo.comp (`EnvironmentAlbedoPush`): every
/// material's directional-albedo table.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct EnvironmentAlbedoPush {
    /// Samples per part (specular, diffuse) per entry.
    pub samples: u32,
}
const _: () = assert!(std::mem::size_of::<EnvironmentAlbedoPush>() == 4);

/// Push constants of environment_code_albedo.comp (`EnvironmentCodeAlbedoPush`): the
/// per-code conductor tables of one (η_i, w).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct EnvironmentCodeAlbedoPush {
    /// Samples per entry.
    pub samples: u32,
    /// Which set of tables (its place in `environment_code_albedo`).
    pub table: u32,
    /// The outside medium's IOR η_i.
    pub outside_ior: f32,
    /// The polarisation weight w.
    pub polarisation_weight: f32,
}
const _: () = assert!(std::mem::size_of::<EnvironmentCodeAlbedoPush>() == 16);
