//! Environment lighting (image-based): what a scene's [`Environment`] becomes on the GPU,
//! baked by compute shaders at upload or edit (never inside a frame), and read by the
//! lighting pass's ENVIRONMENT variant as a split sum (Karis 2013) whose second factor
//! keeps the project's physics:
//!
//! L_o ≈ L̃_spec(r_v, r) · A_spec(n·v, r) + L̄_cos(n) · A_diff(n·v, r, ρ)
//!
//! * L̃_spec: the radiance cube ([`RADIANCE_SIZE`], every mip) prefiltered with GGX by
//!   importance sampling, one level per roughness ([`SPECULAR_LEVELS`], r = level /
//!   (levels − 1)), looked up along the mirror direction;
//! * L̄_cos = E/π: the cosine-weighted mean radiance about the normal (irradiance cube,
//!   [`IRRADIANCE_SIZE`]);
//! * A_spec, A_diff: directional albedos over (n·v, r) computed per material with the
//!   lighting pass's own BRDF — the full Fresnel equations with the material's η + ik per
//!   channel, the outside medium η_i, the polarisation weight and total internal
//!   reflection — instead of the usual Schlick-from-F0 pre-integration; conductors
//!   derived from the base colour get one table per stored 8-bit code.
//!
//! The approximation's error against the f64 rendering equation
//! ([`combustion_optics::environment::integrate_environment`]) is measured in
//! tests/environment.rs.

use std::sync::Arc;
use std::time::Instant;

use combustion_scene::{Environment, Scene};
use combustion_vk::gpu_allocator::MemoryLocation;
use combustion_vk::{
    vk, Buffer, DescriptorPool, DescriptorSetLayout, Device, Image, ImageDesc, ImageView, OneShot,
    Pipeline, PipelineCache, PipelineLayout, Sampler, ShaderCompiler, ShaderModule, ShaderStage,
};

use crate::bindings;
use crate::buffers::filled_storage_buffer;
use crate::error::RenderError;
use crate::gpu_types::{
    conductor_from_base_color_table, material_table, EnvironmentAlbedoPush,
    EnvironmentCodeAlbedoPush, EnvironmentIrradiancePush, EnvironmentPrefilterPush,
    EnvironmentRadiancePush, EnvironmentSource, GpuMaterial, RadianceMode,
};
use crate::graph::{BufferUse, ImageStates, ImageUse, PassUses, TrackedImage};
use crate::pass_io::PassIo;

/// Entries per side of a material's directional-albedo table over (n·v, r)
/// (`ENVIRONMENT_TABLE_SIZE` in the shaders' generated `bindings/constants.glsl`).
pub const TABLE_SIZE: u32 = 32;
/// Entries per side of a per-code conductor table (`ENVIRONMENT_CODE_TABLE_SIZE`,
/// generated).
pub const CODE_TABLE_SIZE: u32 = 16;
/// Texels per side of a face of the radiance cube's level 0 (and of the specular cube).
pub const RADIANCE_SIZE: u32 = 128;
/// Levels of the prefiltered specular cube: 128 … 4 texels, r = 0, 0.2, … 1.
pub const SPECULAR_LEVELS: u32 = 6;
/// Texels per side of a face of the irradiance cube.
pub const IRRADIANCE_SIZE: u32 = 16;
/// The radiance cube level the irradiance sums over (32 texels per side).
pub const IRRADIANCE_SOURCE_LEVEL: u32 = 2;
/// GGX samples per texel of the specular cube.
pub const PREFILTER_SAMPLES: u32 = 256;
/// Samples per part (specular, diffuse) per entry of a material's table.
pub const ALBEDO_SAMPLES: u32 = 512;
/// Samples per entry of a per-code conductor table.
pub const CODE_ALBEDO_SAMPLES: u32 = 256;
/// Per-code tables: one for each stored 8-bit code (`ENVIRONMENT_CODES` in the generated
/// `bindings/constants.glsl`).
pub(crate) const CODES: u32 = 256;

/// The cubes' format. f32, not f16: the bake's normalised sums come out within a few f32
/// ulps of a uniform environment's radiance, and storing them as f16 (which lavapipe
/// rounds towards zero) would move them by up to an f16 step (5e-4 relative).
const FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// Refuses devices that cannot write [`FORMAT`] from compute and filter it linearly.
fn check_format(device: &Device) -> Result<(), RenderError> {
    // SAFETY: plain query.
    let properties = unsafe {
        device
            .instance()
            .get_physical_device_format_properties(device.physical_device(), FORMAT)
    };
    let needed =
        vk::FormatFeatureFlags::STORAGE_IMAGE | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR;
    if properties.optimal_tiling_features.contains(needed) {
        Ok(())
    } else {
        Err(RenderError::EnvironmentUnsupported(format!(
            "{} cannot write {FORMAT:?} from compute shaders or filter it linearly",
            device.info().name
        )))
    }
}

/// Entries per side of the white specular albedo table over (n·v, r)
/// (`ENERGY_TABLE_SIZE` in lighting.frag, generated), its entries placed as the albedo
/// tables' ([`combustion_optics::environment::table_coordinate`]).
pub const ENERGY_TABLE_SIZE: u32 = 32;
/// Hammersley samples per entry of that table.
pub const ENERGY_TABLE_SAMPLES: u32 = 1024;

/// E(μ, r), the GGX specular lobe's directional albedo with F = 1
/// ([`combustion_optics::environment::specular_albedo_white`]) over `ENERGY_TABLE_SIZE`²
/// entries (vertex-centred), μ along rows' entries, r = √α down the rows: the single
/// scattering's share of energy, which multiple-scattering energy compensation
/// ([`crate::ShadingOptions::energy_compensation`]) makes up for.
pub fn white_specular_albedo_table() -> Vec<f32> {
    use combustion_optics::environment::{table_coordinate, table_mu};
    let size = ENERGY_TABLE_SIZE as usize;
    (0..size)
        .flat_map(|j| {
            (0..size).map(move |i| {
                let r = table_coordinate(j, size);
                combustion_optics::environment::specular_albedo_white(
                    table_mu(i, size),
                    r * r,
                    ENERGY_TABLE_SAMPLES,
                ) as f32
            })
        })
        .collect()
}

/// A scene's environment on the GPU, ready for the lighting pass.
pub struct GpuEnvironment {
    pub(crate) specular: Image,
    pub(crate) irradiance: Image,
    /// Per material, `TABLE_SIZE`² entries of 2 vec4 (environment_albedo.comp).
    pub(crate) albedo: Buffer,
    /// Per distinct (η_i, w) of base-colour conductors, 256 codes × `CODE_TABLE_SIZE`².
    pub(crate) code_albedo: Buffer,
    /// Per material: its per-code table (0 when it has none).
    pub(crate) code_table_of_material: Buffer,
    /// Its directions' distribution for the path tracer's next-event estimation
    /// (`crate::environment_importance`).
    pub(crate) importance: Buffer,
    pub(crate) sampler: Sampler,
    /// What was baked.
    pub environment: Environment,
    /// Whether the cubes were copied from an earlier bake's cache entry instead of
    /// computed.
    pub cubes_from_cache: bool,
    /// Wall-clock time of the bake (recording, GPU work and the wait), ms.
    pub bake_ms: f64,
}

impl GpuEnvironment {
    /// What the lighting set binds for scenes without an environment (the bindings
    /// exist in every variant's layout; the shaders without ENVIRONMENT never read
    /// them): 1×1 cubes (never written, never read) and small zeroed tables.
    pub(crate) fn placeholder(device: &Arc<Device>) -> Result<Self, RenderError> {
        let usage = vk::ImageUsageFlags::SAMPLED;
        let cube = |name| Image::new(device, &ImageDesc::cube(name, FORMAT, 1, usage));
        let (specular, irradiance) = (
            cube("environment placeholder")?,
            cube("environment placeholder")?,
        );
        crate::placeholders::make_sampled_placeholders(device, &[&specular, &irradiance])?;
        let table = |name| filled_storage_buffer(device, name, &[0; 32]);
        Ok(Self {
            specular,
            irradiance,
            albedo: table("environment placeholder table")?,
            code_albedo: table("environment placeholder table")?,
            code_table_of_material: table("environment placeholder table")?,
            // Total weight 0: nothing to sample.
            importance: table("environment placeholder table")?,
            sampler: linear_sampler(device, 1)?,
            environment: Environment::Uniform([0.0; 3]),
            cubes_from_cache: false,
            bake_ms: 0.0,
        })
    }
}

/// An environment baked for the materials of an uploaded scene, to light that scene's
/// frames in place of its own ([`crate::FrameInputs::environment`]): a host changes the
/// sky per frame or per view — a day's cycle, a probe per viewport — without a scene
/// edit. Made by [`crate::Renderer::bake_environment`] (an upload step: it waits for
/// the GPU, never inside a frame).
///
/// The bake's directional-albedo tables follow the materials' optics, so it lights any
/// scene whose material table is the one it was baked for: the scene it was baked with,
/// until an edit changes a material's optics or the outside medium (then
/// [`crate::Renderer::record`] refuses it with
/// [`crate::RenderError::EnvironmentOfAnotherScene`]; bake it again).
///
/// Dropping it is safe at any time: as a [`crate::GpuScene`]'s, its resources wait in
/// the renderer's retire queue until the frames recorded before the drop have completed.
pub struct FrameEnvironment {
    pub(crate) gpu: std::mem::ManuallyDrop<GpuEnvironment>,
    /// The material table (as the bake reads it) it was baked for.
    pub(crate) materials: Vec<u8>,
    retire: Arc<crate::retire::RetireQueue>,
}

impl FrameEnvironment {
    pub(crate) fn new(
        gpu: GpuEnvironment,
        materials: Vec<u8>,
        retire: Arc<crate::retire::RetireQueue>,
    ) -> Self {
        Self {
            gpu: std::mem::ManuallyDrop::new(gpu),
            materials,
            retire,
        }
    }

    /// The environment it lights with.
    pub fn environment(&self) -> &Environment {
        &self.gpu.environment
    }

    /// Wall-clock time of its bake (recording, GPU work and the wait), ms.
    pub fn bake_ms(&self) -> f64 {
        self.gpu.bake_ms
    }

    /// Whether it was baked for a scene's material table (`bake_materials`, as the bake
    /// reads it) by the renderer whose retire queue is `retire`.
    pub(crate) fn lights(
        &self,
        bake_materials: &[u8],
        retire: &Arc<crate::retire::RetireQueue>,
    ) -> bool {
        Arc::ptr_eq(&self.retire, retire) && self.materials == bake_materials
    }
}

impl std::fmt::Debug for FrameEnvironment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FrameEnvironment")
            .field("environment", &self.gpu.environment.name())
            .field("bake_ms", &self.gpu.bake_ms)
            .finish_non_exhaustive()
    }
}

impl Drop for FrameEnvironment {
    fn drop(&mut self) {
        // SAFETY: `gpu` is taken once, here, and never touched again.
        let gpu = unsafe { std::mem::ManuallyDrop::take(&mut self.gpu) };
        self.retire.push(Box::new(gpu));
    }
}

/// A bake shader's compute pipeline, with its layout: the bake's descriptor set and,
/// as push constants, the shader's own push struct.
struct BakePipeline {
    layout: PipelineLayout,
    pipeline: Pipeline,
}

/// The bake's compute pipelines, built on the first scene with an environment, and
/// where its cubes are kept between bakes and runs.
pub(crate) struct EnvironmentBaker {
    set_layout: DescriptorSetLayout,
    radiance: BakePipeline,
    prefilter: BakePipeline,
    irradiance: BakePipeline,
    albedo: BakePipeline,
    code_albedo: BakePipeline,
    cubes_cache: Option<CubesCache>,
}

/// The folder environment bakes keep their cubes in by default:
/// `$COMBUSTION_ENVIRONMENT_CACHE` when set (`off` or empty: none), else
/// `$XDG_CACHE_HOME/combustion/environment`, else `$HOME/.cache/combustion/environment`,
/// else none.
pub fn default_environment_cache_dir() -> Option<std::path::PathBuf> {
    combustion_vk::default_cache_dir("COMBUSTION_ENVIRONMENT_CACHE", "environment")
}

/// The specular and irradiance cubes of earlier bakes, on disk
/// ([`combustion_vk::DiskCache`]). They depend on the environment alone (not on the
/// materials, whose tables are computed every bake), so an entry's key is the
/// environment's content and the bake's identity: the device and its driver (vendor,
/// device, name, driver version, pipeline cache UUID), the SPIR-V of the shaders that make the cubes,
/// and the bake's sizes, sample counts and format. An entry is both cubes' texels as
/// the GPU wrote them, so a bake from the cache is bit for bit the bake it saved.
struct CubesCache {
    entries: combustion_vk::DiskCache,
    identity: combustion_vk::Digest,
}

impl CubesCache {
    /// The entry file's magic and format version.
    const MAGIC: [u8; 8] = *b"CMBENV01";
    /// The folder's size limit: 120 bakes' cubes (2.1 MB each, whatever the size of
    /// the environment image), the least recently used removed past it.
    const CAPACITY: u64 = 256 << 20;
    /// How the bake's Rust side makes the cubes (its dispatches, their push values,
    /// samplers and layouts), which the key does not otherwise see: change it when that
    /// changes, and every entry is stale.
    const RECIPE: &'static str = "radiance level 0 analytic or n×n equirect samples \
        (n = width / 512 within 4..32), each next level the mean of the one before; \
        specular level l at r = l / 5, GGX-filtered from the whole radiance cube; \
        irradiance from radiance level 2";

    fn key(&self, environment: &Environment) -> combustion_vk::Digest {
        let source = EnvironmentSource::new(environment);
        let key = self.identity.part(bytemuck::bytes_of(&source));
        match environment {
            Environment::Uniform(_) => key.part(b"uniform"),
            Environment::Studio => key.part(b"studio"),
            Environment::Image(image) => key
                .part(b"image")
                .part(&image.width.to_le_bytes())
                .part(&image.height.to_le_bytes())
                .part_in_words(bytemuck::cast_slice(&image.texels)),
        }
    }
}

/// Every level and face of the specular cube, then the irradiance cube's faces, tightly
/// packed in one buffer: the copies between the cubes and a cache entry.
struct CubeTexels {
    /// Each cube with its regions of the buffer.
    copies: [(vk::Image, Vec<vk::BufferImageCopy>); 2],
    bytes: u64,
}

impl CubeTexels {
    fn new(specular: &Image, irradiance: &Image) -> Self {
        const TEXEL_BYTES: u64 = 16; // FORMAT, RGBA32F
        let (specular_regions, end) = specular.every_level_copy_regions(0, TEXEL_BYTES);
        let (irradiance_regions, bytes) = irradiance.every_level_copy_regions(end, TEXEL_BYTES);
        Self {
            copies: [
                (specular.raw(), specular_regions),
                (irradiance.raw(), irradiance_regions),
            ],
            bytes,
        }
    }

    /// Records the copies from `buffer` into the cubes (in TRANSFER_DST_OPTIMAL), or
    /// from the cubes (in TRANSFER_SRC_OPTIMAL) into `buffer`.
    fn record(&self, device: &Device, cmd: vk::CommandBuffer, buffer: &Buffer, into_cubes: bool) {
        let raw = device.raw();
        for (image, regions) in &self.copies {
            // SAFETY: recording state (the caller's); the buffer and the cubes live until
            // the bake's wait, the cubes in the layout named, which the caller's barrier
            // left them in.
            unsafe {
                if into_cubes {
                    let layout = ImageUse::TransferDestination.state().layout;
                    raw.cmd_copy_buffer_to_image(cmd, buffer.raw(), *image, layout, regions);
                } else {
                    let layout = ImageUse::TransferSource.state().layout;
                    raw.cmd_copy_image_to_buffer(cmd, *image, layout, buffer.raw(), regions);
                }
            }
        }
    }
}

fn linear_sampler(device: &Arc<Device>, levels: u32) -> Result<Sampler, RenderError> {
    sampler_with_mips(device, levels, vk::SamplerMipmapMode::LINEAR)
}

fn sampler_with_mips(
    device: &Arc<Device>,
    levels: u32,
    mipmap_mode: vk::SamplerMipmapMode,
) -> Result<Sampler, RenderError> {
    let info = vk::SamplerCreateInfo::default()
        .mag_filter(vk::Filter::LINEAR)
        .min_filter(vk::Filter::LINEAR)
        .mipmap_mode(mipmap_mode)
        .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .min_lod(0.0)
        .max_lod(levels as f32);
    Ok(Sampler::new(device, &info)?)
}

/// Texels one band of the equirectangular upload carries at most (32 MiB of RGBA32F):
/// the staging memory an upload takes, whatever the image's size.
const UPLOAD_BAND_TEXELS: usize = 1 << 21;

/// The equirectangular source as an RGBA32F image with its sampler (wrapping in u,
/// clamped at the poles), and the texels it is uploaded from: a 1×1 black placeholder
/// for analytic sources.
struct Equirect {
    image: Image,
    sampler: Sampler,
    /// The scene's decoded texels (shared, not copied), if the source is an image.
    source: Option<Arc<combustion_scene::EnvironmentImage>>,
}

impl Equirect {
    fn new(device: &Arc<Device>, environment: &Environment) -> Result<Self, RenderError> {
        let source = match environment {
            Environment::Image(image) => Some(image.clone()),
            _ => None,
        };
        let (width, height) = source
            .as_ref()
            .map_or((1, 1), |image| (image.width, image.height));
        let max = device.max_image_dimension_2d();
        if width > max || height > max {
            return Err(RenderError::TooLarge(format!(
                "environment image of {width}×{height}: this device takes at most {max} per side"
            )));
        }
        let image = Image::new(
            device,
            &ImageDesc::new(
                "environment equirect",
                FORMAT,
                width,
                height,
                vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            ),
        )?;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        Ok(Self {
            image,
            sampler: Sampler::new(device, &info)?,
            source,
        })
    }

    /// Uploads the texels in bands of rows through one staging buffer of at most
    /// [`UPLOAD_BAND_TEXELS`] texels, each band converted to RGBA in it, copied and
    /// waited for (an upload step): the memory beside the scene's texels and the image
    /// is one band's, not a second and third copy of the whole image. Leaves the image
    /// as a copy's destination (`states` knows it).
    fn upload(
        &self,
        device: &Arc<Device>,
        commands: &mut OneShot,
        states: &mut ImageStates,
    ) -> Result<(), RenderError> {
        let extent = self.image.extent();
        let (width, height) = (extent.width as usize, extent.height as usize);
        let rows_per_band = (UPLOAD_BAND_TEXELS / width).clamp(1, height);
        const TEXEL_BYTES: usize = std::mem::size_of::<[f32; 4]>();
        let mut staging = Buffer::new(
            device,
            "environment equirect staging",
            (rows_per_band * width * TEXEL_BYTES) as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        let mut row = vec![[0f32; 4]; width];
        let layout = ImageUse::TransferDestination.state().layout;
        for first in (0..height).step_by(rows_per_band) {
            let rows = rows_per_band.min(height - first);
            for r in 0..rows {
                if let Some(image) = &self.source {
                    let start = (first + r) * width;
                    for (texel, t) in row.iter_mut().zip(&image.texels[start..start + width]) {
                        *texel = [t[0], t[1], t[2], 1.0];
                    }
                }
                staging.write(r * width * TEXEL_BYTES, bytemuck::cast_slice(&row))?;
            }
            let cmd = commands.begin()?;
            let raw = device.raw();
            if first == 0 {
                let uses = PassIo::new("environment upload")
                    .touches((&self.image).into(), ImageUse::TransferDestination)
                    .apply(device);
                states.transition(raw, cmd, &uses);
            } else {
                // The bands before were copied into other rows of the same layout; this
                // copy waits for them all the same (one image, tracked whole).
                let (stage, access) = (
                    vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::TRANSFER_WRITE,
                );
                let barrier = [vk::ImageMemoryBarrier2::default()
                    .src_stage_mask(stage)
                    .src_access_mask(access)
                    .dst_stage_mask(stage)
                    .dst_access_mask(access)
                    .old_layout(layout)
                    .new_layout(layout)
                    .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .image(self.image.raw())
                    .subresource_range(self.image.subresource_range())];
                // SAFETY: recording state; the image is in `layout` since the first band.
                unsafe {
                    raw.cmd_pipeline_barrier2(
                        cmd,
                        &vk::DependencyInfo::default().image_memory_barriers(&barrier),
                    )
                };
            }
            let region = vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_offset(vk::Offset3D {
                    x: 0,
                    y: first as i32,
                    z: 0,
                })
                .image_extent(vk::Extent3D {
                    width: width as u32,
                    height: rows as u32,
                    depth: 1,
                });
            // SAFETY: recording state; the staging buffer holds `rows` packed rows and
            // lives past the wait below; the image is in the layout named.
            unsafe {
                raw.cmd_copy_buffer_to_image(
                    cmd,
                    staging.raw(),
                    self.image.raw(),
                    layout,
                    &[region],
                )
            };
            commands.submit_and_wait()?;
        }
        Ok(())
    }
}

/// Bytes of one material's directional-albedo table (`TABLE_SIZE`² entries of 2 vec4).
const ALBEDO_TABLE_BYTES: u64 = (TABLE_SIZE * TABLE_SIZE) as u64 * 2 * 16;

/// What environment_albedo.comp reads of a material, bit for bit: the conductor's η, k,
/// the outside medium's IOR and the polarisation weight, the dielectric IOR, the
/// diffuse model, whether it has a clear coat, and the coat's IOR. Materials equal in
/// these have the same table (the table spans roughness itself; base colour and
/// metalness weight its parts in the lighting pass), so it is computed once for them.
fn albedo_table_key(material: &GpuMaterial) -> [u32; 12] {
    let [eta_r, eta_g, eta_b, outside_ior] = material.conductor_eta_outside_ior.map(f32::to_bits);
    let [k_r, k_g, k_b, polarisation] = material.conductor_k_polarisation.map(f32::to_bits);
    [
        eta_r,
        eta_g,
        eta_b,
        outside_ior,
        k_r,
        k_g,
        k_b,
        polarisation,
        material.roughness_anisotropy_ior[3].to_bits(),
        material.diffuse_model_flags[0],
        u32::from(material.clearcoat[0] > 0.0),
        material.clearcoat[2].to_bits(),
    ]
}

/// The materials whose directional-albedo tables the bake computes (the first of each
/// distinct [`albedo_table_key`]), and the index among them of each material's table.
fn albedo_tables(materials: &[GpuMaterial]) -> (Vec<GpuMaterial>, Vec<u32>) {
    let mut computed: Vec<GpuMaterial> = Vec::new();
    let mut index_of_key = std::collections::HashMap::new();
    let table_of_material = materials
        .iter()
        .map(|material| {
            *index_of_key
                .entry(albedo_table_key(material))
                .or_insert_with(|| {
                    computed.push(*material);
                    computed.len() as u32 - 1
                })
        })
        .collect();
    (computed, table_of_material)
}

/// The distinct (η_i, w) of the materials whose conductor comes from the base colour,
/// and each material's index among them (0 for the others).
fn code_tables(materials: &[GpuMaterial]) -> (Vec<[f32; 2]>, Vec<u32>) {
    let mut keys: Vec<[f32; 2]> = Vec::new();
    let of_material = materials
        .iter()
        .map(|m| {
            if !m.conductor_from_base_color() {
                return 0;
            }
            let key = [
                m.conductor_eta_outside_ior[3],
                m.conductor_k_polarisation[3],
            ];
            let index = keys
                .iter()
                .position(|k| k.map(f32::to_bits) == key.map(f32::to_bits))
                .unwrap_or_else(|| {
                    keys.push(key);
                    keys.len() - 1
                });
            index as u32
        })
        .collect();
    (keys, of_material)
}

impl EnvironmentBaker {
    /// The bake's pipelines; its cubes kept in `cache_dir` (none: computed every bake).
    pub fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        cache: &PipelineCache,
        cache_dir: Option<std::path::PathBuf>,
    ) -> Result<Self, RenderError> {
        let set_layout = bindings::ENVIRONMENT_BAKE.layout(device)?;
        // What decides the cubes besides the environment (CubesCache).
        // SAFETY: the physical device the device was made from.
        let properties = unsafe {
            device
                .instance()
                .get_physical_device_properties(device.physical_device())
        };
        // The device's name too: a CPU driver's version and cache UUID may not say
        // which LLVM and vector width compiled the shaders, its name does (llvmpipe).
        let device_name: Vec<u8> = properties
            .device_name
            .iter()
            .take_while(|&&c| c != 0)
            .map(|&c| c as u8)
            .collect();
        let mut identity = combustion_vk::Digest::new()
            .part(CubesCache::RECIPE.as_bytes())
            .part(&device_name)
            .part(&properties.vendor_id.to_le_bytes())
            .part(&properties.device_id.to_le_bytes())
            .part(&properties.driver_version.to_le_bytes())
            .part(&properties.pipeline_cache_uuid)
            .part(&FORMAT.as_raw().to_le_bytes());
        for constant in [
            RADIANCE_SIZE,
            SPECULAR_LEVELS,
            IRRADIANCE_SIZE,
            IRRADIANCE_SOURCE_LEVEL,
            PREFILTER_SAMPLES,
        ] {
            identity = identity.part(&constant.to_le_bytes());
        }
        let mut build = |file: &str, push_size: usize, makes_cubes: bool| {
            let push = [vk::PushConstantRange {
                stage_flags: vk::ShaderStageFlags::COMPUTE,
                offset: 0,
                size: push_size as u32,
            }];
            let layout = PipelineLayout::new(device, &[&set_layout], &push)?;
            let words = compiler.compile(file, ShaderStage::Compute, &[])?;
            if makes_cubes {
                identity = identity.part(bytemuck::cast_slice(&words));
            }
            let module = ShaderModule::new(device, &words, ShaderStage::Compute)?;
            let pipeline = Pipeline::compute(device, &module, &layout, Some(cache))?;
            Ok::<_, RenderError>(BakePipeline { layout, pipeline })
        };
        use std::mem::size_of;
        // (shader, its push struct's size, whether it makes the cubes), in field order.
        let shaders = [
            (
                "environment_radiance.comp",
                size_of::<EnvironmentRadiancePush>(),
                true,
            ),
            (
                "environment_prefilter.comp",
                size_of::<EnvironmentPrefilterPush>(),
                true,
            ),
            (
                "environment_irradiance.comp",
                size_of::<EnvironmentIrradiancePush>(),
                true,
            ),
            (
                "environment_albedo.comp",
                size_of::<EnvironmentAlbedoPush>(),
                false,
            ),
            (
                "environment_code_albedo.comp",
                size_of::<EnvironmentCodeAlbedoPush>(),
                false,
            ),
        ];
        let mut built = Vec::with_capacity(shaders.len());
        for (file, push_size, makes_cubes) in shaders {
            built.push(build(file, push_size, makes_cubes)?);
        }
        let Ok([radiance, prefilter, irradiance, albedo, code_albedo]) =
            <[BakePipeline; 5]>::try_from(built)
        else {
            unreachable!("five shaders, five pipelines")
        };
        Ok(Self {
            radiance,
            prefilter,
            irradiance,
            albedo,
            code_albedo,
            set_layout,
            cubes_cache: cache_dir.map(|dir| CubesCache {
                entries: combustion_vk::DiskCache::new(dir, CubesCache::MAGIC, "cubes")
                    .keeping_at_most(CubesCache::CAPACITY),
                identity,
            }),
        })
    }

    /// Bakes `environment` for `scene`'s materials (with their own copies of the
    /// material and conductor tables, so nothing of an uploaded scene is needed: an edit
    /// bakes before it replaces anything). Waits for the GPU: an upload step.
    ///
    /// The cubes depend on the environment alone: with a cache folder they are copied
    /// from an earlier bake's entry when there is one ([`CubesCache`]), else computed and
    /// read back into a new entry. The materials' tables are computed every bake.
    ///
    /// Each dispatch and copy declares what it reads and writes ([`PassIo`], in a
    /// descriptor set of its own), and the barriers between them are derived from those
    /// declarations ([`ImageStates`]), as the frame's passes' are.
    pub fn bake(
        &self,
        device: &Arc<Device>,
        environment: &Environment,
        scene: &Scene,
    ) -> Result<GpuEnvironment, RenderError> {
        let start = Instant::now();
        check_format(device)?;
        let bake = BakeResources::new(device, self.cubes_cache.as_ref(), environment, scene)?;
        let dispatches =
            bake.radiance.mip_levels() + SPECULAR_LEVELS + 2 + bake.code_keys.len() as u32;
        let decl = &bindings::ENVIRONMENT_BAKE;
        let pool = DescriptorPool::new(
            device,
            dispatches,
            &decl.pool_sizes(dispatches, device.ray_queries()),
        )?;
        let mut views = Vec::new();

        let mut commands = OneShot::new(device)?;
        let mut states = ImageStates::default();
        bake.equirect.upload(device, &mut commands, &mut states)?;
        let cmd = commands.begin()?;
        let mut record = Recorder {
            device,
            cmd,
            pool: &pool,
            set_layout: &self.set_layout,
            states: &mut states,
        };
        // The tables first: these shaders read the material and conductor tables and
        // write buffers only.
        self.record_tables(&mut record, &bake)?;
        if let Some(staging) = &bake.cubes_staging {
            // The cubes of an earlier bake of this environment, copied in.
            let upload = PassUses::images(
                "environment cubes upload",
                bake.cubes(ImageUse::TransferDestination),
            );
            record.states.transition(device.raw(), cmd, &upload);
            bake.cube_texels.record(device, cmd, staging, true);
        } else {
            self.record_cubes(&mut record, &bake, environment, &mut views)?;
        }

        // Hand the cubes and tables to the lighting pass's fragment shader (and the
        // cubes' texels, read back, to the host).
        let mut buffers = vec![
            (bake.albedo.raw(), BufferUse::FragmentStorageRead),
            (bake.code_albedo.raw(), BufferUse::FragmentStorageRead),
        ];
        buffers.extend(
            bake.cubes_readback
                .iter()
                .map(|b| (b.raw(), BufferUse::HostRead)),
        );
        let hand_off = PassUses::images(
            "environment hand-off",
            bake.cubes(ImageUse::FragmentSampled),
        )
        .with_buffers(buffers);
        states.transition(device.raw(), cmd, &hand_off);
        commands.submit_and_wait()?;
        if let (Some(cache), Some(key), Some(readback)) =
            (&self.cubes_cache, bake.cache_key, &bake.cubes_readback)
        {
            // The cache never fails a bake: an unreadable buffer only loses the entry.
            if let Ok(texels) = readback.mapped() {
                cache.entries.store(key, texels);
            }
        }
        drop(views);
        drop(pool);
        let cubes_from_cache = bake.cubes_staging.is_some();
        let BakeResources {
            specular,
            irradiance,
            albedo,
            code_albedo,
            code_table_of_material,
            ..
        } = bake;
        let importance = filled_storage_buffer(
            device,
            "environment importance",
            bytemuck::cast_slice(&crate::environment_importance::importance_table(
                environment,
            )),
        )?;
        Ok(GpuEnvironment {
            specular,
            irradiance,
            albedo,
            code_albedo,
            code_table_of_material,
            importance,
            sampler: linear_sampler(device, SPECULAR_LEVELS)?,
            environment: environment.clone(),
            cubes_from_cache,
            bake_ms: start.elapsed().as_secs_f64() * 1e3,
        })
    }

    /// Records the materials' tables: one directional-albedo table per distinct set of
    /// what the albedo shader reads of a material, copied to each material with that
    /// set, and the base-colour conductors' tables per code. Their sets bind the source
    /// images and a target view all the same, which are brought to the layouts bound
    /// here (nothing written in them yet: the cubes are made after).
    fn record_tables(
        &self,
        record: &mut Recorder<'_>,
        bake: &BakeResources,
    ) -> Result<(), RenderError> {
        let (device, cmd) = (record.device, record.cmd);
        let decl = &bindings::ENVIRONMENT_BAKE;
        let tables_io = |name, set| {
            PassIo::new(name)
                .set(decl, set)
                .sampled(
                    "environment_source",
                    &bake.radiance,
                    bake.sampler.raw(),
                    ImageUse::ComputeSampled,
                )
                .sampled(
                    "environment_equirect",
                    &bake.equirect.image,
                    bake.equirect.sampler.raw(),
                    ImageUse::ComputeSampled,
                )
                .image_view(
                    "environment_target",
                    &bake.irradiance,
                    bake.irradiance_view.raw(),
                    ImageUse::ComputeStorageWrite,
                )
        };
        if bake.computed_count > 0 {
            let set = record.set()?;
            let io = tables_io("environment albedo", set)
                .buffer("materials", &bake.materials, BufferUse::ComputeStorageRead)
                .bind_buffer("conductor_from_code", &bake.conductor_table)
                .buffer(
                    "environment_albedo",
                    &bake.computed_albedo,
                    BufferUse::ComputeStorageWrite,
                )
                .bind_buffer("environment_code_albedo", &bake.code_albedo);
            let push = EnvironmentAlbedoPush {
                samples: ALBEDO_SAMPLES,
            };
            let groups = workgroups(TABLE_SIZE, bake.computed_count);
            record.dispatch(&self.albedo, set, io, &push, groups);
            // Each material's table, copied from the one computed for its key.
            let copy =
                PassUses::images("environment albedo copies", Vec::new()).with_buffers(vec![
                    (bake.computed_albedo.raw(), BufferUse::TransferSource),
                    (bake.albedo.raw(), BufferUse::TransferDestination),
                ]);
            record.states.transition(device.raw(), cmd, &copy);
            let regions: Vec<_> = bake
                .table_of_material
                .iter()
                .enumerate()
                .map(|(material, &table)| vk::BufferCopy {
                    src_offset: u64::from(table) * ALBEDO_TABLE_BYTES,
                    dst_offset: material as u64 * ALBEDO_TABLE_BYTES,
                    size: ALBEDO_TABLE_BYTES,
                })
                .collect();
            // SAFETY: recording state; both buffers live until the bake's wait, and the
            // barrier above made the dispatch's writes visible to the copy.
            unsafe {
                device.raw().cmd_copy_buffer(
                    cmd,
                    bake.computed_albedo.raw(),
                    bake.albedo.raw(),
                    &regions,
                );
            }
        }
        for (table, &[outside_ior, polarisation_weight]) in bake.code_keys.iter().enumerate() {
            let set = record.set()?;
            let io = tables_io("environment code albedo", set)
                .bind_buffer("materials", &bake.materials)
                .buffer(
                    "conductor_from_code",
                    &bake.conductor_table,
                    BufferUse::ComputeStorageRead,
                )
                .bind_buffer("environment_albedo", &bake.albedo)
                .buffer(
                    "environment_code_albedo",
                    &bake.code_albedo,
                    BufferUse::ComputeStorageWrite,
                );
            let push = EnvironmentCodeAlbedoPush {
                samples: CODE_ALBEDO_SAMPLES,
                table: table as u32,
                outside_ior,
                polarisation_weight,
            };
            let groups = workgroups(CODE_TABLE_SIZE, CODES);
            record.dispatch(&self.code_albedo, set, io, &push, groups);
        }
        Ok(())
    }

    /// Records the cubes computed from `environment`: the radiance cube level by level,
    /// the GGX-prefiltered specular cube and the irradiance cube from it, and, for the
    /// cache, their texels read back. The views the dispatches write through go to
    /// `views` (they must live until the bake's wait).
    fn record_cubes(
        &self,
        record: &mut Recorder<'_>,
        bake: &BakeResources,
        environment: &Environment,
        views: &mut Vec<ImageView>,
    ) -> Result<(), RenderError> {
        let (device, cmd) = (record.device, record.cmd);
        let decl = &bindings::ENVIRONMENT_BAKE;
        let radiance = &bake.radiance;
        // The radiance cube: level 0 from the source, each next level the mean of the
        // one before, which the same dispatch samples while it writes its own.
        let source = EnvironmentSource::new(environment);
        for level in 0..radiance.mip_levels() {
            let view = level_view(radiance, level)?;
            let size = radiance.mip_extent(level).width;
            let (mode, source_level, samples_across) = match (level, environment) {
                // n × n samples a texel: at least the image's texels across one (its
                // width spans the four side faces), 4 to 32.
                (0, Environment::Image(image)) => {
                    let across = image.width.div_ceil(4 * RADIANCE_SIZE);
                    (RadianceMode::Equirect, 0, across.clamp(4, 32))
                }
                (0, _) => (RadianceMode::Analytic, 0, 0),
                _ => (RadianceMode::Reduce, level - 1, 0),
            };
            let set = record.set()?;
            let chain = ImageUse::ComputeSampledStorageWrite;
            let io = PassIo::new("environment radiance")
                .set(decl, set)
                .sampled(
                    "environment_source",
                    radiance,
                    bake.one_level_sampler.raw(),
                    chain,
                )
                .sampled(
                    "environment_equirect",
                    &bake.equirect.image,
                    bake.equirect.sampler.raw(),
                    ImageUse::ComputeSampled,
                )
                .image_view("environment_target", radiance, view.raw(), chain);
            let push = EnvironmentRadiancePush {
                source,
                size,
                mode: mode as u32,
                source_level,
                samples_across,
            };
            let io = bake.no_tables(io);
            record.dispatch(&self.radiance, set, io, &push, workgroups(size, 6));
            views.push(view);
        }

        // A dispatch that samples the whole radiance cube and writes `view` of `target`
        // (binding no equirect image and no tables).
        let from_radiance = |name, set, target: &Image, view: vk::ImageView| {
            let io = PassIo::new(name)
                .set(decl, set)
                .sampled(
                    "environment_source",
                    radiance,
                    bake.sampler.raw(),
                    ImageUse::ComputeSampled,
                )
                .image_view(
                    "environment_target",
                    target,
                    view,
                    ImageUse::ComputeStorageWrite,
                );
            bake.no_tables(bake.no_equirect(io))
        };

        // The GGX-prefiltered specular cube, a level per roughness, from the whole
        // radiance cube.
        for level in 0..SPECULAR_LEVELS {
            let view = level_view(&bake.specular, level)?;
            let size = bake.specular.mip_extent(level).width;
            let set = record.set()?;
            let io = from_radiance("environment prefilter", set, &bake.specular, view.raw());
            let push = EnvironmentPrefilterPush {
                size,
                samples: PREFILTER_SAMPLES,
                radiance_size: RADIANCE_SIZE,
                roughness: level as f32 / (SPECULAR_LEVELS - 1) as f32,
            };
            record.dispatch(&self.prefilter, set, io, &push, workgroups(size, 6));
            views.push(view);
        }

        // The irradiance cube, from one level of the radiance cube.
        let set = record.set()?;
        let io = from_radiance(
            "environment irradiance",
            set,
            &bake.irradiance,
            bake.irradiance_view.raw(),
        );
        let push = EnvironmentIrradiancePush {
            size: IRRADIANCE_SIZE,
            source_level: IRRADIANCE_SOURCE_LEVEL,
            source_size: radiance.mip_extent(IRRADIANCE_SOURCE_LEVEL).width,
        };
        let groups = workgroups(IRRADIANCE_SIZE, 6);
        record.dispatch(&self.irradiance, set, io, &push, groups);

        if let Some(readback) = &bake.cubes_readback {
            // The cubes as the GPU wrote them, for the cache entry.
            let copy = PassUses::images(
                "environment cubes readback",
                bake.cubes(ImageUse::TransferSource),
            )
            .with_buffers(vec![(readback.raw(), BufferUse::TransferDestination)]);
            record.states.transition(device.raw(), cmd, &copy);
            bake.cube_texels.record(device, cmd, readback, false);
        }
        Ok(())
    }
}

/// Workgroups of 8 × 8 over a `size` × `size` image or table, `z` deep.
fn workgroups(size: u32, z: u32) -> [u32; 3] {
    [size.div_ceil(8), size.div_ceil(8), z]
}

/// A view of mip level `level` of cube `image`, its six faces as a 2D array (what a
/// compute shader writes).
fn level_view(image: &Image, level: u32) -> Result<ImageView, RenderError> {
    Ok(image.view_of(level..level + 1, 0..6, vk::ImageViewType::TYPE_2D_ARRAY)?)
}

/// What one bake makes and reads: the three cubes, the materials' tables and the buffers
/// they are computed from, the cache's entry (the texels copied in, or a buffer they are
/// read back into), the samplers and the source image.
struct BakeResources {
    radiance: Image,
    specular: Image,
    irradiance: Image,
    /// The irradiance cube's one level, as the dispatches write it.
    irradiance_view: ImageView,
    cube_texels: CubeTexels,
    /// The cache entry's key (with a cache folder).
    cache_key: Option<combustion_vk::Digest>,
    /// The materials whose albedo tables are computed, one per distinct key.
    materials: Buffer,
    computed_count: u32,
    /// Per material, the computed table it copies.
    table_of_material: Vec<u32>,
    conductor_table: Buffer,
    computed_albedo: Buffer,
    albedo: Buffer,
    /// The base-colour conductors' tables: (outside IOR, polarisation weight) of each.
    code_keys: Vec<[f32; 2]>,
    code_albedo: Buffer,
    code_table_of_material: Buffer,
    /// The cubes' texels from the cache entry, uploaded.
    cubes_staging: Option<Buffer>,
    /// Where the computed cubes' texels are read back into, for a new entry.
    cubes_readback: Option<Buffer>,
    sampler: Sampler,
    /// Building level L reads level L − 1 alone: a nearest-mip sampler never touches
    /// level L, which the same dispatch writes.
    one_level_sampler: Sampler,
    equirect: Equirect,
}

impl BakeResources {
    /// Creates what a bake of `environment` for `scene`'s materials needs, the cubes
    /// taken from `cache` when it holds an intact entry for the environment.
    fn new(
        device: &Arc<Device>,
        cache: Option<&CubesCache>,
        environment: &Environment,
        scene: &Scene,
    ) -> Result<Self, RenderError> {
        let usage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::SAMPLED;
        let copied = vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST;
        let radiance = Image::new(
            device,
            &ImageDesc::cube("environment radiance", FORMAT, RADIANCE_SIZE, usage).full_mips(),
        )?;
        let specular = Image::new(
            device,
            &ImageDesc::cube(
                "environment specular",
                FORMAT,
                RADIANCE_SIZE,
                usage | copied,
            )
            .mips(SPECULAR_LEVELS),
        )?;
        let irradiance = Image::new(
            device,
            &ImageDesc::cube(
                "environment irradiance",
                FORMAT,
                IRRADIANCE_SIZE,
                usage | copied,
            ),
        )?;
        let cube_texels = CubeTexels::new(&specular, &irradiance);
        let cache_key = cache.map(|cache| cache.key(environment));
        let cached_cubes = cache
            .zip(cache_key)
            .and_then(|(cache, key)| cache.entries.load(key))
            .filter(|texels| {
                // What an entry of another size or of texels that are not radiance
                // (forged, or damaged past its checksum's notice) would light with.
                combustion_vk::disk_cache::bodies::is_radiance(
                    texels,
                    cube_texels.bytes,
                    combustion_scene::MAX_RADIANCE,
                )
            });
        let gpu_materials = material_table(scene, &[]);
        // The albedo dispatch reads the materials whose tables it computes, one each.
        let (computed_materials, table_of_material) = albedo_tables(&gpu_materials);
        let materials = filled_storage_buffer(
            device,
            "environment bake material table",
            bytemuck::cast_slice(&computed_materials),
        )?;
        let conductor_table = filled_storage_buffer(
            device,
            "environment bake conductor table",
            bytemuck::cast_slice(conductor_from_base_color_table()),
        )?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let computed_albedo = Buffer::new(
            device,
            "environment albedo tables computed",
            computed_materials.len().max(1) as u64 * ALBEDO_TABLE_BYTES,
            storage | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let albedo = Buffer::new(
            device,
            "environment albedo tables",
            gpu_materials.len().max(1) as u64 * ALBEDO_TABLE_BYTES,
            storage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let (code_keys, of_material) = code_tables(&gpu_materials);
        let code_albedo = Buffer::new(
            device,
            "environment per-code conductor tables",
            code_keys.len().max(1) as u64
                * u64::from(CODES * CODE_TABLE_SIZE * CODE_TABLE_SIZE)
                * 4,
            storage,
            MemoryLocation::GpuOnly,
        )?;
        let code_table_of_material = filled_storage_buffer(
            device,
            "environment per-code table of each material",
            bytemuck::cast_slice(&of_material),
        )?;
        // The cubes' texels: from the cache entry (uploaded), or read back into a new one.
        let cubes_staging = match &cached_cubes {
            Some(texels) => Some(Buffer::with_data(
                device,
                "environment cubes from the bake cache",
                texels,
                vk::BufferUsageFlags::TRANSFER_SRC,
            )?),
            None => None,
        };
        let cubes_readback = match (&cached_cubes, cache_key) {
            (None, Some(_)) => Some(Buffer::new(
                device,
                "environment cubes for the bake cache",
                cube_texels.bytes,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?),
            _ => None,
        };
        let sampler = linear_sampler(device, radiance.mip_levels())?;
        let one_level_sampler = sampler_with_mips(
            device,
            radiance.mip_levels(),
            vk::SamplerMipmapMode::NEAREST,
        )?;
        // Cubes from the cache read no source: a 1×1 placeholder is bound in its place.
        let equirect = match cached_cubes {
            Some(_) => Equirect::new(device, &Environment::Uniform([0.0; 3]))?,
            None => Equirect::new(device, environment)?,
        };
        let irradiance_view = level_view(&irradiance, 0)?;
        Ok(Self {
            radiance,
            specular,
            irradiance,
            irradiance_view,
            cube_texels,
            cache_key,
            materials,
            computed_count: computed_materials.len() as u32,
            table_of_material,
            conductor_table,
            computed_albedo,
            albedo,
            code_keys,
            code_albedo,
            code_table_of_material,
            cubes_staging,
            cubes_readback,
            sampler,
            one_level_sampler,
            equirect,
        })
    }

    /// The specular and irradiance cubes, each in `use_`.
    fn cubes(&self, use_: ImageUse) -> Vec<(TrackedImage, ImageUse)> {
        vec![
            ((&self.specular).into(), use_),
            ((&self.irradiance).into(), use_),
        ]
    }

    /// `io` with the equirect image bound in the layout it is in, for a dispatch whose
    /// shader does not reach it (every binding of the set is written all the same): no
    /// barrier concerns it.
    fn no_equirect(&self, io: PassIo) -> PassIo {
        io.bind_image(
            "environment_equirect",
            self.equirect.image.view(),
            ImageUse::ComputeSampled.state().layout,
            self.equirect.sampler.raw(),
        )
    }

    /// `io` with the tables bound, for a dispatch whose shader does not reach them.
    fn no_tables(&self, io: PassIo) -> PassIo {
        io.bind_buffer("materials", &self.materials)
            .bind_buffer("conductor_from_code", &self.conductor_table)
            .bind_buffer("environment_albedo", &self.albedo)
            .bind_buffer("environment_code_albedo", &self.code_albedo)
    }
}

/// Records the bake's dispatches into one command buffer, each with its own descriptor
/// set from the bake's pool and the barriers its declaration calls for.
struct Recorder<'a> {
    device: &'a Device,
    cmd: vk::CommandBuffer,
    pool: &'a DescriptorPool,
    set_layout: &'a DescriptorSetLayout,
    states: &'a mut ImageStates,
}

impl Recorder<'_> {
    /// A new descriptor set of the bake's layout, for one dispatch.
    fn set(&self) -> Result<vk::DescriptorSet, RenderError> {
        Ok(self.pool.allocate(self.set_layout)?)
    }

    /// Writes `io`'s descriptors (into `set`, new and not in use), records the barriers
    /// it calls for, then `shader` with `push` over `groups` workgroups.
    fn dispatch<P: bytemuck::Pod>(
        &mut self,
        shader: &BakePipeline,
        set: vk::DescriptorSet,
        io: PassIo,
        push: &P,
        groups: [u32; 3],
    ) {
        let raw = self.device.raw();
        let uses = io.apply(self.device);
        self.states.transition(raw, self.cmd, &uses);
        crate::commands::bind_pass(
            raw,
            self.cmd,
            vk::PipelineBindPoint::COMPUTE,
            &shader.pipeline,
            &shader.layout,
            set,
            vk::ShaderStageFlags::COMPUTE,
            bytemuck::bytes_of(push),
        );
        // SAFETY: recording state; the resources live until the bake's wait, in the
        // layouts the barriers above left them in.
        unsafe { raw.cmd_dispatch(self.cmd, groups[0], groups[1], groups[2]) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base_colour_conductors_share_a_table_per_outside_medium_and_polarisation() {
        let mut scene = combustion_scene::builtin_scene("spheres").expect("built in");
        let mut gltf_metal = combustion_scene::Material {
            conductor_from_base_color: true,
            metalness: 1.0,
            ..combustion_scene::Material::default()
        };
        scene.materials.push(gltf_metal.clone());
        scene.materials.push(gltf_metal.clone());
        gltf_metal.outside_ior = Some(1.33);
        scene.materials.push(gltf_metal);
        let (keys, of_material) = code_tables(&material_table(&scene, &[]));
        assert_eq!(keys.len(), 2);
        let n = of_material.len();
        assert_eq!(&of_material[n - 3..], &[0, 0, 1]);
    }

    /// A push struct's name, size and fields (name and offset, in order) as Rust lays
    /// it out.
    macro_rules! push_layout {
        ($push:ident { $($field:ident),* $(,)? }) => {
            (
                stringify!($push),
                std::mem::size_of::<$push>() as u32,
                vec![$((stringify!($field).to_owned(), std::mem::offset_of!($push, $field) as u32)),*],
            )
        };
    }

    /// Each bake shader's push-constant block, as its compiled SPIR-V lays it out, is
    /// the Rust struct the bake pushes: same name, same members by name at the same
    /// offsets, same size (and the pipeline's push range is that size).
    #[test]
    fn materials_alike_in_what_the_albedo_bake_reads_share_a_table() {
        // The sphere grid: 4 rows (plastic, gold, copper blend, anisotropic aluminium),
        // each at 6 roughnesses; the table spans roughness, so one table per row.
        let scene = combustion_scene::builtin_scene("spheres").expect("built in");
        let materials = material_table(&scene, &[]);
        let (computed, table_of_material) = albedo_tables(&materials);
        assert_eq!(computed.len(), 4);
        let rows: Vec<u32> = (0..24).map(|m| m / 6).collect();
        assert_eq!(table_of_material, rows);
        for (material, &table) in materials.iter().zip(&table_of_material) {
            let computed = &computed[table as usize];
            assert_eq!(albedo_table_key(computed), albedo_table_key(material));
        }
    }

    #[test]
    fn each_bake_shader_declares_its_push_struct() {
        let compiler = ShaderCompiler::new(crate::shader_sources::sources(
            crate::passes::generated_headers(),
        ))
        .expect("shaderc");
        let shaders = [
            (
                "environment_radiance.comp",
                push_layout!(EnvironmentRadiancePush {
                    source,
                    size,
                    mode,
                    source_level,
                    samples_across,
                }),
            ),
            (
                "environment_prefilter.comp",
                push_layout!(EnvironmentPrefilterPush {
                    size,
                    samples,
                    radiance_size,
                    roughness,
                }),
            ),
            (
                "environment_irradiance.comp",
                push_layout!(EnvironmentIrradiancePush {
                    size,
                    source_level,
                    source_size,
                }),
            ),
            (
                "environment_albedo.comp",
                push_layout!(EnvironmentAlbedoPush { samples }),
            ),
            (
                "environment_code_albedo.comp",
                push_layout!(EnvironmentCodeAlbedoPush {
                    samples,
                    table,
                    outside_ior,
                    polarisation_weight,
                }),
            ),
        ];
        let sources = crate::shader_sources::sources(crate::passes::generated_headers());
        for (file, (name, size, members)) in shaders {
            let spirv = compiler
                .compile(file, ShaderStage::Compute, &[])
                .expect("compiles");
            let layout = crate::spirv::push_layout(&spirv)
                .unwrap_or_else(|| panic!("{file} declares no push constants"));
            let (block, names) = crate::spirv::glsl_push_members(sources.get(file).unwrap())
                .unwrap_or_else(|| panic!("{file} declares no push block"));
            assert_eq!(block, name, "{file}");
            assert_eq!(layout.size, size, "{file}");
            let glsl: Vec<_> = names.into_iter().zip(layout.offsets).collect();
            assert_eq!(glsl, members, "{file}");
        }
        // The analytic source inside the radiance push is environment.glsl's struct.
        assert_eq!(std::mem::size_of::<EnvironmentSource>(), 96);
    }

    /// The readers of push blocks find another pass's block (the tone map's), and none
    /// in a shader without push constants. (A nested struct with arrays is read above:
    /// the radiance push's source.)
    #[test]
    fn push_blocks_are_read_from_spirv_and_glsl() {
        let sources = crate::shader_sources::sources(crate::passes::generated_headers());
        let compiler = ShaderCompiler::new(sources.clone()).expect("shaderc");
        let spirv = compiler
            .compile("tonemap.frag", ShaderStage::Fragment, &[])
            .expect("compiles");
        let layout = crate::spirv::push_layout(&spirv).expect("tonemap pushes its exposure");
        assert_eq!(
            layout,
            crate::spirv::PushLayout {
                size: std::mem::size_of::<crate::gpu_types::TonemapPush>() as u32,
                offsets: vec![
                    std::mem::offset_of!(crate::gpu_types::TonemapPush, exposure) as u32,
                    std::mem::offset_of!(crate::gpu_types::TonemapPush, curve) as u32,
                    std::mem::offset_of!(crate::gpu_types::TonemapPush, metered) as u32,
                ],
            }
        );
        assert_eq!(
            crate::spirv::glsl_push_members(sources.get("tonemap.frag").unwrap()),
            Some((
                "TonemapPush".to_owned(),
                vec![
                    "exposure".to_owned(),
                    "curve".to_owned(),
                    "metered".to_owned()
                ]
            ))
        );
        let no_push = compiler
            .compile("fullscreen.vert", ShaderStage::Vertex, &[])
            .expect("compiles");
        assert_eq!(crate::spirv::push_layout(&no_push), None);
        assert_eq!(
            crate::spirv::glsl_push_members(sources.get("fullscreen.vert").unwrap()),
            None
        );
    }
}
