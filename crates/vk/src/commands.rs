use std::sync::Arc;

use ash::vk;

use crate::device::Device;
use crate::error::{VkError, VkResultExt};

/// How long teardown waits for a submission still pending (one whose wait failed, e.g.
/// on device loss) before destroying its objects: bounded, so that teardown cannot hang.
const TEARDOWN_WAIT_NS: u64 = 10_000_000_000;

/// A command pool with one primary command buffer and a fence: record, submit, wait.
/// Reusable: each [`OneShot::begin`] resets the buffer.
///
/// For uploads and set-up work outside the frame loop (it blocks until the GPU is
/// done); frames use a [`FrameRing`]. Submits to the device's queue, taking the queue
/// lock for the submission only.
///
/// ```no_run
/// # fn demo(device: &std::sync::Arc<combustion_vk::Device>) -> Result<(), combustion_vk::VkError> {
/// let mut commands = combustion_vk::OneShot::new(device)?;
/// let cmd = commands.begin()?;
/// // ... record into `cmd` ...
/// commands.submit_and_wait()?;
/// # Ok(()) }
/// ```
pub struct OneShot {
    device: Arc<Device>,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// The fence belongs to a submission that was made and not yet waited for (a failed
    /// submission leaves the fence unsignalled, and nothing must wait for it then).
    pending: bool,
}

impl OneShot {
    /// A command pool on the device's queue family, its command buffer and a fence.
    ///
    /// # Errors
    /// [`VkError`] when a Vulkan object cannot be created (out of memory, mostly).
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
            pending: false,
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        this.cmd =
            unsafe { raw.allocate_command_buffers(&alloc) }.what("vkAllocateCommandBuffers")?[0];
        // Created signalled, so that the first submission resets it like every other.
        let fence_info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        this.fence = unsafe { raw.create_fence(&fence_info, None) }.what("vkCreateFence")?;
        Ok(this)
    }

    /// Resets the command buffer and begins recording; returns it (valid until the next
    /// `begin` or until the `OneShot` is dropped). If an earlier submission is still
    /// pending because its wait failed, waits for it first.
    ///
    /// # Errors
    /// [`VkError`] when the wait, the reset or `vkBeginCommandBuffer` fails.
    pub fn begin(&mut self) -> Result<vk::CommandBuffer, VkError> {
        // A submission whose wait failed may still be running: the buffer is reset only
        // once it has completed.
        self.wait()?;
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

    /// Ends recording, submits, and waits (without a time limit) for the GPU to finish.
    /// Call after [`OneShot::begin`] and recording.
    ///
    /// # Errors
    /// [`VkError`] when ending the buffer, the submission or the wait fails (e.g.
    /// [`VkError::DeviceLost`]). A failed submission leaves nothing pending: the
    /// `OneShot` can begin again, and dropping it does not wait.
    pub fn submit_and_wait(&mut self) -> Result<(), VkError> {
        let raw = self.device.raw();
        unsafe { raw.end_command_buffer(self.cmd) }.what("vkEndCommandBuffer")?;
        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos)];
        unsafe { raw.reset_fences(&[self.fence]) }.what("vkResetFences")?;
        // Only a submission that was made is waited for, here or in Drop: a failed one
        // leaves the fence unsignalled for good.
        self.device.submit(&submit, self.fence)?;
        self.pending = true;
        self.wait()
    }

    /// Waits for the last submission if it was made and not yet waited for.
    fn wait(&mut self) -> Result<(), VkError> {
        if !self.pending {
            return Ok(());
        }
        // A plain wait on our own fence, which the submission made will signal.
        self.device
            .wait_fences(&[self.fence], u64::MAX)
            .what("vkWaitForFences")?;
        self.pending = false;
        Ok(())
    }
}

impl Drop for OneShot {
    fn drop(&mut self) {
        let raw = self.device.raw();
        // SAFETY: wait for any submitted work before destroying what it uses.
        unsafe {
            if self.fence != vk::Fence::null() {
                // Only a submission that was made and whose wait failed (e.g. on device
                // loss) is still pending; bounded, so that teardown cannot hang.
                if self.pending
                    && self
                        .device
                        .wait_fences(&[self.fence], TEARDOWN_WAIT_NS)
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

/// Command buffers for frames in flight, each with its own pool and fence: a frame
/// records into slot `n mod N`, and [`FrameRing::begin`] waits only for the fence of the
/// frame that used that slot last (frame n − N) — the one wait the hot path has.
/// Used by Combustion's own frames (headless rendering, benchmarks); a host that records
/// Combustion into its own command buffers keeps its own ring.
pub struct FrameRing {
    device: Arc<Device>,
    slots: Vec<RingSlot>,
    next: usize,
}

struct RingSlot {
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    /// Signalled when the slot's last submission completed (created signalled).
    fence: vk::Fence,
    /// The fence belongs to a submission that was made (a failed submission leaves it
    /// unsignalled, and nothing must wait for it then).
    pending: bool,
}

/// A frame being recorded: its slot in the ring and its command buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RingFrame {
    /// The ring slot, `0..frames_in_flight`: index per-frame resources (uniform
    /// buffers, descriptor sets, swapchain acquire semaphores) with it.
    pub slot: usize,
    /// The slot's primary command buffer, in the recording state until the frame is
    /// submitted.
    pub cmd: vk::CommandBuffer,
}

impl FrameRing {
    /// A ring of `frames_in_flight` slots (at least 1: 0 is taken as 1), each with its
    /// own command pool, command buffer and fence, on the device's queue family.
    ///
    /// # Errors
    /// [`VkError`] when a Vulkan object cannot be created; what was made is destroyed.
    pub fn new(device: &Arc<Device>, frames_in_flight: usize) -> Result<Self, VkError> {
        let mut ring = FrameRing {
            device: device.clone(),
            slots: Vec::new(),
            next: 0,
        };
        let raw = device.raw();
        for _ in 0..frames_in_flight.max(1) {
            let pool_info =
                vk::CommandPoolCreateInfo::default().queue_family_index(device.queue_family());
            // SAFETY: valid create infos; Drop destroys what was made, also on error.
            let pool =
                unsafe { raw.create_command_pool(&pool_info, None) }.what("vkCreateCommandPool")?;
            let fence_info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            let fence = match unsafe { raw.create_fence(&fence_info, None) } {
                Ok(f) => f,
                Err(e) => {
                    unsafe { raw.destroy_command_pool(pool, None) };
                    return Err(VkError::from_result("vkCreateFence", e));
                }
            };
            ring.slots.push(RingSlot {
                pool,
                cmd: vk::CommandBuffer::null(),
                fence,
                pending: false,
            });
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            let cmd = unsafe { raw.allocate_command_buffers(&alloc) }
                .what("vkAllocateCommandBuffers")?[0];
            ring.slots.last_mut().expect("pushed").cmd = cmd;
        }
        Ok(ring)
    }

    /// The number of slots: how many frames may be recorded or in flight at once.
    pub fn frames_in_flight(&self) -> usize {
        self.slots.len()
    }

    /// The slot the next [`FrameRing::begin`] will use.
    pub fn next_slot(&self) -> usize {
        self.next
    }

    /// Waits for the frame that last used the next slot (n − N), resets its command pool
    /// and begins recording. Submit the frame with [`FrameRing::submit`] or
    /// [`FrameRing::submit_with`] before the next `begin`.
    ///
    /// # Errors
    /// [`VkError`] when the wait, the reset or `vkBeginCommandBuffer` fails.
    pub fn begin(&mut self) -> Result<RingFrame, VkError> {
        let slot = self.next;
        self.wait(slot)?;
        let s = &self.slots[slot];
        let raw = self.device.raw();
        // SAFETY: the slot's previous submission has completed (its fence is signalled).
        unsafe {
            raw.reset_command_pool(s.pool, vk::CommandPoolResetFlags::empty())
                .what("vkResetCommandPool")?;
            raw.begin_command_buffer(
                s.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .what("vkBeginCommandBuffer")?;
        }
        self.next = (slot + 1) % self.slots.len();
        Ok(RingFrame { slot, cmd: s.cmd })
    }

    /// Ends recording and submits the frame; its slot's fence signals when it completes.
    ///
    /// # Errors
    /// As [`FrameRing::submit_with`].
    pub fn submit(&mut self, frame: RingFrame) -> Result<(), VkError> {
        self.submit_with(frame, None, None)
    }

    /// As [`FrameRing::submit`], waiting for `wait` before any of the frame's commands
    /// (e.g. a swapchain image's acquisition) and signalling `signal` when they are done
    /// (e.g. for its presentation). Both semaphores are binary; the wait happens at every
    /// pipeline stage.
    ///
    /// # Errors
    /// [`VkError`] when ending the buffer or the submission fails. A failed submission
    /// leaves the slot with nothing pending: nothing waits for it later.
    pub fn submit_with(
        &mut self,
        frame: RingFrame,
        wait: Option<vk::Semaphore>,
        signal: Option<vk::Semaphore>,
    ) -> Result<(), VkError> {
        let s = &mut self.slots[frame.slot];
        let raw = self.device.raw();
        unsafe { raw.end_command_buffer(s.cmd) }.what("vkEndCommandBuffer")?;
        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(s.cmd)];
        let semaphore = |semaphore| {
            vk::SemaphoreSubmitInfo::default()
                .semaphore(semaphore)
                .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
        };
        let waits: Vec<_> = wait.into_iter().map(semaphore).collect();
        let signals: Vec<_> = signal.into_iter().map(semaphore).collect();
        let submit = [vk::SubmitInfo2::default()
            .command_buffer_infos(&cmd_infos)
            .wait_semaphore_infos(&waits)
            .signal_semaphore_infos(&signals)];
        s.pending = false;
        unsafe { raw.reset_fences(&[s.fence]) }.what("vkResetFences")?;
        self.device.submit(&submit, s.fence)?;
        s.pending = true;
        Ok(())
    }

    /// Waits until the last submission of `slot` has completed (at once if it had none,
    /// or if that submission failed). No time limit. `slot` must be below
    /// [`FrameRing::frames_in_flight`] (it panics otherwise, like any slice index).
    ///
    /// # Errors
    /// [`VkError`] when the wait fails (e.g. [`VkError::DeviceLost`]).
    pub fn wait(&self, slot: usize) -> Result<(), VkError> {
        if !self.slots[slot].pending {
            return Ok(());
        }
        let fence = self.slots[slot].fence;
        self.device
            .wait_fences(&[fence], u64::MAX)
            .what("vkWaitForFences")
    }

    /// Waits until every submitted frame has completed (e.g. before dropping resources
    /// the frames use). No time limit.
    ///
    /// # Errors
    /// [`VkError`] when the wait fails (e.g. [`VkError::DeviceLost`]).
    pub fn wait_all(&self) -> Result<(), VkError> {
        let fences: Vec<_> = self
            .slots
            .iter()
            .filter(|s| s.pending)
            .map(|s| s.fence)
            .collect();
        if fences.is_empty() {
            return Ok(());
        }
        self.device
            .wait_fences(&fences, u64::MAX)
            .what("vkWaitForFences")
    }
}

impl Drop for FrameRing {
    fn drop(&mut self) {
        let raw = self.device.raw();
        for s in &self.slots {
            // SAFETY: wait (bounded) for our own submissions before destroying their objects.
            unsafe {
                if s.pending
                    && self
                        .device
                        .wait_fences(&[s.fence], TEARDOWN_WAIT_NS)
                        .is_err()
                {
                    log::error!("a frame was still pending after 10 s at teardown");
                }
                raw.destroy_fence(s.fence, None);
                raw.destroy_command_pool(s.pool, None);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::cell::Cell;

    use super::*;
    use crate::test_support;
    use crate::InjectedFault;

    thread_local! {
        static LAST_COUNT: Cell<u64> = const { Cell::new(0) };
    }

    /// Fences waited for on `device` since the last call (on this thread).
    fn fences_waited(device: &Device) -> u64 {
        let now = device.counters().fence_waits;
        now - LAST_COUNT.with(|last| last.replace(now))
    }

    /// A failed submission signals no fence: nothing waits for it, neither the failed
    /// call nor teardown (which once waited the full 10 s for it).
    #[test]
    fn a_failed_submission_is_not_waited_for() {
        let device = test_support::device();
        let log = device.validation_log();
        let mut commands = OneShot::new(&device).unwrap();
        commands.begin().unwrap();
        fences_waited(&device);
        device.fail_submission(0, InjectedFault::OutOfMemory);
        assert!(commands.submit_and_wait().is_err());
        drop(commands);
        assert_eq!(
            fences_waited(&device),
            0,
            "fences waited after a failed submit"
        );
        test_support::finish(device, log);
    }

    /// After a failed submission the same `OneShot` records and submits again, each
    /// submission waited for once, and teardown waits for none.
    #[test]
    fn one_shot_works_again_after_a_failed_submission() {
        let device = test_support::device();
        let log = device.validation_log();
        let mut commands = OneShot::new(&device).unwrap();
        commands.begin().unwrap();
        device.fail_submission(0, InjectedFault::OutOfMemory);
        assert!(commands.submit_and_wait().is_err());
        fences_waited(&device);
        commands.begin().unwrap();
        commands.submit_and_wait().unwrap();
        commands.begin().unwrap();
        commands.submit_and_wait().unwrap();
        drop(commands);
        assert_eq!(fences_waited(&device), 2);
        test_support::finish(device, log);
    }

    /// A ring slot whose submission failed is not waited for; the frames after it are,
    /// each once, by `wait_all`.
    #[test]
    fn a_ring_slot_whose_submission_failed_is_not_waited_for() {
        let device = test_support::device();
        let log = device.validation_log();
        let mut ring = FrameRing::new(&device, 2).unwrap();
        let frame = ring.begin().unwrap();
        device.fail_submission(0, InjectedFault::OutOfMemory);
        assert!(ring.submit(frame).is_err());
        fences_waited(&device);
        ring.wait_all().unwrap();
        assert_eq!(
            fences_waited(&device),
            0,
            "the failed frame's slot was waited for"
        );
        for _ in 0..3 {
            let frame = ring.begin().unwrap();
            ring.submit(frame).unwrap();
        }
        ring.wait_all().unwrap();
        drop(ring);
        assert!(
            fences_waited(&device) >= 2,
            "the submitted frames were waited for"
        );
        test_support::finish(device, log);
    }
}
