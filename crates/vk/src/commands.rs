use std::sync::Arc;

use ash::vk;

use crate::device::Device;
use crate::error::{VkError, VkResultExt};

/// A command pool with one primary command buffer and a fence: record, submit, wait.
/// Reusable: each [`OneShot::begin`] resets the buffer.
pub struct OneShot {
    device: Arc<Device>,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
}

impl OneShot {
    pub fn new(device: &Arc<Device>) -> Result<Self, VkError> {
        let raw = device.raw();
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family())
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid create infos; objects are destroyed in Drop (or below on error).
        let pool =
            unsafe { raw.create_command_pool(&pool_info, None) }.what("vkCreateCommandPool")?;
        let mut this = OneShot {
            device: device.clone(),
            pool,
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        this.cmd =
            unsafe { raw.allocate_command_buffers(&alloc) }.what("vkAllocateCommandBuffers")?[0];
        // Created signalled: "nothing pending", so Drop never waits on a fence that was
        // never submitted (e.g. when recording failed).
        let fence_info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        this.fence = unsafe { raw.create_fence(&fence_info, None) }.what("vkCreateFence")?;
        Ok(this)
    }

    /// Resets the command buffer and begins recording; returns it.
    pub fn begin(&mut self) -> Result<vk::CommandBuffer, VkError> {
        let raw = self.device.raw();
        unsafe {
            raw.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())
                .what("vkResetCommandBuffer")?;
            raw.begin_command_buffer(
                self.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .what("vkBeginCommandBuffer")?;
        }
        Ok(self.cmd)
    }

    /// Ends recording, submits, and waits for the GPU to finish.
    pub fn submit_and_wait(&mut self) -> Result<(), VkError> {
        let raw = self.device.raw();
        unsafe { raw.end_command_buffer(self.cmd) }.what("vkEndCommandBuffer")?;
        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos)];
        unsafe { raw.reset_fences(&[self.fence]) }.what("vkResetFences")?;
        self.device.submit(&submit, self.fence)?;
        unsafe { raw.wait_for_fences(&[self.fence], true, u64::MAX) }.what("vkWaitForFences")
    }
}

impl Drop for OneShot {
    fn drop(&mut self) {
        let raw = self.device.raw();
        // SAFETY: wait for any submitted work before destroying what it uses.
        unsafe {
            if self.fence != vk::Fence::null() {
                // Bounded: a fence left unsignalled by a failed submission must not hang teardown.
                if raw
                    .wait_for_fences(&[self.fence], true, 10_000_000_000)
                    .is_err()
                {
                    log::error!("command buffer still pending after 10 s at teardown");
                }
                raw.destroy_fence(self.fence, None);
            }
            raw.destroy_command_pool(self.pool, None);
        }
    }
}
