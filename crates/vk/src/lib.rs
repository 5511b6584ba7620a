//! Vulkan backend of Combustion.
//!
//! Knows nothing of scenes or shading: it owns the instance and device (headless by
//! default; a [`Surface`] and [`Swapchain`] when presenting to a window), memory (gpu-allocator), buffers and images, shader compilation
//! (shaderc, GLSL with `#include`), one-shot command submission, readback and GPU
//! timestamp queries, and the validation-layer messenger.
//!
//! Ownership: [`Device`] lives in an `Arc`; every resource ([`Buffer`], [`Image`],
//! [`Pipeline`], ...) holds a clone of that `Arc` and destroys its Vulkan objects in
//! `Drop`. The device is therefore destroyed only after the last resource, and the
//! validation layer's leak report at device destruction is captured by [`ValidationLog`].
//!
//! Failures are [`VkError`]s; a failed Vulkan call names the call.
//! Synchronisation is the caller's: nothing here waits for the GPU except
//! [`OneShot::submit_and_wait`], [`FrameRing`]'s waits, [`Device::wait_idle`] and the
//! teardown of an owned [`Device`]; every resource must be dropped only once the GPU
//! has finished with it.
//!
//! `ash` and `gpu_allocator` are re-exported so upper crates don't pin their own versions.

#![warn(missing_docs)]

pub use ash;
pub use ash::vk;
pub use gpu_allocator;

mod commands;
mod device;
pub use combustion_disk_cache as disk_cache;
mod error;
mod pipeline;
mod probe;
mod resources;
mod shader;
mod spirv_cache;
mod swapchain;
#[cfg(test)]
mod test_support;
mod timestamps;

pub use commands::{FrameRing, OneShot, RingFrame};
pub use device::{
    Device, DeviceDesc, DeviceInfo, DeviceSelector, EnabledFeatures, HeapTrim, HostDevice,
    QueueLock, RayQueries, Requirements, SharedAllocator, ValidationLog, KEPT_HEAP_MMAP_THRESHOLD,
    KEPT_HEAP_TRIM_THRESHOLD,
};
pub use disk_cache::{default_cache_dir, Digest, DiskCache};
pub use error::{VkError, VkResultExt};
pub use pipeline::{
    ColorBlend, DescriptorPool, DescriptorSetLayout, GraphicsPipelineDesc, Pipeline, PipelineCache,
    PipelineLayout, Sampler,
};
pub use probe::{DeviceCounters, InjectedFault};
pub use resources::{
    color_level0_copy_region, copy_to_host_barrier, full_mip_chain, image_barrier, Buffer, Image,
    ImageDesc, ImageState, ImageView,
};
pub use shader::{ShaderCompiler, ShaderModule, ShaderSources, ShaderStage};
pub use spirv_cache::{default_spirv_cache_dir, COMPILER_IDENTITY};
pub use swapchain::{AcquiredImage, PresentOutcome, Surface, Swapchain};
pub use timestamps::TimestampQueries;
