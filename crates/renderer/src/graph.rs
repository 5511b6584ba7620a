//! Passes declare the images they touch and how; the barriers and layout transitions
//! between them are derived here, in one place, from those declarations.
//!
//! The frame is small and fixed (G-buffer → lighting → output, plus optional copies), so
//! there is no general render graph: each pass lists its `(image, use)` pairs, and
//! [`ImageStates::transition`] turns them into one `vkCmdPipelineBarrier2` against the
//! state every image was last left in. States persist from frame to frame, so the first
//! pass of frame n+1 waits for the last reads of frame n (write-after-read), which is
//! what makes frames in flight safe while they share the renderer's targets.

use std::collections::HashMap;

use combustion_vk::{image_barrier, vk, Image, ImageState};

/// How a pass uses an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageUse {
    /// Written as a colour attachment; earlier contents are discarded (cleared, or every
    /// pixel overwritten).
    ColorAttachmentWrite,
    /// Written (and depth-tested) as the depth attachment; cleared first.
    DepthAttachmentWrite,
    /// Read and written as a colour attachment, its contents kept: fragments blended
    /// over what an earlier pass wrote.
    ColorAttachmentBlend,
    /// Depth-tested against, read-only (no depth written), in the layout fragment shaders
    /// read depth in: a later pass's fragments hidden by what an earlier pass drew.
    DepthAttachmentTest,
    /// Depth-tested against, read-only, and read by the same pass's fragment shaders
    /// (texelFetch), both in the read-only depth layout: the forward pass hidden by the
    /// opaque depth while its refracted rays march against it.
    DepthAttachmentTestAndSampled,
    /// Read by fragment shaders (texelFetch).
    FragmentSampled,
    /// A depth image read by fragment shaders.
    DepthFragmentSampled,
    /// Copied from.
    TransferSource,
    /// Copied to; earlier contents are discarded.
    TransferDestination,
    /// Blitted from (`vkCmdBlitImage`: a copy that converts the format).
    BlitSource,
    /// Blitted to, the whole image; earlier contents are discarded.
    BlitDestination,
    /// Level 0 copied to and every other level blitted from the one before
    /// (`Image::record_mip_chain`, whose own barriers leave every level in
    /// TRANSFER_DST_OPTIMAL); earlier contents are discarded.
    MipChainWrite,
    /// Read by compute shaders through a sampler or texelFetch.
    ComputeSampled,
    /// A depth image read by compute shaders (texelFetch), in the layout fragment
    /// shaders read it in too.
    DepthComputeSampled,
    /// Written by compute shaders as a storage image (GENERAL layout); earlier contents
    /// are kept (a compute pass may write part of an image).
    ComputeStorageWrite,
    /// Sampled and written by compute shaders, both in GENERAL layout: one mip level
    /// written as a storage image while another is read through a view of the whole
    /// image (a mip chain built level by level, each from the one before). Tracked for
    /// the whole image, so each such pass waits for the previous one's writes; earlier
    /// contents are kept.
    ComputeSampledStorageWrite,
}

impl ImageUse {
    /// The stages, accesses and layout of this use (the host's ready-made
    /// [`ImageState`]s where one fits).
    pub fn state(self) -> ImageState {
        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        match self {
            Self::ColorAttachmentWrite => ImageState::COLOR_ATTACHMENT_WRITE,
            Self::DepthAttachmentWrite => ImageState::DEPTH_ATTACHMENT_READ_WRITE,
            Self::ColorAttachmentBlend => ImageState::COLOR_ATTACHMENT_READ_WRITE,
            Self::DepthAttachmentTest => ImageState::new(
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ,
                L::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            ),
            Self::DepthAttachmentTestAndSampled => ImageState::new(
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS | S::FRAGMENT_SHADER,
                A::DEPTH_STENCIL_ATTACHMENT_READ | A::SHADER_SAMPLED_READ,
                L::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            ),
            Self::FragmentSampled => ImageState::FRAGMENT_SAMPLED,
            Self::DepthFragmentSampled => ImageState::new(
                S::FRAGMENT_SHADER,
                A::SHADER_SAMPLED_READ,
                L::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            ),
            Self::TransferSource => ImageState::COPY_SOURCE,
            Self::TransferDestination => {
                ImageState::new(S::COPY, A::TRANSFER_WRITE, L::TRANSFER_DST_OPTIMAL)
            }
            Self::BlitSource => ImageState::new(S::BLIT, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL),
            Self::BlitDestination => {
                ImageState::new(S::BLIT, A::TRANSFER_WRITE, L::TRANSFER_DST_OPTIMAL)
            }
            Self::MipChainWrite => ImageState::new(
                S::ALL_TRANSFER,
                A::from_raw(A::TRANSFER_READ.as_raw() | A::TRANSFER_WRITE.as_raw()),
                L::TRANSFER_DST_OPTIMAL,
            ),
            Self::ComputeSampled => ImageState::COMPUTE_SAMPLED,
            Self::DepthComputeSampled => ImageState::new(
                S::COMPUTE_SHADER,
                A::SHADER_SAMPLED_READ,
                L::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            ),
            Self::ComputeStorageWrite => {
                ImageState::new(S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE, L::GENERAL)
            }
            Self::ComputeSampledStorageWrite => ImageState::new(
                S::COMPUTE_SHADER,
                A::SHADER_SAMPLED_READ | A::SHADER_STORAGE_WRITE,
                L::GENERAL,
            ),
        }
    }

    /// Whether the use replaces the whole contents (so the old layout may be discarded).
    fn discards_contents(self) -> bool {
        matches!(
            self,
            Self::ColorAttachmentWrite
                | Self::DepthAttachmentWrite
                | Self::TransferDestination
                | Self::BlitDestination
                | Self::MipChainWrite
        )
    }
}

/// An image as the frame tracks it: its handle and the subresources a pass touches.
#[derive(Clone, Copy, Debug)]
pub struct TrackedImage {
    /// The image's handle.
    pub raw: vk::Image,
    /// The subresources (aspect, mip levels, layers) the pass touches.
    pub range: vk::ImageSubresourceRange,
}

impl From<&Image> for TrackedImage {
    fn from(image: &Image) -> Self {
        Self {
            raw: image.raw(),
            range: image.subresource_range(),
        }
    }
}

/// How a pass uses a buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferUse {
    /// Read as a vertex stream by the vertex input stage.
    VertexInput,
    /// Read as a storage buffer by vertex shaders.
    VertexStorageRead,
    /// Read as a storage buffer by fragment shaders.
    FragmentStorageRead,
    /// Read as a storage buffer by compute shaders.
    ComputeStorageRead,
    /// Written as a storage buffer by compute shaders.
    ComputeStorageWrite,
    /// Copied to.
    TransferDestination,
    /// Copied from.
    TransferSource,
    /// Read by the CPU once the frame has completed (readback).
    HostRead,
}

impl BufferUse {
    /// The stages and accesses of this use.
    pub fn state(self) -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        match self {
            Self::VertexInput => (S::VERTEX_ATTRIBUTE_INPUT, A::VERTEX_ATTRIBUTE_READ),
            Self::VertexStorageRead => (S::VERTEX_SHADER, A::SHADER_STORAGE_READ),
            Self::FragmentStorageRead => (S::FRAGMENT_SHADER, A::SHADER_STORAGE_READ),
            Self::ComputeStorageRead => (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ),
            Self::ComputeStorageWrite => (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
            Self::TransferDestination => (S::COPY, A::TRANSFER_WRITE),
            Self::TransferSource => (S::COPY, A::TRANSFER_READ),
            Self::HostRead => (S::HOST, A::HOST_READ),
        }
    }

    fn writes(self) -> bool {
        matches!(self, Self::ComputeStorageWrite | Self::TransferDestination)
    }
}

/// One pass's declaration: its name (for timings and messages) and what it touches.
/// Buffers the CPU writes before submission (scene tables, the frame's lights) are
/// declared too: their host writes are visible to the whole submission, so they never
/// need a barrier, but a GPU write to them later would.
pub struct PassUses {
    /// The pass's name (in timings and messages).
    pub name: &'static str,
    /// Each image the pass touches and how.
    pub images: Vec<(TrackedImage, ImageUse)>,
    /// Each buffer the pass touches and how.
    pub buffers: Vec<(vk::Buffer, BufferUse)>,
}

impl PassUses {
    /// A pass that touches `images` and declares no buffers.
    pub fn images(name: &'static str, images: Vec<(TrackedImage, ImageUse)>) -> Self {
        Self {
            name,
            images,
            buffers: Vec::new(),
        }
    }

    /// The same pass declaring `buffers` too (replacing any declared before).
    pub fn with_buffers(self, buffers: Vec<(vk::Buffer, BufferUse)>) -> Self {
        Self { buffers, ..self }
    }
}

/// The state each image was last left in, and the GPU use of each buffer since its last
/// barrier, carried across passes and frames.
#[derive(Default)]
pub struct ImageStates {
    states: HashMap<vk::Image, ImageState>,
    buffers: HashMap<vk::Buffer, BufferUse>,
    /// Each buffer's last GPU write and the reads it has been made visible to since: a
    /// read of another kind (a vertex stream, then a fragment shader's storage read)
    /// needs its own barrier from that write.
    written: HashMap<vk::Buffer, (BufferUse, Vec<BufferUse>)>,
}

impl ImageStates {
    /// The state `image` was last left in (`UNDEFINED` if never seen).
    pub fn get(&self, image: vk::Image) -> ImageState {
        self.states
            .get(&image)
            .copied()
            .unwrap_or(ImageState::UNDEFINED)
    }

    /// Declares where an image the renderer does not own stands (a host's target).
    pub fn set(&mut self, image: vk::Image, state: ImageState) {
        self.states.insert(image, state);
    }

    /// Forgets an image that is being destroyed.
    pub fn forget(&mut self, image: vk::Image) {
        self.states.remove(&image);
    }

    /// Forgets a buffer that is being destroyed.
    pub fn forget_buffer(&mut self, buffer: vk::Buffer) {
        self.buffers.remove(&buffer);
        self.written.remove(&buffer);
    }

    /// Records the barriers that bring every image `pass` declares into the state of its
    /// use, and remembers the new states. No barrier for a read that follows a read in
    /// the same layout.
    pub fn transition(
        &mut self,
        raw: &combustion_vk::ash::Device,
        cmd: vk::CommandBuffer,
        pass: &PassUses,
    ) {
        let barriers: Vec<_> = pass
            .images
            .iter()
            .filter_map(|&(image, use_)| {
                let to = use_.state();
                let from = self.get(image.raw);
                self.states.insert(image.raw, to);
                if from == to && !to.writes() {
                    return None;
                }
                let from = if use_.discards_contents() {
                    ImageState {
                        layout: vk::ImageLayout::UNDEFINED,
                        ..from
                    }
                } else {
                    from
                };
                Some(image_barrier(image.raw, image.range, from, to))
            })
            .collect();
        // Buffers: data the CPU wrote before the submission is visible to all of it. A
        // barrier after a GPU write (read after write, write after write) and before a
        // GPU write that follows GPU reads; none after the CPU read a buffer, since it
        // waited for the frame to do so.
        let memory: Vec<_> = pass
            .buffers
            .iter()
            .filter_map(|&(buffer, use_)| {
                let Some(&before) = self.buffers.get(&buffer) else {
                    // A first use: nothing to wait for. A read is remembered too, so that
                    // a GPU write after it waits for it (a buffer read before its first
                    // GPU write: the previous pose, read empty by a frame's first motion
                    // pass, then written).
                    self.buffers.insert(buffer, use_);
                    if use_.writes() {
                        self.written.insert(buffer, (use_, Vec::new()));
                    }
                    return None;
                };
                self.buffers.insert(buffer, use_);
                if use_.writes() {
                    self.written.insert(buffer, (use_, Vec::new()));
                }
                let mut source = before;
                if before == BufferUse::HostRead {
                    return None;
                }
                if !(before.writes() || use_.writes()) {
                    // A read after reads: a barrier from the last write only if it was
                    // not yet made visible to this kind of read.
                    match self.written.get_mut(&buffer) {
                        Some((write, seen)) if !seen.contains(&use_) => {
                            seen.push(use_);
                            source = *write;
                        }
                        _ => return None,
                    }
                } else if before.writes() && !use_.writes() {
                    if let Some((_, seen)) = self.written.get_mut(&buffer) {
                        seen.push(use_);
                    }
                }
                let (src_stage, src_access) = source.state();
                let (dst_stage, dst_access) = use_.state();
                Some(
                    vk::BufferMemoryBarrier2::default()
                        .src_stage_mask(src_stage)
                        .src_access_mask(src_access)
                        .dst_stage_mask(dst_stage)
                        .dst_access_mask(dst_access)
                        .buffer(buffer)
                        .offset(0)
                        .size(vk::WHOLE_SIZE),
                )
            })
            .collect();
        record_barriers(raw, cmd, &barriers, &memory);
    }

    /// Records the barrier that leaves `image` in `to` (a host's "after" state).
    pub fn release(
        &mut self,
        raw: &combustion_vk::ash::Device,
        cmd: vk::CommandBuffer,
        image: TrackedImage,
        to: ImageState,
    ) {
        let from = self.get(image.raw);
        self.states.insert(image.raw, to);
        // A write is made available to the next use even when that use has the same
        // stages, accesses and layout (a write after a write needs its barrier too).
        if from != to || from.writes() {
            record_barriers(
                raw,
                cmd,
                &[image_barrier(image.raw, image.range, from, to)],
                &[],
            );
        }
    }
}

fn record_barriers(
    raw: &combustion_vk::ash::Device,
    cmd: vk::CommandBuffer,
    images: &[vk::ImageMemoryBarrier2<'_>],
    buffers: &[vk::BufferMemoryBarrier2<'_>],
) {
    if images.is_empty() && buffers.is_empty() {
        return;
    }
    let info = vk::DependencyInfo::default()
        .image_memory_barriers(images)
        .buffer_memory_barriers(buffers);
    // SAFETY: the caller records into a command buffer in the recording state.
    unsafe { raw.cmd_pipeline_barrier2(cmd, &info) };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_after_reads_need_no_barrier_and_writes_always_do() {
        let read = ImageUse::FragmentSampled.state();
        assert!(!read.writes());
        assert!(ImageUse::ColorAttachmentWrite.state().writes());
        assert!(ImageUse::DepthAttachmentWrite.state().writes());
        assert!(ImageUse::ColorAttachmentBlend.state().writes());
        assert!(!ImageUse::DepthAttachmentTest.state().writes());
        assert!(ImageUse::TransferDestination.state().writes());
        assert!(ImageUse::MipChainWrite.state().writes());
        assert!(!ImageUse::TransferSource.state().writes());
        assert!(ImageUse::ComputeSampledStorageWrite.state().writes());
    }

    /// The depth-only and stencil-only layouts need separateDepthStencilLayouts, a
    /// feature Combustion does not ask of a device (nor of a host's): every use, and
    /// every ready-made state a host is offered, keeps to the combined layouts, valid
    /// for a depth-only format too.
    #[test]
    fn no_layout_needs_separate_depth_stencil_layouts() {
        use vk::ImageLayout as L;
        let separate = [
            L::DEPTH_ATTACHMENT_OPTIMAL,
            L::DEPTH_READ_ONLY_OPTIMAL,
            L::STENCIL_ATTACHMENT_OPTIMAL,
            L::STENCIL_READ_ONLY_OPTIMAL,
        ];
        let uses = [
            ImageUse::ColorAttachmentWrite,
            ImageUse::DepthAttachmentWrite,
            ImageUse::ColorAttachmentBlend,
            ImageUse::DepthAttachmentTest,
            ImageUse::DepthAttachmentTestAndSampled,
            ImageUse::FragmentSampled,
            ImageUse::DepthFragmentSampled,
            ImageUse::TransferSource,
            ImageUse::TransferDestination,
            ImageUse::MipChainWrite,
            ImageUse::ComputeSampled,
            ImageUse::DepthComputeSampled,
            ImageUse::ComputeStorageWrite,
            ImageUse::ComputeSampledStorageWrite,
        ];
        let host_states = [
            ImageState::UNDEFINED,
            ImageState::COLOR_ATTACHMENT_WRITE,
            ImageState::COLOR_ATTACHMENT_READ_WRITE,
            ImageState::DEPTH_ATTACHMENT_READ_WRITE,
            ImageState::FRAGMENT_SAMPLED,
            ImageState::COMPUTE_SAMPLED,
            ImageState::COPY_SOURCE,
            ImageState::COPY_DESTINATION,
            ImageState::BLIT_SOURCE,
            ImageState::BLIT_DESTINATION,
            ImageState::SWAPCHAIN_ACQUIRED,
            ImageState::PRESENT,
        ];
        for state in uses.iter().map(|u| u.state()).chain(host_states) {
            assert!(
                !separate.contains(&state.layout),
                "{:?} needs separateDepthStencilLayouts",
                state.layout
            );
        }
    }
}
