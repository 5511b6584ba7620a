use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::device::Device;
use crate::error::{VkError, VkResultExt};

/// A buffer and its memory. Destroyed when dropped.
pub struct Buffer {
    device: Arc<Device>,
    raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
}

impl Buffer {
    /// Creates a buffer of `size` bytes in `location` (`CpuToGpu` and `GpuToCpu` are mapped).
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
        let allocation = device.allocator().allocate(&AllocationCreateDesc {
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
                return Err(VkError::Allocation {
                    name: name.to_owned(),
                    source,
                });
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

    /// Creates a host-visible buffer holding `bytes`.
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

    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Writes into a mapped buffer.
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

    /// The contents of a mapped buffer (e.g. a readback buffer after its copy completed).
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
    pub stage: vk::PipelineStageFlags2,
    pub access: vk::AccessFlags2,
    pub layout: vk::ImageLayout,
}

impl ImageState {
    /// Never used: contents undefined, nothing to wait for.
    pub const UNDEFINED: ImageState = ImageState::new(
        vk::PipelineStageFlags2::NONE,
        vk::AccessFlags2::NONE,
        vk::ImageLayout::UNDEFINED,
    );

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

/// How to create an [`Image`] (2D, one layer).
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc<'a> {
    pub name: &'a str,
    pub format: vk::Format,
    pub width: u32,
    pub height: u32,
    pub usage: vk::ImageUsageFlags,
    /// Mip levels (1 = none); see [`full_mip_chain`].
    pub mip_levels: u32,
}

/// The number of mip levels down to 1×1 for a `width`×`height` image.
pub fn full_mip_chain(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// A 2D image, its memory and a view over all of it. Destroyed when dropped.
pub struct Image {
    device: Arc<Device>,
    raw: vk::Image,
    view: vk::ImageView,
    allocation: Option<Allocation>,
    format: vk::Format,
    extent: vk::Extent2D,
    aspect: vk::ImageAspectFlags,
    mip_levels: u32,
}

impl Image {
    pub fn new(device: &Arc<Device>, desc: &ImageDesc<'_>) -> Result<Image, VkError> {
        let max = device.max_image_dimension_2d();
        if desc.width == 0 || desc.height == 0 || desc.width > max || desc.height > max {
            return Err(VkError::Unsupported(format!(
                "image {} of {}x{} is outside the device's limits (1..={max} per side)",
                desc.name, desc.width, desc.height
            )));
        }
        let aspect = match desc.format {
            vk::Format::D32_SFLOAT | vk::Format::D16_UNORM => vk::ImageAspectFlags::DEPTH,
            _ => vk::ImageAspectFlags::COLOR,
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels.max(1))
            .array_layers(1)
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
            mip_levels: desc.mip_levels.max(1),
        };
        let requirements = unsafe { raw_device.get_image_memory_requirements(raw) };
        let allocation = device
            .allocator()
            .allocate(&AllocationCreateDesc {
                name: desc.name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|source| VkError::Allocation {
                name: desc.name.to_owned(),
                source,
            })?;
        // SAFETY: the memory handle stays valid while the allocation lives (in `image`).
        let (memory, offset) = (unsafe { allocation.memory() }, allocation.offset());
        image.allocation = Some(allocation);
        unsafe { raw_device.bind_image_memory(raw, memory, offset) }.what("vkBindImageMemory")?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(desc.format)
            .subresource_range(image.subresource_range());
        image.view =
            unsafe { raw_device.create_image_view(&view_info, None) }.what("vkCreateImageView")?;
        Ok(image)
    }

    fn range(
        aspect: vk::ImageAspectFlags,
        base_mip_level: u32,
        level_count: u32,
    ) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: aspect,
            base_mip_level,
            level_count,
            base_array_layer: 0,
            layer_count: 1,
        }
    }

    pub fn mip_levels(&self) -> u32 {
        self.mip_levels
    }

    /// One mip level as a subresource range.
    pub fn mip_range(&self, level: u32) -> vk::ImageSubresourceRange {
        Self::range(self.aspect, level, 1)
    }

    pub fn raw(&self) -> vk::Image {
        self.raw
    }
    pub fn view(&self) -> vk::ImageView {
        self.view
    }
    pub fn format(&self) -> vk::Format {
        self.format
    }
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        self.aspect
    }
    /// The whole image as a subresource range.
    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        Self::range(self.aspect, 0, self.mip_levels)
    }

    /// A layout transition of the whole image (synchronization2).
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

    fn layers(&self, mip_level: u32) -> vk::ImageSubresourceLayers {
        vk::ImageSubresourceLayers {
            aspect_mask: self.aspect,
            mip_level,
            base_array_layer: 0,
            layer_count: 1,
        }
    }

    /// All of mip level 0, tightly packed in a buffer.
    fn level0_copy_region(&self) -> vk::BufferImageCopy {
        vk::BufferImageCopy::default()
            .image_subresource(self.layers(0))
            .image_extent(vk::Extent3D {
                width: self.extent.width,
                height: self.extent.height,
                depth: 1,
            })
    }

    /// Records the upload of mip level 0 from `staging` (tightly packed texels) and the
    /// generation of the other levels by linear blits; leaves every level in
    /// SHADER_READ_ONLY_OPTIMAL for fragment shaders. The format must support blits with
    /// linear filtering (RGBA8 does on every device Combustion runs on).
    pub fn record_upload_with_mips(&self, cmd: vk::CommandBuffer, staging: &Buffer) {
        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        let raw = self.device.raw();
        let level_barrier = |level: u32, src: (S, A, L), dst: (S, A, L)| {
            self.barrier_range(self.mip_range(level), src, dst)
        };
        let barrier = |barriers: &[vk::ImageMemoryBarrier2<'_>]| {
            let info = vk::DependencyInfo::default().image_memory_barriers(barriers);
            // SAFETY: recording state is the caller's responsibility.
            unsafe { raw.cmd_pipeline_barrier2(cmd, &info) };
        };
        let dst = (
            S::COPY | S::BLIT,
            A::TRANSFER_WRITE,
            L::TRANSFER_DST_OPTIMAL,
        );
        let src = (S::BLIT, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL);
        let read = (
            S::FRAGMENT_SHADER,
            A::SHADER_SAMPLED_READ,
            L::SHADER_READ_ONLY_OPTIMAL,
        );
        let all_to_dst = self.barrier((S::NONE, A::NONE, L::UNDEFINED), dst);
        barrier(&[all_to_dst]);
        let region = self.level0_copy_region();
        // SAFETY: recording state; staging holds width·height texels.
        unsafe {
            raw.cmd_copy_buffer_to_image(
                cmd,
                staging.raw(),
                self.raw,
                L::TRANSFER_DST_OPTIMAL,
                &[region],
            )
        };
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
                .src_subresource(self.layers(level - 1))
                .src_offsets([vk::Offset3D::default(), vk::Offset3D { x: sw, y: sh, z: 1 }])
                .dst_subresource(self.layers(level))
                .dst_offsets([vk::Offset3D::default(), vk::Offset3D { x: dw, y: dh, z: 1 }]);
            // SAFETY: recording state; levels are in the layouts named.
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
            barrier(&[level_barrier(level - 1, src, read)]);
        }
        barrier(&[level_barrier(self.mip_levels - 1, dst, read)]);
    }

    /// Records a copy of the whole image (in TRANSFER_SRC_OPTIMAL) into `buffer`, tightly packed.
    pub fn record_copy_to_buffer(&self, cmd: vk::CommandBuffer, buffer: &Buffer) {
        let region = self.level0_copy_region();
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
