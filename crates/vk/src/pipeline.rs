use std::sync::Arc;

use ash::vk;

use crate::device::Device;
use crate::error::{VkError, VkResultExt};
use crate::shader::ShaderModule;

/// A descriptor set layout, destroyed when dropped.
pub struct DescriptorSetLayout {
    device: Arc<Device>,
    raw: vk::DescriptorSetLayout,
}

impl DescriptorSetLayout {
    /// A layout of `bindings`: (binding number, descriptor type, descriptor count,
    /// shader stages that use it).
    ///
    /// # Errors
    /// [`VkError`] when the Vulkan call fails (out of memory, mostly).
    pub fn new(
        device: &Arc<Device>,
        bindings: &[(u32, vk::DescriptorType, u32, vk::ShaderStageFlags)],
    ) -> Result<Self, VkError> {
        let bindings: Vec<_> = bindings
            .iter()
            .map(|&(binding, ty, count, stages)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(binding)
                    .descriptor_type(ty)
                    .descriptor_count(count)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info.
        let raw = unsafe { device.raw().create_descriptor_set_layout(&info, None) }
            .what("vkCreateDescriptorSetLayout")?;
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
    /// The Vulkan layout, valid while `self` lives.
    pub fn raw(&self) -> vk::DescriptorSetLayout {
        self.raw
    }
}

impl Drop for DescriptorSetLayout {
    fn drop(&mut self) {
        unsafe {
            self.device
                .raw()
                .destroy_descriptor_set_layout(self.raw, None)
        };
    }
}

/// A `VkSampler`, destroyed when dropped.
pub struct Sampler {
    device: Arc<Device>,
    raw: vk::Sampler,
}

impl Sampler {
    /// A sampler as `info` describes it.
    ///
    /// # Errors
    /// [`VkError`] when the Vulkan call fails (out of memory, mostly).
    pub fn new(device: &Arc<Device>, info: &vk::SamplerCreateInfo<'_>) -> Result<Self, VkError> {
        // SAFETY: valid create info.
        let raw = unsafe { device.raw().create_sampler(info, None) }.what("vkCreateSampler")?;
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
    /// The Vulkan sampler, valid while `self` lives.
    pub fn raw(&self) -> vk::Sampler {
        self.raw
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        unsafe { self.device.raw().destroy_sampler(self.raw, None) };
    }
}

/// A pipeline layout, destroyed when dropped.
pub struct PipelineLayout {
    device: Arc<Device>,
    raw: vk::PipelineLayout,
}

impl PipelineLayout {
    /// A layout of `set_layouts` (set 0, 1, ... in order) and `push_constants` (offsets
    /// and sizes in bytes).
    ///
    /// # Errors
    /// [`VkError`] when the Vulkan call fails (out of memory, mostly).
    pub fn new(
        device: &Arc<Device>,
        set_layouts: &[&DescriptorSetLayout],
        push_constants: &[vk::PushConstantRange],
    ) -> Result<Self, VkError> {
        let sets: Vec<_> = set_layouts.iter().map(|l| l.raw()).collect();
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&sets)
            .push_constant_ranges(push_constants);
        // SAFETY: valid create info.
        let raw = unsafe { device.raw().create_pipeline_layout(&info, None) }
            .what("vkCreatePipelineLayout")?;
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
    /// The Vulkan pipeline layout, valid while `self` lives.
    pub fn raw(&self) -> vk::PipelineLayout {
        self.raw
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        unsafe { self.device.raw().destroy_pipeline_layout(self.raw, None) };
    }
}

/// What a graphics pipeline for dynamic rendering needs. Viewport, scissor and cull mode
/// are dynamic state (cull mode is core in Vulkan 1.3), set when recording.
///
/// Filled, counter-clockwise front faces, lines 1 pixel wide, one sample per pixel.
pub struct GraphicsPipelineDesc<'a> {
    /// What the vertices make: `TRIANGLE_LIST` for surfaces, `LINE_LIST` or `POINT_LIST`
    /// (whose vertex shader must write `gl_PointSize`).
    pub topology: vk::PrimitiveTopology,
    /// The vertex shader (entry point `main`).
    pub vertex: &'a ShaderModule,
    /// The fragment shader (entry point `main`).
    pub fragment: &'a ShaderModule,
    /// The layout the pipeline's descriptor sets and push constants follow.
    pub layout: &'a PipelineLayout,
    /// Vertex buffer bindings (stride in bytes, input rate); empty for shaders that make
    /// their own vertices (e.g. a full-screen triangle from `gl_VertexIndex`).
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    /// Vertex attributes (location, binding, format, byte offset).
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    /// The formats of the colour attachments rendered to, in attachment order.
    pub color_formats: &'a [vk::Format],
    /// Depth attachment format; the depth test is on when set.
    pub depth_format: Option<vk::Format>,
    /// Whether fragments that pass the depth test write their depth (with a depth
    /// attachment; `false` tests against a depth image read-only).
    pub depth_write: bool,
    /// The depth test's comparison of the fragment's depth with the attachment's
    /// (`LESS` for surfaces; with a depth attachment).
    pub depth_compare: vk::CompareOp,
    /// How the fragment's colour meets the attachment's contents.
    pub blend: ColorBlend,
    /// Where compiled pipelines are cached (saved and loaded by the host).
    pub cache: Option<&'a PipelineCache>,
}

/// How a graphics pipeline's fragment colour meets its attachment's contents (α: the
/// fragment's alpha).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorBlend {
    /// The fragment replaces what was there.
    Replace,
    /// `src·α + dst·(1 − α)` for colour; the attachment's alpha kept (overlays).
    OverKeepingAlpha,
    /// Straight-alpha "over": `src·α + dst·(1 − α)` for colour and `α + dst_α·(1 − α)`
    /// for alpha (a surface of coverage α in front of what was there).
    Over,
}

/// A graphics or compute pipeline, destroyed when dropped (once no pending submission
/// uses it).
pub struct Pipeline {
    device: Arc<Device>,
    raw: vk::Pipeline,
}

impl Pipeline {
    /// A graphics pipeline for dynamic rendering as `desc` describes it.
    ///
    /// # Errors
    /// [`VkError`] when `vkCreateGraphicsPipelines` fails.
    pub fn graphics(
        device: &Arc<Device>,
        desc: &GraphicsPipelineDesc<'_>,
    ) -> Result<Self, VkError> {
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(desc.vertex.raw())
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(desc.fragment.raw())
                .name(c"main"),
        ];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(desc.vertex_bindings)
            .vertex_attribute_descriptions(desc.vertex_attributes);
        let input_assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(desc.depth_format.is_some())
            .depth_write_enable(desc.depth_format.is_some() && desc.depth_write)
            .depth_compare_op(desc.depth_compare);
        let blend_attachments: Vec<_> = desc
            .color_formats
            .iter()
            .map(|_| {
                let state = vk::PipelineColorBlendAttachmentState::default()
                    .color_write_mask(vk::ColorComponentFlags::RGBA);
                let over = |alpha_source, alpha_destination| {
                    state
                        .blend_enable(true)
                        .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
                        .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                        .color_blend_op(vk::BlendOp::ADD)
                        .src_alpha_blend_factor(alpha_source)
                        .dst_alpha_blend_factor(alpha_destination)
                        .alpha_blend_op(vk::BlendOp::ADD)
                };
                match desc.blend {
                    ColorBlend::Replace => state,
                    ColorBlend::OverKeepingAlpha => {
                        over(vk::BlendFactor::ZERO, vk::BlendFactor::ONE)
                    }
                    ColorBlend::Over => {
                        over(vk::BlendFactor::ONE, vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                    }
                }
            })
            .collect();
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [
            vk::DynamicState::VIEWPORT,
            vk::DynamicState::SCISSOR,
            vk::DynamicState::CULL_MODE,
        ];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(desc.color_formats)
            .depth_attachment_format(desc.depth_format.unwrap_or(vk::Format::UNDEFINED));
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(desc.layout.raw())
            .push_next(&mut rendering);
        // SAFETY: everything `info` points to lives until the call returns.
        let raw = unsafe {
            device.raw().create_graphics_pipelines(
                PipelineCache::raw_or_null(desc.cache),
                &[info],
                None,
            )
        }
        .map_err(|(_, result)| VkError::from_result("vkCreateGraphicsPipelines", result))?[0];
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
    /// A compute pipeline from `module` (entry point `main`), through `cache` if given.
    ///
    /// # Errors
    /// [`VkError`] when `vkCreateComputePipelines` fails.
    pub fn compute(
        device: &Arc<Device>,
        module: &ShaderModule,
        layout: &PipelineLayout,
        cache: Option<&PipelineCache>,
    ) -> Result<Self, VkError> {
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.raw())
            .name(c"main");
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.raw());
        // SAFETY: everything `info` points to lives until the call returns.
        let raw = unsafe {
            device
                .raw()
                .create_compute_pipelines(PipelineCache::raw_or_null(cache), &[info], None)
        }
        .map_err(|(_, result)| VkError::from_result("vkCreateComputePipelines", result))?[0];
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }

    /// The Vulkan pipeline, valid while `self` lives.
    pub fn raw(&self) -> vk::Pipeline {
        self.raw
    }
}

/// A `VkPipelineCache`: pipelines built through it are found again on the next build of
/// the same state, and its contents can be saved and given back on the next run.
pub struct PipelineCache {
    device: Arc<Device>,
    raw: vk::PipelineCache,
}

impl PipelineCache {
    /// A cache primed with `initial` (what [`PipelineCache::data`] returned on an earlier
    /// run; empty for none). Data from another driver or device is ignored by Vulkan,
    /// which checks the header.
    ///
    /// # Errors
    /// [`VkError`] when the Vulkan call fails (out of memory, mostly).
    pub fn new(device: &Arc<Device>, initial: &[u8]) -> Result<Self, VkError> {
        let info = vk::PipelineCacheCreateInfo::default().initial_data(initial);
        // SAFETY: valid create info; the implementation validates the data's header.
        let raw = unsafe { device.raw().create_pipeline_cache(&info, None) }
            .what("vkCreatePipelineCache")?;
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }

    /// The cache's contents, to save and pass to [`PipelineCache::new`] next time.
    ///
    /// # Errors
    /// [`VkError`] when `vkGetPipelineCacheData` fails.
    pub fn data(&self) -> Result<Vec<u8>, VkError> {
        // SAFETY: valid cache.
        unsafe { self.device.raw().get_pipeline_cache_data(self.raw) }
            .what("vkGetPipelineCacheData")
    }

    /// The Vulkan pipeline cache, valid while `self` lives.
    pub fn raw(&self) -> vk::PipelineCache {
        self.raw
    }

    fn raw_or_null(cache: Option<&PipelineCache>) -> vk::PipelineCache {
        cache.map_or(vk::PipelineCache::null(), |c| c.raw)
    }
}

impl Drop for PipelineCache {
    fn drop(&mut self) {
        unsafe { self.device.raw().destroy_pipeline_cache(self.raw, None) };
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        unsafe { self.device.raw().destroy_pipeline(self.raw, None) };
    }
}

/// A descriptor pool from which sets are allocated once; destroyed (with its sets) when dropped.
pub struct DescriptorPool {
    device: Arc<Device>,
    raw: vk::DescriptorPool,
}

impl DescriptorPool {
    /// A pool for at most `max_sets` sets holding, in all, at most the descriptors
    /// `sizes` lists (per type). Sets are not freed one by one.
    ///
    /// # Errors
    /// [`VkError`] when the Vulkan call fails (out of memory, mostly).
    pub fn new(
        device: &Arc<Device>,
        max_sets: u32,
        sizes: &[vk::DescriptorPoolSize],
    ) -> Result<Self, VkError> {
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(max_sets)
            .pool_sizes(sizes);
        let raw = unsafe { device.raw().create_descriptor_pool(&info, None) }
            .what("vkCreateDescriptorPool")?;
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }

    /// Allocates one set of `layout`; it lives as long as the pool. Write its
    /// descriptors with `vkUpdateDescriptorSets` before use.
    ///
    /// # Errors
    /// [`VkError`] when the pool is exhausted (`VK_ERROR_OUT_OF_POOL_MEMORY`) or the call
    /// fails otherwise.
    pub fn allocate(&self, layout: &DescriptorSetLayout) -> Result<vk::DescriptorSet, VkError> {
        let layouts = [layout.raw()];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.raw)
            .set_layouts(&layouts);
        let sets = unsafe { self.device.raw().allocate_descriptor_sets(&info) }
            .what("vkAllocateDescriptorSets")?;
        Ok(sets[0])
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        unsafe { self.device.raw().destroy_descriptor_pool(self.raw, None) };
    }
}
