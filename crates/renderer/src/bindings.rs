//! Descriptor sets declared once. Each [`SetDecl`] gives, from one list, the GLSL
//! declarations the shaders include (`#include "bindings/NAME.glsl"`, generated at
//! start-up), the Vulkan descriptor-set layout, the pool sizes, and the writes — by
//! name — so a binding number is never written twice by hand.

use std::sync::Arc;

use combustion_vk::{vk, Buffer, DescriptorSetLayout, Device, VkError};

use crate::variant;

/// What a binding holds, and how GLSL declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingKind {
    /// `texture2D`, read with texelFetch (no sampler).
    Texture2D,
    /// `utexture2D`.
    UTexture2D,
    /// `sampler2D`: an image with its sampler.
    Sampler2D,
    /// `samplerCube`: a cube map with its sampler.
    SamplerCube,
    /// `sampler2DArrayShadow`: a depth image's layers with a comparison sampler.
    Sampler2DArrayShadow,
    /// `texture2DArray`, read with texelFetch (no sampler): e.g. a depth image's layers
    /// as depths.
    Texture2DArray,
    /// `image2D` with the given format qualifier (e.g. `rgba16f`), written by compute.
    StorageImage2D {
        /// The GLSL format qualifier.
        format: &'static str,
    },
    /// `image2D` with the given format qualifier, read and written by compute (a level
    /// of bloom's chain built from the one beside it in the same image).
    RwStorageImage2D {
        /// The GLSL format qualifier.
        format: &'static str,
    },
    /// `uimage2D` with the given format qualifier (e.g. `r32ui`), written by compute.
    UStorageImage2D {
        /// The GLSL format qualifier.
        format: &'static str,
    },
    /// `image2DArray` (e.g. one mip level of a cube map, a layer per face), written by
    /// compute.
    StorageImage2DArray {
        /// The GLSL format qualifier.
        format: &'static str,
    },
    /// `readonly buffer BLOCK { ELEMENT NAME[]; }` (std430).
    StorageBuffer {
        /// The block's name.
        block: &'static str,
        /// The array's element type (a GLSL type or a struct of `gpu_types.glsl`).
        element: &'static str,
    },
    /// `accelerationStructureEXT` (the shader enables GL_EXT_ray_query first): a top-level
    /// structure traced by ray queries.
    AccelerationStructure,
    /// `buffer BLOCK { ELEMENT NAME[]; }` (std430), written by shaders.
    RwStorageBuffer {
        /// The block's name.
        block: &'static str,
        /// The array's element type (a GLSL type or a struct of `gpu_types.glsl`).
        element: &'static str,
    },
}

impl BindingKind {
    /// The Vulkan descriptor type of this kind (sampled image, combined image sampler,
    /// storage image or storage buffer).
    pub fn descriptor_type(self) -> vk::DescriptorType {
        match self {
            Self::Texture2D | Self::UTexture2D | Self::Texture2DArray => {
                vk::DescriptorType::SAMPLED_IMAGE
            }
            Self::Sampler2D | Self::SamplerCube | Self::Sampler2DArrayShadow => {
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER
            }
            Self::StorageImage2D { .. }
            | Self::RwStorageImage2D { .. }
            | Self::UStorageImage2D { .. }
            | Self::StorageImage2DArray { .. } => vk::DescriptorType::STORAGE_IMAGE,
            Self::StorageBuffer { .. } | Self::RwStorageBuffer { .. } => {
                vk::DescriptorType::STORAGE_BUFFER
            }
            Self::AccelerationStructure => vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
        }
    }
}

/// One binding: its GLSL name, kind and stages; `only_with` names a `#define` without
/// which the shaders do not see it (the layout always has it).
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    /// The GLSL name of the binding (and the name [`SetDecl::index`] looks it up by).
    pub name: &'static str,
    /// What it holds and how GLSL declares it.
    pub kind: BindingKind,
    /// The shader stages that read or write it (the layout's stage flags).
    pub stages: vk::ShaderStageFlags,
    /// The `#define` without which the generated GLSL leaves the declaration out (`None`:
    /// always declared). The layout has the binding either way.
    pub only_with: Option<&'static str>,
    /// A second `#define` that also declares it (with `only_with`: either does).
    pub or_with: Option<&'static str>,
    /// Read only by ray queries' shaders ([`Binding::for_ray_queries`]): left out of the
    /// layouts of devices without them, as an acceleration structure is.
    pub for_ray_queries: bool,
}

impl Binding {
    /// A binding declared for every shader (`only_with` is `None`).
    pub const fn new(name: &'static str, kind: BindingKind, stages: vk::ShaderStageFlags) -> Self {
        Self {
            name,
            kind,
            stages,
            only_with: None,
            or_with: None,
            for_ray_queries: false,
        }
    }

    /// The same binding, read only by shaders that trace rays: devices without ray
    /// queries have no such shader, and their layouts leave it out.
    pub const fn for_ray_queries(self) -> Self {
        Self {
            for_ray_queries: true,
            ..self
        }
    }

    /// The same binding, declared in GLSL only where `define` is defined.
    pub const fn only_with(self, define: &'static str) -> Self {
        Self {
            only_with: Some(define),
            ..self
        }
    }

    /// The same binding, declared in GLSL also where `define` is defined (beside its
    /// `only_with`).
    pub const fn or_with(self, define: &'static str) -> Self {
        Self {
            or_with: Some(define),
            ..self
        }
    }

    /// Whether it holds an acceleration structure: a descriptor only devices with ray
    /// queries have. Elsewhere the set's layout leaves its number out (the shaders that
    /// declare it, behind a define of a pass that needs ray queries, never run there).
    pub fn needs_ray_queries(&self) -> bool {
        self.for_ray_queries || self.kind == BindingKind::AccelerationStructure
    }

    /// Whether the layouts of a device with (`ray_queries`) or without ray queries have it.
    fn on(&self, ray_queries: bool) -> bool {
        ray_queries || !self.needs_ray_queries()
    }
}

/// A descriptor set: its header's name, its set number, and its bindings (binding i is
/// `bindings[i]`).
#[derive(Clone, Copy, Debug)]
pub struct SetDecl {
    /// The header's name: shaders include `bindings/NAME.glsl`, and the GLSL include guard
    /// derives from it.
    pub name: &'static str,
    /// The descriptor set number (`layout(set = N, …)`).
    pub set: u32,
    /// The bindings, binding number i being `bindings[i]`.
    pub bindings: &'static [Binding],
    /// Headers this one's declarations need (e.g. `gpu_types.glsl` for struct types).
    pub includes: &'static [&'static str],
}

impl SetDecl {
    /// The path shaders include: `bindings/NAME.glsl`.
    pub fn header_path(&self) -> String {
        format!("bindings/{}.glsl", self.name)
    }

    /// The GLSL declarations of every binding.
    pub fn glsl(&self) -> String {
        let guard = format!("COMBUSTION_BINDINGS_{}_GLSL", self.name.to_uppercase());
        let mut out = format!(
            "// Generated from combustion_renderer::bindings::{} (bindings.rs); do not edit.\n#ifndef {guard}\n#define {guard}\n",
            self.name.to_uppercase()
        );
        for include in self.includes {
            out += &format!("#include \"{include}\"\n");
        }
        for (index, b) in self.bindings.iter().enumerate() {
            let layout = format!("set = {}, binding = {index}", self.set);
            let declaration = match b.kind {
                BindingKind::Texture2D => format!("layout({layout}) uniform texture2D {};", b.name),
                BindingKind::UTexture2D => {
                    format!("layout({layout}) uniform utexture2D {};", b.name)
                }
                BindingKind::Sampler2D => format!("layout({layout}) uniform sampler2D {};", b.name),
                BindingKind::SamplerCube => {
                    format!("layout({layout}) uniform samplerCube {};", b.name)
                }
                BindingKind::Sampler2DArrayShadow => {
                    format!("layout({layout}) uniform sampler2DArrayShadow {};", b.name)
                }
                BindingKind::Texture2DArray => {
                    format!("layout({layout}) uniform texture2DArray {};", b.name)
                }
                BindingKind::StorageImage2D { format } => {
                    format!(
                        "layout({layout}, {format}) uniform writeonly image2D {};",
                        b.name
                    )
                }
                BindingKind::RwStorageImage2D { format } => {
                    format!("layout({layout}, {format}) uniform image2D {};", b.name)
                }
                BindingKind::UStorageImage2D { format } => {
                    format!(
                        "layout({layout}, {format}) uniform writeonly uimage2D {};",
                        b.name
                    )
                }
                BindingKind::StorageImage2DArray { format } => {
                    format!(
                        "layout({layout}, {format}) uniform writeonly image2DArray {};",
                        b.name
                    )
                }
                BindingKind::StorageBuffer { block, element } => format!(
                    "layout(std430, {layout}) readonly buffer {block} {{ {element} {}[]; }};",
                    b.name
                ),
                BindingKind::AccelerationStructure => {
                    format!(
                        "layout({layout}) uniform accelerationStructureEXT {};",
                        b.name
                    )
                }
                BindingKind::RwStorageBuffer { block, element } => format!(
                    "layout(std430, {layout}) buffer {block} {{ {element} {}[]; }};",
                    b.name
                ),
            };
            match (b.only_with, b.or_with) {
                (Some(define), Some(other)) => {
                    out += &format!(
                        "#if defined({define}) || defined({other})\n{declaration}\n#endif\n"
                    )
                }
                (Some(define), None) => out += &format!("#ifdef {define}\n{declaration}\n#endif\n"),
                _ => out += &format!("{declaration}\n"),
            }
        }
        out + "#endif\n"
    }

    /// The binding number of `name`. The names are the crate's own constants, so a
    /// missing one is a programming error caught by every test that records a frame.
    pub fn index(&self, name: &str) -> u32 {
        self.bindings
            .iter()
            .position(|b| b.name == name)
            .unwrap_or_else(|| panic!("descriptor set {} has no binding {name}", self.name))
            as u32
    }

    /// Creates the Vulkan descriptor-set layout: one descriptor per binding, numbered by its
    /// position, with its kind's descriptor type and its stages (on a device without ray
    /// queries, acceleration structures' numbers left out: [`Binding::needs_ray_queries`]).
    ///
    /// # Errors
    /// The device's error if the layout cannot be created.
    pub fn layout(&self, device: &Arc<Device>) -> Result<DescriptorSetLayout, VkError> {
        let bindings: Vec<_> = self
            .bindings
            .iter()
            .enumerate()
            .filter(|(_, b)| b.on(device.ray_queries()))
            .map(|(i, b)| (i as u32, b.kind.descriptor_type(), 1, b.stages))
            .collect();
        DescriptorSetLayout::new(device, &bindings)
    }

    /// The descriptors `sets` sets of this layout take from a pool, on a device with
    /// (`ray_queries`) or without ray queries.
    pub fn pool_sizes(&self, sets: u32, ray_queries: bool) -> Vec<vk::DescriptorPoolSize> {
        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for b in self.bindings.iter().filter(|b| b.on(ray_queries)) {
            let ty = b.kind.descriptor_type();
            match sizes.iter_mut().find(|s| s.ty == ty) {
                Some(s) => s.descriptor_count += sets,
                None => sizes.push(vk::DescriptorPoolSize {
                    ty,
                    descriptor_count: sets,
                }),
            }
        }
        sizes
    }

    /// Starts the writes of one set of this layout.
    pub fn writer(&'static self, set: vk::DescriptorSet) -> SetWriter {
        SetWriter {
            decl: self,
            set,
            images: Vec::new(),
            buffers: Vec::new(),
            structures: Vec::new(),
        }
    }
}

/// Writes of one descriptor set, by binding name.
pub struct SetWriter {
    decl: &'static SetDecl,
    set: vk::DescriptorSet,
    images: Vec<(u32, [vk::DescriptorImageInfo; 1])>,
    buffers: Vec<(u32, [vk::DescriptorBufferInfo; 1])>,
    structures: Vec<(u32, [vk::AccelerationStructureKHR; 1])>,
}

impl SetWriter {
    /// An image (sampled, storage, or with a sampler for combined bindings) in `layout`.
    pub fn image(
        mut self,
        name: &str,
        view: vk::ImageView,
        layout: vk::ImageLayout,
        sampler: vk::Sampler,
    ) -> Self {
        self.add_image(name, view, layout, sampler);
        self
    }

    /// A whole buffer.
    pub fn buffer(mut self, name: &str, buffer: &Buffer) -> Self {
        self.add_buffer(name, buffer);
        self
    }

    /// As [`SetWriter::image`], in place.
    pub fn add_image(
        &mut self,
        name: &str,
        view: vk::ImageView,
        layout: vk::ImageLayout,
        sampler: vk::Sampler,
    ) {
        let index = self.decl.index(name);
        self.images.push((
            index,
            [vk::DescriptorImageInfo {
                sampler,
                image_view: view,
                image_layout: layout,
            }],
        ));
    }

    /// An acceleration structure, in place.
    pub fn add_acceleration_structure(
        &mut self,
        name: &str,
        structure: vk::AccelerationStructureKHR,
    ) {
        let index = self.decl.index(name);
        self.structures.push((index, [structure]));
    }

    /// As [`SetWriter::buffer`], in place.
    pub fn add_buffer(&mut self, name: &str, buffer: &Buffer) {
        let index = self.decl.index(name);
        self.buffers.push((
            index,
            [vk::DescriptorBufferInfo {
                buffer: buffer.raw(),
                offset: 0,
                range: vk::WHOLE_SIZE,
            }],
        ));
    }

    /// Applies the writes. The set must not be in use by a pending frame. Every binding
    /// the device's layout has must have been given (a placeholder where a resource is
    /// absent): a binding left as an earlier write set it may name a resource freed
    /// since, and a driver may read every descriptor of a bound set.
    pub fn apply(self, device: &Device) {
        debug_assert!(
            self.decl
                .bindings
                .iter()
                .enumerate()
                .all(|(i, b)| !b.on(device.ray_queries())
                    || self
                        .images
                        .iter()
                        .map(|(index, _)| index)
                        .chain(self.buffers.iter().map(|(index, _)| index))
                        .chain(self.structures.iter().map(|(index, _)| index))
                        .any(|&index| index as usize == i)),
            "set {}: every binding must be written ({:?} declared)",
            self.decl.name,
            self.decl
                .bindings
                .iter()
                .map(|b| b.name)
                .collect::<Vec<_>>()
        );
        let ty = |index: u32| self.decl.bindings[index as usize].kind.descriptor_type();
        let mut writes: Vec<vk::WriteDescriptorSet<'_>> = self
            .images
            .iter()
            .map(|(index, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(self.set)
                    .dst_binding(*index)
                    .descriptor_type(ty(*index))
                    .image_info(info)
            })
            .collect();
        writes.extend(self.buffers.iter().map(|(index, info)| {
            vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(*index)
                .descriptor_type(ty(*index))
                .buffer_info(info)
        }));
        let mut structure_writes: Vec<vk::WriteDescriptorSetAccelerationStructureKHR<'_>> = self
            .structures
            .iter()
            .map(|(_, structure)| {
                vk::WriteDescriptorSetAccelerationStructureKHR::default()
                    .acceleration_structures(structure)
            })
            .collect();
        for ((index, _), write) in self.structures.iter().zip(structure_writes.iter_mut()) {
            let mut descriptor = vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(*index)
                .descriptor_type(ty(*index))
                .push_next(write);
            // The count comes from the chained structure's, which push_next does not set.
            descriptor.descriptor_count = 1;
            writes.push(descriptor);
        }
        // SAFETY: the caller guarantees the set is not in use by a pending frame.
        unsafe { device.raw().update_descriptor_sets(&writes, &[]) };
    }
}

pub(crate) const FRAGMENT: vk::ShaderStageFlags = vk::ShaderStageFlags::FRAGMENT;
pub(crate) const VERTEX: vk::ShaderStageFlags = vk::ShaderStageFlags::VERTEX;
pub(crate) const COMPUTE: vk::ShaderStageFlags = vk::ShaderStageFlags::COMPUTE;

/// The material table as the lighting pass reads it (the G-buffer pass declares its own,
/// also visible to its vertex stage).
pub(crate) const MATERIALS: Binding = Binding::new(
    "materials",
    BindingKind::StorageBuffer {
        block: "Materials",
        element: "GpuMaterial",
    },
    FRAGMENT,
);

/// The object table, read by the vertex stage of the passes that rasterise the scene.
pub(crate) const OBJECTS: Binding = Binding::new(
    "objects",
    BindingKind::StorageBuffer {
        block: "Objects",
        element: "GpuObject",
    },
    VERTEX,
);

/// The material table as the rasterising passes read it: the vertex stage (texture
/// transforms) and the fragment stage.
const MATERIALS_BOTH_STAGES: Binding = Binding::new(
    "materials",
    BindingKind::StorageBuffer {
        block: "Materials",
        element: "GpuMaterial",
    },
    vk::ShaderStageFlags::from_raw(FRAGMENT.as_raw() | VERTEX.as_raw()),
);

/// Set 0 of the G-buffer pass: the object table (vertex stage) and the material table
/// (both stages).
pub static GBUFFER: SetDecl = SetDecl {
    name: "gbuffer",
    set: 0,
    // The vertex stage reads the texture transforms (TEXTURE_TRANSFORMS variant).
    bindings: &[OBJECTS, MATERIALS_BOTH_STAGES],
    includes: &["gpu_types.glsl"],
};

/// Set 1 of the G-buffer pass: one material's textures, in `TextureSlot::ALL` order.
pub static MATERIAL_TEXTURES: SetDecl = SetDecl {
    name: "material_textures",
    set: 1,
    bindings: &[
        Binding::new("base_color_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new(
            "metallic_roughness_texture",
            BindingKind::Sampler2D,
            FRAGMENT,
        ),
        Binding::new("normal_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("occlusion_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("emissive_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("anisotropy_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("specular_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("specular_color_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("transmission_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("thickness_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("clearcoat_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new(
            "clearcoat_roughness_texture",
            BindingKind::Sampler2D,
            FRAGMENT,
        ),
        Binding::new("clearcoat_normal_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("sheen_color_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("sheen_roughness_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new("iridescence_texture", BindingKind::Sampler2D, FRAGMENT),
        Binding::new(
            "iridescence_thickness_texture",
            BindingKind::Sampler2D,
            FRAGMENT,
        ),
    ],
    includes: &[],
};

/// The bindings of what lights a surface, shared by the passes that shade
/// (lighting_terms.glsl): the frame's lights, the conductor-from-base-colour table, the
/// energy table, the sheen's albedo table, the environment's cubes and tables, the
/// shadow maps.
pub(crate) const LIT_BY: [Binding; 14] = [
    Binding::new(
        "lights",
        BindingKind::StorageBuffer {
            block: "Lights",
            element: "GpuLight",
        },
        FRAGMENT,
    ),
    // η, k of a conductor derived from its base colour, per stored 8-bit code
    // (gpu_types::conductor_from_base_color_table).
    Binding::new(
        "conductor_from_code",
        BindingKind::StorageBuffer {
            block: "ConductorTable",
            element: "vec2",
        },
        FRAGMENT,
    ),
    // The white specular lobe's directional albedo over (n·v, r) (read in the
    // ENERGY_COMPENSATION variant; environment::white_specular_albedo_table).
    Binding::new(
        "energy_white_albedo",
        BindingKind::StorageBuffer {
            block: "EnergyWhiteAlbedo",
            element: "float",
        },
        FRAGMENT,
    )
    .only_with(variant::ENERGY_COMPENSATION.define),
    // The white sheen lobe's directional albedo over (n·v, r) (read in the SHEEN
    // variant; combustion_optics::sheen::sheen_albedo_table).
    Binding::new(
        "sheen_albedo",
        BindingKind::StorageBuffer {
            block: "SheenAlbedo",
            element: "float",
        },
        FRAGMENT,
    )
    .only_with(variant::SHEEN.define),
    // Environment lighting (ENVIRONMENT variant; see crate::environment): the
    // prefiltered specular cube, the irradiance cube, the directional-albedo tables
    // per material, the per-code tables of conductors derived from the base colour
    // and which of those each material reads.
    Binding::new("environment_specular", BindingKind::SamplerCube, FRAGMENT)
        .only_with(variant::ENVIRONMENT.define),
    Binding::new("environment_irradiance", BindingKind::SamplerCube, FRAGMENT)
        .only_with(variant::ENVIRONMENT.define),
    Binding::new(
        "environment_albedo",
        BindingKind::StorageBuffer {
            block: "EnvironmentAlbedo",
            element: "vec4",
        },
        FRAGMENT,
    )
    .only_with(variant::ENVIRONMENT.define),
    Binding::new(
        "environment_code_albedo",
        BindingKind::StorageBuffer {
            block: "EnvironmentCodeAlbedo",
            element: "float",
        },
        FRAGMENT,
    )
    .only_with(variant::ENVIRONMENT.define),
    Binding::new(
        "environment_code_table_of_material",
        BindingKind::StorageBuffer {
            block: "EnvironmentCodeTableOfMaterial",
            element: "uint",
        },
        FRAGMENT,
    )
    .only_with(variant::ENVIRONMENT.define),
    // Shadows (SHADOWS variant; see crate::shadows): the cascades' maps, the spot and
    // point lights' maps, and each layer's placement.
    Binding::new("shadow_maps", BindingKind::Sampler2DArrayShadow, FRAGMENT)
        .only_with(variant::SHADOWS.define),
    Binding::new(
        "local_shadow_maps",
        BindingKind::Sampler2DArrayShadow,
        FRAGMENT,
    )
    .only_with(variant::SHADOWS.define),
    // The same maps read as depths, for the blocker search of lights with a size.
    Binding::new("shadow_depths", BindingKind::Texture2DArray, FRAGMENT)
        .only_with(variant::SHADOWS.define),
    Binding::new("local_shadow_depths", BindingKind::Texture2DArray, FRAGMENT)
        .only_with(variant::SHADOWS.define),
    Binding::new(
        "shadow_cascades",
        BindingKind::StorageBuffer {
            block: "ShadowCascades",
            element: "GpuShadowCascade",
        },
        FRAGMENT,
    )
    .only_with(variant::SHADOWS.define),
];

/// `first` then `then`, as one array of `N` bindings (a set's list from shared parts).
pub(crate) const fn joined<const N: usize>(first: &[Binding], then: &[Binding]) -> [Binding; N] {
    assert!(
        first.len() + then.len() == N,
        "N must be the two lists' total"
    );
    let mut out = [then[0]; N];
    let mut i = 0;
    while i < first.len() {
        out[i] = first[i];
        i += 1;
    }
    while i < N {
        out[i] = then[i - first.len()];
        i += 1;
    }
    out
}

/// The traced scene's four bindings (traced_scene.glsl: the top-level structure and the
/// cut-outs' tables), read by `stages`, declared in GLSL only with `only_with` if given.
pub(crate) const fn traced_scene(
    stages: vk::ShaderStageFlags,
    only_with: Option<&'static str>,
) -> [Binding; 4] {
    let all = [
        Binding::new("scene", BindingKind::AccelerationStructure, stages),
        Binding::new(
            "cutouts",
            BindingKind::StorageBuffer {
                block: "TracedCutouts",
                element: "uvec4",
            },
            stages,
        ),
        Binding::new(
            "cutout_corners",
            BindingKind::StorageBuffer {
                block: "TracedCutoutCorners",
                element: "vec4",
            },
            stages,
        ),
        Binding::new(
            "cutout_alphas",
            BindingKind::StorageBuffer {
                block: "TracedCutoutAlphas",
                element: "uint",
            },
            stages,
        ),
    ];
    let all = [
        all[0].for_ray_queries(),
        all[1].for_ray_queries(),
        all[2].for_ray_queries(),
        all[3].for_ray_queries(),
    ];
    match only_with {
        Some(define) => [
            all[0].only_with(define),
            all[1].only_with(define),
            all[2].only_with(define),
            all[3].only_with(define),
        ],
        None => all,
    }
}

/// The `#define` of the shaders that read what their rays meet, derived in the shaders
/// from the passes' (lighting.frag: PATH_TRACE or RAY_TRACED_REFLECTIONS; forward.frag:
/// RAY_TRACED_REFRACTION): their surface and texture tables are declared with it.
pub(crate) const TRACED_SURFACES: &str = "TRACED_SURFACES";

/// What a ray that meets the scene's surfaces reads there (traced_surfaces.glsl): the
/// surface table and the scene's textures (`accel::TracedSurfaces`), read by fragments.
pub(crate) const TRACED_SURFACE_TABLES: [Binding; 2] = [
    Binding::new(
        "traced_surfaces",
        BindingKind::StorageBuffer {
            block: "TracedSurfaces",
            element: "uvec4",
        },
        FRAGMENT,
    )
    .for_ray_queries()
    .only_with(TRACED_SURFACES),
    Binding::new(
        "traced_textures",
        BindingKind::StorageBuffer {
            block: "TracedTextures",
            element: "uvec4",
        },
        FRAGMENT,
    )
    .for_ray_queries()
    .only_with(TRACED_SURFACES),
];

/// The forward set's traced bindings: the scene and what its rays meet, for ray-traced
/// refraction (declared where forward.frag defines TRACED_SURFACES).
const FORWARD_TRACED: [Binding; 6] = {
    let [scene, cutouts, corners, alphas] = traced_scene(FRAGMENT, Some(TRACED_SURFACES));
    let [surfaces, textures] = TRACED_SURFACE_TABLES;
    [scene, cutouts, corners, alphas, surfaces, textures]
};

const FORWARD_OWN: [Binding; 6 + FORWARD_TRACED.len()] = joined(
    &[
        OBJECTS,
        MATERIALS_BOTH_STAGES,
        // The lit image behind the transmissive objects, every mip level (TRANSMISSION
        // variant; the behind pass makes it).
        Binding::new("behind", BindingKind::Sampler2D, FRAGMENT)
            .only_with(variant::TRANSMISSION.define),
        // The opaque surfaces' depth (the pass's own depth attachment, read-only): how
        // far behind glass they are (a rough surface's blur), and what rays leaving a
        // transmissive volume march against (TRANSMISSION variant).
        Binding::new("scene_depth", BindingKind::Texture2D, FRAGMENT)
            .only_with(variant::TRANSMISSION.define),
        // The transmissive volumes' nearest back faces, depth and normal, where the rays
        // refracted into them leave (VOLUME variant; the back faces pass draws them).
        Binding::new("back_face_depth", BindingKind::Texture2D, FRAGMENT)
            .only_with(variant::VOLUME.define),
        Binding::new("back_face_normal", BindingKind::Sampler2D, FRAGMENT)
            .only_with(variant::VOLUME.define),
    ],
    &FORWARD_TRACED,
);

const FORWARD_BINDINGS: [Binding; FORWARD_OWN.len() + LIT_BY.len()] = joined(&FORWARD_OWN, &LIT_BY);

/// The forward pass (gbuffer.vert, forward.frag): the object and material tables as the
/// G-buffer pass's set declares them (bindings 0 and 1, what gbuffer.vert reads), the
/// image behind transmissive objects, the traced scene (ray-traced refraction), and what
/// lights a surface (`LIT_BY`: lighting_terms.glsl).
pub static FORWARD: SetDecl = SetDecl {
    name: "forward",
    set: 0,
    bindings: &FORWARD_BINDINGS,
    includes: &["gpu_types.glsl"],
};

/// The back faces pass (back_faces.vert, back_faces.frag): the object table.
pub static BACK_FACES: SetDecl = SetDecl {
    name: "back_faces",
    set: 0,
    bindings: &[OBJECTS],
    includes: &["gpu_types.glsl"],
};

/// The shadow-caster pass (shadow.vert, shadow.frag): the object and material tables.
pub static SHADOW_CASTERS: SetDecl = SetDecl {
    name: "shadow_casters",
    set: 0,
    // The cut-out casters' pipeline (ALPHA_MASK) reads the materials: the base colour
    // slot's transform (vertex) and the alpha factor, cutoff and texture (fragment).
    bindings: &[OBJECTS, MATERIALS_BOTH_STAGES],
    includes: &["gpu_types.glsl"],
};

/// The output pass: the HDR image.
pub static OUTPUT: SetDecl = SetDecl {
    name: "output",
    set: 0,
    bindings: &[
        Binding::new("hdr_image", BindingKind::Texture2D, FRAGMENT),
        Binding::new(
            "exposure_state",
            BindingKind::StorageBuffer {
                block: "ExposureState",
                element: "uint",
            },
            FRAGMENT,
        ),
    ],
    includes: &[],
};

/// A read-only storage buffer of `element`s named `name` in block `block`, for compute.
const fn compute_input(name: &'static str, block: &'static str, element: &'static str) -> Binding {
    Binding::new(name, BindingKind::StorageBuffer { block, element }, COMPUTE)
}

/// Set 0 of the deform pass (deform.comp): the deformed objects' rest vertices, joint
/// influences and morph displacements (the scene's), the frame's joint matrices and
/// morph weights (the slot's), and the posed vertices it writes (the scene's).
pub static DEFORM: SetDecl = SetDecl {
    name: "deform",
    set: 0,
    bindings: &[
        compute_input("rest_vertices", "RestVertices", "float"),
        compute_input("influence_ranges", "InfluenceRanges", "uvec2"),
        compute_input("influences", "Influences", "uvec2"),
        compute_input("morph_displacements", "MorphDisplacements", "vec4"),
        compute_input("morph_weights", "MorphWeights", "float"),
        compute_input("joint_matrices", "JointMatrices", "mat4"),
        Binding::new(
            "posed_vertices",
            BindingKind::RwStorageBuffer {
                block: "PosedVertices",
                element: "float",
            },
            COMPUTE,
        ),
    ],
    includes: &[],
};

/// Tiled light culling (compute): the G-buffer depth and the frame's lights in, each
/// tile's light list out.
pub static LIGHT_CULL: SetDecl = SetDecl {
    name: "light_cull",
    set: 0,
    bindings: &[
        Binding::new("gbuffer_depth", BindingKind::Texture2D, COMPUTE),
        Binding::new(
            "lights",
            BindingKind::StorageBuffer {
                block: "Lights",
                element: "GpuLight",
            },
            COMPUTE,
        ),
        Binding::new(
            "tile_lights",
            BindingKind::RwStorageBuffer {
                block: "TileLights",
                element: "uint",
            },
            COMPUTE,
        ),
    ],
    includes: &["gpu_types.glsl"],
};

/// The text overlay (drawn in the output pass): the frame's quads, the font atlas and the
/// overlay image (RGBA8 packed in `uint`s).
pub static OVERLAY: SetDecl = SetDecl {
    name: "overlay",
    set: 0,
    bindings: &[
        Binding::new(
            "overlay_quads",
            BindingKind::StorageBuffer {
                block: "OverlayQuads",
                element: "OverlayQuad",
            },
            VERTEX,
        ),
        Binding::new(
            "overlay_atlas",
            BindingKind::StorageBuffer {
                block: "OverlayAtlas",
                element: "uint",
            },
            FRAGMENT,
        ),
        Binding::new(
            "overlay_image",
            BindingKind::StorageBuffer {
                block: "OverlayImage",
                element: "uint",
            },
            FRAGMENT,
        ),
    ],
    includes: &["overlay.glsl"],
};

/// The environment bake (compute, at upload; crate::environment): a radiance cube read
/// with its mips, one cube level written (as a layer per face), the material table and
/// the conductor-from-code table in, the directional-albedo tables out.
pub static ENVIRONMENT_BAKE: SetDecl = SetDecl {
    name: "environment_bake",
    set: 0,
    bindings: &[
        Binding::new("environment_source", BindingKind::SamplerCube, COMPUTE),
        // An equirectangular source image (or a 1×1 placeholder).
        Binding::new("environment_equirect", BindingKind::Sampler2D, COMPUTE),
        Binding::new(
            "environment_target",
            BindingKind::StorageImage2DArray { format: "rgba32f" },
            COMPUTE,
        ),
        Binding::new(
            "materials",
            BindingKind::StorageBuffer {
                block: "Materials",
                element: "GpuMaterial",
            },
            COMPUTE,
        ),
        Binding::new(
            "conductor_from_code",
            BindingKind::StorageBuffer {
                block: "ConductorTable",
                element: "vec2",
            },
            COMPUTE,
        ),
        Binding::new(
            "environment_albedo",
            BindingKind::RwStorageBuffer {
                block: "EnvironmentAlbedo",
                element: "vec4",
            },
            COMPUTE,
        ),
        Binding::new(
            "environment_code_albedo",
            BindingKind::RwStorageBuffer {
                block: "EnvironmentCodeAlbedo",
                element: "float",
            },
            COMPUTE,
        ),
    ],
    includes: &["gpu_types.glsl"],
};

/// The sets declared here (the passes declare theirs in their own files:
/// `passes::declared_sets` lists both).
pub static ALL: &[&SetDecl] = &[
    &DEFORM,
    &GBUFFER,
    &MATERIAL_TEXTURES,
    &FORWARD,
    &BACK_FACES,
    &SHADOW_CASTERS,
    &OUTPUT,
    &OVERLAY,
    &LIGHT_CULL,
    &ENVIRONMENT_BAKE,
];

#[cfg(test)]
mod tests {
    use super::*;

    /// A set of the kinds the tests below look at, one binding only with a define.
    static EXAMPLE: SetDecl = SetDecl {
        name: "example",
        set: 0,
        bindings: &[
            Binding::new("depth", BindingKind::Texture2D, FRAGMENT),
            Binding::new("coat", BindingKind::Texture2D, FRAGMENT)
                .only_with(variant::CLEARCOAT.define),
            Binding::new(
                "lights",
                BindingKind::StorageBuffer {
                    block: "Lights",
                    element: "GpuLight",
                },
                FRAGMENT,
            ),
            Binding::new("cube", BindingKind::SamplerCube, FRAGMENT),
            Binding::new(
                "table",
                BindingKind::StorageBuffer {
                    block: "Table",
                    element: "float",
                },
                FRAGMENT,
            ),
        ],
        includes: &["gpu_types.glsl"],
    };

    #[test]
    fn headers_number_bindings_in_declaration_order() {
        let glsl = EXAMPLE.glsl();
        assert!(glsl.contains("#include \"gpu_types.glsl\"\n"));
        assert!(glsl.contains("layout(set = 0, binding = 0) uniform texture2D depth;"));
        assert!(glsl.contains(
            "#ifdef CLEARCOAT\nlayout(set = 0, binding = 1) uniform texture2D coat;\n#endif"
        ));
        assert!(glsl.contains(
            "layout(std430, set = 0, binding = 2) readonly buffer Lights { GpuLight lights[]; };"
        ));
        assert_eq!(EXAMPLE.index("lights"), 2);
        assert_eq!(EXAMPLE.index("table"), 4);
        assert_eq!(
            MATERIAL_TEXTURES.bindings.len(),
            combustion_scene::TextureSlot::ALL.len()
        );
    }

    /// The forward pass runs gbuffer.vert, which declares the G-buffer pass's set: the
    /// forward set begins with the same bindings, and both sets end with what lights a
    /// surface.
    #[test]
    fn the_forward_set_serves_gbuffer_vert_and_the_lighting_terms() {
        let names = |bindings: &[Binding]| bindings.iter().map(|b| b.name).collect::<Vec<_>>();
        let stages = |bindings: &[Binding]| bindings.iter().map(|b| b.stages).collect::<Vec<_>>();
        assert_eq!(names(&FORWARD.bindings[..2]), names(GBUFFER.bindings));
        assert_eq!(stages(&FORWARD.bindings[..2]), stages(GBUFFER.bindings));
        let tail = |decl: &SetDecl| names(&decl.bindings[decl.bindings.len() - LIT_BY.len()..]);
        assert_eq!(tail(&FORWARD), names(&LIT_BY));
        assert_eq!(tail(&crate::passes::lighting::SET), names(&LIT_BY));
    }

    /// Every binding a feature switches on names a feature of the variant's table
    /// (`variant::FEATURES`, the environment, shadows) — through its constant, never a
    /// string of its own (a misspelt define would leave the binding out of every
    /// shader that needs it).
    #[test]
    fn every_binding_is_switched_by_a_declared_feature() {
        let declared: Vec<&str> = variant::FEATURES
            .iter()
            .map(|f| f.define)
            .chain([variant::ENVIRONMENT.define, variant::SHADOWS.define])
            .chain(crate::passes::optional_passes().map(|p| p.define))
            .chain([TRACED_SURFACES])
            .collect();
        for decl in crate::passes::declared_sets() {
            for binding in decl.bindings {
                for define in binding.only_with.iter().chain(binding.or_with.iter()) {
                    assert!(
                        declared.contains(define),
                        "{}: {} is only with {define}, which no feature declares",
                        decl.name,
                        binding.name
                    );
                }
            }
        }
        let raw = concat!("only_with", "(\"");
        assert!(
            !include_str!("bindings.rs").contains(raw),
            "a binding names its feature by a string of its own"
        );
    }

    #[test]
    fn pool_sizes_count_each_descriptor_type() {
        let sizes = EXAMPLE.pool_sizes(2, true);
        let count = |ty| {
            sizes
                .iter()
                .find(|s| s.ty == ty)
                .map_or(0, |s| s.descriptor_count)
        };
        assert_eq!(count(vk::DescriptorType::SAMPLED_IMAGE), 4);
        assert_eq!(count(vk::DescriptorType::COMBINED_IMAGE_SAMPLER), 2);
        assert_eq!(count(vk::DescriptorType::STORAGE_BUFFER), 4);
        assert_eq!(count(vk::DescriptorType::STORAGE_IMAGE), 0);
    }
}
