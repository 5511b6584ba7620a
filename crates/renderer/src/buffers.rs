//! Storage-buffer helpers shared by the passes, the frame slots and the environment
//! bake: creating a storage buffer, filling one from the host, and growing a per-slot
//! buffer to fit.

use std::sync::Arc;

use combustion_vk::{vk, Buffer, Device, VkError};

/// A storage buffer of `bytes` bytes (at least 4) in `location`.
pub(crate) fn storage_buffer(
    device: &Arc<Device>,
    name: &str,
    bytes: u64,
    location: combustion_vk::gpu_allocator::MemoryLocation,
) -> Result<Buffer, VkError> {
    Buffer::new(
        device,
        name,
        bytes.max(4),
        vk::BufferUsageFlags::STORAGE_BUFFER,
        location,
    )
}

/// A host-visible storage buffer holding `bytes`.
pub(crate) fn filled_storage_buffer(
    device: &Arc<Device>,
    name: &str,
    bytes: &[u8],
) -> Result<Buffer, VkError> {
    let mut buffer = storage_buffer(device, name, bytes.len() as u64, CPU_TO_GPU)?;
    buffer.write(0, bytes)?;
    Ok(buffer)
}

/// Writes `bytes` at the start of a per-slot host-visible `buffer`, replacing it by one
/// of the next power-of-two size when they do not fit. The caller guarantees that the
/// slot's previous frame, the old buffer's last reader, has completed.
pub(crate) fn write_growing(
    device: &Arc<Device>,
    buffer: &mut Buffer,
    name: &str,
    bytes: &[u8],
) -> Result<(), VkError> {
    if bytes.len() as u64 > buffer.size() {
        *buffer = storage_buffer(
            device,
            name,
            (bytes.len() as u64).next_power_of_two(),
            CPU_TO_GPU,
        )?;
    }
    buffer.write(0, bytes)
}

/// Host-visible memory the CPU writes and the GPU reads.
pub(crate) const CPU_TO_GPU: combustion_vk::gpu_allocator::MemoryLocation =
    combustion_vk::gpu_allocator::MemoryLocation::CpuToGpu;
/// Device memory only the GPU touches.
pub(crate) const GPU_ONLY: combustion_vk::gpu_allocator::MemoryLocation =
    combustion_vk::gpu_allocator::MemoryLocation::GpuOnly;
