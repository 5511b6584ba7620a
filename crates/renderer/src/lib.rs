//! The deferred renderer of Combustion.
//!
//! A frame (`Renderer::render`):
//! 1. **G-buffer pass** ([`gbuffer`]): rasterise every object into base colour +
//!    metalness, normal + roughness + anisotropy, material index + anisotropy direction,
//!    and depth.
//! 2. **Lighting pass** (`lighting.frag`): full-screen; per pixel, decode the G-buffer,
//!    reconstruct the position from depth, evaluate the BRDF (`brdf.glsl`) for every
//!    light, write HDR radiance.
//! 3. **Tonemap pass** (`tonemap.frag`): exposure and `1 − e^(−x)` into an sRGB 8-bit image.
//! 4. Optional readback of the HDR and display images (and the G-buffer, for parity tests).
//!
//! GPU timestamps bracket each pass; [`Frame::timings`] reports them.

pub mod gbuffer;
pub mod gpu_types;

mod fullscreen;
mod scene_upload;
mod shader_sources;
mod textures;

use std::collections::HashMap;
use std::sync::Arc;

use combustion_scene::{Scene, SceneError};
use combustion_vk::{
    vk, Buffer, DescriptorPool, DescriptorSetLayout, Device, Image, ImageDesc, OneShot,
    ShaderCompiler, TimestampQueries, VkError,
};

use fullscreen::FullscreenPass;
use gbuffer::{GBufferPass, GBufferReadback, GBufferTargets, GBufferTexel};
use gpu_types::{LightingPush, TonemapPush};
pub use scene_upload::GpuScene;

/// The shader features a scene needs. Each distinct variant gets its own G-buffer and
/// lighting pipelines (compile-time `#define`s), so a scene does not pay for features it
/// lacks; variants are built on first use and kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ShaderVariant {
    /// An emissive target in the G-buffer, added to the lit radiance.
    pub emissive: bool,
    /// Schlick's approximation instead of the full Fresnel equations
    /// ([`FresnelModel::Schlick`]; a renderer setting, not a scene feature).
    pub schlick: bool,
}

impl ShaderVariant {
    /// The `#define`s of this variant.
    pub(crate) fn defines(&self) -> Vec<(&'static str, Option<&'static str>)> {
        let mut defines = Vec::new();
        if self.emissive {
            defines.push(("EMISSIVE", None));
        }
        if self.schlick {
            defines.push(("FRESNEL_SCHLICK", None));
        }
        defines
    }
}

/// Why rendering failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Vulkan(#[from] VkError),
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error("image size {width}x{height} is not allowed: each side must be between 1 and {max} on this device")]
    InvalidSize { width: u32, height: u32, max: u32 },
    #[error("exposure {0} must be a positive finite number")]
    InvalidExposure(f32),
    #[error("scene too large: {0}")]
    TooLarge(String),
}

/// Storage of the HDR (lit) image.
///
/// Measured on lavapipe at 1280×720 (builtin:spheres, median of 30 frames): RGBA32F costs
/// ≈ 0.5 ms more in the lighting pass and ≈ 0.9 ms more in the tonemap pass than RGBA16F
/// (≈ 1.5 % of the frame), while RGBA16F's rounding (up to 2⁻¹² relative) is larger than
/// the whole shading error the parity tests measure (mean ≈ 4e-6). Hence RGBA32F by default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HdrFormat {
    /// RGBA16F: half the bandwidth; ≈ 3 significant digits (relative step 2⁻¹¹).
    Rgba16Float,
    /// RGBA32F: the radiance as the lighting pass computed it.
    #[default]
    Rgba32Float,
}

impl HdrFormat {
    fn vk(self) -> vk::Format {
        match self {
            Self::Rgba16Float => vk::Format::R16G16B16A16_SFLOAT,
            Self::Rgba32Float => vk::Format::R32G32B32A32_SFLOAT,
        }
    }
    fn bytes_per_pixel(self) -> u64 {
        match self {
            Self::Rgba16Float => 8,
            Self::Rgba32Float => 16,
        }
    }
}

/// What a frame copies back to the CPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Readback {
    /// The HDR radiance and the tonemapped sRGB image.
    pub images: bool,
    /// The G-buffer and depth (for parity checks).
    pub gbuffer: bool,
}

/// Per-pass GPU times of one frame, from timestamp queries, in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimings {
    pub gbuffer_ms: f64,
    pub lighting_ms: f64,
    pub tonemap_ms: f64,
    pub total_ms: f64,
}

/// A rendered frame.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Linear HDR radiance, RGBA, row-major from the top-left (empty without readback).
    pub hdr: Vec<[f32; 4]>,
    /// Tonemapped, sRGB-encoded RGBA8 (empty without readback).
    pub ldr: Vec<[u8; 4]>,
    pub gbuffer: Option<GBufferReadback>,
    pub timings: PassTimings,
}

/// Settings of the renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RendererSettings {
    pub hdr_format: HdrFormat,
    /// Multiplies radiance before the tone curve.
    pub exposure: f32,
    pub fresnel: FresnelModel,
}

/// Which Fresnel term the lighting pass evaluates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FresnelModel {
    /// The full dielectric and conductor Fresnel equations with the outside medium's IOR,
    /// polarisation and total internal reflection (the reference; default).
    #[default]
    Full,
    /// Schlick's curve through the exact normal-incidence reflectance: cheaper, no total
    /// internal reflection. Its speed and error are measured and reported (README,
    /// "Performance and accuracy"); it exists for comparison, not as a default.
    Schlick,
}

impl Default for RendererSettings {
    fn default() -> Self {
        Self {
            hdr_format: HdrFormat::default(),
            exposure: 1.0,
            fresnel: FresnelModel::default(),
        }
    }
}

/// CPU mirror of `tonemap_exponential` (tonemap.glsl): the display value before sRGB encoding.
pub fn tonemap_exponential(x: f64) -> f64 {
    1.0 - (-x.max(0.0)).exp()
}

/// The sRGB encoding (IEC 61966-2-1) the tonemap pass applies (`srgb_encode`).
pub fn linear_to_srgb(linear: f64) -> f64 {
    if linear <= 0.0031308 {
        linear * 12.92
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// The images of one frame size, their readback buffers and descriptor sets.
struct FrameTargets {
    variant: ShaderVariant,
    gbuffer: GBufferTargets,
    hdr: Image,
    ldr: Image,
    hdr_readback: Buffer,
    ldr_readback: Buffer,
    gbuffer_readback: [Buffer; 4],
}

impl FrameTargets {
    fn new(
        device: &Arc<Device>,
        width: u32,
        height: u32,
        hdr_format: HdrFormat,
        variant: ShaderVariant,
    ) -> Result<Self, RenderError> {
        let pixels = u64::from(width) * u64::from(height);
        let readback = |name: &str, bytes_per_pixel: u64| {
            Buffer::new(
                device,
                name,
                pixels * bytes_per_pixel,
                vk::BufferUsageFlags::TRANSFER_DST,
                combustion_vk::gpu_allocator::MemoryLocation::GpuToCpu,
            )
        };
        let output_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let output = |name, format| {
            Image::new(
                device,
                &ImageDesc {
                    name,
                    format,
                    width,
                    height,
                    usage: output_usage,
                    mip_levels: 1,
                },
            )
        };
        Ok(Self {
            variant,
            gbuffer: GBufferTargets::new(device, width, height, variant)?,
            hdr: output("hdr radiance", hdr_format.vk())?,
            ldr: output("display (sRGB-encoded)", vk::Format::R8G8B8A8_UNORM)?,
            hdr_readback: readback("hdr readback", hdr_format.bytes_per_pixel())?,
            ldr_readback: readback("display readback", 4)?,
            gbuffer_readback: [
                readback("gbuffer readback 0", 4)?,
                readback("gbuffer readback 1", 8)?,
                readback("gbuffer readback 2", 4)?,
                readback("depth readback", 4)?,
            ],
        })
    }
}

pub(crate) fn set_viewport_and_scissor(
    raw: &combustion_vk::ash::Device,
    cmd: vk::CommandBuffer,
    extent: vk::Extent2D,
) {
    // SAFETY: recording state is the caller's responsibility.
    unsafe {
        raw.cmd_set_viewport(
            cmd,
            0,
            &[vk::Viewport {
                x: 0.0,
                y: 0.0,
                width: extent.width as f32,
                height: extent.height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            }],
        );
        raw.cmd_set_scissor(
            cmd,
            0,
            &[vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent,
            }],
        );
    }
}

/// Timestamp slots: start, after G-buffer, after lighting, after tonemap.
const TIMESTAMPS: u32 = 4;

/// The G-buffer and lighting passes of one [`ShaderVariant`], with their descriptor sets.
struct VariantPasses {
    gbuffer_set: vk::DescriptorSet,
    lighting_set: vk::DescriptorSet,
    /// Owns the two descriptor sets above.
    _descriptor_pool: DescriptorPool,
    gbuffer: GBufferPass,
    lighting: FullscreenPass,
}

impl VariantPasses {
    fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        material_set_layout: &DescriptorSetLayout,
        variant: ShaderVariant,
        hdr_format: HdrFormat,
    ) -> Result<Self, RenderError> {
        let gbuffer = GBufferPass::new(device, compiler, material_set_layout, variant)?;
        let sampled = vk::DescriptorType::SAMPLED_IMAGE;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let mut bindings = vec![
            (0, sampled),
            (1, sampled),
            (2, sampled),
            (3, sampled),
            (4, storage),
            (5, storage),
            (6, storage),
        ];
        if variant.emissive {
            bindings.push((7, sampled));
        }
        let lighting = FullscreenPass::new(
            device,
            compiler,
            "lighting.frag",
            &variant.defines(),
            &bindings,
            std::mem::size_of::<LightingPush>() as u32,
            hdr_format.vk(),
        )?;
        let pool = DescriptorPool::new(
            device,
            2,
            &[
                vk::DescriptorPoolSize {
                    ty: sampled,
                    descriptor_count: 5,
                },
                vk::DescriptorPoolSize {
                    ty: storage,
                    descriptor_count: 5,
                },
            ],
        )?;
        Ok(Self {
            gbuffer_set: pool.allocate(&gbuffer.set_layout)?,
            lighting_set: pool.allocate(&lighting.set_layout)?,
            _descriptor_pool: pool,
            gbuffer,
            lighting,
        })
    }
}

/// The deferred renderer. One per device; renders [`GpuScene`]s at any size.
pub struct Renderer {
    // Field order is drop order: everything below holds the device alive.
    targets: Option<FrameTargets>,
    variants: HashMap<ShaderVariant, VariantPasses>,
    compiler: ShaderCompiler,
    /// Set 1 of the G-buffer pass: one material's textures.
    material_set_layout: DescriptorSetLayout,
    tonemap_set: vk::DescriptorSet,
    /// Owns the tonemap descriptor set.
    _tonemap_pool: DescriptorPool,
    tonemap_pass: FullscreenPass,
    commands: OneShot,
    timestamps: Option<TimestampQueries>,
    settings: RendererSettings,
    device: Arc<Device>,
}

impl Renderer {
    /// Compiles the shaders and builds the pipelines.
    pub fn new(device: Arc<Device>, settings: RendererSettings) -> Result<Self, RenderError> {
        if !(settings.exposure.is_finite() && settings.exposure > 0.0) {
            return Err(RenderError::InvalidExposure(settings.exposure));
        }
        let compiler = ShaderCompiler::new(shader_sources::sources())?;
        let sampled = vk::DescriptorType::SAMPLED_IMAGE;
        let tonemap_pass = FullscreenPass::new(
            &device,
            &compiler,
            "tonemap.frag",
            &[],
            &[(0, sampled)],
            std::mem::size_of::<TonemapPush>() as u32,
            vk::Format::R8G8B8A8_UNORM,
        )?;
        let tonemap_pool = DescriptorPool::new(
            &device,
            1,
            &[vk::DescriptorPoolSize {
                ty: sampled,
                descriptor_count: 1,
            }],
        )?;
        let tonemap_set = tonemap_pool.allocate(&tonemap_pass.set_layout)?;
        let material_set_layout = textures::material_set_layout(&device)?;
        // The plain variant is built now, so shader errors surface at construction.
        let mut variants = HashMap::new();
        let plain = ShaderVariant {
            schlick: settings.fresnel == FresnelModel::Schlick,
            ..ShaderVariant::default()
        };
        variants.insert(
            plain,
            VariantPasses::new(
                &device,
                &compiler,
                &material_set_layout,
                plain,
                settings.hdr_format,
            )?,
        );
        let timestamps = match TimestampQueries::new(&device, TIMESTAMPS) {
            Ok(t) => Some(t),
            Err(VkError::Unsupported(why)) => {
                log::warn!("pass timings unavailable: {why}");
                None
            }
            Err(e) => return Err(e.into()),
        };
        Ok(Self {
            targets: None,
            variants,
            compiler,
            material_set_layout,
            tonemap_set,
            _tonemap_pool: tonemap_pool,
            tonemap_pass,
            commands: OneShot::new(&device)?,
            timestamps,
            settings,
            device,
        })
    }

    pub fn device(&self) -> &Arc<Device> {
        &self.device
    }

    pub fn settings(&self) -> RendererSettings {
        self.settings
    }

    /// Validates and uploads a scene.
    pub fn upload(&self, scene: &Scene) -> Result<GpuScene, RenderError> {
        GpuScene::new(&self.device, scene, &self.material_set_layout)
    }

    fn ensure_targets(
        &mut self,
        width: u32,
        height: u32,
        variant: ShaderVariant,
    ) -> Result<(), RenderError> {
        let max = self.device.max_image_dimension_2d();
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::InvalidSize { width, height, max });
        }
        let fits = self.targets.as_ref().is_some_and(|t| {
            t.ldr.extent() == vk::Extent2D { width, height } && t.variant == variant
        });
        if !fits {
            self.targets = None; // free the old targets first
            self.targets = Some(FrameTargets::new(
                &self.device,
                width,
                height,
                self.settings.hdr_format,
                variant,
            )?);
        }
        if !self.variants.contains_key(&variant) {
            let passes = VariantPasses::new(
                &self.device,
                &self.compiler,
                &self.material_set_layout,
                variant,
                self.settings.hdr_format,
            )?;
            self.variants.insert(variant, passes);
        }
        Ok(())
    }

    fn write_descriptors(&self, passes: &VariantPasses, targets: &FrameTargets, scene: &GpuScene) {
        let image_info = |image: &Image, layout| {
            [vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: image.view(),
                image_layout: layout,
            }]
        };
        let buffer_info = |buffer: &Buffer| {
            [vk::DescriptorBufferInfo {
                buffer: buffer.raw(),
                offset: 0,
                range: vk::WHOLE_SIZE,
            }]
        };
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let depth_read = vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL;
        let g = &targets.gbuffer;
        let lighting = passes.lighting_set;
        let mut images = vec![
            (lighting, 0, image_info(&g.base_color_metalness, read)),
            (
                lighting,
                1,
                image_info(&g.normal_roughness_anisotropy, read),
            ),
            (lighting, 2, image_info(&g.material_direction, read)),
            (lighting, 3, image_info(&g.depth, depth_read)),
            (self.tonemap_set, 0, image_info(&targets.hdr, read)),
        ];
        if let Some(emissive) = &g.emissive {
            images.push((lighting, 7, image_info(emissive, read)));
        }
        let buffers = [
            (passes.gbuffer_set, 0, buffer_info(&scene.objects)),
            (passes.gbuffer_set, 1, buffer_info(&scene.materials)),
            (lighting, 4, buffer_info(&scene.materials)),
            (lighting, 5, buffer_info(&scene.lights)),
            (lighting, 6, buffer_info(&scene.conductor_table)),
        ];
        let mut writes: Vec<vk::WriteDescriptorSet<'_>> = images
            .iter()
            .map(|(set, binding, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(*set)
                    .dst_binding(*binding)
                    .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
                    .image_info(info)
            })
            .collect();
        writes.extend(buffers.iter().map(|(set, binding, info)| {
            vk::WriteDescriptorSet::default()
                .dst_set(*set)
                .dst_binding(*binding)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .buffer_info(info)
        }));
        // SAFETY: the previous frame was waited for, so no set is in use.
        unsafe { self.device.raw().update_descriptor_sets(&writes, &[]) };
    }

    /// Renders `scene` at `width`×`height` and waits for the GPU; copies back what
    /// `readback` asks for.
    pub fn render(
        &mut self,
        scene: &GpuScene,
        width: u32,
        height: u32,
        readback: Readback,
    ) -> Result<Frame, RenderError> {
        let variant = ShaderVariant {
            schlick: self.settings.fresnel == FresnelModel::Schlick,
            ..scene.variant
        };
        self.ensure_targets(width, height, variant)?;
        let targets = self.targets.as_ref().expect("ensured");
        let passes = &self.variants[&variant];
        self.write_descriptors(passes, targets, scene);
        let camera = &scene.scene.camera;
        let view_projection = camera.view_projection(width as f32 / height as f32);
        let lighting_push = LightingPush::new(view_projection, camera.position, scene.light_count);
        let tonemap_push = TonemapPush {
            exposure: self.settings.exposure,
        };

        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        let device = &*self.device;
        let raw = device.raw();
        let cmd = self.commands.begin()?;
        let stamp = |index: u32| {
            if let Some(t) = &self.timestamps {
                t.record(cmd, S::ALL_COMMANDS, index);
            }
        };
        if let Some(t) = &self.timestamps {
            t.record_reset(cmd);
        }
        let barrier = |barriers: &[vk::ImageMemoryBarrier2<'_>]| {
            let info = vk::DependencyInfo::default().image_memory_barriers(barriers);
            // SAFETY: recording state.
            unsafe { raw.cmd_pipeline_barrier2(cmd, &info) };
        };
        stamp(0);
        let g = &targets.gbuffer;
        let undefined = (S::NONE, A::NONE, L::UNDEFINED);
        let color_out = (
            S::COLOR_ATTACHMENT_OUTPUT,
            A::COLOR_ATTACHMENT_WRITE,
            L::COLOR_ATTACHMENT_OPTIMAL,
        );
        let depth_stages = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
        let depth_out = (
            depth_stages,
            A::DEPTH_STENCIL_ATTACHMENT_WRITE | A::DEPTH_STENCIL_ATTACHMENT_READ,
            L::DEPTH_ATTACHMENT_OPTIMAL,
        );
        let sampled = (
            S::FRAGMENT_SHADER,
            A::SHADER_SAMPLED_READ,
            L::SHADER_READ_ONLY_OPTIMAL,
        );
        let depth_sampled = (
            S::FRAGMENT_SHADER,
            A::SHADER_SAMPLED_READ,
            L::DEPTH_READ_ONLY_OPTIMAL,
        );
        let mut to_attachment: Vec<_> = g
            .attachments()
            .into_iter()
            .map(|image| image.barrier(undefined, color_out))
            .collect();
        to_attachment.push(g.depth.barrier(undefined, depth_out));
        barrier(&to_attachment);
        passes
            .gbuffer
            .record(device, cmd, g, scene, passes.gbuffer_set, view_projection);
        stamp(1);
        let mut to_sampled: Vec<_> = g
            .attachments()
            .into_iter()
            .map(|image| image.barrier(color_out, sampled))
            .collect();
        to_sampled.push(g.depth.barrier(depth_out, depth_sampled));
        to_sampled.push(targets.hdr.barrier(undefined, color_out));
        barrier(&to_sampled);
        passes.lighting.record(
            device,
            cmd,
            &targets.hdr,
            passes.lighting_set,
            bytemuck::bytes_of(&lighting_push),
        );
        stamp(2);
        barrier(&[
            targets.hdr.barrier(color_out, sampled),
            targets.ldr.barrier(undefined, color_out),
        ]);
        self.tonemap_pass.record(
            device,
            cmd,
            &targets.ldr,
            self.tonemap_set,
            bytemuck::bytes_of(&tonemap_push),
        );
        stamp(3);
        let transfer_src = (S::COPY, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL);
        let mut copies: Vec<(&Image, &Buffer, (S, A, L))> = Vec::new();
        if readback.images {
            copies.push((&targets.hdr, &targets.hdr_readback, sampled));
            copies.push((&targets.ldr, &targets.ldr_readback, color_out));
        }
        if readback.gbuffer {
            for (image, buffer) in g.colors().into_iter().zip(&targets.gbuffer_readback) {
                copies.push((image, buffer, sampled));
            }
            copies.push((&g.depth, &targets.gbuffer_readback[3], depth_sampled));
        }
        if !copies.is_empty() {
            let to_src: Vec<_> = copies
                .iter()
                .map(|(image, _, from)| image.barrier(*from, transfer_src))
                .collect();
            barrier(&to_src);
            for (image, buffer, _) in &copies {
                image.record_copy_to_buffer(cmd, buffer);
            }
            let to_host = [vk::MemoryBarrier2::default()
                .src_stage_mask(S::COPY)
                .src_access_mask(A::TRANSFER_WRITE)
                .dst_stage_mask(S::HOST)
                .dst_access_mask(A::HOST_READ)];
            // SAFETY: recording state.
            unsafe {
                raw.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().memory_barriers(&to_host),
                )
            };
        }
        self.commands.submit_and_wait()?;

        let timings = match &self.timestamps {
            Some(t) => {
                let ms = t.read_ms()?;
                PassTimings {
                    gbuffer_ms: ms[1] - ms[0],
                    lighting_ms: ms[2] - ms[1],
                    tonemap_ms: ms[3] - ms[2],
                    total_ms: ms[3] - ms[0],
                }
            }
            None => PassTimings::default(),
        };
        let mut frame = Frame {
            width,
            height,
            timings,
            ..Frame::default()
        };
        if readback.images {
            let bytes = targets.hdr_readback.mapped()?;
            frame.hdr = match self.settings.hdr_format {
                HdrFormat::Rgba32Float => bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(bytes),
                HdrFormat::Rgba16Float => bytemuck::pod_collect_to_vec::<u8, [u16; 4]>(bytes)
                    .into_iter()
                    .map(|p| p.map(f16_to_f32))
                    .collect(),
            };
            frame.ldr = bytemuck::pod_collect_to_vec(targets.ldr_readback.mapped()?);
        }
        if readback.gbuffer {
            let [b0, b1, b2, b3] = &targets.gbuffer_readback;
            let base: Vec<[u8; 4]> = bytemuck::pod_collect_to_vec(b0.mapped()?);
            let nra: Vec<[u16; 4]> = bytemuck::pod_collect_to_vec(b1.mapped()?);
            let md: Vec<[u16; 2]> = bytemuck::pod_collect_to_vec(b2.mapped()?);
            let depth: Vec<f32> = bytemuck::pod_collect_to_vec(b3.mapped()?);
            let texels = (0..base.len())
                .map(|i| GBufferTexel {
                    base_color_metalness: base[i],
                    normal_roughness_anisotropy: nra[i],
                    material_direction: md[i],
                    depth: depth[i],
                })
                .collect();
            frame.gbuffer = Some(GBufferReadback {
                width,
                height,
                texels,
            });
        }
        Ok(frame)
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // Everything this renderer submitted must be finished before its objects go.
        if let Err(e) = self.device.wait_idle() {
            log::error!("waiting for the device before teardown: {e}");
        }
    }
}

/// IEEE 754 binary16 → binary32 (exact).
pub fn f16_to_f32(bits: u16) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0f32 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let mantissa = f32::from(bits & 0x3ff);
    match exponent {
        0 => sign * mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        e => sign * (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f16_decoding_matches_known_values() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
        assert!(f16_to_f32(0x7c00).is_infinite());
        assert!(f16_to_f32(0x7e00).is_nan());
    }

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255 {
            let e = f64::from(i) / 255.0;
            let back = linear_to_srgb(gbuffer::srgb_to_linear(e));
            assert!((back - e).abs() < 1e-12, "{i}");
        }
    }
}
