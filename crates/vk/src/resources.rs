use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::device::Device;
use crate::error::{VkError, VkResultExt};

/// A buffer and its memory (gpu-allocator). Destroyed when dropped: drop it only once
/// the GPU has finished every submission that uses it.
pub struct Buffer {
    device: Arc<Device>,
    raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
}

impl Buffer {
    /// Creates a buffer of `size` bytes (at least 4: smaller sizes are rounded up) in
    /// `location` (`CpuToGpu` and `GpuToCpu` are mapped, so [`Buffer::write`] and
    /// [`Buffer::mapped`] work on them). `name` labels the allocation in the allocator's
    /// reports and in errors.
    ///
    /// # Errors
    /// [`VkError::OutOfMemory`] or [`VkError::Allocation`] when memory cannot be
    /// allocated; [`VkError`] when a Vulkan call fails. Nothing is left behind.
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Buffer, VkError> {
        let size = size.max(4);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let raw_device = device.raw();
        // SAFETY: valid create info; the buffer is destroyed on every error path below.
        let raw = unsafe { raw_device.create_buffer(&info, None) }.what("vkCreateBuffer")?;
        let requirements = unsafe { raw_device.get_buffer_memory_requirements(raw) };
        let allocation = device.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(source) => {
                unsafe { raw_device.destroy_buffer(raw, None) };
                return Err(VkError::allocation(name, source));
            }
        };
        let buffer = Buffer {
            device: device.clone(),
            raw,
            allocation: Some(allocation),
            size,
        };
        let allocation = buffer.allocation.as_ref().expect("set above");
        // SAFETY: memory and offset come from the allocator for this buffer's requirements.
        unsafe { raw_device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .what("vkBindBufferMemory")?;
        Ok(buffer)
    }

    /// Creates a host-visible buffer (`CpuToGpu`) holding `bytes`, e.g. a staging buffer
    /// for an upload. Host writes are visible to the device from the next submission on.
    ///
    /// # Errors
    /// As [`Buffer::new`].
    pub fn with_data(
        device: &Arc<Device>,
        name: &str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Buffer, VkError> {
        let mut buffer = Buffer::new(
            device,
            name,
            bytes.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
        )?;
        buffer.write(0, bytes)?;
        Ok(buffer)
    }

    /// The Vulkan buffer, valid while `self` lives.
    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }
    /// The buffer's size in bytes (as created: at least 4).
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Writes `bytes` into a mapped buffer at byte `offset`. The GPU must not be using
    /// the written range (no pending submission reads it).
    ///
    /// # Errors
    /// [`VkError::Unsupported`] when the buffer is not host-visible or the write would
    /// end past the buffer's end (nothing is written then).
    pub fn write(&mut self, offset: usize, bytes: &[u8]) -> Result<(), VkError> {
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| VkError::Unsupported("buffer memory is not host-visible".into()))?;
        let end = offset
            .checked_add(bytes.len())
            .filter(|&end| end <= slice.len())
            .ok_or_else(|| VkError::Unsupported("write past the end of a buffer".into()))?;
        slice[offset..end].copy_from_slice(bytes);
        Ok(())
    }

    /// The contents of a mapped buffer (e.g. a readback buffer after its copy completed
    /// and was made visible to the host), [`Buffer::size`] bytes.
    ///
    /// # Errors
    /// [`VkError::Unsupported`] when the buffer is not host-visible.
    pub fn mapped(&self) -> Result<&[u8], VkError> {
        let slice = self
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .ok_or_else(|| VkError::Unsupported("buffer memory is not host-visible".into()))?;
        Ok(&slice[..self.size as usize])
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: callers wait for the GPU to finish with a buffer before dropping it.
        unsafe { self.device.raw().destroy_buffer(self.raw, None) };
        if let Some(allocation) = self.allocation.take() {
            if let Err(e) = self.device.allocator().free(allocation) {
                log::error!("freeing buffer memory: {e}");
            }
        }
    }
}

/// Where an image stands for synchronisation: its layout, and the pipeline stages and
/// accesses of its last use (before a barrier) or next use (after it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageState {
    /// The pipeline stages of the use.
    pub stage: vk::PipelineStageFlags2,
    /// The memory accesses of the use.
    pub access: vk::AccessFlags2,
    /// The image layout the use needs.
    pub layout: vk::ImageLayout,
}

impl ImageState {
    /// Never used: contents undefined, nothing to wait for.
    pub const UNDEFINED: ImageState = ImageState::new(
        vk::PipelineStageFlags2::NONE,
        vk::AccessFlags2::NONE,
        vk::ImageLayout::UNDEFINED,
    );

    /// Written as a colour attachment (a render pass that clears or overwrites it).
    pub const COLOR_ATTACHMENT_WRITE: ImageState = ImageState::new(
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    );
    /// Drawn into on top of what is there (load op LOAD, blending): read and written.
    pub const COLOR_ATTACHMENT_READ_WRITE: ImageState = ImageState::new(
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::COLOR_ATTACHMENT_READ.as_raw()
                | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw(),
        ),
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    );
    /// Depth-tested and written by the host's own geometry.
    pub const DEPTH_ATTACHMENT_READ_WRITE: ImageState = ImageState::new(
        vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
        ),
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
        ),
        vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
    );
    /// Sampled by fragment shaders.
    pub const FRAGMENT_SAMPLED: ImageState = ImageState::new(
        vk::PipelineStageFlags2::FRAGMENT_SHADER,
        vk::AccessFlags2::SHADER_SAMPLED_READ,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    );
    /// Sampled by compute shaders.
    pub const COMPUTE_SAMPLED: ImageState = ImageState::new(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_SAMPLED_READ,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    );
    /// Copied from (`vkCmdCopyImage`, `vkCmdCopyImageToBuffer`).
    pub const COPY_SOURCE: ImageState = ImageState::new(
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    /// Copied or cleared into (`vkCmdCopy*`, `vkCmdClearColorImage`).
    pub const COPY_DESTINATION: ImageState = ImageState::new(
        vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::COPY.as_raw() | vk::PipelineStageFlags2::CLEAR.as_raw(),
        ),
        vk::AccessFlags2::TRANSFER_WRITE,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    );
    /// Blitted from (`vkCmdBlitImage`).
    pub const BLIT_SOURCE: ImageState = ImageState::new(
        vk::PipelineStageFlags2::BLIT,
        vk::AccessFlags2::TRANSFER_READ,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    /// Blitted or cleared into.
    pub const BLIT_DESTINATION: ImageState = ImageState::new(
        vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::BLIT.as_raw() | vk::PipelineStageFlags2::CLEAR.as_raw(),
        ),
        vk::AccessFlags2::TRANSFER_WRITE,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    );
    /// A swapchain image just acquired, its old contents not needed: the layout change
    /// names colour output, a stage the acquire semaphore's wait covers (submit the
    /// frame waiting for that semaphore at colour output or at every stage).
    pub const SWAPCHAIN_ACQUIRED: ImageState = ImageState::new(
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::NONE,
        vk::ImageLayout::UNDEFINED,
    );
    /// Handed to the presentation engine: no access; the present waits on a semaphore.
    pub const PRESENT: ImageState = ImageState::new(
        vk::PipelineStageFlags2::NONE,
        vk::AccessFlags2::NONE,
        vk::ImageLayout::PRESENT_SRC_KHR,
    );

    /// A state of `layout` after (or before) `access` at `stage`.
    pub const fn new(
        stage: vk::PipelineStageFlags2,
        access: vk::AccessFlags2,
        layout: vk::ImageLayout,
    ) -> Self {
        Self {
            stage,
            access,
            layout,
        }
    }

    /// Whether the access includes a write.
    pub fn writes(&self) -> bool {
        use vk::AccessFlags2 as A;
        self.access.intersects(
            A::SHADER_WRITE
                | A::SHADER_STORAGE_WRITE
                | A::COLOR_ATTACHMENT_WRITE
                | A::DEPTH_STENCIL_ATTACHMENT_WRITE
                | A::TRANSFER_WRITE
                | A::HOST_WRITE
                | A::MEMORY_WRITE,
        )
    }
}

/// The barrier that makes a copy's writes visible to the host (a readback after the
/// submission's wait).
pub fn copy_to_host_barrier() -> vk::MemoryBarrier2<'static> {
    vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COPY)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)
}

/// A barrier moving `range` of `image` from `from` to `to` (synchronization2).
pub fn image_barrier(
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    from: ImageState,
    to: ImageState,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(from.stage)
        .src_access_mask(from.access)
        .old_layout(from.layout)
        .dst_stage_mask(to.stage)
        .dst_access_mask(to.access)
        .new_layout(to.layout)
        .image(image)
        .subresource_range(range)
}

/// A buffer ↔ image copy of all of mip level 0 of layer 0 of a colour image of `extent`,
/// tightly packed (for images made elsewhere, such as a swapchain's; an [`Image`] has
/// [`Image::level0_copy_region`]).
pub fn color_level0_copy_region(extent: vk::Extent2D) -> vk::BufferImageCopy {
    packed_copy_region(
        vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        },
        extent,
    )
}

/// A buffer ↔ image copy of all of `subresource` (of size `extent`), tightly packed.
fn packed_copy_region(
    subresource: vk::ImageSubresourceLayers,
    extent: vk::Extent2D,
) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(subresource)
        .image_extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        })
}

/// How to create an [`Image`] (2D, one layer).
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc<'a> {
    /// A label for the allocator's reports and for errors.
    pub name: &'a str,
    /// The texel format; it decides the image's aspect (colour, depth, stencil).
    pub format: vk::Format,
    /// Width of mip level 0, in texels (1 to the device's maximum 2D dimension).
    pub width: u32,
    /// Height of mip level 0, in texels (1 to the device's maximum 2D dimension).
    pub height: u32,
    /// What the image is used for; uploads need `TRANSFER_DST`, and mip generation
    /// also `TRANSFER_SRC`.
    pub usage: vk::ImageUsageFlags,
    /// Mip levels (1 = none); see [`full_mip_chain`].
    pub mip_levels: u32,
    /// Array layers (1 for a plain image; 6 per cube for a cube map).
    pub layers: u32,
    /// A cube map (or an array of them): square, `layers` a multiple of 6, viewed as
    /// `samplerCube` (`CUBE` or `CUBE_ARRAY`).
    pub cube: bool,
}

impl<'a> ImageDesc<'a> {
    /// A plain 2D image of `width`×`height` texels: one mip level, one layer.
    pub fn new(
        name: &'a str,
        format: vk::Format,
        width: u32,
        height: u32,
        usage: vk::ImageUsageFlags,
    ) -> Self {
        Self {
            name,
            format,
            width,
            height,
            usage,
            mip_levels: 1,
            layers: 1,
            cube: false,
        }
    }

    /// With `levels` mip levels (1 to [`full_mip_chain`]; checked by [`Image::new`]).
    pub fn mips(self, levels: u32) -> Self {
        Self {
            mip_levels: levels,
            ..self
        }
    }

    /// With every mip level down to 1×1.
    pub fn full_mips(self) -> Self {
        self.mips(full_mip_chain(self.width, self.height))
    }

    /// An array of `layers` layers (at least 1; checked by [`Image::new`]).
    pub fn array(self, layers: u32) -> Self {
        Self { layers, ..self }
    }

    /// A cube map of `size`×`size` faces (6 layers, in the order +X, −X, +Y, −Y, +Z, −Z),
    /// one mip level; add levels with [`ImageDesc::mips`] or [`ImageDesc::full_mips`].
    pub fn cube(name: &'a str, format: vk::Format, size: u32, usage: vk::ImageUsageFlags) -> Self {
        Self {
            layers: 6,
            cube: true,
            ..Self::new(name, format, size, size, usage)
        }
    }

    /// The view type of a view over every layer.
    fn view_type(&self) -> vk::ImageViewType {
        match (self.cube, self.layers) {
            (true, 6) => vk::ImageViewType::CUBE,
            (true, _) => vk::ImageViewType::CUBE_ARRAY,
            (false, 1) => vk::ImageViewType::TYPE_2D,
            (false, _) => vk::ImageViewType::TYPE_2D_ARRAY,
        }
    }

    /// Why this description cannot be made, if it cannot.
    fn check(&self, max: u32) -> Result<(), String> {
        let name = self.name;
        if self.width == 0 || self.height == 0 || self.width > max || self.height > max {
            return Err(format!(
                "image {name} of {}x{} is outside the device's limits (1..={max} per side)",
                self.width, self.height
            ));
        }
        let full = full_mip_chain(self.width, self.height);
        if self.mip_levels == 0 || self.mip_levels > full {
            return Err(format!(
                "image {name} asks for {} mip levels; a {}x{} image has 1 to {full}",
                self.mip_levels, self.width, self.height
            ));
        }
        if self.layers == 0 {
            return Err(format!("image {name} has no layers"));
        }
        if self.cube && (self.width != self.height || self.layers % 6 != 0) {
            return Err(format!(
                "cube map {name} must be square with a multiple of 6 layers, not {}x{} with {}",
                self.width, self.height, self.layers
            ));
        }
        Ok(())
    }
}

/// The aspects of an image of `format`: depth, stencil or both for depth/stencil formats,
/// colour for every other.
fn format_aspect(format: vk::Format) -> vk::ImageAspectFlags {
    use vk::{Format as F, ImageAspectFlags as A};
    match format {
        F::D16_UNORM | F::X8_D24_UNORM_PACK32 | F::D32_SFLOAT => A::DEPTH,
        F::D16_UNORM_S8_UINT | F::D24_UNORM_S8_UINT | F::D32_SFLOAT_S8_UINT => {
            A::DEPTH | A::STENCIL
        }
        F::S8_UINT => A::STENCIL,
        _ => A::COLOR,
    }
}

/// The number of mip levels down to 1×1 for a `width`×`height` image (1 for a 1×1 or
/// empty image).
pub fn full_mip_chain(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// A 2D image (plain, array or cube map, with or without mips), its memory (device-local)
/// and a view over all of it. Destroyed when dropped: drop it only once the GPU has
/// finished every submission that uses it.
///
/// Created in `UNDEFINED` layout; the caller moves it between layouts with barriers
/// ([`Image::barrier`], [`image_barrier`] and [`ImageState`]).
pub struct Image {
    device: Arc<Device>,
    raw: vk::Image,
    view: vk::ImageView,
    allocation: Option<Allocation>,
    format: vk::Format,
    extent: vk::Extent2D,
    aspect: vk::ImageAspectFlags,
    usage: vk::ImageUsageFlags,
    mip_levels: u32,
    layers: u32,
}

impl Image {
    /// Creates the image, binds memory and creates a view of every level and layer
    /// (`TYPE_2D`, `TYPE_2D_ARRAY`, `CUBE` or `CUBE_ARRAY` by the description). The
    /// aspect follows the format: `DEPTH` for D16, X8_D24 and D32, `DEPTH | STENCIL` for
    /// the combined depth-stencil formats, `STENCIL` for S8, `COLOR` for the others.
    ///
    /// # Errors
    /// [`VkError::Unsupported`] when the description is impossible (a side of 0 or
    /// beyond the device's limit, too many mip levels, no layers, a cube map that is not
    /// square or whose layers are not a multiple of 6), with the reason;
    /// [`VkError::OutOfMemory`] or [`VkError::Allocation`] when memory cannot be
    /// allocated; [`VkError`] when a Vulkan call fails (e.g. the format does not support
    /// the usage). Nothing is left behind.
    pub fn new(device: &Arc<Device>, desc: &ImageDesc<'_>) -> Result<Image, VkError> {
        desc.check(device.max_image_dimension_2d())
            .map_err(VkError::Unsupported)?;
        let aspect = format_aspect(desc.format);
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels)
            .array_layers(desc.layers)
            .flags(if desc.cube {
                vk::ImageCreateFlags::CUBE_COMPATIBLE
            } else {
                vk::ImageCreateFlags::empty()
            })
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let raw_device = device.raw();
        // SAFETY: valid create info; on error every created object is destroyed by Drop.
        let raw = unsafe { raw_device.create_image(&info, None) }.what("vkCreateImage")?;
        let mut image = Image {
            device: device.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: None,
            format: desc.format,
            extent: vk::Extent2D {
                width: desc.width,
                height: desc.height,
            },
            aspect,
            usage: desc.usage,
            mip_levels: desc.mip_levels,
            layers: desc.layers,
        };
        let requirements = unsafe { raw_device.get_image_memory_requirements(raw) };
        let allocation = device
            .allocate(&AllocationCreateDesc {
                name: desc.name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|source| VkError::allocation(desc.name, source))?;
        // SAFETY: the memory handle stays valid while the allocation lives (in `image`).
        let (memory, offset) = (unsafe { allocation.memory() }, allocation.offset());
        image.allocation = Some(allocation);
        unsafe { raw_device.bind_image_memory(raw, memory, offset) }.what("vkBindImageMemory")?;
        image.view = image.create_view(desc.view_type(), image.subresource_range())?;
        Ok(image)
    }

    fn create_view(
        &self,
        view_type: vk::ImageViewType,
        range: vk::ImageSubresourceRange,
    ) -> Result<vk::ImageView, VkError> {
        let view_info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(view_type)
            .format(self.format)
            .subresource_range(range);
        // SAFETY: valid create info for this image.
        unsafe { self.device.raw().create_image_view(&view_info, None) }.what("vkCreateImageView")
    }

    /// A view of part of the image: mip levels `mips`, layers `layers`, as `view_type`
    /// (e.g. one mip level of a cube map as a `TYPE_2D_ARRAY` storage image for compute,
    /// or one face as `TYPE_2D`). The view has the image's format and aspect; keep the
    /// image alive while the view is used.
    ///
    /// # Errors
    /// [`VkError::Unsupported`] when a range is empty or beyond the image; [`VkError`]
    /// when `vkCreateImageView` fails (e.g. a view type the layers do not fit).
    pub fn view_of(
        &self,
        mips: std::ops::Range<u32>,
        layers: std::ops::Range<u32>,
        view_type: vk::ImageViewType,
    ) -> Result<ImageView, VkError> {
        if mips.is_empty()
            || mips.end > self.mip_levels
            || layers.is_empty()
            || layers.end > self.layers
        {
            return Err(VkError::Unsupported(format!(
                "a view of mips {mips:?} and layers {layers:?} is outside an image of {} mips and {} layers",
                self.mip_levels, self.layers
            )));
        }
        let range = vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: mips.start,
            level_count: mips.len() as u32,
            base_array_layer: layers.start,
            layer_count: layers.len() as u32,
        };
        Ok(ImageView {
            device: self.device.clone(),
            raw: self.create_view(view_type, range)?,
        })
    }

    fn range(&self, base_mip_level: u32, level_count: u32) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level,
            level_count,
            base_array_layer: 0,
            layer_count: self.layers,
        }
    }

    /// The number of array layers (6 per cube for a cube map).
    pub fn layers(&self) -> u32 {
        self.layers
    }

    /// The number of mip levels.
    pub fn mip_levels(&self) -> u32 {
        self.mip_levels
    }

    /// One mip level of every layer as a subresource range.
    pub fn mip_range(&self, level: u32) -> vk::ImageSubresourceRange {
        self.range(level, 1)
    }

    /// The Vulkan image, valid while `self` lives.
    pub fn raw(&self) -> vk::Image {
        self.raw
    }
    /// The view of every mip level and layer, valid while `self` lives.
    pub fn view(&self) -> vk::ImageView {
        self.view
    }
    /// The texel format.
    pub fn format(&self) -> vk::Format {
        self.format
    }
    /// The size of mip level 0, in texels.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }
    /// The aspects of the format (see [`Image::new`]), used by every range, barrier and
    /// copy region the image makes.
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        self.aspect
    }
    /// The usage flags it was created with.
    pub fn usage(&self) -> vk::ImageUsageFlags {
        self.usage
    }
    /// The whole image (every level and layer, every aspect) as a subresource range.
    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        self.range(0, self.mip_levels)
    }

    /// A layout transition of the whole image (synchronization2): `src` and `dst` are
    /// (stages, accesses, layout) before and after, as in [`ImageState`]. Record it with
    /// `vkCmdPipelineBarrier2`.
    pub fn barrier(
        &self,
        src: (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout),
        dst: (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout),
    ) -> vk::ImageMemoryBarrier2<'static> {
        self.barrier_range(self.subresource_range(), src, dst)
    }

    /// A layout transition of `range` of this image (synchronization2).
    fn barrier_range(
        &self,
        range: vk::ImageSubresourceRange,
        src: (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout),
        dst: (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout),
    ) -> vk::ImageMemoryBarrier2<'static> {
        image_barrier(
            self.raw,
            range,
            ImageState::new(src.0, src.1, src.2),
            ImageState::new(dst.0, dst.1, dst.2),
        )
    }

    fn subresource_layers(&self, mip_level: u32, layer: u32) -> vk::ImageSubresourceLayers {
        vk::ImageSubresourceLayers {
            aspect_mask: self.aspect,
            mip_level,
            base_array_layer: layer,
            layer_count: 1,
        }
    }

    /// Mip level `mip_level` of every layer.
    fn all_layers(&self, mip_level: u32) -> vk::ImageSubresourceLayers {
        vk::ImageSubresourceLayers {
            layer_count: self.layers,
            ..self.subresource_layers(mip_level, 0)
        }
    }

    /// The size of mip level `level`, in texels (at least 1×1).
    pub fn mip_extent(&self, level: u32) -> vk::Extent2D {
        vk::Extent2D {
            width: (self.extent.width >> level).max(1),
            height: (self.extent.height >> level).max(1),
        }
    }

    /// All of one mip level of one layer, tightly packed in a buffer.
    fn copy_region(&self, mip_level: u32, layer: u32) -> vk::BufferImageCopy {
        packed_copy_region(
            self.subresource_layers(mip_level, layer),
            self.mip_extent(mip_level),
        )
    }

    /// Every mip level of every layer, tightly packed in a buffer from `offset` on (a
    /// level's layers one after another, then the next level), for copies to or from it
    /// of a colour image of `texel_bytes` per texel; and the offset after the last.
    pub fn every_level_copy_regions(
        &self,
        offset: u64,
        texel_bytes: u64,
    ) -> (Vec<vk::BufferImageCopy>, u64) {
        let mut end = offset;
        let regions = (0..self.mip_levels)
            .map(|level| {
                let extent = self.mip_extent(level);
                let region = packed_copy_region(self.all_layers(level), extent).buffer_offset(end);
                end += u64::from(extent.width)
                    * u64::from(extent.height)
                    * u64::from(self.layers)
                    * texel_bytes;
                region
            })
            .collect();
        (regions, end)
    }

    /// All of mip level 0 of layer 0, tightly packed in a buffer, for a copy to or from
    /// it. With the image's aspect: for a combined depth-stencil image, set one aspect
    /// before using it (a buffer copy takes one).
    pub fn level0_copy_region(&self) -> vk::BufferImageCopy {
        self.copy_region(0, 0)
    }

    /// Records the upload of mip level 0 of every layer from `staging` (tightly packed
    /// texels, layer after layer) and the generation of the other levels of every layer
    /// by linear blits; leaves every level in SHADER_READ_ONLY_OPTIMAL for fragment
    /// shaders. The format must support blits with linear filtering (RGBA8 does on every
    /// device Combustion runs on).
    ///
    /// The image needs `TRANSFER_DST` usage (and `TRANSFER_SRC` with more than one mip
    /// level) and a colour format; `staging` holds `width·height·layers` texels of the
    /// format and stays alive until the submission completes; `cmd` is in the recording
    /// state. The previous contents are discarded.
    pub fn record_upload_with_mips(&self, cmd: vk::CommandBuffer, staging: &Buffer) {
        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        let raw = self.device.raw();
        let barrier =
            |barriers: &[vk::ImageMemoryBarrier2<'_>]| record_image_barriers(raw, cmd, barriers);
        let dst = MIP_CHAIN_DESTINATION;
        let read = (
            S::FRAGMENT_SHADER,
            A::SHADER_SAMPLED_READ,
            L::SHADER_READ_ONLY_OPTIMAL,
        );
        let all_to_dst = self.barrier((S::NONE, A::NONE, L::UNDEFINED), dst);
        barrier(&[all_to_dst]);
        // Tightly packed layers follow each other in the buffer, which is what one
        // region over every layer reads.
        let region = packed_copy_region(self.all_layers(0), self.extent);
        // SAFETY: recording state; staging holds width·height texels per layer.
        unsafe {
            raw.cmd_copy_buffer_to_image(
                cmd,
                staging.raw(),
                self.raw,
                L::TRANSFER_DST_OPTIMAL,
                &[region],
            )
        };
        self.record_mip_chain(cmd, read);
    }

    /// Records the generation of every level but the first, of every layer, by linear
    /// blits, each level from the one before, and leaves every level in `after` (stages,
    /// accesses, layout of its next use). Level 0 must have been written and every level
    /// be in TRANSFER_DST_OPTIMAL, the writes by copies or blits. The image needs
    /// `TRANSFER_SRC` and `TRANSFER_DST` usage and a format that supports blits with
    /// linear filtering; `cmd` is in the recording state.
    pub fn record_mip_chain(
        &self,
        cmd: vk::CommandBuffer,
        after: (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout),
    ) {
        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        let raw = self.device.raw();
        let level_barrier = |level: u32, src: (S, A, L), dst: (S, A, L)| {
            self.barrier_range(self.mip_range(level), src, dst)
        };
        let barrier =
            |barriers: &[vk::ImageMemoryBarrier2<'_>]| record_image_barriers(raw, cmd, barriers);
        let dst = MIP_CHAIN_DESTINATION;
        let src = (S::BLIT, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL);
        let size = |level: u32| {
            (
                (self.extent.width >> level).max(1) as i32,
                (self.extent.height >> level).max(1) as i32,
            )
        };
        for level in 1..self.mip_levels {
            barrier(&[level_barrier(level - 1, dst, src)]);
            let ((sw, sh), (dw, dh)) = (size(level - 1), size(level));
            let blit = vk::ImageBlit::default()
                .src_subresource(self.all_layers(level - 1))
                .src_offsets([vk::Offset3D::default(), vk::Offset3D { x: sw, y: sh, z: 1 }])
                .dst_subresource(self.all_layers(level))
                .dst_offsets([vk::Offset3D::default(), vk::Offset3D { x: dw, y: dh, z: 1 }]);
            // SAFETY: recording state; levels (of every layer) are in the layouts named.
            unsafe {
                raw.cmd_blit_image(
                    cmd,
                    self.raw,
                    L::TRANSFER_SRC_OPTIMAL,
                    self.raw,
                    L::TRANSFER_DST_OPTIMAL,
                    &[blit],
                    vk::Filter::LINEAR,
                )
            };
            barrier(&[level_barrier(level - 1, src, after)]);
        }
        barrier(&[level_barrier(self.mip_levels - 1, dst, after)]);
    }

    /// Records a copy of mip level 0 of layer 0 (in TRANSFER_SRC_OPTIMAL) into `buffer`,
    /// tightly packed; the whole image when it has one level and one layer. `buffer`
    /// needs `TRANSFER_DST` usage and room for the texels.
    pub fn record_copy_to_buffer(&self, cmd: vk::CommandBuffer, buffer: &Buffer) {
        self.record_level_copy_to_buffer(cmd, buffer, 0, 0);
    }

    /// Records a copy of mip level `mip_level` of layer `layer` (in TRANSFER_SRC_OPTIMAL)
    /// into `buffer`, tightly packed. `buffer` needs `TRANSFER_DST` usage and room for
    /// [`Image::mip_extent`] texels; the level and layer must exist.
    pub fn record_level_copy_to_buffer(
        &self,
        cmd: vk::CommandBuffer,
        buffer: &Buffer,
        mip_level: u32,
        layer: u32,
    ) {
        let region = self.copy_region(mip_level, layer);
        // SAFETY: the caller records into a command buffer in the recording state.
        unsafe {
            self.device.raw().cmd_copy_image_to_buffer(
                cmd,
                self.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer.raw(),
                &[region],
            )
        };
    }
}

/// Where every level of an image stands while a mip chain is written into it: copied or
/// blitted to.
const MIP_CHAIN_DESTINATION: (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout) = (
    vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::COPY.as_raw() | vk::PipelineStageFlags2::BLIT.as_raw(),
    ),
    vk::AccessFlags2::TRANSFER_WRITE,
    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
);

/// Records `barriers` into `cmd` (in the recording state: the caller's responsibility).
fn record_image_barriers(
    raw: &ash::Device,
    cmd: vk::CommandBuffer,
    barriers: &[vk::ImageMemoryBarrier2<'_>],
) {
    let info = vk::DependencyInfo::default().image_memory_barriers(barriers);
    // SAFETY: recording state is the caller's responsibility.
    unsafe { raw.cmd_pipeline_barrier2(cmd, &info) };
}

/// A view of part of an [`Image`] ([`Image::view_of`]), destroyed when dropped (before
/// its image: it holds no reference to it, so keep the image alive while it is used).
pub struct ImageView {
    device: Arc<Device>,
    raw: vk::ImageView,
}

impl ImageView {
    /// The Vulkan image view, valid while `self` (and its image) live.
    pub fn raw(&self) -> vk::ImageView {
        self.raw
    }
}

impl Drop for ImageView {
    fn drop(&mut self) {
        // SAFETY: the caller keeps views alive only while frames using them are pending.
        unsafe { self.device.raw().destroy_image_view(self.raw, None) };
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: callers wait for the GPU to finish with an image before dropping it.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.device.raw().destroy_image_view(self.view, None);
            }
            self.device.raw().destroy_image(self.raw, None);
        }
        if let Some(allocation) = self.allocation.take() {
            if let Err(e) = self.device.allocator().free(allocation) {
                log::error!("freeing image memory: {e}");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_aspect_follows_the_format() {
        use vk::{Format as F, ImageAspectFlags as A};
        for (format, aspect) in [
            (F::D16_UNORM, A::DEPTH),
            (F::X8_D24_UNORM_PACK32, A::DEPTH),
            (F::D32_SFLOAT, A::DEPTH),
            (F::D16_UNORM_S8_UINT, A::DEPTH | A::STENCIL),
            (F::D24_UNORM_S8_UINT, A::DEPTH | A::STENCIL),
            (F::D32_SFLOAT_S8_UINT, A::DEPTH | A::STENCIL),
            (F::S8_UINT, A::STENCIL),
            (F::R8G8B8A8_UNORM, A::COLOR),
            (F::R32G32B32A32_SFLOAT, A::COLOR),
            (F::B10G11R11_UFLOAT_PACK32, A::COLOR),
        ] {
            assert_eq!(format_aspect(format), aspect, "{format:?}");
        }
    }
}
